"""The loads of a time-domain run: the ``[[simulation.loads]]`` histories and their load
vectors on q, and the generator, brake and gearbox friction (:mod:`assembly.dynamics.drive_torques`)
-- a plain load when the generator's torque is given (constant or recorded) and nothing else
acts on the shaft, else forces along a few rows of the model (:class:`RunLoads`).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis.drivetrain import chain_ends
from ..errors import SceneError
from ..model.probes import body_point, point_vector, spin_row, unit_wrench
from ..scene.time_domain import Simulation
from .drive_torques import ShaftTorques
from .frf_channels import output_channels
from .load_series import constant, file_history, generator_history, ramp


@dataclass(frozen=True)
class RunLoads:
    """The loads of a run: ``vectors`` (n x k) times the ``histories`` (k series of t) make
    the external load ``force(t)``; ``torques``: the generator, brake and friction forces
    along the model's rows (:class:`~assembly.dynamics.drive_torques.ShaftTorques`) or None."""

    vectors: np.ndarray
    histories: tuple
    torques: object = None

    def force(self, t: float) -> np.ndarray:
        """The external load vector on q at time ``t`` (s)."""
        if not self.histories:
            return np.zeros(self.vectors.shape[0])
        return self.vectors @ np.array([h(t) for h in self.histories])

    __call__ = force

    @property
    def recorded(self) -> list:
        """Every history read from a file or a table (the loads' and the generator's)."""
        gen = [self.torques.history] if self.torques is not None and self.torques.history is not None else []
        return [*self.histories, *gen]


def run_loads(model, scene, sim: Simulation, dt: float, v0: np.ndarray, base_dir: Path, phi) -> RunLoads:
    """The :class:`RunLoads` of ``sim`` on ``model`` (``v0`` the starting velocity, ``phi`` the
    reference's rigid-body mode or None; files relative to ``base_dir``)."""
    n = model.K.shape[0]
    torques, generator_load = shaft_torques(model, scene, sim, dt, v0, base_dir, phi)
    vecs, hist = [], []
    for i, ld in enumerate(sim.loads):
        path = f"simulation.loads[{i}]"
        hist.append(load_history(ld, path, base_dir))
        vecs.append(load_vector(model, ld, path))
    if generator_load is not None:
        vecs.append(generator_load[0])
        hist.append(generator_load[1])
    return RunLoads(np.array(vecs).T if vecs else np.zeros((n, 0)), tuple(hist), torques)


def load_history(ld, path: str, base_dir: Path):
    """The :class:`assembly.dynamics.load_series.Series` of a ``[[simulation.loads]]`` entry."""
    unit = "N m" if ld.kind != "force" else "N"
    if ld.end_value is not None and (ld.table is not None or ld.openfast is not None):
        raise SceneError(f"{path}.end_value", ld.end_value, "a table or openfast file gives the history itself")
    s = file_history(ld, path, base_dir, unit)
    if s is not None:
        return s
    for key in ("time_offset", "time_window"):
        if getattr(ld, key):
            raise SceneError(f"{path}.{key}", getattr(ld, key), "applies to a table or openfast file only")
    if ld.end_value is not None or ld.t_end is not None:
        if ld.end_value is None or ld.t_end is None:
            missing = "end_value" if ld.end_value is None else "t_end"
            raise SceneError(f"{path}.{missing}", None, "missing: a ramp needs end_value and t_end")
        return ramp(ld.value, ld.end_value, ld.t_start, ld.t_end, f"{path}", unit, field=path)
    return constant(ld.value, path, unit)


def load_vector(model, ld, path: str) -> np.ndarray:
    """Load vector on q of a unit load of ``ld``'s kind, body and direction."""
    where = ld.body if ld.interface is None else f"{ld.body}:{ld.interface}"
    body, iface = body_point(model, where, f"{path}.body", where)
    if ld.kind == "torque":
        w = unit_wrench(model, body, "spin")
    else:
        d = np.asarray(ld.direction, float)
        if not np.linalg.norm(d) > 0:
            raise SceneError(f"{path}.direction", ld.direction, "must be a nonzero vector")
        w = np.zeros(6)
        w[(0 if ld.kind == "force" else 3):][:3] = d / np.linalg.norm(d)
    return point_vector(model, body, iface, w)


def shaft_torques(model, scene, sim: Simulation, dt: float, v0: np.ndarray, base_dir=Path("."), phi=None):
    """(the generator / brake / friction part or None, (load vector, history) or None): a
    generator of a constant or recorded torque alone is a plain load (its vector on q times
    the torque), needing no nonlinear part. The generator's sense is its starting sense; from
    standstill, for a recorded torque, the sense it turns in when the reference turns
    positively (``phi``)."""
    gen, brake, eta = sim.generator, sim.brake, sim.gearbox_efficiency
    if gen is None and brake is None and eta >= 1.0:
        return None, None
    if gen is not None and gen.law == "pi" and gen.rated_speed is None:
        raise SceneError("simulation.generator.rated_speed", None, "missing: the PI law needs the generator's "
                                                                   "rated speed (rad/s)")
    history = generator_history(gen, "simulation.generator", base_dir) if gen is not None else None

    g_body = table_body(model, scene, gen, "simulation.generator")
    r_gen = spin_row(model, g_body)
    sense = float(np.sign(r_gen @ v0)) or (float(np.sign(r_gen @ phi)) if history is not None and phi is not None
                                           else 0.0) or 1.0
    if gen is not None and gen.law != "pi" and brake is None and eta >= 1.0:
        torque = history if history is not None else constant(gen.torque, "generator", "N m")
        return None, (-sense * r_gen, torque)
    r_brake = spin_row(model, brake_body(model, scene, sim)) if brake is not None else None
    lss = None
    if eta < 1.0:
        rotor = chain_ends(scene)[0]
        name = sim.lss_shaft or next((el.name.split(":")[0] for el in model.elements if el.kind == "shaft"
                                      and rotor in el.bodies), None)
        if name is None:
            raise SceneError("simulation.lss_shaft", None, "missing: no shaft joins the rotor; name the "
                                                           "low-speed shaft whose torque sign sets the friction")
        ch = output_channels(model, f"torque:{name}", "simulation.lss_shaft")[0]
        s_rot = float(np.sign(spin_row(model, rotor) @ v0)) or 1.0
        lss = [s_rot * ch.k_row, s_rot * (ch.c_row if ch.c_row is not None else np.zeros_like(ch.k_row))]
    J = polar_inertia(model, g_body)
    return ShaftTorques(model.K.shape[0], dt, gen, r_gen, sense, brake, r_brake, eta, lss, J, history), None


def table_body(model, scene, table, path: str) -> str:
    """The body a generator or brake table names, default the body of role "generator"."""
    if table is not None and table.body is not None:
        return body_point(model, table.body, f"{path}.body", table.body)[0]
    return chain_ends(scene)[1]


def brake_body(model, scene, sim) -> str:
    """The body the brake table names, default the body of role "generator"."""
    return table_body(model, scene, sim.brake, "simulation.brake")


def polar_inertia(model, body: str) -> float:
    """The body's inertia about its own axis (kg m^2): its rigid-body rotation's kinetic
    energy per unit speed squared, x 2."""
    bm = model.bodies[body]
    sl = model.body_slice(body)
    Mb = model.M_abs[sl][:, sl]
    P = bm.rigid_projection()
    w = np.zeros(6)
    w[3:] = bm.axes[:, 2]
    try:
        u = np.linalg.lstsq(P, w, rcond=None)[0]           # the body's motion of a unit spin
    except np.linalg.LinAlgError:
        return 0.0
    return float(u @ (Mb @ u))
