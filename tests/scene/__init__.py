"""Tests of the scene floor (assembly/scene)."""
