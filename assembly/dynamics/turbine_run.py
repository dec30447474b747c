"""The turbine around the drivetrain in a time-domain run: the ``[turbine]`` table
(:class:`assembly.scene.turbine.Turbine`) made into the parts :func:`assembly.dynamics.simulate.simulate`
integrates with the drivetrain.

* the rotor's aerodynamic torque and thrust (:class:`assembly.dynamics.rotor_aero.RotorAero`) on
  the rotor body's rotation and axial rows, from the surface, radius and density, the wind
  (:mod:`assembly.dynamics.wind`) and the actuator's pitch;
* the controller (:mod:`assembly.dynamics.discon` or :mod:`assembly.dynamics.variable_speed`) in
  the loop (:class:`assembly.dynamics.turbine_loop.ControllerLoop`) at its own sample time, its
  generator torque held on the generator body's rotation row against the generator's turning
  (ElastoDyn's sense: a positive generator torque brakes the generator); the reaction goes
  into the housing through the bearings, as every internal torque's does.

Gravity (turned by the shaft tilt, the table's or its deck's), the nacelle's motion and the
unbalances are the run's body loads (:mod:`assembly.dynamics.body_loads`).

Start: every body at its share of the starting speed; the generator torque at t = 0 is the one
that balances the aerodynamic torque there through the speeds (T_g = Q Omega / omega_g), so the
static start holds, and the controller's first call (at t = 0) takes over from it.

Outputs (``turbine:NAME``, :data:`OUTPUTS`): the wind speed, the pitch, the generator torque
(held), the rotor speed (rad/s in its turning sense), the aerodynamic torque and thrust and the
electrical power ``efficiency x T_g x omega_g``, each of the accepted step.
"""
from __future__ import annotations

import dataclasses
import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis.drivetrain import chain_ends
from ..errors import SceneError
from ..model.probes import point_vector, spin_row
from . import wind as wind_series
from .load_series import file_history, require_cover
from .openfast_deck import read_deck
from .rosco_data import NREL5MW_SURFACE, rosco_file
from .rotor_aero import RotorAero
from .rotor_laws import AERO_THRUST, AERO_TORQUE, PITCH, WIND
from .rotor_surface import read_surface
from .run_loads import polar_inertia
from .sampled import Sampled, sample_steps
from .turbine_loop import ControllerLoop, PitchActuator, SecondOrderPitch
from .variable_speed import NREL5MW_BASELINE, SimpleVariableSpeed, TorqueLawController

log = logging.getLogger(__name__)

#: The turbine's outputs and their units.
OUTPUTS = {"turbine:wind": "m/s", "turbine:pitch": "rad", "turbine:generator_torque": "N m",
           "turbine:rotor_speed": "rad/s", "turbine:aero_torque": "N m", "turbine:thrust": "N",
           "turbine:power": "W"}
#: ROSCO's compiled controller and its NREL 5 MW input in the rosco wheel.
ROSCO_LIBRARY = "rosco/lib/libdiscon.so"
ROSCO_INPUT = "Examples/Test_Cases/NREL-5MW/DISCON.IN"
#: The NREL 5 MW OpenFAST deck in the rosco wheel (``[turbine] openfast = "rosco"``).
ROSCO_DECK = "Examples/Test_Cases/NREL-5MW/NREL-5MW.fst"
#: Defaults when neither the scene nor a deck gives them.
DENSITY = 1.225
CONTROLLER_PERIOD = 0.01


@dataclass(frozen=True)
class TurbineData:
    """What the run uses of the turbine, resolved from the scene and its deck: ``surface``
    (path), ``radius`` m, ``density`` kg/m^3, ``hub_height`` m or None, ``tilt`` rad, the
    controller's ``library``/``input`` paths or None and ``period`` s; ``sources`` {field:
    where it came from}; ``rotor_inertia`` (kg m^2) the deck's, None without one."""

    surface: Path
    radius: float
    density: float
    hub_height: float | None
    tilt: float
    library: Path | None
    input: Path | None
    period: float
    sources: dict
    rotor_inertia: float | None = None


def turbine_data(turbine, base_dir) -> TurbineData:
    """The :class:`TurbineData` of a ``[turbine]`` table: each field as the table gives it, else
    from its OpenFAST deck (``openfast``), else the default; SceneError for what is missing."""
    base_dir = Path(base_dir or ".")
    deck = None
    if turbine.openfast is not None:
        deck = read_deck(rosco_file(ROSCO_DECK) if turbine.openfast == "rosco" else base_dir / turbine.openfast,
                         "turbine.openfast")
    sources = {}

    def pick(name, given, deck_name=None, default=None):
        if given is not None:
            sources[name] = "scene"
            return given
        value = getattr(deck, deck_name or name, None) if deck is not None else None
        if value is not None:
            sources[name] = deck.sources.get(deck_name or name, "the OpenFAST deck")
            return value
        if default is not None:
            sources[name] = "default"
        return default

    ctrl = turbine.controller
    surface = pick("surface", turbine.surface)
    if surface is None:
        raise SceneError("turbine.surface", None, "missing: a Cp_Ct_Cq file, 'rosco', or an openfast deck")
    surface = rosco_file(NREL5MW_SURFACE) if surface == "rosco" else Path(base_dir / surface if sources["surface"]
                                                                         == "scene" else surface)
    radius = pick("radius", turbine.radius)
    if radius is None:
        raise SceneError("turbine.radius", None, "missing: the rotor's tip radius (m), or an openfast deck")
    density = pick("density", turbine.density, default=DENSITY)
    hub = pick("hub_height", turbine.hub_height)
    tilt = pick("tilt", turbine.tilt, default=0.0)
    kind = ctrl.kind if ctrl is not None else "rosco"
    library = inp = None
    if kind in ("rosco", "discon"):
        library = pick("controller.library", ctrl.library if ctrl else None, "controller_library")
        inp = pick("controller.input", ctrl.input if ctrl else None, "controller_input")
        if kind == "rosco" and (library is None or sources.get("controller.library") != "scene"):
            library, sources["controller.library"] = rosco_file(ROSCO_LIBRARY), "the rosco wheel"
        if kind == "rosco" and inp is None:
            inp, sources["controller.input"] = rosco_file(ROSCO_INPUT), "the rosco wheel"
        for key, p in (("library", library), ("input", inp)):
            if p is None:
                raise SceneError(f"turbine.controller.{key}", None, f"missing: kind {kind!r} needs the DISCON "
                                                                    f"{key}")
        library = Path(base_dir / library) if sources["controller.library"] == "scene" else Path(library)
        inp = Path(base_dir / inp) if sources["controller.input"] == "scene" else Path(inp)
    period = pick("controller.period", ctrl.period if ctrl else None, "controller_period",
                  default=CONTROLLER_PERIOD)
    return TurbineData(surface, float(radius), float(density), None if hub is None else float(hub), float(tilt),
                       library, inp, float(period), sources, deck.rotor_inertia if deck is not None else None)


class HeldOutputs:
    """``held(Y)`` of the turbine's rows (:class:`assembly.dynamics.observe_rows.Rows`): the
    generator torque the controller holds over the stretch into the column ``torque``, and the
    column ``power`` (the generator's speed) times ``efficiency x T_g``; None for a column not
    recorded."""

    def __init__(self, loop, torque, power):
        self.loop, self.torque, self.power = loop, torque, power

    def __call__(self, Y):
        T = self.loop.torque
        if self.torque is not None:
            Y[:, self.torque] = T
        if self.power is not None:
            Y[:, self.power] *= self.loop.eta * T


class TurbineRun:
    """The turbine's parts of one run (module notes): ``nonlinear`` (the aerodynamics),
    ``sampled`` (the controller's held torque), ``start_force`` (the generator torque at t = 0
    on q), ``data`` (:class:`TurbineData`); :meth:`close` ends the controller."""

    def __init__(self, model, scene, sim, dt: float, t_end: float, v0: np.ndarray, base_dir, phi=None):
        tb = scene.turbine
        if sim.generator is not None:
            raise SceneError("simulation.generator", "a generator table", "the [turbine] controller sets the "
                                                                          "generator torque; remove one of them")
        self.data = d = turbine_data(tb, base_dir)
        for k, v in d.sources.items():
            log.info("turbine.%s: %s", k, v if v in ("scene", "default") else f"from {v}")
        surface = read_surface(d.surface, "turbine.surface")
        rotor, generator = chain_ends(scene, tb.rotor, tb.generator)
        r_rot, r_gen = spin_row(model, rotor), tb.generator_ratio * spin_row(model, generator)
        s_rot = float(np.sign(r_rot @ v0)) or 1.0
        s_gen = float(np.sign(r_gen @ v0)) or (float(np.sign(r_gen @ phi)) if phi is not None else 0.0) or 1.0
        self.wind = make_wind(tb.wind, d, t_end, base_dir)
        ctrl = tb.controller
        if ctrl is not None and ctrl.pitch_omega is not None:
            if ctrl.pitch_tau:
                raise SceneError("turbine.controller.pitch_tau", ctrl.pitch_tau, "give pitch_tau (first order) or "
                                                                                "pitch_omega (second order), not both")
            self.actuator = SecondOrderPitch(ctrl.pitch_omega, ctrl.pitch_zeta, tb.pitch)
        else:
            self.actuator = PitchActuator(ctrl.pitch_tau if ctrl else 0.0, tb.pitch)
        axial = None
        if tb.thrust:
            w = np.zeros(6)
            w[:3] = model.bodies[rotor].axes[:, 2]
            axial = point_vector(model, rotor, None, w)
            if not np.any(axial):
                axial = None                                # a torsional rotor: no axial row
        self.aero = RotorAero(r_rot, surface, d.radius, d.density, self.wind, self.actuator.pitch, s_rot, axial)
        omega_r, omega_g = s_rot * float(r_rot @ v0), s_gen * float(r_gen @ v0)
        q0 = self.aero.loads(0.0, np.array([s_rot * omega_r]))
        torque0 = q0.torque * omega_r / omega_g if omega_g > 0.0 else 0.0
        sample_steps(d.period, dt, "turbine.controller.period")    # checked before the controller loads
        self.controller = make_controller(ctrl, d, tb.pitch)
        eta = ctrl.efficiency if ctrl else 0.944
        self.loop = ControllerLoop(self.controller, r_gen, r_rot, d.period, self.wind, self.actuator, eta, s_gen,
                                   torque0)
        self.sampled = Sampled(self.loop.vector(), d.period, self.loop.law)
        self.start_force = self.loop.vector()[:, 0] * torque0
        self.torque0 = torque0
        self.nonlinear = [self.aero]
        self.warnings = []
        if d.rotor_inertia is not None:                     # the deck's rotor beside the scene's
            j = polar_inertia(model, rotor)
            if abs(j - d.rotor_inertia) > 0.01 * d.rotor_inertia:
                self.warnings.append(f"turbine.openfast: the deck's rotor inertia {d.rotor_inertia:.6g} kg m^2 "
                                     f"differs from body {rotor!r}'s {j:.6g} kg m^2 by more than 1 %; the run "
                                     f"uses the body's")

    def observer(self, rows, names):
        """The drivetrain's ``rows`` (:class:`assembly.dynamics.observe_rows.Rows`) and then the
        turbine's outputs ``names`` (:data:`OUTPUTS`) of the accepted step, as rows too: the
        rotor's speed and the generator's (for the power) rows on v, the wind speed, pitch,
        aerodynamic torque and thrust picked from the rotor's state, the held generator torque
        and the power filled in for each stretch (:class:`HeldOutputs`)."""
        aero, loop = self.aero, self.loop
        base, n = rows.size, rows.Sv.shape[1]
        picked = {"turbine:wind": WIND, "turbine:pitch": PITCH, "turbine:aero_torque": AERO_TORQUE,
                  "turbine:thrust": AERO_THRUST}
        on_v = {"turbine:rotor_speed": aero.sense * aero.U[:, 0], "turbine:power": loop.sense * loop.g}
        Sv = np.vstack([rows.Sv, *(on_v.get(k, np.zeros(n)) for k in names)]).reshape(-1, n)
        picks = tuple((base + i, picked[k]) for i, k in enumerate(names) if k in picked)
        col = {k: base + i for i, k in enumerate(names)}
        held = HeldOutputs(loop, col.get("turbine:generator_torque"), col.get("turbine:power"))
        return dataclasses.replace(rows, Sv=Sv, picks=rows.picks + picks, values=aero, held=held)

    def info(self) -> dict:
        return {"controller_calls": len(self.loop.times), "controller_period_s": self.data.period,
                "_controller_times": list(self.loop.times),
                "generator_torque_start_Nm": self.torque0,
                "turbine_sources": {k: str(v) for k, v in self.data.sources.items()}}

    def close(self) -> None:
        self.controller.close()


def make_wind(w, d: TurbineData, t_end: float, base_dir) -> wind_series.WindSeries:
    """The wind series of a ``[turbine.wind]`` table over the run (0 .. ``t_end``)."""
    f = "turbine.wind"
    if w is None:
        raise SceneError(f, None, "missing: a [turbine.wind] table (speed, steps, a ramp, a file or turbulence)")
    s = file_history(w, f, base_dir, "m/s")
    if s is not None:
        key = f"{f}.{'table' if w.table else 'openfast'}"
        require_cover(s, t_end, key)
        return wind_series.WindSeries(s.time_s, s.values, key)
    if w.steps is not None:
        if w.speed is not None or w.turbulence is not None:
            raise SceneError(f"{f}.steps", w.steps, "give steps alone, without speed or turbulence")
        return wind_series.steps(w.steps, t_end, f"{f}.steps")
    if w.speed is None:
        raise SceneError(f"{f}.speed", None, "missing: the wind speed (m/s)")
    if w.turbulence is not None:
        if d.hub_height is None:
            raise SceneError("turbine.hub_height", None, "missing: turbulence needs the hub height (m)")
        return wind_series.iec_turbulence(w.speed, w.turbulence, d.radius, d.hub_height, t_end, w.sample, w.seed,
                                          w.grid, f"{f}.turbulence")
    if w.end_speed is not None or w.t_end is not None:
        if w.end_speed is None or w.t_end is None:
            missing = "end_speed" if w.end_speed is None else "t_end"
            raise SceneError(f"{f}.{missing}", None, "missing: a ramp needs end_speed and t_end")
        return wind_series.ramp(w.speed, w.end_speed, w.t_start, w.t_end, t_end, f)
    return wind_series.constant(w.speed, t_end, f)


def make_controller(ctrl, d: TurbineData, pitch: float):
    """The controller of a ``[turbine.controller]`` table: a DISCON library or a torque law."""
    kind = ctrl.kind if ctrl is not None else "rosco"
    if kind in ("rosco", "discon"):
        from .discon import Discon
        return Discon(d.library, d.input, "turbine.controller")
    if kind == "baseline":
        return TorqueLawController(NREL5MW_BASELINE, pitch)
    for key in ("rated_speed", "rated_torque", "region2_k", "slip"):
        if getattr(ctrl, key) is None:
            raise SceneError(f"turbine.controller.{key}", None, "missing: the simple law needs rated_speed, "
                                                                "rated_torque, region2_k and slip")
    return TorqueLawController(SimpleVariableSpeed(ctrl.rated_speed, ctrl.rated_torque, ctrl.region2_k, ctrl.slip),
                               pitch)

