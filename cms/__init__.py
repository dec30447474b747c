"""Craig-Bampton component mode synthesis for flexgear.

Public API::

    from cms import CraigBamptonReductor, Superelement
    red = CraigBamptonReductor(K, M, boundary_dofs, n_modes=30, node_coords=X)
    se = red.reduce()                 # Superelement: K, M (reduced), Phi, Psi, ...
    u = red.reconstruct(q)            # full DOF vector from reduced coordinates

Reduced coordinates: boundary DOFs first (in the given order), then the modal
coordinates of the mass-normalised fixed-interface modes. SI units throughout.
"""
from __future__ import annotations

import importlib

#: Public name -> submodule; each is imported on first use (``from cms import X`` works), so
#: importing ``cms.errors`` does not load scikit-fem or scipy.sparse.linalg.
_EXPORTS = {
    "SuperelementCache": "cache", "array_hash": "cache", "cache_key": "cache",
    "CraigBamptonReductor": "craig_bampton", "SolverOptions": "craig_bampton", "guyan": "craig_bampton",
    "count_rigid_modes": "eigen", "free_free_shift": "eigen", "lowest_modes": "eigen",
    "CacheError": "errors", "EigenSolveError": "errors", "InteriorMechanismError": "errors",
    "ModeLimitError": "errors", "ReductionError": "errors",
    "cholmod_available": "linsolve", "factor": "linsolve",
    "NodalStress": "stress", "recover_stress": "stress",
    "Superelement": "superelement",
}
__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
