"""The benchmarks (``flexgear bench fe``, assembly/app/bench/fe.py; ``flexgear bench drivetrain``,
assembly/app/bench/drivetrain.py) run end to end on small inputs: the tables, not the timings."""
from __future__ import annotations

import pytest

pytestmark = pytest.mark.gmsh


@pytest.mark.slow
def test_bench_fe_main_prints_table(capsys):
    from assembly.app.bench.fe import main

    assert main(["--components", "carrier", "--target-dofs", "20000", "--levels", "1", "--modes", "6"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    assert out[0].startswith("| component |") and len(out) == 3
    cells = [x.strip() for x in out[2].strip("|").split("|")]
    assert cells[0] == "carrier" and int(cells[3]) > 0
    freqs = [float(f) for f in cells[-1].split(",")]
    assert len(freqs) == 6 and all(f > 0 for f in freqs) and freqs == sorted(freqs)


def _table(lines: list, head: str) -> list:
    """Rows (lists of cells) of the Markdown table whose header starts with ``head``."""
    i = next(k for k, line in enumerate(lines) if line.startswith(head))
    rows = []
    for line in lines[i + 2:]:
        if not line.startswith("|"):
            break
        rows.append([c.strip() for c in line.strip("|").split("|")])
    return rows


@pytest.mark.slow
def test_bench_drivetrain_prints_sizes_times_and_the_in_band_error(tmp_path):
    # A free steel shaft, flexible (P2, 6 fixed-interface modes) and rigid, on two bearings.
    import io

    import numpy as np

    from assembly.analysis.modal import solve_modes
    from assembly.app.bench.drivetrain import main
    from assembly.model.assemble import assemble
    from assembly.scene.schema import load_scene
    from tests.support.shaft_scene import shaft_scene

    flex, rigid = tmp_path / "flex.toml", tmp_path / "rigid.toml"
    flex.write_text(shaft_scene("flexible"))
    rigid.write_text(shaft_scene("rigid"))
    buf = io.StringIO()
    assert main(["--scene", str(flex), "--rigid-scene", str(rigid), "--repeat", "2"], out=buf) == 0
    lines = buf.getvalue().splitlines()
    assert " cores, load average " in lines[0] and "sparse backend" in lines[0]
    # rigid: one free body has 6 DOFs and 6 modes; its torsional variant one DOF (the spin)
    (r, t) = _table(lines, "| scene | fidelity")
    assert r[1:4] == ["rigid", "6", "6"] and t[1:4] == ["torsional", "1", "1"]
    assert all(len(row[4].split(",")) == 2 and all(float(x) > 0 for x in row[4].split(",")) for row in (r, t))
    (row,) = _table(lines, "| scene | flexible bodies")
    # reduced DOFs: 2 interfaces x 6 master DOFs + 6 fixed-interface modes + one residual
    # vector per boundary DOF (12) = 30; the model is that one body
    red = solve_modes(assemble(load_scene(flex)))
    full = solve_modes(assemble(load_scene(flex), full_fe=True), n_modes=len(red.frequencies_hz))
    n_fe = full.model.K.shape[0]
    assert row[1] == f"shaft {n_fe} -> 30" and row[2] == "30" and row[5] == str(n_fe)
    cold, warm = ([float(x) for x in row[k].split(",")] for k in (3, 4))
    assert len(cold) == len(warm) == 2 and all(x > 0 for x in cold + warm)
    # the in-band error, recomputed here from the two models' sorted elastic frequencies (the
    # shaft's modes pair in order); reduced >= full mode by mode (Rayleigh-Ritz), up to the
    # relative error to which each solve resolves its frequencies
    f_red = red.frequencies_hz[red.n_rigid:]
    f_full = full.frequencies_hz[full.n_rigid:full.n_rigid + len(f_red)]
    rtol = red.info["frequency_rtol"] + full.info["frequency_rtol"]
    assert np.all(f_red >= f_full * (1 - rtol))
    band = f_red < 3000.0
    # the reference solved beyond the band: at least the in-band count of the reduced model
    # plus its rigid-body mode and bench_drivetrain.EXTRA_MODES
    n_full = int(row[7].split()[0])
    assert n_full >= band.sum() + 1 + 10 and full.frequencies_hz[n_full - 1] > 3000.0
    assert row[8] == f"{band.sum()} ({band.sum()})"
    # printed to 2 significant digits: rounding moves it by at most 5 % of itself
    assert float(row[9]) == pytest.approx(100 * np.max(f_red[band] / f_full[band] - 1), rel=0.05)
    assert 0.9 < float(row[10]) <= 1.0 + 1e-12                       # MAC of a pair of one mode
    reduced_mb, full_mb = (float(x) for x in row[11].split("/"))
    assert 0 < reduced_mb <= full_mb


def test_bench_frf_prints_the_table_with_errors(tmp_path):
    # the coarse flexible steel shaft on two bearings (30 reduced DOFs, 1530 FE DOFs), a
    # transverse force at one end; every error against the direct solve of the same model
    # (1e-6, the acceptance bound of the modal solve) and against the unreduced model (the
    # reduction's own error, well inside the 3000 Hz band: its first bending mode is far above)
    import io

    from assembly.app.bench.frf import main
    from tests.support.shaft_scene import shaft_scene

    path = tmp_path / "shaft.toml"
    path.write_text(shaft_scene("flexible"))
    buf = io.StringIO()
    assert main(["--scene", str(path), "--input", "force:shaft:end_a:x", "--points", "300", "--fmin", "10",
                 "--fmax", "500", "--full-points", "2"], out=buf) == 0
    lines = buf.getvalue().splitlines()
    rows = _table(lines, "| method |")
    assert [r[0] for r in rows][:2] == ["modal, modes to 30 x fmax", "modal, every mode"]
    for r in rows[:2]:
        assert r[1] == "30" and float(r[4]) <= 1e-6
        assert 0 < float(r[5].split()[0]) < 1e-6
    assert rows[2][4] == "reference" and rows[3][1] == "1530"


def test_bench_transient_prints_cost_and_drivetrain_tables():
    # tables 1 and 2 on the rigid 5 MW models, a few steps: each row's numbers are present (the
    # compiled step's where numba is installed) and the drivetrain's mean main-shaft torque is
    # the rated rotor torque (the loads balance through the gear ratio, Jonkman et al. 2009 /
    # the scene's teeth) to its mesh ripple
    import io

    from assembly.app.bench.transient import main
    from assembly.dynamics import jit
    buf = io.StringIO()
    assert main(["--tables", "1,2", "--no-flexible", "--steps", "50", "--repeat", "50", "--seconds", "0.01",
                 "--estimate", "0.005"], out=buf) == 0
    lines = buf.getvalue().splitlines()
    step = _table(lines, "| scene | DOFs | rank m |")
    assert step[0][:3] == ["nrel5mw_transient", "126", "26"] and float(step[0][6]) > 0 and float(step[0][7]) > 0
    if jit.COMPILED:
        assert float(step[0][5]) > 0 and step[0][11] in ("yes", "no")
        long = _table(lines, "| scene | DOFs | simulated [s] |")
        assert long[0][:3] == ["nrel5mw_transient", "126", "0.005"] and float(long[0][6]) > 0
    drive = _table(lines, "| scene | DOFs | assemble [s] |")
    assert drive[0][3] == "100" and abs(float(drive[0][9]) - 1.0) < 1e-2


def test_bench_study_prints_the_overhead_table_with_identical_results(capsys):
    # the rigid study alone, 10 variants, in this process and on a 2-worker local cluster:
    # both rows printed, every variant solved, and the two engines' result columns identical
    from assembly.app.bench.study import main

    assert main(["--no-flexible", "--rigid-variants", "10", "--workers", "2"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("`flexgear bench study`: 2 workers; ")
    rows = _table(lines, "| engine | workers | variants | wall [s] |")
    assert [r[:3] for r in rows] == [["serial", "1", "10"], ["local", "2", "10"]]
    assert all(r[10] == "0" for r in rows)                               # errors
    assert all(float(r[3]) > 0 and float(r[4]) > 0 for r in rows)        # wall, sum of time_s
    assert float(rows[1][8]) > 0 and rows[0][11] == "(client)" and float(rows[1][11]) > 0
    assert any(line.startswith("Result columns, local vs serial: identical (max abs diff of frequencies 0 Hz)")
               for line in lines)
    assert not any(line.startswith("| engine | workers (processes) |") for line in lines)   # no flexible table


def test_bench_turbine_prints_the_cost_beside_the_drivetrain_alone(capsys):
    pytest.importorskip("rosco", reason="the rosco package is not installed")
    pytest.importorskip("pyconturb", reason="the wind extra is not installed")
    from assembly.app.bench.turbine import main
    assert main(["--t-end", "0.05", "--bases", "nrel5mw"]) == 0
    rows = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("| nrel5mw |")]
    assert len(rows) == 1
    cells = [c.strip() for c in rows[0].strip("|").split("|")]
    # 0.05 s of the deck's 0.00625 s steps, the controller called at each; a ratio of two times
    assert cells[2] == "8" and cells[6] == "8" and float(cells[-1]) > 0.0


@pytest.mark.slow
def test_bench_runup_times_each_part_of_a_short_runup(tmp_path, capsys):
    # a run-up of the 5 MW over a few hundredths of a second, one output: the command's files are
    # written, every part of the table has a time, and the functions it timed are put back
    import assembly.dynamics.simulate as sim_module
    from assembly.app.bench.runup import main
    simulate = sim_module.simulate
    out = tmp_path / "runup"
    assert main(["nrel5mw_transient", "--speed-range", "6.9", "12.1", "--rate", "100", "--dt", "1e-4", "--settle",
                 "0.005", "--track", "generator", "--output", "force:stage3", "--out", str(out)]) == 0
    assert sim_module.simulate is simulate
    text = capsys.readouterr().out
    rows = {r[0]: r[1] for r in _table(text.splitlines(), "| part | wall [s] |")}
    for part in ("simulation", "history file", "simulation images", "life", "total (command)"):
        assert float(rows[part]) >= 0.0, part
    assert "steps," in text and (out / "life.csv").exists() and (out / "index.html").exists()
    # every bearing and gear rated (placeholder ratings): 19 bearings, 26 gears of 13 meshes
    assert len((out / "life_bearings.csv").read_text().splitlines()) == 1 + 19
    assert len((out / "life_gears.csv").read_text().splitlines()) == 1 + 26

