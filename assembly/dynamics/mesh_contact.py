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
from .mesh_variation import DeadZone, Series, check_positive, series
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
        self._i, self._j = np.arange(self.m), np.arange(self.m, 2 * self.m)
        self._series, self._zone = Series(self.A, self.P), DeadZone(self.backlash)
        n = model.K.shape[0]
        self.U = np.vstack(rows_g + rows_r).T if self.m else np.zeros((n, 0))
        self.contact = np.ones(self.m, dtype=bool)
        self.losses = np.zeros(self.m, dtype=np.int64)
        self.last_force = np.zeros(self.m)
        self._last = None                   # the last forces() evaluation: commit reads it
        #: Least contact slope a tangent uses (0: exact). A static solve raises it so that
        #: Newton's method can step across an open gap (whose exact tangent is singular).
        self.gap_slope = 0.0

    def state(self, x: np.ndarray, xd: np.ndarray, second: bool = False):
        """(force along the line of action N, k N/m, contact slope, e, f', f'') at ``x``, ``x'``."""
        m = self.m
        delta, ddot = x[:m], xd[:m]
        f, df, *d2 = self._series(x[m:] - self.phase, second)
        e, s = self._zone(delta)
        k = self.k0 * f
        return k * e + self.c * s * ddot, k, s, e, df, (d2[0] if d2 else None)

    def forces(self, t, x, xd):
        """Forces along (g, r) and their tangents: the Hessian of the mesh potential on (delta,
        angle) less the linear model's k0 (module notes), and the contact damper's slope."""
        m = self.m
        force, k, s, e, df, d2f = self._last = self.state(x, xd, second=True)
        kdf = self.k0 * df
        con = self._con
        nu, dc, Kt = np.empty(2 * m), np.zeros(2 * m), np.zeros((2 * m, 2 * m))
        nu[:m] = force - self.k0 * x[:m] - self.c * xd[:m]
        nu[m:] = con * 0.5 * kdf * e * e
        # the terms nu[:m] is the difference of (force_scale); nu[m:] is computed directly
        self._scale = np.concatenate([np.abs(k * e) + np.abs(self.c * s * xd[:m]) + np.abs(self.k0 * x[:m])
                                      + np.abs(self.c * xd[:m]), np.abs(nu[m:])])
        dc[:m] = self.c * (s - 1.0)
        i, j = self._i, self._j
        Kt[i, i] = k * np.maximum(s, self.gap_slope) - self.k0
        Kt[i, j] = kdf * e                               # d nu_g / d angle
        Kt[j, i] = con * kdf * e * s                     # d nu_r / d delta (symmetric: a potential's Hessian)
        Kt[j, j] = con * 0.5 * self.k0 * d2f * e * e
        return nu, Kt, dc

    def commit(self, t, x, xd):
        force, _, s, _, _, _ = self._last if self._last is not None else self.state(x, xd)
        touching = s > 0
        self.losses += self.contact & ~touching
        self.contact = touching
        self.last_force = force

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
