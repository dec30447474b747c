"""The errors of the command line and the one list of user errors.

A user error (a scene, a part, a cache, a solve, an output folder or a command-line value
the program cannot use) ends in one line on stderr naming the field and the value, exit code
2, never a traceback (:func:`user_errors`); the report pipeline uses the same list for what
it notes instead of stopping on.
"""
from __future__ import annotations


class UsageError(ValueError):
    """A command-line value the program cannot use (e.g. ``--modes -5``)."""


class Terminated(BaseException):
    """SIGTERM arrived; a BaseException like KeyboardInterrupt, so cleanup code runs."""


def user_errors() -> tuple:
    """Exception types the package raises on input it cannot use (scene, geometry, meshing,
    coupling, reduction and its cache, eigen solve, a singular matrix, output folder, command
    line): reported in one line with exit code 2, never a traceback."""
    from numpy.linalg import LinAlgError

    from cms.errors import ReductionError
    from fe_components.errors import CouplingError, GeometryError, MeshCacheError, MeshingError

    from ..errors import MechanismError, SceneError, SolverError
    from .output import OutputDirError
    return (SceneError, MechanismError, SolverError, OutputDirError, GeometryError, MeshingError, MeshCacheError,
            CouplingError, ReductionError, UsageError, ModeSelectionError, LinAlgError)


class ModeSelectionError(ValueError):
    """``RunOptions.mode_numbers`` names a mode the scene does not have."""
