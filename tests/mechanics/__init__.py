"""Tests of the mechanics floor (assembly/mechanics)."""
