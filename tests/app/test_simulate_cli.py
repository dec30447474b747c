"""``flexgear simulate``: JSON object, output folder (HDF5, plots, index), bad input in one line
with exit code 2, a stopped run's partial result.

Scene: the shipped ``nrel5mw_transient`` (rated rotor torque against the rated generator torque,
which balance through the gear ratio: the static start then carries the rotor torque in the main
shaft from t = 0) and a small torsional pair written here."""
from __future__ import annotations

import json
import math
import os

import numpy as np
import pytest

from assembly.app.cli import main
from assembly.app.report.links import folder_problems

# Jonkman et al. (2009): rated generator torque 43 093.55 N m; the scene's gear ratio 96.354
# (Nejad et al. 2016 teeth) makes the rated rotor torque the scene applies, 4.152243e6 N m.
ROTOR_TORQUE = 4.152243e6
J_ROTOR = 38759236.0       # kg m^2, rotor inertia about the shaft (Jonkman et al. 2009), nrel5mw.toml

PAIR = """
name = "pair"
[[bodies]]
name = "rotor"
mass = 10.0
polar_inertia = 2.0
fidelity = "torsional"
role = "rotor"
[[bodies]]
name = "generator"
mass = 10.0
polar_inertia = 0.5
position = [{c}, 0.0, 0.0]
fidelity = "torsional"
role = "generator"
[[meshes]]
name = "m"
gear1 = "rotor"
gear2 = "generator"
stiffness = 1.0e8
base_radius1 = 0.05
base_radius2 = 0.15
pressure_angle_deg = 20.0
{mesh}
[simulation]
speed = 10.0
{sim}
"""


def pair_file(tmp_path, mesh: str = "", sim: str = "") -> str:
    p = tmp_path / "pair.toml"
    p.write_text(PAIR.format(c=0.2 / math.cos(math.radians(20.0)), mesh=mesh, sim=sim), encoding="utf-8")
    return str(p)


def test_json_prints_time_outputs_units(capsys):
    assert main(["simulate", "nrel5mw_transient", "--t-end", "0.002", "--dt", "1e-4", "--output",
                 "torque:main_shaft", "--output", "force:stage1.sun-planet0", "--output", "speed:rotor",
                 "--json", "-q"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert set(data) >= {"time_s", "outputs", "units"}
    np.testing.assert_allclose(data["time_s"], np.arange(21) * 1e-4, atol=1e-15)
    assert data["units"] == {"torque:main_shaft": "N m", "force:stage1.sun-planet0": "N", "speed:rotor": "rad/s"}
    # the rotor's own balance at the start: main shaft torque = rotor torque - J_R alpha. alpha is
    # not zero although rotor and generator torques balance through the gears: the meshes'
    # energy-consistent torques (1/2 dk/dtheta delta^2 at the planets' phased angles) act on the
    # chain too. alpha from the first step (average acceleration: exact for constant alpha).
    w = data["outputs"]["speed:rotor"]
    alpha = (w[1] - w[0]) / 1e-4
    assert data["outputs"]["torque:main_shaft"][0] == pytest.approx(ROTOR_TORQUE - J_ROTOR * alpha, rel=1e-5)
    assert data["outputs"]["speed:rotor"][0] == pytest.approx(1.2671, rel=1e-12)      # 12.1 rpm
    assert data["complete"] is True


def test_out_writes_hdf5_plots_index(tmp_path, capsys):
    import h5py
    out = tmp_path / "res"
    scene = pair_file(tmp_path, mesh="backlash = 1.0e-4\nvariation = { amplitudes = [0.2], teeth = 20 }",
                      sim='loads = [{ body = "rotor", value = 100.0 }]\ngenerator = { torque = 300.0 }')
    assert main(["simulate", scene, "--t-end", "0.01", "--dt", "1e-4", "--output", "force:m", "--output",
                 "speed:generator", "--out", str(out), "-q"]) == 0
    assert "index.html" in capsys.readouterr().out
    for f in ("simulation.h5", "summary.json", "trace_01.png", "spectrum_01.png", "trace_02.png", "index.html"):
        assert (out / f).is_file(), f
    with h5py.File(out / "simulation.h5") as h:
        assert len(h["time_s"]) == 101 and h["outputs/force:m"].attrs["unit"] == "N"
        # balanced torques (300 N m = 3 x 100 N m): the mesh carries 100 / 0.05 N from the start, to
        # the energy-consistent torque at the static twist (phi ~ 1e-3 rad: a relative 1e-8)
        assert h["outputs/force:m"][0] == pytest.approx(2000.0, rel=1e-6)
    assert "contact losses" in (out / "index.html").read_text()
    assert folder_problems(out) == []      # the shared style, the navigation, every link and anchor


BAD = [
    (["--dt", "0"], "--dt"), (["--dt", "-1e-4"], "--dt"), (["--dt", "nan"], "--dt"),
    (["--t-end", "0"], "--t-end"), (["--t-end", "-1"], "--t-end"), (["--t-end", "inf"], "--t-end"),
    (["--output", "force:nomesh"], "--output"), (["--output", "speed:nobody"], "--output"),
]


@pytest.mark.parametrize("args, named", BAD, ids=[" ".join(a) for a, _ in BAD])
def test_bad_arguments_are_one_line_exit_2(tmp_path, capsys, args, named):
    scene = pair_file(tmp_path)
    base = {"--t-end": "0.01", "--dt": "1e-4"}
    for flag, value in zip(args[::2], args[1::2]):
        base[flag] = value
    argv = ["simulate", scene, "-q", "--out", str(tmp_path / "never")]
    for flag, value in base.items():
        argv += [flag, value]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and named in err[0], err
    assert not (tmp_path / "never").exists()


BAD_SCENE = [
    ("backlash = -1.0e-4", "", "meshes[0].backlash"),
    ("variation = { amplitudes = [1.5], teeth = 20 }", "", "meshes[0].variation.amplitudes"),
    ("", 'loads = [{ body = "rotor", table = "missing.csv", column = "T" }]', "simulation.loads[0].table"),
    ("", 'brake = { torque = 1.0e3, ramp_time = -1.0 }', "simulation.brake.ramp_time"),
]


@pytest.mark.parametrize("mesh, sim, named", BAD_SCENE, ids=[n for *_, n in BAD_SCENE])
def test_bad_scene_values_are_one_line_exit_2(tmp_path, capsys, mesh, sim, named):
    scene = pair_file(tmp_path, mesh=mesh, sim=sim)
    assert main(["simulate", scene, "-q", "--t-end", "0.01", "--dt", "1e-4", "--out", str(tmp_path / "never")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and named in err[0], err
    assert not (tmp_path / "never").exists()


def test_a_stopped_run_keeps_a_named_partial_result(tmp_path, capsys, monkeypatch):
    # the integrator stops after 10 steps (as when a state stops being finite): the command says
    # so, keeps those steps in partial_simulation.h5 (complete = False) and exits with 1
    import h5py

    _stop_after_10(monkeypatch)
    out = tmp_path / "res"
    assert main(["simulate", pair_file(tmp_path), "-q", "--t-end", "0.1", "--dt", "1e-4", "--output", "force:m",
                 "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert "run stopped" in err and "rotor.rz" in err and "partial_simulation.h5" in err
    with h5py.File(out / "partial_simulation.h5") as h:
        assert not h.attrs["complete"] and len(h["time_s"]) == 11


def test_documented_command_runs(tmp_path, capsys):
    # the command of docs/simulate.md, as written, into a temporary folder
    from pathlib import Path
    text = (Path(__file__).parents[2] / "docs" / "simulate.md").read_text(encoding="utf-8")
    line = next(ln for ln in text.splitlines() if ln.startswith(".venv/bin/flexgear simulate"))
    argv = line.split()[1:]
    argv[argv.index("--out") + 1] = str(tmp_path / "sim")
    assert main([*argv, "-q"]) == 0
    s = json.loads((tmp_path / "sim" / "summary.json").read_text())
    assert s["complete"] and s["steps"] == 5000 and len(s["outputs"]) == 4


# A run that stops goes through the output rules as a complete one does (assembly/app/output.py):
# its partial result replaces --out whole, marked partial, or is refused before the run; without
# --out nothing is written anywhere.
PARTIAL_FILES = ["flexgear_run.json", "index.html", "partial_simulation.h5", "spectrum_01.png", "spectrum_low_01.png",
                 "summary.json", "trace_01.png"]


def _stop_after_10(monkeypatch, calls=None):
    import assembly.dynamics.simulate as sim_mod
    from tests.support.tiny_runs import stop_after
    monkeypatch.setattr(sim_mod, "integrate", stop_after(10, calls))


def test_a_stopped_run_replaces_an_earlier_result_marked_partial(tmp_path, capsys, monkeypatch):
    import h5py

    out, scene = tmp_path / "res", pair_file(tmp_path)
    argv = ["simulate", scene, "-q", "--dt", "1e-4", "--output", "force:m", "--out", str(out)]
    assert main([*argv, "--t-end", "0.002"]) == 0                     # an earlier complete result
    (out / "notes.txt").write_text("the user's")
    _stop_after_10(monkeypatch)
    assert main([*argv, "--t-end", "0.1"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "run stopped" in err[0] and "partial_simulation.h5" in err[0] and "marked partial" in err[0]
    # the earlier complete result is gone as a whole (no simulation.h5 beside the partial one)
    assert sorted(os.listdir(out)) == sorted([*PARTIAL_FILES, "notes.txt"])
    assert (out / "notes.txt").read_text() == "the user's"
    assert sorted(os.listdir(tmp_path)) == ["pair.toml", "res"]        # no work folder, no lock left
    with h5py.File(out / "partial_simulation.h5") as h:
        assert not h.attrs["complete"] and "rotor.rz" in h.attrs["stopped"] and len(h["time_s"]) == 11
    s = json.loads((out / "summary.json").read_text())
    assert s["complete"] is False and "rotor.rz" in s["stopped"] and s["steps"] == 10
    assert json.loads((out / "flexgear_run.json").read_text())["complete"] is False
    page = (out / "index.html").read_text()
    assert "Partial result: the run stopped" in page and 'href="partial_simulation.h5"' in page
    assert folder_problems(out) == []


def test_a_stopped_run_without_out_writes_nothing(tmp_path, capsys, monkeypatch):
    scene = pair_file(tmp_path)
    monkeypatch.chdir(tmp_path)
    _stop_after_10(monkeypatch)
    assert main(["simulate", scene, "-q", "--t-end", "0.1", "--dt", "1e-4", "--output", "force:m"]) == 1
    cap = capsys.readouterr()
    assert os.listdir(tmp_path) == ["pair.toml"]                        # not in the working folder
    assert "PARTIAL" in cap.out and "force:m" in cap.out                # the summary, marked
    err = cap.err.strip().splitlines()
    assert len(err) == 1 and "run stopped" in err[0] and "give --out DIR to keep it" in err[0]


def test_the_summary_alone_keeps_statistics_not_the_history(tmp_path, capsys, monkeypatch):
    # neither --out nor --json: only the summary is printed, so the run keeps its statistics
    # (memory flat in --t-end) and prints what the run kept whole in memory would
    import assembly.dynamics.simulate as sim_mod
    scene = pair_file(tmp_path)
    seen = []
    real = sim_mod.simulate

    def spy(*a, **kw):
        seen.append(kw.get("arrays", True))
        return real(*a, **kw)
    monkeypatch.setattr(sim_mod, "simulate", spy)
    args = ["simulate", scene, "-q", "--t-end", "0.01", "--dt", "1e-4", "--output", "force:m"]
    assert main(args) == 0
    text = capsys.readouterr().out
    assert seen == [False]
    assert main(args + ["--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert seen == [False, True]
    y = np.array(data["outputs"]["force:m"])
    # the summary's mean, min and max (6 significant digits) are those of the whole history
    line = next(x for x in text.splitlines() if x.strip().startswith("force:m"))
    assert f"mean {y.mean():.6g}, min {y.min():.6g}, max {y.max():.6g}" in line


def test_a_stopped_run_never_writes_into_a_foreign_folder(tmp_path, capsys, monkeypatch):
    out, scene = tmp_path / "mine", pair_file(tmp_path)
    out.mkdir()
    (out / "partial_simulation.h5").write_bytes(b"the user's own")
    calls = []
    _stop_after_10(monkeypatch, calls)
    assert main(["simulate", scene, "-q", "--t-end", "0.1", "--dt", "1e-4", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"--out {out}" in err[0] and "no earlier flexgear run" in err[0]
    assert not calls                                                   # refused before the run
    assert os.listdir(out) == ["partial_simulation.h5"]
    assert (out / "partial_simulation.h5").read_bytes() == b"the user's own"


def test_the_api_writes_a_partial_result_by_the_same_rules(tmp_path, monkeypatch):
    from assembly.app.output import OutputDirError
    from assembly.app.report.simulate import sim_to_dir
    from assembly.dynamics.simulate import simulate
    from assembly.dynamics.transient import Diverged
    from assembly.scene.schema import load_scene

    _stop_after_10(monkeypatch)
    with pytest.raises(Diverged) as stopped:
        simulate(load_scene(pair_file(tmp_path)), 0.1, 1e-4, ["force:m"])
    partial = stopped.value.partial
    sim_to_dir(partial, tmp_path / "res", "pair")
    assert sorted(os.listdir(tmp_path / "res")) == PARTIAL_FILES
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "data.csv").write_text("1,2\n")
    with pytest.raises(OutputDirError, match="no earlier flexgear run"):
        sim_to_dir(partial, tmp_path / "mine", "pair")
    assert os.listdir(tmp_path / "mine") == ["data.csv"]


def test_a_window_keeps_the_spectrum_to_its_part_of_the_record():
    # a 40 Hz sinusoid of amplitude 2 until t = 1 s, then 0.5: the window [1, 1.999] s (1000 samples,
    # 40 whole periods: the line on a bin) sees 0.5; the symmetric Hann window (numpy's) scales a
    # sinusoid on a bin to its amplitude up to O(1/n^2), its sum (n - 1)/2 against the periodic n/2
    from assembly.app.report.simulate import spectrum_blocks, windowed
    t = np.arange(0, 2.0 + 1e-12, 1e-3)
    y = np.where(t < 1.0, 2.0, 0.5) * np.sin(2 * np.pi * 40.0 * t)
    blocks = [(t[:700], y[:700]), (t[700:], y[700:])]
    kept = list(windowed(blocks, 1.0, 1.9995))
    n = sum(len(b) for _, b in kept)
    f, a = spectrum_blocks(kept, n, float(np.mean(np.concatenate([b for _, b in kept]))))
    assert a[np.argmin(np.abs(f - 40.0))] == pytest.approx(0.5, rel=1.0 / n ** 2)
