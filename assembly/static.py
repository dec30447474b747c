"""Static load cases: a torque into one body, reacted by holding another, and the solve.

The input torque (N m) acts about the input body's axis (at a flexible body, on the named
interface master); the output body is held against rotation about its own axis
(:mod:`assembly.loads`). Solved on the same assembled stiffness as the modes -- one
factorisation per model serves every load case -- and the forces in every spring follow
from the deflections (:mod:`assembly.reactions`); flexible bodies are back-expanded for
stresses. Sign conventions and checks: docs/static.md.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .errors import MechanismError
from .loads import held_column, held_name, input_load, free_motions
from .model import assemble
from .scene import LoadCase

#: Largest model (independent DOFs) solved with a dense Cholesky factorisation.
DENSE_MAX = 3000


@dataclass
class StaticResult:
    """Static response of ``model`` to ``load`` (scene path ``path``): ``q`` on the
    independent coordinates (0 at the held one), ``z = T q`` on the absolute ones (m, rad,
    flexible bodies: component coordinates); ``held``: the column of q holding the output
    (None when a constraint already holds it)."""

    model: object
    z: np.ndarray
    load: LoadCase
    q: np.ndarray = None
    held: int | None = None
    path: str = "load"

    def body_dofs(self, name: str) -> np.ndarray:
        return self.z[self.model.body_slice(name)]


def solve_static(scene, load: LoadCase, bodies: dict | None = None, model=None,
                 path: str = "load") -> StaticResult:
    """Static response to ``load``; ``model``: the assembled ``scene`` to reuse (else it is
    assembled, with pre-built ``bodies`` if given). Raises MechanismError naming ``path``
    if the held assembly can still move."""
    return solve_static_cases(scene, [(path, load)], bodies, model)[0]


def solve_static_cases(scene, cases, bodies: dict | None = None, model=None) -> list:
    """:class:`StaticResult` of every (path, load case) in ``cases`` on one model
    (default :meth:`Scene.load_cases`); cases holding the same coordinate share one
    factorisation."""
    m = model if model is not None else assemble(scene, bodies=bodies)
    cases = list(scene.load_cases() if cases is None else cases)
    out, solvers = [], {}
    for path, load in cases:
        col = held_column(m, load)
        if col not in solvers:
            _refuse_mechanism(m, load, path, col)
            solvers[col] = _factor(m.K, col)
        keep, solve = solvers[col]
        Fq = np.asarray(m.T.T @ input_load(m, load)).ravel()
        q = np.zeros(m.K.shape[0])
        q[keep] = solve(Fq[keep])
        out.append(StaticResult(m, np.asarray(m.T @ q).ravel(), load, q, col, path))
    return out


def _refuse_mechanism(m, load, path: str, col) -> None:
    free = free_motions(m, col)
    if free.shape[1]:
        j = int(np.argmax(np.abs(free[:, 0])))
        raise MechanismError(f"{path} ({load.name!r}): with {held_name(m, load)} held the assembly still has "
                             f"{free.shape[1]} free motion(s) (dominant DOF {m.dof_names[j]}); no static "
                             "solution", m.dof_names[j])


def _factor(K, col):
    """(kept columns, solve) for K without row/column ``col``."""
    keep = np.ones(K.shape[0], bool)
    if col is not None:
        keep[col] = False
    Kk = K[keep][:, keep]
    if Kk.shape[0] <= DENSE_MAX:
        import scipy.linalg as sla
        c = sla.cho_factor(Kk.toarray() if sp.issparse(Kk) else Kk)
        return keep, lambda b: sla.cho_solve(c, b)
    from cms.linsolve import factor
    f = factor(sp.csc_matrix(Kk))
    return keep, f.solve


def stress_summary(model, Z: np.ndarray, names=None) -> dict:
    """Per flexible body: max von Mises (Pa) and its global location for each column of Z."""
    out = {}
    for b, bm in model.bodies.items():
        if not bm.flexible:
            continue
        rows = []
        Zb = Z[model.body_slice(b)]
        for j in range(Zb.shape[1] if Zb.ndim > 1 else 1):
            st = bm.stress(Zb[:, j] if Zb.ndim > 1 else Zb)
            k = int(np.argmax(st.von_mises))
            rows.append({"case": names[j] if names else j, "max_von_mises_Pa": float(st.von_mises[k]),
                         "location_m": (bm.origin + bm.axes @ st.points[k]).tolist()})
        out[b] = rows
    return out
