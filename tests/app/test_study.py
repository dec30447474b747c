"""``flexgear study``: the shipped studies against the scenes and closed forms they reproduce,
each analysis's row against the analysis run directly, the results folder, and bad studies
refused in one line (exit 2, nothing written) before any variant runs."""
from __future__ import annotations

import csv
import math
import time

import numpy as np
import pytest

from assembly import assemble, load_scene, scale_bearings, solve_modes
from assembly.app.cli import main
from assembly.app.report.links import folder_problems
from assembly.app.study.engine import run_study
from assembly.app.study.file import read_study
from tests.app.test_simulate_cli import pair_file

# The torsional pair of tests/app/test_simulate_cli.py: rotor J1 = 2, generator J2 = 0.5 kg m^2,
# base radii 0.05 / 0.15 m, mesh stiffness k along the line of action; its one elastic mode has
# w^2 = k (rb1^2 / J1 + rb2^2 / J2) (two inertias on a spring through the base radii).
J1, J2, RB1, RB2 = 2.0, 0.5, 0.05, 0.15


def pair_hz(k: float) -> float:
    return math.sqrt(k * (RB1 ** 2 / J1 + RB2 ** 2 / J2)) / (2 * math.pi)


def _study(tmp_path, text: str, name: str = "study.toml") -> str:
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return str(p)


def _rows(path: str):
    return run_study(read_study(path), "serial")


def test_helix_angle_study_reproduces_the_shipped_pairs():
    # Peeters et al. (2006) Fig. 7: at 0 and 20 deg the rows are the kahraman_beta0 / beta20 scenes
    rows = {r["helix_angle_deg"]: r for r in _rows("helix_angle")}
    assert sorted(rows) == [float(x) for x in range(31)]
    for deg, name in ((0.0, "kahraman_beta0"), (20.0, "kahraman_beta20")):
        ref = solve_modes(assemble(load_scene(name)))
        want = np.sort(ref.frequencies_hz)[ref.n_rigid:]
        got = [rows[deg][f"f{j + 1}_hz"] for j in range(len(want))]
        assert got == pytest.approx(want, rel=1e-9)


def test_bearing_factor_study_is_the_scaled_scene_and_tends_to_rigid_supports():
    rows = _rows("bearing_factor")
    assert [r["bearing_factor"] for r in rows] == pytest.approx(np.geomspace(1, 1e6, 25), rel=1e-12)
    scene = load_scene("kahraman_beta20")
    for r in (rows[0], rows[16]):        # factors 1 and 1e4
        ref = solve_modes(assemble(scale_bearings(scene, r["bearing_factor"])))
        want = np.sort(ref.frequencies_hz)[ref.n_rigid:]
        assert [r[f"f{j + 1}_hz"] for j in range(len(want))] == pytest.approx(want, rel=1e-9)
    # Peeters Fig. 11a: the bearing modes grow as sqrt(factor) (x10 in frequency for x100 in
    # stiffness at the top of the range) while the lowest gear mode levels off
    top, below = rows[-1], rows[-9]      # factors 1e6 and 1e4 (4 values a decade)
    assert top["f11_hz"] / below["f11_hz"] == pytest.approx(10.0, rel=1e-3)
    assert top["f1_hz"] / below["f1_hz"] == pytest.approx(1.0, abs=1e-3)


def test_planet_count_study_gives_lin_parkers_stages_and_refuses_overlapping_planets():
    rows = _rows("planet_count")
    assert [r["planets"] for r in rows] == [3, 4, 5, 6, 7]
    for r in rows[:3]:
        ref = solve_modes(assemble(load_scene(f"lin_parker_n{r['planets']}")))
        want = ref.frequencies_hz[ref.n_rigid:ref.n_rigid + 24]
        assert r["status"] == "ok" and r["n_rigid"] == ref.n_rigid
        assert [r[f"f{j + 1}_hz"] for j in range(len(want))] == pytest.approx(want, rel=1e-9)
    # six planets on a 97.8 mm carrier radius: centres 97.8 mm apart < 110.4 mm tip diameter
    for r in rows[3:]:
        assert r["status"] == "error" and "planets overlap" in r["error"] and "f1_hz" not in r


PAIR_STUDY = """
scene = "pair.toml"
analysis = "{analysis}"
{extra}
[[parameters]]
path = "meshes[0].stiffness"
values = [1.0e8, 4.0e8]
"""


@pytest.fixture
def pair(tmp_path):
    pair_file(tmp_path)
    return tmp_path


def test_modes_rows_follow_the_closed_form(pair):
    rows = _rows(_study(pair, PAIR_STUDY.format(analysis="modes", extra="")))
    for r in rows:
        assert r["f1_hz"] == pytest.approx(pair_hz(r["meshes[0].stiffness"]), rel=1e-9)
        assert r["n_rigid"] == 1 and "f2_hz" not in r     # one rigid rotation, one elastic mode


def test_frf_rows_peak_at_the_resonance_and_equal_the_direct_frf(pair):
    from assembly.dynamics.frf import frequency_response
    extra = """[frf]
input = "torque:rotor"
outputs = ["force:m", "motion:generator:rz"]
fmin = 300.0
fmax = 800.0
points = 501
"""
    rows = _rows(_study(pair, PAIR_STUDY.format(analysis="frf", extra=extra)))
    f = np.linspace(300.0, 800.0, 501)                          # 1 Hz grid
    for r in rows:
        fn = pair_hz(r["meshes[0].stiffness"])                   # 342.3 and 684.5 Hz
        assert abs(r["peak_hz[force:m]"] - fn) <= 0.5            # the grid point nearest resonance
        # the same call as the study's (both outputs at once: one output alone is another matrix
        # product, whose last bit may differ)
        direct = frequency_response(assemble(load_scene(str(pair / "pair.toml")).with_values(
            {"meshes[0].stiffness": r["meshes[0].stiffness"]})), "torque:rotor", ["force:m", "motion:generator:rz"], f)
        assert r["peak[force:m]"] == np.max(np.abs(direct.outputs["force:m"]))


def test_simulate_rows_are_the_runs_summary(pair):
    from assembly.app.report.simulate import summary
    from assembly.dynamics.simulate import simulate
    extra = """[keep]
stats = ["peak", "mean", "rms", "min", "max", "peak_time_s"]
[simulate]
t_end = 0.01
dt = 1.0e-4
outputs = ["force:m"]
"""
    rows = _rows(_study(pair, PAIR_STUDY.format(analysis="simulate", extra=extra)))
    for r in rows:
        scene = load_scene(str(pair / "pair.toml")).with_values({"meshes[0].stiffness": r["meshes[0].stiffness"]})
        s = summary(simulate(scene, 0.01, 1e-4, ["force:m"], base_dir=pair), "pair")["outputs"]["force:m"]
        # the study keeps no history (statistics on the fly): the numbers of the run kept whole
        for stat in ("peak", "mean", "rms", "min", "max", "peak_time_s"):
            assert r[f"{stat}[force:m]"] == s[stat], stat
        assert r["contact_losses"] == 0


def test_load_case_study_scales_both_torques_and_keeps_every_statistic():
    # the shipped 600 s load cases: the rotor's torque and the generator's together at 50, 75 and
    # 100 % of rated (Jonkman et al. 2009: 43 093.55 N m at the generator; x 96.354, the gear
    # ratio of nrel5mw.toml's teeth, on the rotor), 6e6 steps a case (IEC 61400-1's 10 minutes)
    import dataclasses
    study = read_study("nrel5mw_load_cases")
    assert study.analysis == "simulate" and study.settings["t_end"] == 600.0 and study.settings["dt"] == 1e-4
    for v, factor in zip(study.variants, (0.5, 0.75, 1.0)):
        assert v.values == {"simulation.loads[0].value": factor * 4.152243e6,
                            "simulation.generator.torque": factor * 43093.55}
    # a few steps of each case: every kept statistic of every output, finite, and the run's own
    short = dataclasses.replace(study, settings=dict(study.settings, t_end=0.002))
    rows = run_study(short, "serial")
    outs = study.settings["outputs"]
    for r in rows:
        assert r["status"] == "ok"
        for name in outs:
            for stat in study.keep["stats"]:
                assert math.isfinite(r[f"{stat}[{name}]"]), (stat, name)
    # and the rated case's row is its run's summary: the extremes and their times number for
    # number; the mean and RMS summed block by block as the run went (no history kept) against
    # numpy's sum of the whole array, so within the rounding of a sum of N = 21 rows, N eps
    from threadpoolctl import threadpool_limits

    from assembly.app.report.simulate import summary
    from assembly.dynamics.simulate import simulate
    scene = load_scene("nrel5mw_transient").with_values(study.variants[-1].values)
    with threadpool_limits(1):                     # as a variant runs (one BLAS thread)
        s = summary(simulate(scene, 0.002, 1e-4, outs), scene.name)["outputs"]
    for name in outs:
        for stat in study.keep["stats"]:
            tol = 21 * np.finfo(float).eps if stat in ("mean", "rms") else 0.0
            assert rows[-1][f"{stat}[{name}]"] == pytest.approx(s[name][stat], rel=tol, abs=0.0), (stat, name)


def test_compare_rows_hold_each_fidelity(pair):
    rows = _rows(_study(pair, PAIR_STUDY.format(analysis="compare", extra="")))
    for r in rows:
        assert r["torsional_f1_hz"] == pytest.approx(pair_hz(r["meshes[0].stiffness"]), rel=1e-9)
        assert r["rigid_n_rigid"] >= 1 and r["rigid_f1_hz"] > 0


def test_cli_writes_the_table_plots_and_index(pair, capsys):
    import pyarrow.parquet as pq
    out = pair / "out"
    assert main(["study", _study(pair, PAIR_STUDY.format(analysis="modes", extra="")), "--out", str(out),
                 "--serial", "-q"]) == 0
    assert {"study.parquet", "study.csv", "runs.csv", "frequencies_vs_meshes_0_stiffness.png", "index.html",
            "flexgear_run.json"} <= {p.name for p in out.iterdir()}
    rows = list(csv.DictReader(open(out / "study.csv")))
    table = pq.read_table(out / "study.parquet").to_pylist()
    assert [float(r["f1_hz"]) for r in rows] == [t["f1_hz"] for t in table]     # CSV keeps every digit
    assert [t["status"] for t in table] == ["ok", "ok"]
    assert "time_s" not in rows[0] and "time_s" in next(csv.DictReader(open(out / "runs.csv")))
    assert folder_problems(out) == []      # the shared style, the navigation, every link and anchor


@pytest.mark.parametrize("text, where, words", [
    # a path the scene does not have: named, with the nearest one it has
    ('scene = "kahraman_beta20"\n[[parameters]]\npath = "bearings[0].k_radiall"\nvalues = [1e8]\n',
     "parameters[0].path = 'bearings[0].k_radiall'", "nearest valid path: bearings[0].k_radial"),
    ('scene = "kahraman_beta20"\n[[parameters]]\npath = "bearings[0].k_radial"\nvalues = ["stiff"]\n',
     "parameters[0].values[0] = 'stiff'", "takes a number"),
    ('scene = "kahraman_beta20"\n[[parameters]]\npath = "bearings[0].k_radial"\nvalues = []\n',
     "parameters[0].values = []", "non-empty"),                           # zero variants
    ('scene = "kahraman_beta20"\n[design]\nkind = "lhs"\nsamples = 0\n'
     '[[parameters]]\npath = "bearings[0].k_radial"\nbounds = [1e8, 1e9]\n', "design.samples = 0", "integer"),
    ('scene = "kahraman_beta20"\n', "parameters = None", "at least one"),
    ('scene = "no_such_scene.toml"\n[[parameters]]\npath = "a"\nvalues = [1]\n', "no_such_scene", ""),
    ('scene = "kahraman_beta20"\nanalysis = "fft"\n', "analysis = 'fft'", "modes"),
    ('scene = "kahraman_beta20"\nanlysis = "modes"\n', "anlysis = 'modes'", "unknown key (did you mean 'analysis'?)"),
    ('scene = "kahraman_beta20"\nanalysis = "frf"\n[frf]\ninput = "torque:pinion"\noutputs = ["force:pinion-wheel"]\n'
     'fmax = -5.0\n[[parameters]]\npath = "bearings[0].k_radial"\nvalues = [1e8]\n', "frf.fmax = -5.0", "> 0"),
])
def test_bad_studies_are_one_line_and_write_nothing(tmp_path, capsys, text, where, words):
    out = tmp_path / "out"
    assert main(["study", _study(tmp_path, text), "--out", str(out), "-q"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and where in err and words in err, err
    assert not out.exists()


def test_an_unreachable_scheduler_is_one_line_within_seconds(tmp_path, capsys, monkeypatch):
    # nothing listens on port 9 (discard) of localhost. The refused connection is retried until
    # the connect timeout; its documented 5 s is timed by test_study_read.py
    # (test_a_silent_scheduler_is_given_up_after_the_documented_timeout), so here 1 s: the
    # same path to the same one line, 4 s sooner
    from assembly.app.study import engine
    monkeypatch.setattr(engine, "CONNECT_TIMEOUT_S", 1)
    out = tmp_path / "out"
    t0 = time.perf_counter()
    assert main(["study", "helix_angle", "--out", str(out), "--scheduler", "tcp://127.0.0.1:9", "-q"]) == 2
    assert time.perf_counter() - t0 < 11.0     # CONNECT_TIMEOUT_S = 1 plus the 10 s start-up allowed before
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--scheduler = 'tcp://127.0.0.1:9'" in err and "no Dask scheduler" in err
    assert not out.exists()


def test_the_documented_study_file_reads(tmp_path):
    # docs/study.md's example: a 5 x 2 grid on the shipped flexible planetary stage
    from pathlib import Path
    doc = (Path(__file__).resolve().parents[2] / "docs" / "study.md").read_text(encoding="utf-8")
    block = doc.split("```toml\n", 1)[1].split("```", 1)[0]
    study = read_study(_study(tmp_path, block))
    assert study.analysis == "modes" and study.keep["modes"] == 8 and len(study.variants) == 10
    assert study.parameters == ["stages[0].planets.bearing.k_radial", "stages[0].carrier.flex.cutoff_hz"]


def test_frf_rows_keep_each_bands_own_peak(pair):
    # the pair's one mode at 342.3 Hz (k = 1e8) and 684.5 Hz (4e8): a band around each holds its
    # own peak, and a band without the mode its edge value
    extra = """[frf]
input = "torque:rotor"
outputs = ["force:m"]
fmin = 300.0
fmax = 800.0
points = 501
bands = [[300.0, 500.0], [500.0, 800.0]]
"""
    rows = _rows(_study(pair, PAIR_STUDY.format(analysis="frf", extra=extra)))
    low, high = rows
    assert abs(low["peak_hz[force:m][300-500 Hz]"] - pair_hz(1e8)) <= 0.5          # the 1 Hz grid
    assert abs(high["peak_hz[force:m][500-800 Hz]"] - pair_hz(4e8)) <= 0.5
    assert low["peak[force:m][300-500 Hz]"] == low["peak[force:m]"]
    assert low["peak[force:m][500-800 Hz]"] < low["peak[force:m]"]


@pytest.mark.parametrize("bands,field", [("[[500.0, 300.0]]", "frf.bands[0]"), ("[[100.0, 400.0]]", "frf.bands[0]"),
                                         ('[[300.0, 400.0], "x"]', "frf.bands[1]"),
                                         # between two samples of the 11-point grid (50 Hz apart): no peak
                                         ("[[342.0, 343.0]]", "frf.bands[0]"),
                                         # one column name [500-800 Hz] for two bands
                                         ("[[500.0, 800.0], [500.0000001, 800.0]]", "frf.bands[1]")])
def test_a_bad_frf_band_is_refused_naming_it(pair, bands, field):
    extra = f"""[frf]
input = "torque:rotor"
outputs = ["force:m"]
fmin = 300.0
fmax = 800.0
points = 11
bands = {bands}
"""
    from assembly.errors import SceneError
    with pytest.raises(SceneError) as e:
        read_study(_study(pair, PAIR_STUDY.format(analysis="frf", extra=extra)))
    assert e.value.path == field
