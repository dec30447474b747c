"""The compiled step (assembly.dynamics.step_kernel) against the Python step on runs with the
rotor's aerodynamics (assembly.dynamics.rotor_aero): the law is one code
(assembly.dynamics.rotor_laws) and the wind speed and pitch of a step are the same numbers on
both (Python evaluates them at the step's time, for the stretch or for the step), so the two
runs do the same arithmetic and agree to round-off -- 1e-12 relative on every recorded output,
the turbine's (wind, pitch, generator torque, rotor speed, aerodynamic torque, thrust, power),
a shaft torque and the rotor's speed, with the same Newton iteration counts -- as the
drivetrain's compiled step does (test_compiled_step.py). A state the surface does not cover
stops both with the same refusal, naming turbine.surface.

Scenes (tests/support/turbine_scenes.py): the two-mass torsional drivetrain with ElastoDyn's
NREL 5 MW numbers, a torque doublet on the generator and a wind ramp, its controller every step
(stretches of one step) and every 10 steps, and with a brake and the gearbox's friction (the
shaft torques' columns before the rotor's); the rotor and generator as rigid bodies on their
bearings, the thrust on the rotor's axial row; and the rotor on an axial spring under a pitch
controller whose first-order actuator moves the pitch between samples.
"""
from __future__ import annotations

import dataclasses
import math
from types import SimpleNamespace

import numpy as np
import pytest

from assembly.dynamics import jit, stretches
from assembly.dynamics.discon import DisconOutput
from assembly.dynamics.observe_rows import state_rows
from assembly.dynamics.rosco_data import NREL5MW_SURFACE, rosco_file
from assembly.dynamics.rotor_aero import RotorAero
from assembly.dynamics.rotor_laws import AERO_THRUST, AERO_TORQUE, PITCH, WIND
from assembly.dynamics.rotor_surface import read_surface, rotor_loads
from assembly.dynamics.sampled import Sampled
from assembly.dynamics.simulate import simulate
from assembly.dynamics.transient import integrate
from assembly.dynamics.turbine_loop import ControllerLoop, PitchActuator
from assembly.dynamics.turbine_run import OUTPUTS
from assembly.dynamics.wind import ramp
from assembly.errors import SceneError
from tests.support.turbine_scenes import J_GEN, J_ROTOR, M_ROTOR, RADIUS, RATED_TQ, RATIO, RPM, rigid_rotor, two_mass

pytest.importorskip("rosco", reason="the rosco package (turbine extra) is not installed")
needs_numba = pytest.mark.skipif(not jit.COMPILED, reason="numba not installed (the speed extra) or switched off")
AGREE = 1e-12                   # relative: the two steps do the same arithmetic
RHO = 1.225
OMEGA0, TQ = 12.1 * RPM, RATED_TQ * RATIO       # rated rotor speed, rated torque on the low-speed side
PITCH0 = 0.2                                    # rad: inside the surface at 16-17 m/s and rated speed
RAMP = {"speed": 16.0, "end_speed": 17.0, "t_start": 0.1, "t_end": 0.4}


def _both(run, monkeypatch) -> dict:
    """{"compiled": run(), "python": run()}: the same run on each step."""
    out = {}
    for path in ("compiled", "python"):
        monkeypatch.setattr(jit, "ENABLED", path == "compiled")
        out[path] = run()
    return out


def _agree(runs, names) -> None:
    c, p = runs["compiled"], runs["python"]
    assert c.info["compiled"] and not p.info["compiled"]
    assert c.info["mean_iterations"] == p.info["mean_iterations"]
    np.testing.assert_array_equal(c.time_s, p.time_s)
    for name in names:
        ref = p.outputs[name]
        assert np.all(np.isfinite(c.outputs[name]))
        assert np.max(np.abs(c.outputs[name] - ref)) <= AGREE * np.max(np.abs(ref)), name


#: the shaft torques beside the rotor's columns (theirs first): ElastoDyn's HSS brake ramping in
#: at 0.5 s (a tenth of the rated torque, on the low-speed side here) and its gearbox efficiency
#: 94.4 % (Jonkman et al. 2009)
TORQUES = {"simulation.brake": {"torque": 0.1 * TQ, "deploy_time": 0.5, "ramp_time": 0.1},
           "simulation.gearbox_efficiency": 0.944}


@needs_numba
@pytest.mark.parametrize("every, torques", [(1, False), (10, False), (1, True)])
def test_a_two_mass_turbine_runs_the_same_on_both_steps(every, torques, monkeypatch):
    dt = 2e-3
    scene = two_mass(OMEGA0, PITCH0, RAMP, 0.05 * TQ, (0.2, 0.4), dt, TQ, period=every * dt)
    if torques:
        scene = scene.with_values(TORQUES)
    names = ["torque:shaft", "speed:rotor", *OUTPUTS]
    runs = _both(lambda: simulate(scene, 1.0, dt, outputs=names), monkeypatch)
    assert runs["compiled"].info["rank"] == (5 if torques else 1)   # + generator, brake, 2 shaft rows
    _agree(runs, names)
    out = runs["compiled"].outputs
    # what was compared moves: the wind ramps, the rotor answers it and the doublet
    assert out["turbine:wind"][-1] == 17.0 and np.ptp(out["turbine:aero_torque"]) > 0.01 * TQ
    assert runs["compiled"].info["controller_calls"] == round(1.0 / (every * dt))


@needs_numba
def test_a_rigid_rotor_with_thrust_on_its_axial_row_runs_the_same_on_both_steps(monkeypatch):
    dt = 2e-3
    scene = rigid_rotor(OMEGA0, PITCH0, RAMP, 0.01, TQ)
    names = ["torque:shaft", "speed:rotor", "motion:rotor:z", *OUTPUTS]
    runs = _both(lambda: simulate(scene, 0.5, dt, outputs=names), monkeypatch)
    assert runs["compiled"].info["rank"] == 2                  # the torque's and the thrust's columns
    _agree(runs, names)
    # the thrust acts on the axial row: at the static start the rotor's mount carries it, z = T / k,
    # to the start's Newton tolerance (1e-12 of the forces, assembly.dynamics.run_start)
    out = runs["compiled"].outputs
    assert out["motion:rotor:z"][0] == pytest.approx(out["turbine:thrust"][0] / 5.0e8, rel=1e-12)


class _PitchLaw:
    """A proportional pitch law on the rotor's speed above ``ref`` and a constant generator torque:
    :class:`assembly.dynamics.discon.Discon`'s ``step``."""

    def __init__(self, torque, ref, pitch0, gain):
        self.torque, self.ref, self.pitch0, self.gain = torque, ref, pitch0, gain

    def step(self, t, dt, generator_speed, rotor_speed, pitch, generator_torque, wind, power=0.0):
        demand = self.pitch0 + self.gain * (rotor_speed - self.ref)
        return DisconOutput(self.torque, demand, (demand,) * 3)


@needs_numba
def test_the_pitch_between_samples_and_the_thrust_tangent_are_the_same_on_both_steps(monkeypatch):
    s = read_surface(rosco_file(NREL5MW_SURFACE))
    J, k, dt, period, t_end = J_ROTOR + J_GEN * RATIO ** 2, 5.0e8, 2e-3, 0.01, 1.0
    q0 = rotor_loads(s, RADIUS, RHO, 16.0, OMEGA0, PITCH0)
    c = 2 * 0.2 * math.sqrt(k * M_ROTOR)                    # 20 % damping on the axial mount

    def run():
        wind = ramp(16.0, 19.0, 0.1, 0.4, t_end)
        act = PitchActuator(0.05, PITCH0)                  # beta moves between samples: exp(-t / tau)
        loop = ControllerLoop(_PitchLaw(q0.torque, OMEGA0, PITCH0, 2.0), [1.0, 0.0], [1.0, 0.0], period, wind, act,
                              torque0=q0.torque)
        aero = RotorAero([1.0, 0.0], s, RADIUS, RHO, wind, act.pitch, axial=[0.0, 1.0])
        rows = state_rows(2, q=True, v=True)                # q (2), v (2), then the rotor's state (4)
        rows = dataclasses.replace(rows, Sv=np.vstack([rows.Sv, np.zeros((4, 2))]), values=aero,
                                   picks=tuple((4 + i, j) for i, j in enumerate((WIND, PITCH, AERO_TORQUE,
                                                                                  AERO_THRUST))))
        out = integrate(np.diag([J, M_ROTOR]), np.diag([0.0, c]), np.diag([0.0, k]), lambda t: np.zeros(2),
                        [0.0, q0.thrust / k], [OMEGA0, 0.0], dt, t_end, nonlinear=aero, observe=rows,
                        sampled=Sampled(loop.vector(), period, loop.law))
        out.outputs = {i: out.y[:, i] for i in range(out.y.shape[1])}
        return out

    runs = _both(run, monkeypatch)
    _agree(runs, range(8))
    y = runs["compiled"].y
    # the pitch moved, and between samples too (the actuator's exponential at every step) once the
    # wind's ramp has moved the rotor (from 0.2 s: rows 101 .., 5 steps a sample)
    assert np.ptp(y[:, 5]) > 1e-3 and np.all(np.diff(y[101:, 5].reshape(-1, 5), axis=1) != 0.0)


@needs_numba
def test_a_rotor_leaving_its_surface_is_refused_alike_on_both_steps(monkeypatch):
    # the wind falls from 16 to 4 m/s: lambda = Omega R / V passes the table's last tip-speed
    # ratio, 14.5, where V < 1.267 x 63 / 14.5 = 5.5 m/s
    dt = 0.01
    scene = two_mass(OMEGA0, PITCH0, {"speed": 16.0, "end_speed": 4.0, "t_start": 0.05, "t_end": 0.15}, 0.0,
                     (0.5, 0.6), dt, TQ)
    compiled_calls = []
    run = stretches.CompiledSteps.run
    monkeypatch.setattr(stretches.CompiledSteps, "run", lambda self, *a: compiled_calls.append(1) or run(self, *a))
    refusals = {}
    for path in ("compiled", "python"):
        monkeypatch.setattr(jit, "ENABLED", path == "compiled")
        with pytest.raises(SceneError) as exc:
            simulate(scene, 0.3, dt, outputs=["speed:rotor"])
        assert exc.value.path == "turbine.surface"
        refusals[path] = str(exc.value)
    assert compiled_calls                                      # the compiled step ran and stopped there
    assert refusals["compiled"] == refusals["python"]
    assert "tip-speed ratio" in refusals["python"]


def test_the_compiled_step_takes_meshes_torques_and_a_rotor_in_that_order(monkeypatch):
    if not jit.COMPILED:
        pytest.skip("numba not installed (the speed extra) or switched off")
    monkeypatch.setattr(jit, "ENABLED", True)
    meshes, torques, rotor, unbalance = (SimpleNamespace(compiled=k, gap_slope=0.0)
                                         for k in ("meshes", "torques", "rotor", None))
    rows, Z = state_rows(1), np.zeros((1, 2))

    def parts(*p, observe=rows):
        return stretches.compiled_parts(SimpleNamespace(parts=list(p)), observe, Z)

    assert parts(meshes, torques, rotor) == (meshes, torques, rotor)
    assert parts(meshes, rotor) == (meshes, None, rotor)
    assert parts(rotor) == (None, None, rotor)
    assert parts(rotor, torques) is None                       # not the columns' order
    assert parts(rotor, rotor) is None
    assert parts(meshes, torques, rotor, unbalance) is None    # an unbalance: the Python step
    other = dataclasses.replace(rows, picks=((0, WIND),), values=SimpleNamespace(s=np.zeros(4)))
    assert parts(rotor, observe=other) is None                 # picks of a state the step does not keep
