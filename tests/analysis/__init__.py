"""Tests of the analysis floor (assembly/analysis)."""
