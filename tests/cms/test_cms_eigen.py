"""Helpers beside the eigen solver (cms.eigen)."""
from cms.eigen import count_rigid_modes


def test_count_rigid_modes():
    # a free-free spectrum (Hz): six rigid-body modes at round-off level, of either sign,
    # then elastic modes many decades above them
    assert count_rigid_modes([1e-4, -2e-4, 3e-5, 1e-4, 2e-4, 5e-5, 900.0, 901.0]) == 6
