"""Tests of the model floor (assembly/model)."""
