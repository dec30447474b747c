"""Every public function a Python user calls refuses an argument of the wrong kind with the
package's one-line SceneError naming that argument and its value (the line the command line
prints), never a TypeError, AttributeError, IndexError or KeyError from deep inside.

The table crosses each argument of each function (the exports of :mod:`assembly`,
docs/python_api.md, README's Python section and the dynamics entry points) with the wrong
kinds that fit it: None, a string for a number, a number for a string, a list for a scalar,
an empty list, NaN, an object of another class, a scene where a model is expected and the
other way round, an unknown name. Every other argument holds a valid value, so the one
replaced is the only fault. Valid values of other forms (numpy numbers, a name for a list of
names, a tuple for a list, a pathlib.Path) still run.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from assembly import (
    LoadCase,
    SceneError,
    assemble,
    classify_modes,
    compare,
    load_scene,
    pair_modes,
    save_scene,
    scale_bearings,
    scene_from_dict,
    scene_to_toml,
    solve_modes,
    track_modes,
    with_fidelity,
)
from assembly.analysis.gear_table import gear_table
from assembly.analysis.reactions import static_report
from assembly.analysis.referred import referred_inertia
from assembly.analysis.static import solve_static, solve_static_cases
from assembly.analysis.two_mass import two_mass
from assembly.app import run_report
from assembly.dynamics.campbell import campbell
from assembly.dynamics.frf import frequency_response
from assembly.dynamics.order_tracking import order_cut, order_map, resonance_passages, shaft_angle
from assembly.dynamics.simulate import simulate
from assembly.scene.edit import get_value, with_value, with_values
from assembly.scene.stage_alone import stage_alone
from tests.support.gear_pair_scene import gear_pair

NAN = math.nan


class Other:
    """An object of a class no argument takes."""

    def __repr__(self):
        return "<Other>"


OTHER = Other()


@pytest.fixture(scope="module")
def objects(tmp_path_factory):
    """A torsional spur pair with a rotor and a generator, its model, modes, a static load case
    and its solution, and its TOML file."""
    d = gear_pair(2.0, 0.5, 0.05, 0.15, 1e8, roles=("rotor", "generator"), simulation={"speed": 10.0})
    scene = scene_from_dict(d)
    model = assemble(scene)
    result = solve_modes(model)
    load = LoadCase(input="g1", output="g2", torque=100.0)
    folder = tmp_path_factory.mktemp("api")
    path = save_scene(scene, folder / "pair.toml")
    omap = order_map(REC_T, REC_ANGLE, REC_VALUE, max_order=10, revolutions=4)
    return {"scene": scene, "model": model, "result": result, "load": load, "static": solve_static(model, load),
            "file": str(path), "folder": folder, "planetary": load_scene("lin_parker_n3"),
            "omap": omap, "cut": order_cut(omap, 1.0)}


# a run-up record for order tracking: 2 s at 5 -> 9 Hz, 14 revolutions (lists: the table's
# values are compared with its shorthands)
_T = np.arange(0.0, 2.0, 1e-3)
REC_T, REC_ANGLE = _T.tolist(), (2 * math.pi * (5.0 * _T + _T**2)).tolist()
REC_VALUE = np.cos(REC_ANGLE).tolist()


# wrong kinds, by what the argument holds ("S", "M", "R": the scene, model, modes of `objects`)
SCENE = [None, 5, "pair.toml", "M", "R", {}, OTHER]
MODEL = [None, 5, "S", "R", OTHER]
# an analysis of one model takes a model or a scene (assembled as given)
MODEL_OR_SCENE = [None, 5, "pair.toml", "R", {}, OTHER]
MODES = [None, 5, "S", "M", OTHER]
FLAG = ["yes", 1, None, OTHER]
NAME = [None, 5, "", ["g1"], OTHER]
OPTIONAL_NAME = [5, "", ["g1"], OTHER]
TIME = [None, "1e-3", [1e-3], NAN, math.inf, -1e-3, 0.0, True, 1e308, OTHER]
COUNT = ["3", 1.5, NAN, True, None, [3], OTHER]
FREQUENCIES = [None, "10", [], [NAN], [-1.0], [[1.0, 2.0]], ["a"], [1e308], OTHER]
FILE = [None, 5, "", ["x.toml"], OTHER]
TABLE = [None, [], "x", 5, OTHER]
SERIES = [None, 5, "x", [], [1.0, 2.0], [[1.0, 2.0]], ["a"] * 5, OTHER]

#: (function label, call(objects, **arguments), valid arguments, {argument: wrong values}).
#: Valid arguments may name an entry of `objects` by its key in angle brackets.
TABLE_OF_CALLS = [
    ("load_scene", lambda o, **a: load_scene(a["scene"]), {"scene": "<file>"}, {"scene": FILE}),
    ("scene_from_dict", lambda o, **a: scene_from_dict(a["data"]), {"data": {}}, {"data": TABLE}),
    ("save_scene", lambda o, **a: save_scene(a["scene"], a["path"]),
     {"scene": "<scene>", "path": "<folder>/out.toml"}, {"scene": SCENE, "path": FILE}),
    ("scene_to_toml", lambda o, **a: scene_to_toml(a["scene"]), {"scene": "<scene>"}, {"scene": SCENE}),
    ("assemble", lambda o, **a: assemble(**a), {"scene": "<scene>"},
     {"scene": SCENE, "full_fe": FLAG, "bodies": [5, "x", []], "caches": [5, "x", OTHER], "source": [5, "M", OTHER]}),
    ("solve_modes", lambda o, **a: solve_modes(**a), {"model": "<model>"},
     {"model": MODEL, "n_modes": ["3", 1.5, NAN, True, 0, -1, [3], OTHER], "check": FLAG}),
    ("classify_modes", lambda o, **a: classify_modes(**a), {"result": "<result>"},
     {"result": MODES, "nodal_diameters": FLAG}),
    ("pair_modes", lambda o, **a: pair_modes(**a), {"res_a": "<result>", "res_b": "<result>"},
     {"res_a": MODES, "res_b": MODES}),
    ("track_modes", lambda o, **a: track_modes(**a), {"results": ["<result>", "<result>"]},
     {"results": [None, 5, "x", "R", [None], ["M"], OTHER], "threshold": ["0.8", NAN, -0.1, 1.5, None, OTHER]}),
    ("get_value", lambda o, **a: get_value(**a), {"scene": "<scene>", "path": "meshes[0].stiffness"},
     {"scene": SCENE, "path": NAME, "given": FLAG}),
    ("with_value", lambda o, **a: with_value(**a), {"scene": "<scene>", "path": "meshes[0].stiffness", "value": 2e8},
     {"scene": SCENE, "path": NAME}),
    ("with_values", lambda o, **a: with_values(**a), {"scene": "<scene>", "changes": {"meshes[0].stiffness": 2e8}},
     {"scene": SCENE, "changes": [None, [], "x", 5, {5: 1.0}, OTHER]}),
    ("Scene.get_value", lambda o, **a: o["scene"].get_value(a["path"]), {"path": "meshes[0].stiffness"},
     {"path": NAME}),
    ("Scene.with_value", lambda o, **a: o["scene"].with_value(a["path"], 2e8), {"path": "meshes[0].stiffness"},
     {"path": NAME}),
    ("Scene.with_values", lambda o, **a: o["scene"].with_values(a["changes"]),
     {"changes": {"meshes[0].stiffness": 2e8}}, {"changes": [None, [], "x", 5, OTHER]}),
    ("Scene.body", lambda o, **a: o["scene"].body(a["name"]), {"name": "g1"}, {"name": [None, 5, "", "g3", OTHER]}),
    ("compare", lambda o, **a: compare(**a), {"scene": "<scene>"},
     {"scene": SCENE, "n_rows": ["3", 1.5, NAN, -1, True, [3], OTHER], "given": [5, "M", "S", OTHER],
      "flexible_components": FLAG}),
    ("with_fidelity", lambda o, **a: with_fidelity(**a), {"scene": "<scene>", "fidelity": "rigid"},
     {"scene": SCENE, "fidelity": [None, 5, "", "rgid", OTHER], "bodies": [5, [5], "", "g3", [None], OTHER]}),
    ("scale_bearings", lambda o, **a: scale_bearings(**a), {"scene": "<scene>", "factor": 2.0},
     {"scene": SCENE, "factor": ["2", NAN, None, [2.0], 0.0, -1.0, True, OTHER],
      "directions": [5, None, [5], "k_radal", [], OTHER]}),
    ("stage_alone", lambda o, **a: stage_alone(**a), {"scene": "<planetary>", "stage_name": "stage"},
     {"scene": SCENE, "stage_name": [None, 5, "", "stag", OTHER], "bearings": [5, "x", [], OTHER],
      "planar": FLAG}),
    ("frequency_response", lambda o, **a: frequency_response(**a),
     {"model": "<model>", "input": "torque:g1", "outputs": ["force:m"], "frequency_hz": [1.0, 10.0]},
     {"model": MODEL, "input": NAME + ["torque:g3"], "outputs": [None, 5, [5], [None], [], [""], OTHER],
      "frequency_hz": FREQUENCIES, "method": [None, 5, "", "exact", OTHER], "result": [5, "M", "S", OTHER],
      "modes_hz": ["1e3", NAN, [1e3], -1.0, 0.0, True, OTHER], "residual": FLAG}),
    ("simulate", lambda o, **a: simulate(**a), {"model": "<model>", "t_end": 1e-3, "dt": 1e-4, "outputs": ["force:m"]},
     {"model": MODEL_OR_SCENE, "t_end": TIME, "dt": TIME, "outputs": [5, [5], [None], [""], ["speed:g3"], OTHER],
      "simulation": [5, {}, "S", OTHER], "base_dir": [5, "", OTHER],
      "speed": ["1", NAN, math.inf, [1.0], True, 1e308, OTHER], "progress": [5, "x"], "full_fe": FLAG}),
    ("campbell", lambda o, **a: campbell(**a), {"model": "<model>", "speed_range": (0.0, 100.0)},
     {"model": MODEL_OR_SCENE, "speed_range": [None, 5, "0 100", [1.0], [0.0, NAN], [0.0, "1"], [0.0, 1.0, 2.0], [0.0, 1e308],
                                      OTHER],
      "reference": OPTIONAL_NAME + ["g3"], "points": COUNT + [1], "harmonics": COUNT + [0],
      "gyroscopic": FLAG}),
    ("order_map", lambda o, **a: order_map(**a),
     {"time": REC_T, "angle": REC_ANGLE, "value": REC_VALUE, "max_order": 10.0, "revolutions": 4},
     {"time": SERIES + [REC_T[::-1]], "angle": SERIES + [REC_ANGLE[::-1], REC_ANGLE[:-1]],
      "value": SERIES + [REC_VALUE[:-1], [NAN] * len(REC_T)],
      "max_order": ["10", NAN, 0.0, -1.0, None, [10.0], True, OTHER], "revolutions": COUNT + [0],
      "overlap": ["0.5", NAN, 1.0, -0.1, None, OTHER], "lowest_order": ["1", NAN, 0.0, -1.0, None, OTHER],
      "run_up": FLAG}),
    ("order_cut", lambda o, **a: order_cut(**a), {"omap": "<omap>", "order": 1.0},
     {"omap": [None, 5, "M", "<cut>", OTHER], "order": ["1", NAN, 0.0, -1.0, 0.1, 1e3, None, [1.0], OTHER]}),
    ("resonance_passages", lambda o, **a: resonance_passages(**a), {"cut": "<cut>", "modes": [(20.0, "torsional")]},
     {"cut": [None, 5, "<omap>", OTHER], "modes": [None, 5, "x", {20.0: "t"}, [5], [(20.0,)], [("20", "t")],
                                                    [(-1.0, "t")], [(20.0, 5)], [(20.0, "")], OTHER],
      "band": ["0.1", NAN, 0.0, None, OTHER], "static_below": ["0.5", NAN, 0.0, 1.0, None, OTHER]}),
    ("shaft_angle", lambda o, **a: shaft_angle(**a), {"time": REC_T, "speed": [v + 1.0 for v in REC_T]},
     {"time": SERIES + [REC_T[::-1]], "speed": SERIES + [REC_T[:-1]], "start": ["0", NAN, None, [0.0], OTHER]}),
    ("two_mass", lambda o, **a: two_mass(**a), {"scene": "<scene>"},
     {"scene": SCENE, "rotor": OPTIONAL_NAME + ["g3"], "generator": OPTIONAL_NAME + ["g3"]}),
    ("solve_static", lambda o, **a: solve_static(**a), {"model": "<model>", "load": "<load>"},
     {"model": MODEL_OR_SCENE, "load": [None, 5, "x", {}, "S", OTHER], "path": [None, 5, ""]}),
    ("solve_static_cases", lambda o, **a: solve_static_cases(**a), {"model": "<model>", "cases": [("load", "<load>")]},
     {"model": MODEL_OR_SCENE, "cases": [5, "x", [5], [("load", None)], ["<load>"], OTHER]}),
    ("static_report", lambda o, **a: static_report(**a), {"st": "<static>"}, {"st": [None, 5, "M", "S", OTHER]}),
    ("gear_table", lambda o, **a: gear_table(**a), {"scene": "<scene>"}, {"scene": SCENE}),
    ("referred_inertia", lambda o, **a: referred_inertia(**a), {"model": "<model>", "shaft": "g1"},
     {"model": MODEL_OR_SCENE, "shaft": NAME + ["g3"]}),
    ("run_report", lambda o, **a: run_report(**a), {"scene": "<scene>", "out": "<folder>/never"},
     {"scene": [None, 5, "M", OTHER], "out": [None, 5, "", OTHER], "progress": FLAG,
      "n_modes": ["3", -1, 1.5, None, OTHER], "animated_modes": ["3", -1, 1.5, None, OTHER],
      "compare": FLAG, "images": FLAG,
      "window_size": [5, "x", [0, 0], [1200.0, NAN], OTHER], "n_mode": [3]}),
]


def _value(objects, v):
    """A table value with the shorthands of `objects` filled in."""
    if isinstance(v, str) and v.startswith("<") and ">" in v:
        key, rest = v[1:].split(">", 1)
        return str(objects[key]) + rest if rest else objects[key]
    if v in ("S", "M", "R"):
        return objects[{"S": "scene", "M": "model", "R": "result"}[v]]
    if isinstance(v, list):
        return [_value(objects, x) for x in v]
    if isinstance(v, tuple):
        return tuple(_value(objects, x) for x in v)
    return v


CASES = [(label, arg, i) for label, _, _, wrong in TABLE_OF_CALLS for arg, values in wrong.items()
         for i in range(len(values))]


def test_the_table_covers_every_function_of_the_python_api_doc():
    # every function docs/python_api.md and README's Python section call with arguments is in the table
    doc = (Path(__file__).parents[2] / "docs" / "python_api.md").read_text(encoding="utf-8")
    called = {label.split(".")[-1] for label, *_ in TABLE_OF_CALLS}
    for name in ("load_scene", "assemble", "solve_modes", "with_fidelity", "compare", "save_scene", "scene_to_toml",
                 "run_report", "track_modes", "two_mass", "frequency_response", "simulate", "with_value",
                 "with_values", "get_value"):
        assert f"{name}(" in doc and name in called, name
    assert len(CASES) >= 250, len(CASES)


@pytest.mark.parametrize("label, arg, i", CASES, ids=[f"{label}-{arg}-{i}" for label, arg, i in CASES])
def test_a_wrong_kind_of_argument_is_one_scene_error_naming_it(objects, label, arg, i):
    _, call, valid, wrong = next(t for t in TABLE_OF_CALLS if t[0] == label)
    bad = wrong[arg][i]
    args = {k: _value(objects, v) for k, v in valid.items()}
    args[arg] = _value(objects, bad)
    with pytest.raises(SceneError) as err:
        call(objects, **args)
    msg = str(err.value)
    assert "\n" not in msg and len(msg) < 600, msg
    assert err.value.path.split("[")[0].split(".")[0] == arg, msg


def test_valid_arguments_of_other_forms_run(objects):
    # numpy numbers, one name for a list of names, tuples, a Path, a scalar frequency
    scene, model = objects["scene"], objects["model"]
    assert load_scene(Path(objects["file"])) == scene
    assert len(solve_modes(model, np.int64(2)).frequencies_hz) == 2
    r = frequency_response(model, "torque:g1", "force:m", np.float64(10.0))
    assert r.outputs["force:m"].shape == (1,)
    r = frequency_response(model, "torque:g1", ("force:m",), (1.0, 10.0), modes_hz=math.inf)
    assert np.all(np.isfinite(r.outputs["force:m"]))
    s = simulate(scene, np.float64(1e-3), np.float32(1e-4), "force:m", speed=np.float64(5.0))
    assert s.complete and set(s.outputs) == {"force:m"}
    assert simulate(scene, 1e-3, 1e-4, []).outputs == {}
    c = campbell(scene, np.array([0.0, 100.0]), points=np.int64(3), harmonics=np.int32(2))
    assert len(c.speeds_rpm) == 3
    assert compare(scene, n_rows=np.int64(2)).rows
    planetary = objects["planetary"]
    assert scale_bearings(planetary, np.float64(2.0), "k_radial") == scale_bearings(planetary, 2.0, ("k_radial",))
    assert scale_bearings(planetary, 2.0, "k_radial") != planetary
    assert with_fidelity(scene, "rigid", "g1").body("g1").fidelity == "rigid"


def test_every_export_stays_what_it_names_after_its_submodule_is_imported():
    # `from assembly import stage_alone` gave the module assembly.scene.stage_alone when that
    # submodule had been imported first (an import binds the package attribute to the
    # submodule): in a fresh interpreter, each submodule named like an export is imported
    # before the export is looked up
    import subprocess
    import sys
    code = """
import importlib, types
import assembly
bad = []
for name in assembly.__all__:
    try:
        importlib.import_module("assembly." + name)
    except ModuleNotFoundError:
        continue
    if isinstance(getattr(assembly, name), types.ModuleType):
        bad.append(name)
print(bad)
"""
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and p.stdout.strip() == "[]", (p.stdout, p.stderr)
