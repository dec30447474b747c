"""Tests of the dynamics floor (assembly/dynamics)."""
