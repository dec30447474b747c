"""Gear meshes of a time-domain run: stiffness driven by the gear angle, backlash, contact loss.

Each mesh with a ``variation`` or a ``backlash`` becomes two directions of the run's
nonlinear forces (:mod:`assembly.dynamics.transient`) on the independent coordinates q:

* its line of action ``g`` (the compression delta = g q, the mesh row of the linear model);
* its angle ``r = z (r_gear - r_frame)``, phi = r q - phase, with r_body the row of a body's
  rotation about its own axis (:func:`assembly.analysis.load_cases.axial_rotation`).

The linear model already holds the mean spring and damper ``k0 g g'``, ``c g g'``, so the
forces along the two directions are the corrections (:mod:`assembly.dynamics.mesh_variation`):
``nu_g = k(phi) e + c s delta' - k0 delta - c delta'`` (the damper acts in contact only)
and ``nu_r = 1/2 k0 f'(phi) e^2`` (the energy-consistent term, when asked for). A
contact-loss event is a step at whose end a mesh that was in contact is not.
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from ..model.probes import spin_row, strain_rows
from ..scene.paths import body_origins, element_paths, stage_mesh_side
from ..scene.tables import HOUSING
from .jit import either, pick, plain
from .mesh_laws import every_mesh, mesh_commit, mesh_forces, mesh_law
from .mesh_variation import check_positive, series
from .transient import Nonlinear

log = logging.getLogger(__name__)


@dataclass
class MeshInfo:
    """One mesh of the run: ``name``, scene ``path``, counting ``teeth`` and bodies
    (``gear``, ``frame``: None = the housing), harmonics kept, backlash (m; NaN none)."""

    name: str
    path: str
    teeth: int | None
    gear: str
    frame: str | None
    harmonics: int
    backlash: float


def _frame(scene, gear1: str, gear2: str) -> str | None:
    frames = {scene.body(g).frame for g in (gear1, gear2)} - {HOUSING}
    return frames.pop() if frames else None


class Meshes(Nonlinear):
    """The nonlinear meshes of an assembled model (module notes)."""

    compiled = "meshes"                     # the compiled step knows these laws

    def __init__(self, model, consistent: bool = True):
        scene, src = model.scene, model.source or model.scene
        paths = dict((id(m), p) for p, m in element_paths(src, scene, "meshes", body_origins(src, scene), "gear1"))
        rows_g, rows_r, k0, c, b, A, P, phase, self.info = [], [], [], [], [], [], [], [], []
        for el in model.elements:
            if el.kind != "mesh":
                continue
            m = scene.meshes[el.item[1]]
            if m.variation is None and m.backlash is None:
                continue
            path = paths.get(id(m), f"meshes[{el.item[1]}]")
            rows_g.append(strain_rows(model, el)[0])
            frame = _frame(scene, m.gear1, m.gear2)
            v = m.variation
            if v is not None:
                gear = m.gear1 if v.counting_gear == "gear1" else m.gear2
                a, p = series(v)
                where = (f"{path}.variation_{stage_mesh_side(scene, m)}" if path.startswith("stages")
                         else f"{path}.variation")
                check_positive(a, p, where + (".amplitudes" if v.amplitudes is not None else ".step"))
                r = v.teeth * (spin_row(model, gear) - (spin_row(model, frame) if frame else 0.0))
                z, ph = v.teeth, v.phase
            else:
                gear, a, p, r, z, ph = m.gear1, np.zeros(0), np.zeros(0), np.zeros(model.K.shape[0]), None, 0.0
            rows_r.append(r)
            k0.append(float(el.k[0]))
            c.append(0.0 if el.c is None else float(el.c[0]))
            b.append(math.nan if m.backlash is None else m.backlash)
            A.append(a)
            P.append(p)
            phase.append(ph)
            self.info.append(MeshInfo(m.name or f"{m.gear1}-{m.gear2}", path, z, gear, frame, len(a), b[-1]))
        H = max([len(a) for a in A], default=0)
        self.m = len(k0)
        self.A = np.array([np.pad(a, (0, H - len(a))) for a in A]).reshape(self.m, H)
        self.P = np.array([np.pad(p, (0, H - len(p))) for p in P]).reshape(self.m, H)
        self.k0, self.c, self.backlash = np.array(k0), np.array(c), np.array(b)
        self.phase = np.array(phase)
        self.consistent = consistent
        self._con = 1.0 if consistent else 0.0
        self.cP, self.sP = np.cos(self.P), np.sin(self.P)
        self.linear = np.isnan(self.backlash)
        self.lin = self.linear.astype(float)
        self.gap = np.where(self.linear, 0.0, self.backlash)
        n = model.K.shape[0]
        self.U = np.vstack(rows_g + rows_r).T if self.m else np.zeros((n, 0))
        self.contact = np.ones(self.m, dtype=bool)
        self.losses = np.zeros(self.m, dtype=np.int64)
        self.last_force = np.zeros(self.m)
        #: the contact force and slope of the last forces() evaluation (commit reads them)
        self.force, self.slope, self.evaluated = np.zeros(self.m), np.ones(self.m), False
        #: Least contact slope a tangent uses (0: exact). A static solve raises it so that
        #: Newton's method can step across an open gap (whose exact tangent is singular).
        self.gap_slope = 0.0

    def laws(self) -> tuple:
        """The meshes' parameters as the arrays of :func:`assembly.dynamics.mesh_laws.mesh_forces`."""
        return self.k0, self.c, self.A, self.cP, self.sP, self.phase, self.lin, self.gap

    def state(self, x: np.ndarray, xd: np.ndarray, second: bool = False):
        """(force along the line of action N, k N/m, contact slope, e, f', f'') at ``x``, ``x'``."""
        m = self.m
        x, xd = np.asarray(x, float), np.asarray(xd, float)
        return plain(mesh_law)(x[:m], xd[:m], x[m:2 * m] - self.phase, self.k0, self.c, self.A.T, self.cP.T,
                               self.sP.T, self.lin, self.gap)

    def forces(self, t, x, xd):
        """Forces along (g, r) and their tangents: the Hessian of the mesh potential on (delta,
        angle) less the linear model's k0 (module notes), and the contact damper's slope
        (:func:`assembly.dynamics.mesh_laws.mesh_forces`)."""
        m2 = 2 * self.m
        nu, dc, Kt, self._scale = np.empty(m2), np.empty(m2), np.empty((m2, m2)), np.empty(m2)
        law = either(mesh_forces, every_mesh)
        law(x, xd, *self.laws(), self._con, self.gap_slope, nu, Kt, dc, self._scale, self.force, self.slope)
        self.evaluated = True
        return nu, Kt, dc

    def commit(self, t, x, xd):
        if not self.evaluated:
            self.force[:], _, self.slope[:], _, _, _ = self.state(x, xd)
        pick(mesh_commit)(self.contact, self.losses, self.slope)
        self.last_force = self.force.copy()

    def force_scale(self, nu: np.ndarray) -> np.ndarray:
        """The size of the forces the last :meth:`forces` summed: the contact force's spring and
        damper terms and the linear model's k0 delta and c delta' it is corrected by."""
        return self._scale

    def coast_preload(self, x: np.ndarray) -> np.ndarray:
        """Forces along (g, r) that move every mesh with backlash whose compression in ``x``
        is negative onto its coast flank: ``k0 b`` on its line of action (the linear spring
        ``k0 delta`` then carries ``k0 (delta + b)``, the coast flank's force)."""
        m = self.m
        out = np.zeros(2 * m)
        coast = ~np.isnan(self.backlash) & (x[:m] < 0)
        out[:m][coast] = self.k0[coast] * self.backlash[coast]
        return out

    def energy(self, x: np.ndarray) -> float:
        """Strain energy 1/2 k(phi) e^2 summed over the meshes (J), minus the linear
        model's share 1/2 k0 delta^2 (which ``1/2 q' K q`` counts)."""
        m = self.m
        _, k, _, e, _, _ = self.state(x, np.zeros_like(x))
        return float(0.5 * np.sum(k * e * e - self.k0 * x[:m] ** 2))
