"""A speed-controlled drive (assembly.dynamics.speed_drive): a free inertia run up by the servo.

Theory. An inertia J driven by the servo T = k (theta_ref - theta) + c (omega_ref - omega),
k = J w^2, c = 2 J w: J theta'' + c theta' + k theta = k theta_ref + c omega_ref. Newmark's
average acceleration on this one coordinate is the trapezoidal rule on (theta, omega), computed
here in closed form step by step; the run equals it to Newton-free round-off. The continuous
error e = theta - theta_ref obeys e'' + 2 w e' + w^2 e = -a on a ramp of rate a: from e = e' = 0,
e(s) = -(a / w^2)(1 - (1 + w s) e^{-w s}), e'(s) = -a s e^{-w s} -- the speed error vanishes and the
angle lags by a / w^2; the trapezoidal rule follows it to O((w h)^2).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.dynamics.simulate import simulate
from assembly.errors import SceneError
from assembly.scene.schema import scene_from_dict

pytestmark = pytest.mark.usefixtures("step_path")

J, W0, W1, T0, T1, FB = 50.0, 10.0, 30.0, 0.1, 1.1, 5.0       # kg m^2, rad/s, s, Hz


def _inertia(**drive):
    return scene_from_dict({
        "name": "driven inertia", "fidelity": "torsional",
        "bodies": [{"name": "rotor", "role": "rotor", "mass": 1.0, "polar_inertia": J, "position": [0, 0, 0]}],
        "bearings": [{"body": "rotor", "k_radial": 1e9, "k_axial": 1e9, "k_tilt": 1e9}],
        "simulation": {"speed": W0, "drive": {"end_speed": W1, "t_start": T0, "t_end": T1, "bandwidth": FB,
                                              **drive}}})


def _reference(t):
    u = np.clip((t - T0) / (T1 - T0), 0, 1)
    a = (W1 - W0) / (T1 - T0)
    s = np.clip(t, T0, T1) - T0
    return W0 + (W1 - W0) * u, W0 * np.minimum(t, T0) + W0 * s + 0.5 * a * s * s + W1 * np.maximum(t - T1, 0)


def test_a_run_up_is_the_servo_s_closed_form():
    h, t_end = 1e-3, 2.0
    run = simulate(_inertia(), t_end, h, outputs=["speed:rotor", "motion:rotor:rz"])
    w = 2 * math.pi * FB
    k, c = J * w * w, 2 * J * w
    # the trapezoidal rule on J theta'' + c theta' + k theta = k theta_ref + c omega_ref
    n = round(t_end / h)
    t = np.arange(n + 1) * h
    om_r, th_r = _reference(t)
    f = k * th_r + c * om_r
    th, om = np.zeros(n + 1), np.zeros(n + 1)
    om[0] = W0
    acc = (f[0] - c * om[0] - k * th[0]) / J
    for i in range(n):
        # theta+ = theta + h om + h^2/4 (acc + acc+), om+ = om + h/2 (acc + acc+), J acc+ = f+ - c om+ - k theta+
        A = np.array([[1 + k * h * h / (4 * J), c * h * h / (4 * J)], [k * h / (2 * J), 1 + c * h / (2 * J)]])
        b = np.array([th[i] + h * om[i] + h * h / 4 * (acc + f[i + 1] / J), om[i] + h / 2 * (acc + f[i + 1] / J)])
        th[i + 1], om[i + 1] = np.linalg.solve(A, b)
        acc = (f[i + 1] - c * om[i + 1] - k * th[i + 1]) / J
    got = run.outputs["speed:rotor"]
    # round-off of the run's sums over 2000 steps, relative to the speed
    assert np.max(np.abs(got - om)) <= 1e-9 * W1
    # the continuous servo: the speed error -a s e^{-w s} on the ramp, the angle lag a / w^2 at its end
    a = (W1 - W0) / (T1 - T0)
    on = (t >= T0) & (t <= T1)
    s = t[on] - T0
    assert np.max(np.abs((got[on] - om_r[on]) - (-a * s * np.exp(-w * s)))) <= (w * h) ** 2 * a / w
    lag = run.outputs["motion:rotor:rz"][np.searchsorted(t, T1)] - th_r[np.searchsorted(t, T1)]
    assert lag == pytest.approx(-(a / w ** 2) * (1 - (1 + w * (T1 - T0)) * math.exp(-w * (T1 - T0))), rel=(w * h) ** 2)
    # held after the ramp: the speed settles on the end speed
    assert got[-1] == pytest.approx(W1, rel=1e-6)


@pytest.mark.parametrize("drive, field", [({"t_end": 0.05}, "simulation.drive.t_end"),
                                          ({"body": "rotr"}, "simulation.drive.body"),
                                          ({"bandwidth": 0.0}, "simulation.drive.bandwidth")])
def test_a_bad_drive_is_refused_naming_the_field(drive, field):
    with pytest.raises(SceneError) as exc:
        simulate(_inertia(**drive), 0.01, 1e-3)
    assert exc.value.path == field


def test_a_run_up_through_a_range_lasts_its_ramp_and_settles_at_its_end(capsys):
    # flexgear runup: 2 settle + |n1 - n0| / rate seconds; the reference held at n0, ramped, held at n1
    from assembly.app.cli import main
    from assembly.dynamics.runup import runup_length, runup_simulation
    assert runup_length([100.0, 400.0], 600.0, 0.5) == pytest.approx(2 * 0.5 + 300.0 / 600.0, rel=1e-15)
    sim = runup_simulation(_inertia(), [100.0, 400.0], 600.0, settle_s=0.5, bandwidth=FB)
    assert sim.speed == pytest.approx(100.0 * math.pi / 30, rel=1e-15)
    assert (sim.drive.t_start, sim.drive.t_end) == (0.5, 1.0)
    scene = _inertia()
    from assembly.scene.tables import with_simulation
    run = simulate(with_simulation(scene, sim), 1.5, 1e-3, outputs=["speed:rotor"])
    w = run.outputs["speed:rotor"]
    # 0.5 s after the ramp's end, e^{-w s}(...) of its speed error is left: (a s) e^{-w s} at s = 0.5
    a, wb = 300.0 * math.pi / 30 / 0.5, 2 * math.pi * FB
    assert abs(w[-1] - 400.0 * math.pi / 30) <= 2 * a * 0.5 * math.exp(-wb * 0.5)
    # the command line on the 5 MW (its meshes' laws): 6.9 -> 12.1 rpm at 52 rpm/s is 0.1 s from 6.9 rpm
    import json
    capsys.readouterr()
    assert main(["runup", "nrel5mw_transient", "--speed-range", "6.9", "12.1", "--rate", "52", "--dt", "1e-3",
                 "--settle", "0.0", "--output", "speed:rotor", "--json", "-q"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["time_s"][-1] == pytest.approx(0.1, rel=1e-12)
    assert data["outputs"]["speed:rotor"][0] == pytest.approx(6.9 * math.pi / 30, rel=1e-12)
