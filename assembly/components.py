"""Component bodies: a body's ``component`` table -> fe_components parameters, placement,
interface master points, and the FE model (meshed with gmsh, assembled with scikit-fem).

Master points come from the component geometry alone (no meshing), so a scene is
validated before anything is meshed. FE models are memoised per process, so the
torsional, rigid and flexible variants of one scene assemble each mesh once; meshes are
cached on disk in :class:`CacheDirs` (or read from the committed reference meshes).
Component placement: a local point ``x`` sits at ``position + R x`` with
``R = axis_frame(axis)`` (local z = the body's axis). SI units.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .kinematics import axis_frame
from .scene import FlexOptions
from .schema import component_from_table

log = logging.getLogger(__name__)

#: Default folder of generated meshes and reductions (not in git).
DEFAULT_CACHE = Path(__file__).resolve().parent.parent / "meshes" / "cache"


@dataclass(frozen=True)
class CacheDirs:
    """Folders of the on-disk caches: ``meshes`` (gmsh .msh files, keyed by geometry and
    mesh options) and ``superelements`` (Craig-Bampton reductions, keyed by what they were
    built from). Pass one to :func:`assembly.model.assemble` to keep a study's caches apart."""

    meshes: Path = DEFAULT_CACHE
    superelements: Path = field(default=DEFAULT_CACHE / "cms")


def component_params(body, path: str):
    """fe_components parameters of a body's ``component`` table (errors name ``path``)."""
    return component_from_table(body.component, path)


def local_masters(params) -> dict:
    """Interface name -> master position in the component's local axes (m); no meshing."""
    from fe_components.geometry import interface_defs
    return {d.name: np.asarray(d.master, float) for d in interface_defs(params)}


def placement(body):
    """(origin (3,), R (3x3)) mapping local component points to global: x_g = o + R x."""
    return np.asarray(body.position, float), axis_frame(body.axis)


def global_masters(body, params) -> dict:
    """Interface name -> global master position (m) of a placed component body."""
    o, R = placement(body)
    return {k: o + R @ v for k, v in local_masters(params).items()}


def mesh_size(params, options: FlexOptions) -> float:
    """The element size (m): the option, or the component's default (thinnest wall)."""
    from fe_components.fe_model import default_mesh_size
    return options.mesh_size if options.mesh_size is not None else default_mesh_size(params)


def mesh_dir(params, size: float, order: int, caches: CacheDirs) -> Path:
    """Committed reference mesh folder if it holds this exact mesh, else the mesh cache."""
    from fe_components.meshing import MeshOptions, mesh_path
    from fe_components.reference import REF_DIR
    return REF_DIR if mesh_path(params, MeshOptions(size=size, order=order), REF_DIR).exists() else caches.meshes


#: Bulk-to-shear modulus ratio K/G = 2(1 + nu) / (3(1 - 2 nu)) above which linear (P1)
#: tetrahedra lock volumetrically (nu > ~0.45): stiffness and frequencies come out too high.
LOCKING_RATIO = 10.0


def check_locking(order: int, nu: float) -> bool:
    """Warn (and return True) when P1 tetrahedra will lock at this Poisson ratio."""
    ratio = 2 * (1 + nu) / (3 * (1 - 2 * nu))
    if order == 1 and ratio > LOCKING_RATIO:
        log.warning("P1 tetrahedra lock volumetrically at nu = %.4g (bulk/shear modulus %.3g > %.0f): "
                    "results will be too stiff; use order = 2", nu, ratio, LOCKING_RATIO)
        return True
    return False


_FE_MEMO: dict = {}
_FE_MEMO_SIZE = 8


def forget_fe_models() -> None:
    """Drop the FE models memoised in this process (meshes stay cached on disk)."""
    _FE_MEMO.clear()


def build_fe(params, options: FlexOptions, caches: CacheDirs):
    """Mesh (cached on disk) and assemble the component's FE model (memoised per process)."""
    from fe_components.fe_model import build_component
    from fe_components.params import params_digest
    from fe_components.quality import check_quality
    m = options.material
    size = mesh_size(params, options)
    check_locking(options.order, m.nu)
    folder = mesh_dir(params, size, options.order, caches)
    key = params_digest(params, size, options.order, m.E, m.nu, m.rho) + str(folder)
    if key not in _FE_MEMO:
        if len(_FE_MEMO) >= _FE_MEMO_SIZE:
            _FE_MEMO.pop(next(iter(_FE_MEMO)))
        fe = build_component(params, m, mesh_size=size, order=options.order, cache_dir=folder)
        rep = check_quality(fe.mesh.p.T, fe.mesh.t.T)
        log.info("mesh quality: worst element %d, q = %.3g", rep.worst, rep.worst_quality)
        _FE_MEMO[key] = fe
    return _FE_MEMO[key]


def mass_properties(body, params, options: FlexOptions, caches: CacheDirs):
    """(mass kg, COM global, inertia global about COM, FE model) of a component body."""
    fe = build_fe(params, options, caches)
    o, R = placement(body)
    return fe.mass, o + R @ fe.center_of_mass, R @ fe.inertia @ R.T, fe
