"""gmsh's volume mesh of the current model: sizes, element order, curved second-order edges,
inverted second-order elements repaired.

One rule for every solid: the generated components (:func:`fe_components.meshing.generate_mesh`)
and a user's CAD part (:func:`fe_components.part.cad.generate_part_mesh`). The ``gmsh`` module
is passed in by the caller, who opened it with :func:`fe_components.gmsh_session.gmsh_model`.
A change here that changes the meshes produced bumps ``fe_components.meshing.MESHER_VERSION``.
"""
from __future__ import annotations

import logging

import numpy as np

log = logging.getLogger(__name__)


def mesh_volume(gmsh, options, unit: float = 1.0) -> None:
    """Mesh the current gmsh model's volumes with ``options`` (a
    :class:`~fe_components.meshing.MeshOptions`: binary output, curved P2 edges, inverted
    second-order elements repaired); ``unit``: metres per model unit (the sizes are given in m)."""
    gmsh.option.setNumber("Mesh.MeshSizeMax", options.size / unit)
    gmsh.option.setNumber("Mesh.MeshSizeMin", options.min_size / unit)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", options.curvature_elements)
    gmsh.option.setNumber("Mesh.Algorithm3D", options.algorithm_3d)
    gmsh.option.setNumber("Mesh.ElementOrder", options.order)
    gmsh.option.setNumber("Mesh.SecondOrderLinear", 0)
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.model.mesh.generate(3)
    types, _, _ = gmsh.model.mesh.getElements(3)
    if len(types) == 0:
        raise RuntimeError("gmsh produced no volume elements")
    if options.order == 2:
        _repair_inverted(gmsh)


def _min_scaled_jacobians(gmsh) -> np.ndarray:
    _, tags, _ = gmsh.model.mesh.getElements(3)
    all_tags = np.concatenate([np.asarray(t) for t in tags])
    return np.asarray(gmsh.model.mesh.getElementQualities(all_tags.tolist(), "minSJ"))


def _repair_inverted(gmsh) -> None:
    """Curving P2 edges onto the CAD can fold coarse elements (minimum scaled Jacobian <= 0):
    untangle them with gmsh's high-order optimiser; valid meshes are left untouched."""
    n_bad = int(np.sum(_min_scaled_jacobians(gmsh) <= 0))
    if not n_bad:
        return
    log.info("%d inverted second-order elements: running gmsh high-order optimisation", n_bad)
    gmsh.option.setNumber("Mesh.HighOrderThresholdMin", 0.1)
    gmsh.model.mesh.optimize("HighOrder")
    left = int(np.sum(_min_scaled_jacobians(gmsh) <= 0))
    if left:
        raise RuntimeError(f"{left} of {n_bad} inverted second-order elements remain after high-order "
                           "optimisation: use a smaller mesh size or order=1")
