"""Static load case on an assembly: a torque into one body, reacted at another.

The input torque (N m) acts about the input body's axis (at a flexible body, on the
named interface master); the output body is held against rotation about its own axis
(its reaction). Solved on the same assembled stiffness as the modes; flexible bodies are
then back-expanded for stresses.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from .errors import MechanismError, SceneError
from .scene import Fixed


@dataclass(frozen=True)
class LoadCase:
    """Rated-torque load case: ``torque`` (N m) about ``input``'s axis, reacted by holding
    ``output`` against rotation. ``input_interface`` names where the torque enters a
    flexible (component) body, e.g. its coupling seat."""

    input: str
    output: str
    torque: float
    input_interface: Optional[str] = None
    name: str = "rated torque"

    def check(self, path: str, bodies: dict) -> None:
        for f in ("input", "output"):
            if getattr(self, f) not in bodies:
                raise SceneError(f"{path}.{f}", getattr(self, f), "no body of that name")
        if self.input == self.output:
            raise SceneError(f"{path}.output", self.output, "input and output must differ")
        if not (math.isfinite(self.torque) and self.torque != 0):
            raise SceneError(f"{path}.torque", self.torque, "must be a finite, non-zero torque (N m)")
        if bodies[self.output].fidelity == "flexible":
            raise SceneError(f"{path}.output", self.output, "the reacting body must be rigid or torsional")
        b = bodies[self.input]
        if b.component is not None and self.input_interface is None:
            raise SceneError(f"{path}.input_interface", None, f"{self.input} is a component: name the "
                                                              "interface the torque enters at")


@dataclass
class StaticResult:
    model: object
    z: np.ndarray
    load: LoadCase

    def body_dofs(self, name: str) -> np.ndarray:
        return self.z[self.model.body_slice(name)]


def solve_static(scene, load: LoadCase, bodies: dict | None = None) -> StaticResult:
    """Static response to ``load``; raises MechanismError if the held scene can still move."""
    from .model import assemble
    sc = scene.expanded()
    held = dataclasses.replace(sc, fixed=sc.fixed + (Fixed(load.output, ("rz",)),))
    m = assemble(held, bodies=bodies)
    bm = m.bodies[load.input]
    F = np.zeros(m.n_abs)
    sl = m.body_slice(load.input)
    if hasattr(bm, "masters"):
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
        if not hasattr(bm, "stress"):
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
