"""Static load cases: applied torques and point loads, held outputs and supports, and the
solve.

The applied loads and the held directions of a case come from :mod:`assembly.analysis.load_cases`: a
torque about the input body's axis reacted by holding the output against rotation, point
loads anywhere, supports holding chosen DOFs for that case only. The held directions are
constraint rows ``C q = 0``; they are eliminated exactly (``q = N q_r``, each row solved
for one pivot coordinate -- for a plain held coordinate that is dropping its column), and
the reduced stiffness ``N' K N`` is factorised once per distinct set of holds (cases
holding the same directions share it). Solved on the same assembled stiffness as the modes;
the forces in every spring follow from the deflections (:mod:`assembly.analysis.reactions`), the
hold reactions from the residual ``K q - F = C' lambda``; flexible bodies are
back-expanded for stresses. Sign conventions and checks: docs/static.md.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from .. import arguments
from ..errors import MechanismError, SceneError
from ..mechanics.nullity import STRUCT_RTOL
from ..model.assemble import model_of, source_scene, sparse_model
from ..model.frame_motion import scene_gravity
from ..scene.tables import LoadCase
from .load_cases import free_motions, held_directions, load_vector
from .modal import DENSE_MAX


@dataclass(frozen=True)
class StaticResult:
    """Static response of ``model`` to ``load`` (scene path ``path``): ``q`` on the
    independent coordinates (0 in every held direction), ``z = T q`` on the absolute ones
    (m, rad, flexible bodies: component coordinates); ``held``: the held directions
    (:class:`assembly.analysis.load_cases.Held`) and ``hold_reactions`` their reactions (N or N m: the
    force or moment the hold exerts on the body along that local direction)."""

    model: object
    z: np.ndarray
    load: LoadCase
    q: np.ndarray = None
    held: list = field(default_factory=list)
    path: str = "load"
    hold_reactions: np.ndarray = None

    @property
    def output_held(self) -> bool:
        """Whether the torque case's output hold is a held direction (False: a constraint
        already holds that rotation)."""
        return any(h.support is None for h in self.held)

    def body_dofs(self, name: str) -> np.ndarray:
        return self.z[self.model.body_slice(name)]


def solve_static(model, load: LoadCase, path: str = "load") -> StaticResult:
    """Static response of ``model`` (an :class:`AssembledModel`, or a Scene assembled as
    given) to ``load``. Raises MechanismError naming ``path`` if the held assembly can still
    move."""
    arguments.instance("load", load, LoadCase, "a LoadCase")
    arguments.text("path", path)
    return solve_static_cases(model, [(path, load)])[0]


def solve_static_cases(model, cases=None) -> list:
    """:class:`StaticResult` of every (path, load case) in ``cases`` on ``model`` (an
    :class:`AssembledModel`, or a Scene assembled as given; ``cases`` default: its scene's
    :meth:`Scene.load_cases`); cases holding the same directions share one factorisation."""
    scene = source_scene("model", model)
    if cases is not None:
        if not isinstance(cases, (list, tuple)):
            raise arguments.refuse("cases", cases, "must be a list of (name, LoadCase) pairs")
        for i, c in enumerate(cases):
            if not (isinstance(c, (list, tuple)) and len(c) == 2 and isinstance(c[0], str)):
                raise arguments.refuse(f"cases[{i}]", c, "must be a (name, LoadCase) pair")
            arguments.instance(f"cases[{i}]", c[1], LoadCase, "a (name, LoadCase) pair")
    m = sparse_model(model_of("model", model))
    cases = list(scene.load_cases() if cases is None else cases)
    gravity = scene_gravity(m, scene.turbine)           # every case's body load, when the scene asks
    out, solvers = [], {}
    for path, load in cases:
        held = held_directions(m, load)
        key = tuple(h.name for h in held)
        if key not in solvers:
            C = np.array([h.row for h in held]).reshape(len(held), m.K.shape[0])
            _refuse_mechanism(m, load, path, held, C)
            N = constraint_basis(C, [_hold_path(path, h) for h in held])
            solvers[key] = (C, N, _factor((N.T @ m.K @ N).tocsr()))
        C, N, solve = solvers[key]
        Fq = np.asarray(m.T.T @ load_vector(m, load)).ravel()
        if gravity is not None:
            Fq = Fq + gravity
        q = np.asarray(N @ solve(np.asarray(N.T @ Fq).ravel())).ravel()
        lam = np.linalg.solve(C @ C.T, C @ (m.K @ q - Fq)) if len(held) else np.zeros(0)
        out.append(StaticResult(m, np.asarray(m.T @ q).ravel(), load, q, held, path, lam))
    return out


def _hold_path(path: str, h) -> tuple[str, str]:
    """(scene path, value) naming a held direction in an error."""
    if h.support is None:
        return f"{path}.output", h.body
    return f"{path}.supports[{h.support}].dofs", h.dof


def constraint_basis(C: np.ndarray, paths: list) -> sp.csr_matrix:
    """``N`` (n_q x (n_q - n_c)) with ``C N = 0``: each row of ``C`` solved for one pivot
    coordinate among the few it touches (column-pivoted QR), the other coordinates kept.
    A row dependent on the rows before it holds nothing new: SceneError at its ``paths``
    entry (scene path, value)."""
    n_q = C.shape[1]
    if C.shape[0] == 0:
        return sp.identity(n_q, format="csr")
    J = np.flatnonzero(np.any(C != 0, axis=0))
    Cj = C[:, J] / np.linalg.norm(C[:, J], axis=1, keepdims=True)
    for k in range(1, Cj.shape[0]):
        s = np.linalg.svd(Cj[:k + 1], compute_uv=False)
        if len(s) < k + 1 or s[-1] <= STRUCT_RTOL * s[0]:
            raise SceneError(*paths[k], "holds a direction the case already holds (another support, or the "
                                        "output hold): give it once")
    _, _, piv = sla.qr(Cj, pivoting=True, mode="economic")
    P, F = J[piv[:C.shape[0]]], J[piv[C.shape[0]:]]
    A = np.linalg.solve(Cj[:, piv[:C.shape[0]]], Cj[:, piv[C.shape[0]:]])    # q_P = -A q_F
    keep = np.setdiff1d(np.arange(n_q), P)
    col = np.full(n_q, -1)
    col[keep] = np.arange(len(keep))
    rows, cols, vals = list(keep), list(range(len(keep))), [1.0] * len(keep)
    for i, p in enumerate(P):
        for f, a in zip(F, A[i]):
            if a != 0.0:
                rows.append(p)
                cols.append(col[f])
                vals.append(-a)
    return sp.csr_matrix((vals, (rows, cols)), shape=(n_q, len(keep)))


def _refuse_mechanism(m, load, path: str, held: list, C: np.ndarray) -> None:
    free = free_motions(m, C)
    if free.shape[1]:
        j = int(np.argmax(np.abs(free[:, 0])))
        what = ", ".join(h.name for h in held) if held else "nothing"
        raise MechanismError(f"{path} ({load.name!r}): with {what} held the assembly still has "
                             f"{free.shape[1]} free motion(s) (dominant DOF {m.dof_names[j]}); no static "
                             "solution", m.dof_names[j])


def _factor(K):
    """Solve function of the symmetric positive definite ``K`` (dense Cholesky up to
    DENSE_MAX (the modal solve's dense limit), else the sparse factorisation of :mod:`cms.linsolve`)."""
    if K.shape[0] <= DENSE_MAX:
        c = sla.cho_factor(K.toarray() if sp.issparse(K) else K)
        return lambda b: sla.cho_solve(c, b)
    from cms.linsolve import factor
    f = factor(sp.csc_matrix(K))
    return f.solve


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
