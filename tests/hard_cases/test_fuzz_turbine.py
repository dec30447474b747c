"""Property-based fuzzing of the turbine's input: a ``[turbine]`` table, ``[[simulation.nacelle]]`` and
``[[simulation.unbalance]]`` with junk in any key (or a key deleted, or an unknown key added) end in
one SceneError naming a field path and the value -- when the scene is read or when the run
starts -- or a run whose every output is finite; never another exception."""
import copy
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from assembly.dynamics.simulate import simulate
from assembly.errors import SceneError
from assembly.scene.schema import scene_from_dict
from tests.support.fuzz import examples, tree_paths

pytest.importorskip("rosco", reason="the rosco package (its NREL 5 MW surface) is not installed")

RPM = math.pi / 30.0
BASE = {
    "name": "fuzzed turbine", "fidelity": "rigid",
    "bodies": [{"name": "rotor", "role": "rotor", "mass": 1.1e5, "polar_inertia": 3.9e7, "position": [0.0, 0.0, 0.0]},
               {"name": "generator", "role": "generator", "mass": 1.0e3, "polar_inertia": 5.0e6,
                "position": [0.0, 0.0, 5.0]}],
    "bearings": [{"body": b, "position": [0.0, 0.0, z], "k_radial": 1e9, "k_axial": 1e9, "k_tilt": 1e9}
                 for b, z in (("rotor", 0.0), ("generator", 5.0))],
    "shafts": [{"name": "shaft", "body1": "rotor", "body2": "generator", "k_torsion": 8.7e8, "c_torsion": 6.2e6}],
    "simulation": {"speed": 12.1 * RPM,
                   "nacelle": [{"dof": "y", "amplitude": 0.5, "frequency": 0.3}],
                   "unbalance": [{"body": "rotor", "mass": 10.0, "radius": 1.0, "phase_deg": 30.0}]},
    "turbine": {"surface": "rosco", "radius": 63.0, "pitch_deg": 12.0, "gravity": True, "tilt_deg": 5.0,
                "wind": {"speed": 16.0, "end_speed": 17.0, "t_end": 0.02},
                "controller": {"kind": "simple", "period": 0.01, "rated_speed": 1161.963 * RPM / 97.0,
                               "rated_torque": 4.18e6, "region2_k": 2.33 * 97.0 ** 3, "slip": 0.1}}}

JUNK = st.one_of(st.none(), st.booleans(), st.integers(-10**6, 10**6), st.text(max_size=6),
                 st.floats(allow_nan=True, allow_infinity=True), st.lists(st.integers(-3, 3), max_size=3),
                 st.sampled_from([0.0, -1.0, 1e300, -1e-300, math.inf, math.nan, "rosco", "A", "x" * 80, "a\nb",
                                  "generator", "housing"]))


@st.composite
def mutated(draw):
    tree = copy.deepcopy(BASE)
    roots = [("turbine",), ("simulation", "nacelle"), ("simulation", "unbalance")]
    for _ in range(draw(st.integers(1, 2))):
        root = draw(st.sampled_from(roots))
        node = tree
        for k in root:
            node = node[k]
        paths = [root + p for p in tree_paths(node)]
        path = draw(st.sampled_from(paths))
        parent = tree
        for p in path[:-1]:
            parent = parent[p]
        op = draw(st.sampled_from(["replace", "delete", "extra"]))
        if op == "delete" and isinstance(parent, dict):
            del parent[path[-1]]
        elif op == "extra" and isinstance(parent, dict):
            parent[draw(st.text(min_size=1, max_size=6))] = draw(JUNK)
        else:
            parent[path[-1]] = draw(JUNK)
    return tree


@settings(max_examples=examples(150), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated())
def test_a_malformed_turbine_gives_one_clear_error_or_a_finite_run(tree):
    try:
        run = simulate(scene_from_dict(tree), 0.02, 0.01)
    except SceneError as exc:
        assert exc.path and "\n" not in str(exc)
        return
    assert all(np.all(np.isfinite(v)) for v in run.outputs.values())
