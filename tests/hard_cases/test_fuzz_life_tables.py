"""Fuzz ``[simulation.life]``: every draw of its fields (names that exist or not, numbers of
every sign and size, NaN, inf, wrong kinds) is either refused with one SceneError naming a
field under ``simulation.life`` before the run starts, or accepted and run to tables that
hold only finite numbers or None (with the row's note), written as strict JSON."""
from __future__ import annotations

import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from assembly.app import strict_json
from assembly.dynamics.simulate import simulate
from assembly.errors import SceneError
from assembly.scene.schema import scene_from_dict
from tests.support.fuzz import examples

BAD = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10, 10**9),
                st.sampled_from([0.0, -0.0, 1e-300, 1e300]), st.text(max_size=3), st.booleans())
GOOD = st.floats(0.05, 1e7)
NUMBERS = st.one_of(GOOD, GOOD, GOOD, GOOD, BAD)          # most draws valid, so that tables run
WINDOW = st.one_of(st.lists(st.floats(-1.0, 1.0), max_size=3),
                   st.tuples(st.floats(0.0, 0.009), st.floats(0.011, 0.02)).map(list))
BEARING = st.fixed_dictionaries({"bearing": st.sampled_from(["B", "B", "B", "R", "b", "", "m"]), "rating": NUMBERS},
                                optional={"exponent": NUMBERS, "radial_factor": NUMBERS,
                                          "axial_factor": NUMBERS})
GEAR = st.fixed_dictionaries({"mesh": st.sampled_from(["m", "m", "m", "B", "M"]), "torque_ref": NUMBERS,
                              "cycles_ref": NUMBERS, "slope": NUMBERS},
                             optional={"gear": st.sampled_from(["pinion", "wheel", "wheel", "x"]),
                                       "torque_limit": NUMBERS})
LIFE = st.fixed_dictionaries({}, optional={
    "bearings": st.lists(BEARING, max_size=2), "gears": st.lists(GEAR, max_size=2),
    "exponents": st.lists(NUMBERS, max_size=3), "cycles_ref": NUMBERS,
    "bins": st.one_of(st.integers(1, 50), st.integers(1, 50), BAD),
    "shaft": st.sampled_from(["wheel", "pinion", "nowhere"]),
    "window": WINDOW})


def scene(life: dict) -> dict:
    # a rigid pinion on a bearing B (and R, radially rigid) driving a torsional wheel, 100 N m
    # through the mesh m, both turning
    c = 0.2 / math.cos(math.radians(20.0))
    return {"name": "fuzz life", "bodies": [
        {"name": "pinion", "mass": 10.0, "polar_inertia": 2.0, "fidelity": "rigid", "role": "rotor"},
        {"name": "wheel", "mass": 10.0, "polar_inertia": 0.5, "fidelity": "torsional", "position": [c, 0.0, 0.0],
         "role": "generator"}],
        "bearings": [{"name": "B", "body": "pinion", "k_radial": 1e8, "k_axial": 1e8, "k_tilt": 1e6, "c_radial": 2e3,
                      "c_axial": 2e3, "c_tilt": 20.0},
                     {"name": "R", "body": "pinion", "k_radial": math.inf, "k_axial": 1e8, "k_tilt": 1e6}],
        "meshes": [{"name": "m", "gear1": "pinion", "gear2": "wheel", "stiffness": 1e8, "base_radius1": 0.05,
                    "base_radius2": 0.15, "pressure_angle_deg": 20.0, "damping": 100.0}],
        "simulation": {"speed": 10.0, "loads": [{"body": "pinion", "value": 100.0}],
                       "generator": {"torque": 300.0}, "life": life}}


def _finite_or_none(x) -> bool:
    return x is None or isinstance(x, str) or (isinstance(x, (int, float)) and math.isfinite(x))


@settings(max_examples=examples(60), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(LIFE)
def test_a_life_table_is_refused_by_field_or_gives_finite_tables(life):
    try:
        r = simulate(scene_from_dict(scene(life)), 0.02, 1e-3, ["force:m"])
    except SceneError as exc:
        assert exc.path.startswith("simulation.life"), exc
        assert "\n" not in str(exc)
        return
    for row in (*r.life.bearings, *r.life.gears):
        assert all(_finite_or_none(v) for v in vars(row).values()), row
        assert any(v is None for v in vars(row).values()) <= bool(row.note), row
    for o in r.life.outputs.values():
        assert all(math.isfinite(v) for v in o.dels.values())
    strict_json.dumps({"b": [vars(b) for b in r.life.bearings], "g": [vars(g) for g in r.life.gears]})
