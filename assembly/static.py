"""The static load case: a torque into one body, reacted at another, and its stresses.

The input torque (N m) acts about the input body's axis (at a flexible body, on the
named interface master); the output body is held against rotation about its own axis
(its reaction). Solved on the same assembled stiffness as the modes; flexible bodies are
then back-expanded for stresses.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import MechanismError
from .model import assemble
from .scene import Fixed, LoadCase, derive


@dataclass
class StaticResult:
    model: object
    z: np.ndarray
    load: LoadCase

    def body_dofs(self, name: str) -> np.ndarray:
        return self.z[self.model.body_slice(name)]


def solve_static(scene, load: LoadCase, bodies: dict | None = None) -> StaticResult:
    """Static response to ``load``; raises MechanismError if the held scene can still move."""
    sc = scene.expanded()
    held = derive(sc, fixed=sc.fixed + (Fixed(load.output, ("rz",)),))
    m = assemble(held, bodies=bodies)
    bm = m.bodies[load.input]
    F = np.zeros(m.n_abs)
    sl = m.body_slice(load.input)
    if bm.flexible:
        idx = bm.masters[load.input_interface][1]
        Fb = np.zeros(bm.ndof)  # body DOFs are in local axes: z = the body's axis
        Fb[idx[3:]] = [0.0, 0.0, load.torque]
        F[sl] = Fb
    else:
        F[sl.start + 3:sl.start + 6] = load.torque * bm.axes[:, 2]
    Fq = m.T.T @ F
    K = m.K.toarray() if m.K.shape[0] <= 3000 else m.K
    try:
        if isinstance(K, np.ndarray):
            w, V = np.linalg.eigh(K)
            if w[0] <= 1e-12 * w[-1]:
                free = V[:, 0]
                j = int(np.argmax(np.abs(free)))
                raise MechanismError(f"load case '{load.name}': the held assembly still moves freely "
                                     f"(dominant DOF {m.dof_names[j]})", m.dof_names[j])
            q = np.linalg.solve(K, Fq)
        else:
            from cms.linsolve import factor
            q = factor(K.tocsc()).solve(Fq)
    except np.linalg.LinAlgError as exc:
        raise MechanismError(f"load case '{load.name}': singular stiffness ({exc})") from exc
    return StaticResult(m, np.asarray(m.T @ q).ravel(), load)


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
