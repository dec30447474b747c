"""gmsh for flexgear: the one place it is imported (lazily: importing flexgear never loads it),
and a gmsh model of one's own for the duration of a block."""
from __future__ import annotations

import contextlib
import os


def gmsh_module():
    """The ``gmsh`` module, imported on the first call. A block that builds, meshes or writes
    opens a model with :func:`gmsh_model`; this is for a caller that only needs the module
    loaded (a benchmark importing its libraries before the clock starts)."""
    import gmsh
    return gmsh


@contextlib.contextmanager
def gmsh_model(name: str):
    """Yield the ``gmsh`` module with a fresh current model ``<name>-<pid>``: gmsh initialised
    here if it is not already (then finalised after, else the model removed), its terminal
    output off, and the OpenCASCADE target unit (process-wide STEP translator state) restored."""
    gmsh = gmsh_module()
    own = not gmsh.isInitialized()
    if own:
        gmsh.initialize(readConfigFiles=False, interruptible=False)
    unit = gmsh.option.getString("Geometry.OCCTargetUnit")
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(f"{name}-{os.getpid()}")
        yield gmsh
    finally:
        gmsh.option.setString("Geometry.OCCTargetUnit", unit)
        if own:
            gmsh.finalize()
        else:
            gmsh.model.remove()
