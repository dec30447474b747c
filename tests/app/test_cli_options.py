"""Every numeric and name option of every subcommand is checked like a scene value: crossed
with NaN, inf, -inf, 0, a negative number, a huge one (1e308), a word where a number belongs,
an empty string and unknown names, each is either refused in one line naming the flag and
the value, with exit code 2, or valid and run (exit 0). An unknown name gets the names there
are and the nearest one. In-process through ``main`` (fast), a few through the real program.
"""
from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

from assembly.app.cli import main
from tests.app.test_simulate_cli import pair_file  # a torsional pair: rotor, generator, mesh m

NUMBERS = ["nan", "inf", "-inf", "0", "-1", "1e308", "abc", ""]
NAMES = ["", "nope", "rotr"]
S = "SCENE"
P = "PART"
T = "TURBINE"          # the pair in a small turbine (the scene fixture writes it beside the pair)
TURBINE = """
[turbine]
surface = "rosco"
radius = 2.0
pitch_deg = 0.0
wind = { speed = 4.0 }
controller = { kind = "baseline", period = 1e-3 }
"""
RUNUP = ["runup", S, "--speed-range", "100", "101", "--rate", "100", "--dt", "1e-3", "--settle", "0.001",
         "--output", "speed:rotor"]
COUPLING = ["coupling", T, "--t-end", "0.02", "--dt", "1e-3", "--segment", "0.005", "--tooth-force", "force:m",
            "--bearing-axial", "force:m"]

#: (subcommand and its valid arguments, flag, values tried, the values that are valid there).
#: A flag's value replaces the base one; "-inf" is passed as --flag=-inf (else argparse takes it
#: for an option).
OPTIONS = [
    (["simulate", S, "--t-end", "1e-3", "--dt", "1e-4", "--output", "force:m"], "--t-end", NUMBERS + ["2e-4"],
     {"2e-4"}),
    (["simulate", S, "--t-end", "1e-3", "--dt", "1e-4", "--output", "force:m"], "--dt", NUMBERS + ["5e-4"], {"5e-4"}),
    (["simulate", S, "--t-end", "1e-3", "--dt", "1e-4", "--output", "force:m"], "--speed", NUMBERS + ["5"],
     {"0", "-1", "5"}),
    (["simulate", S, "--t-end", "1e-3", "--dt", "1e-4"], "--output", ["", "speed:nope", "speed:rotr", "force:mm",
                                                                      "torque:", "speed:rotor"], {"speed:rotor"}),
    (["campbell", S, "--speed-range", "0", "100"], "--reference", NAMES + ["generator"], {"generator"}),
    (["campbell", S, "--speed-range", "0", "100"], "--rated-rpm", NUMBERS + ["50"], {"0", "50"}),
    (["campbell", S, "--speed-range", "0", "100"], "--points", NUMBERS + ["1", "1.5", "3"], {"3"}),
    (["campbell", S, "--speed-range", "0", "100"], "--harmonics", NUMBERS + ["1.5", "2"], {"2"}),
    (["frf", S, "--input", "torque:rotor", "--output", "force:m", "--fmax", "50", "--points", "5"], "--fmin",
     NUMBERS + ["1"], {"1"}),
    (["frf", S, "--input", "torque:rotor", "--output", "force:m", "--points", "5"], "--fmax", NUMBERS + ["50"],
     {"50"}),
    (["frf", S, "--input", "torque:rotor", "--output", "force:m", "--fmax", "50"], "--points", NUMBERS + ["1", "5"],
     {"5"}),
    (["frf", S, "--input", "torque:rotor", "--output", "force:m", "--fmax", "50", "--points", "5"], "--modes-hz",
     NUMBERS + ["1e4"], {"inf", "1e4"}),
    (["frf", S, "--output", "force:m", "--fmax", "50", "--points", "5"], "--input",
     ["", "torque:nope", "torque:rotr", "x", "mesh:mm", "torque:generator"], {"torque:generator"}),
    (["frf", S, "--input", "torque:rotor", "--fmax", "50", "--points", "5"], "--output",
     ["", "force:mm", "motion:rotr:rz", "torque:nope", "motion:rotor:rz"], {"motion:rotor:rz"}),
    (["frf", S, "--input", "torque:rotor", "--output", "force:m"], "--method", ["", "exact"], set()),
    (["export", "elastodyn", S], "--rotor", NAMES + ["generator", "rotor"], {"rotor"}),
    (["export", "elastodyn", S], "--generator", NAMES + ["rotor", "generator"], {"generator"}),
    (["export", "superelement", S, "--out", "OUT"], "--body", NAMES + ["rotor"], set()),
    (["compare", S], "--modes", NUMBERS + ["2"], {"0", "2"}),
    (["run", S, "--out", "OUT"], "--modes", ["", "-1", "0,", "abc", "nan", "1e308"], set()),
    (["study", "planet_count", "--out", "OUT"], "--scheduler", [""], set()),
    (["study", "planet_count", "--out", "OUT"], "--workers", NUMBERS + ["100000"], set()),
    (["modes"], "", ["", "nope", "nrel5m"], set()),
    # flexgear part FILE (a steel bar of linear tetrahedra, tests/support/mesh_writers.kuhn_box)
    (["part", P, "--units", "m"], "--units", ["", "nope", "mx", "m"], {"m"}),
    (["part", P, "--units", "m"], "--order", NUMBERS + ["2"], {"2"}),
    (["part", P, "--units", "m"], "--axis", ["", "nan,0,0", "0,0,0", "1,0", "abc", "1e308,0,0", "0,1,0"],
     {"0,1,0"}),
    (["part", P, "--units", "m"], "--origin", ["", "nan,0,0", "1,2", "abc", "0,0,0"], {"0,0,0"}),
    (["part", P, "--units", "m"], "--mesh-size", NUMBERS + ["0.01"], set()),
    (["part", P, "--units", "m"], "--modes", NUMBERS + ["101", "3"], {"3"}),
    (["modes", S, "--cache-dir"], "", [""], set()),
    (RUNUP, "--rate", NUMBERS + ["50"], {"50"}),
    (RUNUP, "--settle", NUMBERS + ["0.002"], {"0", "0.002"}),
    (RUNUP, "--bandwidth", NUMBERS + ["20"], {"20"}),
    (RUNUP, "--body", NAMES + ["generator"], {"generator"}),
    (RUNUP, "--track", NAMES + ["generator"], {"generator"}),
]
#: the coupling command's cases: its scene reads the rosco wheel's surface (installed by make; where
#: it is not, the turbine's own tests skip and so do these)
COUPLING_CASES = [
    (COUPLING, "--t-end", NUMBERS + ["0.03"], {"0.03"}),
    (COUPLING, "--dt", NUMBERS + ["5e-4"], {"5e-4"}),
    (COUPLING, "--segment", NUMBERS + ["0.004"], {"0.004"}),
    (COUPLING, "--skip", NUMBERS + ["0.002"], {"0", "0.002"}),
    (COUPLING, "--tooth-force", ["", "force:mm", "torque:nope", "force:m"], {"force:m"}),
    (COUPLING, "--bearing-axial", ["", "force:mm", "speed:rotor", "force:m"], {"force:m", "speed:rotor"}),
    (COUPLING, "--fidelity", ["", "stiff", "torsional"], {"torsional"}),
]
ROSCO = importlib.util.find_spec("rosco") is not None
OPTIONS += COUPLING_CASES if ROSCO else []
#: what a flag's value feeds when the error is the analysis' own (--fmin 0 Hz on a free chain)
FEEDS = {"--fmin": "frequency_hz"}
#: a typo and the name the message must offer
NEAREST = {"rotr": "rotor", "mm": "m", "nrel5m": "nrel5mw"}

CASES = [(i, v) for i, (_, _, values, _) in enumerate(OPTIONS) for v in values]


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    path = pair_file(tmp_path_factory.mktemp("cli"))
    Path(path).with_name("turbine.toml").write_text(Path(path).read_text() + TURBINE, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def part(tmp_path_factory):
    import meshio

    from tests.support.mesh_writers import kuhn_box
    pts, tets = kuhn_box((0.1, 0.02, 0.02), (5, 1, 1))
    path = tmp_path_factory.mktemp("cli-part") / "bar.vtu"
    meshio.write(path, meshio.Mesh(pts, [("tetra", tets)]))
    return str(path)


def _argv(i: int, value: str, scene: str, out: str, part: str = "") -> list:
    base, flag, _, _ = OPTIONS[i]
    turbine = str(Path(scene).with_name("turbine.toml"))
    argv = [scene if a == S else turbine if a == T else out if a == "OUT" else part if a == P else a for a in base]
    if not flag:                                    # a positional value (the scene) or a value-only option
        return argv + [value] if argv[-1] != "--cache-dir" else [argv[-1], value, *argv[:-1]]
    if flag in argv and flag not in ("--output",):
        k = argv.index(flag)
        del argv[k:k + 2]
    return argv + ([f"{flag}={value}"] if value.startswith("-") else [flag, value])


def _value_forms(value: str) -> list:
    """How a message may show ``value``: as typed, quoted, or as the float it parses to."""
    forms = [repr(value)]
    if value:
        forms.append(value)
    try:
        x = float(value)
        forms += [repr(x), str(x), f"{x:g}"]
    except ValueError:
        pass
    return forms


@pytest.mark.parametrize("i, value", CASES, ids=[f"{OPTIONS[i][0][0]}{OPTIONS[i][1]}={v!r}" for i, v in CASES])
def test_option_value_is_refused_in_one_line_or_runs(scene, part, tmp_path, capsys, monkeypatch, i, value):
    monkeypatch.chdir(tmp_path)                      # a run may write partial results into the working folder
    out = tmp_path / "out"
    _, flag, _, valid = OPTIONS[i]
    rc = main(_argv(i, value, scene, str(out), part))
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    if value in valid:
        assert rc == 0, err
        return
    assert rc == 2 and len(err) == 1 and err[0].startswith("flexgear: error: "), err
    line = err[0]
    named = flag or ("--cache-dir" if OPTIONS[i][0][-1] == "--cache-dir" else "scene")
    assert named in line or FEEDS.get(flag, named) in line, line
    assert any(f in line for f in _value_forms(value)) or (flag in ("--input", "--output") and value in line), line
    for typo, near in NEAREST.items():
        if value.endswith(typo):
            assert f"nearest: {near!r}" in line, line
    assert not out.exists() and os.listdir(tmp_path) == [], os.listdir(tmp_path)


def test_the_table_has_every_option_of_every_subcommand():
    # every option of build_parser that takes a number or a name is crossed above (output
    # folders and --format belong to their own tests; bench passes its arguments on)
    from assembly.app.cli import build_parser
    parser = build_parser()
    crossed = {flag for _, flag, _, _ in OPTIONS} | {"--cache-dir", "--speed-range", "--window"}
    skip = {"--help", "--out", "--format", "--verbose", "--json", "--quiet", "--all", "--log", "--gyroscopic",
            "--unreduced", "--no-compare", "--no-images", "--serial"}

    def options(p):
        for a in p._actions:
            if hasattr(a, "choices") and isinstance(a.choices, dict):
                for sub in a.choices.values():
                    yield from options(sub)
            for s in a.option_strings:
                if s.startswith("--"):
                    yield s
    if not ROSCO:                                       # the coupling command's own flags: not crossed here
        skip |= {flag for _, flag, _, _ in COUPLING_CASES}
    missing = sorted(set(options(parser)) - crossed - skip)
    assert not missing, missing
    assert len(CASES) >= 150, len(CASES)


@pytest.mark.parametrize("flag, value", [("--speed-range", ["nan", "100"]), ("--speed-range", ["100", "0"]),
                                         ("--speed-range", ["0", "1e308"]), ("--speed-range", ["-1", "5"])])
def test_speed_range_entries_are_checked(scene, capsys, flag, value):
    assert main(["campbell", scene, flag, *value]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"flexgear: error: {flag}"), err


@pytest.mark.parametrize("value", [["nan", "5e-4"], ["5e-4", "2e-4"], ["0", "1e308"], ["-1", "5e-4"], ["0", "2e-3"],
                                   ["inf", "1"], ["0", "abc"]])
def test_window_entries_are_checked(scene, tmp_path, capsys, monkeypatch, value):
    # the spectra's window must lie in the record (1 ms here): one line naming --window, nothing written
    monkeypatch.chdir(tmp_path)
    rc = main(["simulate", scene, "--t-end", "1e-3", "--dt", "1e-4", "--output", "force:m", "--window", *value,
               "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "--window" in err[0], err
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("argv, named", [
    (["simulate", S, "--t-end", "1e-3", "--dt", "1e-4", "--speed", "nan"], "--speed = nan"),
    (["simulate", S, "--t-end", "1e308", "--dt", "1e-4"], "--t-end = 1e+308"),
    (["campbell", S, "--speed-range", "0", "100", "--reference", "rotr"], "nearest: 'rotor'"),
    (["study", "planet_count", "--out", "OUT", "--workers", "0"], "--workers = 0"),
])
def test_the_real_program_refuses_in_one_line(scene, tmp_path, argv, named):
    argv = [scene if a == S else str(tmp_path / "out") if a == "OUT" else a for a in argv]
    p = subprocess.run([sys.executable, "-m", "assembly.app.cli", *argv], capture_output=True, text=True,
                       cwd=tmp_path, timeout=120)
    err = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(err) == 1 and named in err[0], (p.returncode, p.stderr)
    assert os.listdir(tmp_path) == []
