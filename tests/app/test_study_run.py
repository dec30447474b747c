"""One study variant to one table row (assembly/app/study/run.py): the row's frequencies are the
scene's own modal solve with the variant's values, and a variant the scene refuses is a row
with its error, not an exception."""
from __future__ import annotations

import pickle

import numpy as np

from assembly.analysis.modal import solve_modes
from assembly.app.study.run import run_variant
from assembly.app.study.spec import variants
from assembly.model.assemble import assemble
from assembly.scene.schema import load_scene


def test_rows_are_the_variants_own_modal_solves():
    scene = load_scene("lin_parker_n3")
    vs = variants(scene, {"parameters": [{"path": "stages[0].planets.bearing.k_radial",
                                          "values": [5.0e7, 1.0e8, 2.0e8]}]})
    for v in vs:
        row = run_variant("lin_parker_n3", v, keep={"modes": 6})
        direct = solve_modes(assemble(scene.with_values(v.values)))
        want = direct.frequencies_hz[direct.n_rigid:direct.n_rigid + 6]
        assert row["status"] == "ok" and row["error"] == "" and row["variant"] == v.index
        assert row["stages[0].planets.bearing.k_radial"] == v.values["stages[0].planets.bearing.k_radial"]
        np.testing.assert_array_equal([row[f"f{i}_hz"] for i in range(1, 7)], want)
    # stiffer planet bearings never lower a frequency (Rayleigh: K grows, M fixed)
    rows = [run_variant("lin_parker_n3", v, keep={"modes": 6}) for v in vs]
    f = np.array([[r[f"f{i}_hz"] for i in range(1, 7)] for r in rows])
    assert np.all(np.diff(f, axis=0) >= -1e-9 * f[:-1])


def test_a_refused_variant_is_an_error_row():
    # 4 planets on stage 1 of the 5 MW gearbox: (19 + 56) / 4 is not an integer (assembly
    # condition, Lynwander 1983): the row says so, the study goes on
    scene = load_scene("nrel5mw")
    v = variants(scene, {"parameters": [{"path": "stages[0].planets.count", "values": [4]}]})[0]
    row = run_variant("nrel5mw", v)
    assert row["status"] == "error" and row["error"].startswith("stages[0].planets.count")
    assert "f1_hz" not in row


def test_rows_and_arguments_pickle():
    # what a distributed worker receives and returns
    scene = load_scene("lin_parker_n3")
    v = variants(scene, {"parameters": [{"path": "stages[0].planets.bearing.k_radial", "values": [1e8]}]})[0]
    assert pickle.loads(pickle.dumps(v)) == v
    row = run_variant("lin_parker_n3", v, keep={"modes": 2})
    assert pickle.loads(pickle.dumps(row)) == row
