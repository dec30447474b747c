"""Von Mises stress as an FRF output (``stress:BODY:X,Y,Z``, back-expansion of a flexible body).

* The cycle peak of a harmonic stress Re(S e^{iwt}): for S real it is the von Mises stress
  of S; multiplying S by e^{i phi} only shifts time, so the peak is unchanged; for
  sigma_xx = s cos(wt), tau_xy = -s sin(wt) (S = (s, 0, 0, 0, 0, i s)) von Mises^2 =
  s^2 cos^2 + 3 s^2 sin^2, peak sqrt(3) s.
* Far below the first natural frequency the response is the static one, to (f/f_1)^2: the
  FRF's von Mises at 0.01 Hz equals the von Mises of the static solution K q = f recovered
  over the whole body (:meth:`FlexibleBodyModel.stress`, the projector of the stress
  images), a path independent of the single-node functional the FRF uses.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly import SceneError, assemble
from assembly.dynamics.frf import frequency_response
from assembly.dynamics.frf_channels import von_mises_peak
from assembly.scene.schema import load_scene
from cms.stress import von_mises


def test_von_mises_peak_closed_forms():
    rng = np.random.default_rng(7)
    a = rng.normal(size=(5, 6))
    tensor = np.zeros((5, 3, 3))
    for c, (i, j) in enumerate(((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))):
        tensor[:, i, j] = tensor[:, j, i] = a[:, c]
    assert np.allclose(von_mises_peak(a.astype(complex)), von_mises(tensor), rtol=1e-13)
    assert np.allclose(von_mises_peak(a * np.exp(0.7j)), von_mises(tensor), rtol=1e-13)
    s = 2.5e6
    assert von_mises_peak(np.array([s, 0, 0, 0, 0, 1j * s])) == pytest.approx(math.sqrt(3) * s, rel=1e-14)


@pytest.fixture(scope="module")
def held_stage():
    # the HS stage with its output shaft held in torsion by a spring: no rigid-body mode, K invertible
    scene = load_scene("hs_parallel_stage.toml").with_values({"bearings[2].k_torsion": 1.0e7})
    return assemble(scene)


def test_stress_frf_at_low_frequency_is_the_static_stress(held_stage):
    model = held_stage
    wheel = model.bodies["wheel"]
    iface = sorted(model.bodies["pinion"].masters)[0]
    src = f"torque:pinion:{iface}"
    # the static solution and its nodal stresses on the whole wheel
    from assembly.dynamics.frf_channels import input_channel
    q = np.linalg.solve(model.K.toarray(), input_channel(model, src).k_row)
    zb = (model.T @ q)[model.body_slice("wheel")]
    static = wheel.stress(zb)
    node = int(np.argmax(static.von_mises))                           # the most stressed node
    point = wheel.origin + wheel.axes @ static.points[node]
    name = "stress:wheel:" + ",".join(f"{v:.17g}" for v in point)
    r = frequency_response(model, src, [name], [0.01])
    f1 = 600.0                                                        # Hz, below the first elastic mode
    assert r.units[name] == "Pa/(N m)"
    assert abs(r.outputs[name][0].real / static.von_mises[node] - 1) <= 1e-9 + 10 * (0.01 / f1) ** 2
    assert r.outputs[name][0].imag == 0.0


def test_stress_point_off_the_body_or_on_a_rigid_body_is_refused(held_stage):
    iface = sorted(held_stage.bodies["pinion"].masters)[0]
    with pytest.raises(SceneError, match="off the body") as err:
        frequency_response(held_stage, f"torque:pinion:{iface}", ["stress:wheel:5,5,5"], [1.0])
    assert err.value.path == "outputs"
    with pytest.raises(SceneError, match="not a flexible body"):
        frequency_response(held_stage, f"torque:pinion:{iface}", ["stress:output_shaft:0,0,0.2"], [1.0])
    with pytest.raises(SceneError, match="X,Y,Z"):
        frequency_response(held_stage, f"torque:pinion:{iface}", ["stress:wheel:0,0"], [1.0])


def test_time_domain_stress_starts_at_the_static_stress(held_stage):
    # flexgear simulate's stress output: the von Mises stress of the six back-expanded components
    # at each instant; from the static start under a constant torque it is the static stress of
    # the whole-body recovery at t = 0 (the same path as above, independent of the run)
    from assembly.dynamics.frf_channels import input_channel
    from assembly.dynamics.simulate import simulate
    model = held_stage
    wheel = model.bodies["wheel"]
    iface = sorted(model.bodies["pinion"].masters)[0]
    q = np.linalg.solve(model.K.toarray(), input_channel(model, f"torque:pinion:{iface}").k_row)
    static = wheel.stress((model.T @ q)[model.body_slice("wheel")])
    node = int(np.argmax(static.von_mises))
    name = "stress:wheel:" + ",".join(f"{v:.17g}" for v in wheel.origin + wheel.axes @ static.points[node])
    scene = model.source.with_values({"simulation": {"loads": [{"body": "pinion", "interface": iface, "value": 1.0}]}})
    r = simulate(model, 2e-4, 1e-5, [name], simulation=scene.simulation)
    assert r.units[name] == "Pa"
    assert r.outputs[name][0] == pytest.approx(static.von_mises[node], rel=1e-9)
    # held at rest under a constant load: the stress stays static (to the run's round-off)
    np.testing.assert_allclose(r.outputs[name], static.von_mises[node], rtol=1e-8)


def test_named_stress_point_is_the_coordinate_output(held_stage):
    # [[simulation.points]] names a point: stress:NAME records the same history as the
    # coordinate form, and a run without outputs records it (with each nonlinear mesh's force)
    from assembly.dynamics.simulate import simulate
    model = held_stage
    iface = sorted(model.bodies["pinion"].masters)[0]
    wheel = model.bodies["wheel"]
    p = wheel.origin + wheel.axes @ wheel.stress(np.zeros(wheel.ndof)).points[0]
    sim = {"loads": [{"body": "pinion", "interface": iface, "value": 1.0}],
           "points": [{"name": "rim", "body": "wheel", "point": p.tolist()}]}
    scene = model.source.with_values({"simulation": sim})
    named = simulate(model, 2e-4, 1e-5, simulation=scene.simulation)
    coord = simulate(model, 2e-4, 1e-5, ["stress:wheel:" + ",".join(f"{v:.17g}" for v in p)], simulation=scene.simulation)
    assert list(named.outputs) == ["stress:rim"] and named.units["stress:rim"] == "Pa"
    np.testing.assert_array_equal(named.outputs["stress:rim"], next(iter(coord.outputs.values())))
    bad = model.source.with_values({"simulation": {**sim, "points": [{"name": "x", "body": "wheel",
                                                                       "point": [5.0, 5.0, 5.0]}]}})
    with pytest.raises(SceneError, match="off the body") as err:
        simulate(model, 2e-4, 1e-5, simulation=bad.simulation)
    assert err.value.path == "simulation.points[0]"
