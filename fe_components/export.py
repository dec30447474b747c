"""Export of a component mesh with nodal fields to VTU (ParaView) via meshio."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Mapping

import numpy as np

from .fe_model import FEModel


def write_vtu(path: str | os.PathLike, model: FEModel, point_data: Mapping[str, np.ndarray] | None = None,
              interfaces: bool = False) -> Path:
    """Write the model's volume mesh and nodal fields to ``path`` (.vtu), atomically.

    P2 meshes are written as VTK quadratic tetrahedra ("tetra10"), P1 as "tetra".
    point_data : {name: array (n_nodes,) or (n_nodes, 3)} in the model's node
        order (``model.nodes``); a full DOF vector (3 n_nodes,) is reshaped to (n_nodes, 3).
    interfaces : also write one 0/1 field ``interface_<name>`` per interface node set.
    """
    import meshio

    path = Path(path)
    nodes = model.nodes
    n = len(nodes)
    # cells in node numbering: element DOFs of the x component, divided by 3
    cell_nodes = model.basis.element_dofs[0::3, :].T // 3
    cell_type = "tetra10" if model.order == 2 else "tetra"
    data = {}
    for name, arr in (point_data or {}).items():
        a = np.asarray(arr)
        if a.ndim == 1 and a.shape[0] == 3 * n:
            a = a.reshape(n, 3)
        if a.shape[0] != n:
            raise ValueError(f"point_data[{name!r}] has {a.shape[0]} rows, the mesh has {n} nodes")
        data[name] = a
    if interfaces:
        for name, iface in model.interfaces.items():
            mask = np.zeros(n)
            mask[iface.nodes] = 1.0
            data[f"interface_{name}"] = mask
    mesh = meshio.Mesh(nodes, [(cell_type, cell_nodes)], point_data=data)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.tmp.vtu")
    try:
        meshio.write(tmp, mesh, file_format="vtu")
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path
