"""Craig-Bampton component mode synthesis for flexgear.

Public API::

    from cms import CraigBamptonReductor, Superelement
    red = CraigBamptonReductor(K, M, boundary_dofs, n_modes=30, node_coords=X)
    se = red.reduce()                 # Superelement: K, M (reduced), Phi, Psi, ...
    u = red.reconstruct(q)            # full DOF vector from reduced coordinates

Reduced coordinates: boundary DOFs first (in the given order), then the modal
coordinates of the mass-normalised fixed-interface modes. SI units throughout.
"""
from .cache import SuperelementCache, array_hash, cache_key
from .craig_bampton import CraigBamptonReductor, SolverOptions, guyan
from .eigen import count_rigid_modes, free_free_shift, lowest_modes
from .errors import CacheError, EigenSolveError, InteriorMechanismError, ModeLimitError, ReductionError
from .linsolve import cholmod_available, factor
from .stress import NodalStress, recover_stress
from .superelement import Superelement

__all__ = ["CraigBamptonReductor", "SolverOptions", "guyan", "Superelement", "SuperelementCache",
           "array_hash", "cache_key", "lowest_modes", "free_free_shift", "count_rigid_modes",
           "factor", "cholmod_available", "recover_stress", "NodalStress", "ReductionError",
           "InteriorMechanismError", "EigenSolveError", "CacheError", "ModeLimitError"]
