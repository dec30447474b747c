"""A design study's variants (assembly/app/study/spec.py): paths with wildcards checked against
the scene, values as lists, ranges and log ranges, grid / Latin hypercube / random designs,
and bad studies named by their field."""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.app.study.spec import variants
from assembly.errors import SceneError
from assembly.scene.schema import load_scene


@pytest.fixture(scope="module")
def scene():
    return load_scene("nrel5mw")


def test_grid_is_every_combination(scene):
    v = variants(scene, {"parameters": [{"path": "meshes[0].stiffness", "values": [1e9, 2e9]},
                                        {"path": "stages[0].planets.count", "range": [3, 5, 3]}]})
    assert [x.values for x in v] == [{"meshes[0].stiffness": a, "stages[0].planets.count": b}
                                     for a in (1e9, 2e9) for b in (3, 4, 5)]
    assert all(type(x.values["stages[0].planets.count"]) is int for x in v)  # a count stays whole


def test_log_range_is_geometric(scene):
    v = variants(scene, {"parameters": [{"path": "bearings[0].k_radial_y", "log_range": [1e8, 1e10, 3]}]})
    assert [x.values["bearings[0].k_radial_y"] for x in v] == pytest.approx([1e8, 1e9, 1e10], rel=1e-12)


def test_wildcard_sets_every_item(scene):
    v = variants(scene, {"parameters": [{"path": "bearings[*].c_axial", "values": [5.0]}]})
    assert set(v[0].values) == {f"bearings[{i}].c_axial" for i in range(len(scene.bearings))}
    assert set(v[0].values.values()) == {5.0}


def test_latin_hypercube_fills_each_stratum_once_and_repeats_with_its_seed(scene):
    # McKay, Beckman & Conover (1979): n samples, each variable's range cut into n equal strata,
    # exactly one sample in each; on a log scale the strata are equal in log
    study = {"design": {"kind": "lhs", "samples": 16, "seed": 7},
             "parameters": [{"path": "meshes[0].stiffness", "bounds": [1e9, 2e9]},
                            {"path": "bearings[0].k_radial_y", "bounds": [1e8, 1e10], "log": True}]}
    v = variants(scene, study)
    k = np.array([x.values["meshes[0].stiffness"] for x in v])
    b = np.log10([x.values["bearings[0].k_radial_y"] for x in v])
    assert sorted(np.floor((k - 1e9) / 1e9 * 16).astype(int)) == list(range(16))
    assert sorted(np.floor((b - 8) / 2 * 16).astype(int)) == list(range(16))
    assert [x.values for x in variants(scene, study)] == [x.values for x in v]
    other = variants(scene, {**study, "design": {**study["design"], "seed": 8}})
    assert [x.values for x in other] != [x.values for x in v]


def test_random_design_stays_in_bounds(scene):
    v = variants(scene, {"design": {"kind": "random", "samples": 50, "seed": 1},
                         "parameters": [{"path": "meshes[0].stiffness", "bounds": [1e9, 2e9]}]})
    k = [x.values["meshes[0].stiffness"] for x in v]
    assert len(v) == 50 and min(k) >= 1e9 and max(k) <= 2e9


BAD = [
    ({"parameters": [{"path": "bearings[2].k_radiall", "values": [1.0]}]}, "parameters[0].path",
     "nearest valid path: bearings[2].k_radial"),
    ({"parameters": [{"path": "stages[0].planets.cuont", "values": [3]}]}, "parameters[0].path",
     "nearest valid path: stages[0].planets.count"),
    ({"parameters": [{"path": "nothing[*].k", "values": [1.0]}]}, "parameters[0].path", "not a list"),
    ({"parameters": []}, "parameters", "at least one"),
    ({"parameters": [{"values": [1.0]}]}, "parameters[0].path", "missing"),
    ({"parameters": [{"path": "meshes[0].stiffness", "values": []}]}, "parameters[0].values", "non-empty"),
    ({"parameters": [{"path": "meshes[0].stiffness", "range": [1, 2, 0]}]}, "parameters[0].range", "n"),
    ({"parameters": [{"path": "meshes[0].stiffness", "range": [1, "x", 3]}]}, "parameters[0].range", "finite"),
    ({"parameters": [{"path": "meshes[0].stiffness", "log_range": [0, 2, 3]}]}, "parameters[0].log_range", "> 0"),
    ({"parameters": [{"path": "meshes[0].stiffness", "values": [1], "range": [1, 2, 2]}]}, "parameters[0]",
     "exactly one"),
    ({"design": {"kind": "sobol"}, "parameters": [{"path": "meshes[0].stiffness", "values": [1]}]},
     "design.kind", "one of"),
    ({"design": {"kind": "lhs", "samples": 0}, "parameters": [{"path": "meshes[0].stiffness", "bounds": [1, 2]}]},
     "design.samples", "integer"),
    ({"design": {"kind": "lhs", "samples": 4}, "parameters": [{"path": "meshes[0].stiffness", "values": [1]}]},
     "parameters[0].values", "bounds"),
    ({"parameters": [{"path": "meshes[0].stiffness", "bounds": [1, 2]}]}, "parameters[0].bounds", "grid"),
    ({"design": {"kind": "random", "samples": 3}, "parameters": [{"path": "meshes[0].stiffness",
                                                                   "bounds": [2, 1]}]},
     "parameters[0].bounds", "low < high"),
    ({"parameters": [{"path": "meshes[0].stiffness", "range": [1, 2, 1000]},
                     {"path": "bearings[0].k_axial", "range": [1, 2, 1000]}]}, "parameters", "at most"),
]


@pytest.mark.parametrize("study, path, words", BAD, ids=[f"{p}:{w}" for _, p, w in BAD])
def test_bad_study_names_its_field(scene, study, path, words):
    with pytest.raises(SceneError) as e:
        variants(scene, study)
    assert str(e.value).startswith(path) and words in str(e.value), str(e.value)
    assert "\n" not in str(e.value)


def test_variant_values_build_valid_scenes(scene):
    # (5 planets: (19 + 56) / 5 = 15, the assembly condition of stage 1, Lynwander 1983)
    v = variants(scene, {"parameters": [{"path": "stages[0].planets.count", "values": [5]}]})
    assert scene.with_values(v[0].values).stages[0].planets.count == 5
    assert math.isfinite(v[0].values["stages[0].planets.count"])


@pytest.mark.parametrize("param, where, words", [
    ({"path": "stages[0].planets.count", "values": [5, "five"]}, "parameters[0].values[1] = 'five'", "whole number"),
    ({"path": "stages[0].planets.count", "values": [3.5]}, "parameters[0].values[0] = 3.5", "whole number"),
    ({"path": "meshes[0].stiffness", "values": [1e9, "stiff"]}, "parameters[0].values[1]", "a number"),
    ({"path": "meshes[0].stiffness", "values": [True]}, "parameters[0].values[0] = True", "a number"),
    ({"path": "meshes[0].name", "values": [3]}, "parameters[0].values[0] = 3", "text"),
    ({"path": "meshes[0].name", "scale": True, "values": [2.0]}, "parameters[0].values[0]", "scale"),
    ({"path": "meshes[0].stiffness", "scale": "yes", "values": [2.0]}, "parameters[0].scale", "true or false"),
])
def test_wrong_value_types_are_refused_when_the_study_is_read(scene, param, where, words):
    # before any variant runs: the message names the study field, the value and what the path takes
    with pytest.raises(SceneError) as e:
        variants(scene, {"parameters": [param]})
    assert str(e.value).startswith(where) and words in str(e.value), str(e.value)


def test_scale_multiplies_each_paths_own_value_and_a_name_labels_several_paths(scene):
    # one factor on every bearing's radial and tilt stiffness (a bearing-factor study)
    pair = load_scene("kahraman_beta20")
    study = {"parameters": [{"name": "bearing_factor", "path": ["bearings[*].k_radial", "bearings[*].k_tilt"],
                             "scale": True, "values": [1.0, 10.0]}]}
    v = variants(pair, study)
    assert [x.params for x in v] == [{"bearing_factor": 1.0}, {"bearing_factor": 10.0}]
    for i, b in enumerate(pair.bearings):
        assert v[1].values[f"bearings[{i}].k_radial"] == 10.0 * b.k_radial
        assert v[1].values[f"bearings[{i}].k_tilt"] == 10.0 * b.k_tilt
    # a derived value (not in the file) cannot be scaled
    with pytest.raises(SceneError, match=r"^parameters\[0\]\.scale.*bearings\[0\]\.k_radial_y is not given"):
        variants(scene, {"parameters": [{"path": "bearings[*].k_radial_y", "scale": True, "values": [2.0]}]})
    with pytest.raises(SceneError, match=r"^parameters\[0\]\.name"):   # several paths need a name
        variants(pair, {"parameters": [{"path": ["bearings[0].k_radial", "bearings[1].k_radial"], "values": [1e9]}]})


def test_sampled_counts_are_whole(scene):
    v = variants(scene, {"design": {"kind": "lhs", "samples": 8, "seed": 1},
                         "parameters": [{"path": "stages[0].planets.count", "bounds": [3, 7]}]})
    assert {type(x.values["stages[0].planets.count"]) for x in v} == {int}
    assert {x.values["stages[0].planets.count"] for x in v} <= set(range(3, 8))
