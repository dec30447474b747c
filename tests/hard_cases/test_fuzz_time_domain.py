"""Fuzz the time-domain input: mesh stiffness series, backlash, load tables, through scene
building, the run and the load files. Every draw is either refused with one SceneError naming
a field of the scene (``meshes[0]...``, ``simulation.loads[0]...``), or accepted and run to the
end with finite histories whose mesh stiffness never goes negative.

The negative-stiffness check samples a series at 64 points per period of its highest harmonic;
here it is compared with a dense sampling (20 000 points per mesh period): a series whose dense
minimum is below -1e-3 k0 must be refused, one above +1e-3 k0 accepted (between, sampling may
go either way). A stiffness dipping below NEAR_ZERO of its mean may also end in a refused start
or a stopped run (named, with a finite partial result)."""
from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from assembly.dynamics.mesh_variation import factor
from assembly.dynamics.simulate import simulate
from assembly.dynamics.transient import Diverged
from assembly.errors import SceneError
from assembly.scene.schema import scene_from_dict
from tests.support.fuzz import examples

R1, R2 = 0.05, 0.15
#: A series whose stiffness dips below this fraction of its mean makes the mesh nearly a
#: mechanism: its static start may be refused and its run may stop (with a named reason).
NEAR_ZERO = 0.05


def scene(mesh: dict, sim: dict) -> dict:
    c = (R1 + R2) / math.cos(math.radians(20.0))
    return {"name": "fuzz", "bodies": [
        {"name": "a", "mass": 1.0, "polar_inertia": 0.01, "fidelity": "torsional", "role": "rotor"},
        {"name": "b", "mass": 1.0, "polar_inertia": 0.05, "position": [c, 0.0, 0.0], "fidelity": "torsional"}],
        "meshes": [{"name": "m", "gear1": "a", "gear2": "b", "stiffness": 1.0e7, "base_radius1": R1,
                    "base_radius2": R2, "pressure_angle_deg": 20.0, **mesh}],
        "simulation": {"speed": 20.0, **sim}}


def dense_min(a, p) -> float:
    phi = np.linspace(0, 2 * math.pi, 20000, endpoint=False)
    f, _ = factor(phi, np.broadcast_to(a, (len(phi), len(a))), np.broadcast_to(p, (len(phi), len(a))))
    return float(f.min())


amplitudes = st.lists(st.floats(-1.3, 1.3, allow_nan=False), min_size=1, max_size=6)
backlash = st.one_of(st.none(), st.floats(0.0, 1e-4), st.floats(-1e-4, -1e-12))


@settings(max_examples=examples(30), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(a=amplitudes, seed=st.integers(0, 2**31 - 1), b=backlash, torque=st.floats(-50.0, 50.0))
def test_mesh_series_and_backlash_refused_or_run(a, seed, b, torque):
    p = np.random.default_rng(seed).uniform(-math.pi, math.pi, len(a))
    mesh = {"variation": {"amplitudes": a, "phases": p.tolist(), "teeth": 20}}
    if b is not None:
        mesh["backlash"] = b
    lowest = dense_min(np.array(a), p)
    try:
        s = scene_from_dict(scene(mesh, {"loads": [{"body": "a", "value": torque}]}))
        r = simulate(s, 0.002, 2e-5, ["force:m", "speed:b"])
    except Diverged as exc:
        # a stiffness that nearly vanishes leaves the gear all but free, and the teeth then
        # meet at any depth: the run may stop, with a named reason and a finite partial result
        assert lowest < NEAR_ZERO and not exc.partial.complete, (lowest, str(exc))
        assert all(np.all(np.isfinite(y)) for y in exc.partial.outputs.values())
        return
    except SceneError as exc:
        msg = str(exc)
        assert "\n" not in msg, msg
        if "is not physical" in msg:                 # the field rules: a magnitude such as 1e-313
            assert any(0 < abs(x) < 1e-100 for x in [*a, *p, torque, b or 0.0])
            assert msg.startswith(("simulation.loads[0].value", "meshes[0]."))
        elif msg.startswith("meshes[0].variation.amplitudes"):
            assert lowest < 1e-3
        elif msg.startswith("simulation.static_start"):          # a near-mechanism at the start
            assert lowest < NEAR_ZERO
        else:
            assert msg.startswith("meshes[0].backlash") and b is not None and b < 0
        return
    assert lowest > -1e-3 and (b is None or b >= 0)
    assert r.complete and all(np.all(np.isfinite(y)) for y in r.outputs.values())


rows = st.lists(st.tuples(st.one_of(st.floats(-1.0, 1.0), st.just(float("nan")), st.text(max_size=3)),
                          st.one_of(st.floats(-1e3, 1e3), st.text(max_size=3))), min_size=0, max_size=6)


@settings(max_examples=examples(30), deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=rows, column=st.sampled_from(["T", "torque", "Time"]))
def test_load_tables_refused_or_run(tmp_path, data, column):
    # any table text: refused naming simulation.loads[0].table, or read and run
    lines = ["time,T"] + [f"{t},{v}" for t, v in data]
    (tmp_path / "load.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")
    s = scene_from_dict(scene({}, {"loads": [{"body": "a", "table": "load.csv", "column": column}]}))
    try:
        r = simulate(s, 0.002, 1e-4, ["force:m"], base_dir=tmp_path)
    except SceneError as exc:
        assert str(exc).startswith("simulation.loads[0].table"), str(exc)
        return
    assert column == "T" and r.complete and np.all(np.isfinite(r.outputs["force:m"]))
