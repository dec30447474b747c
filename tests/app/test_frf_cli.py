"""``flexgear frf``: JSON object, output folder, bad input in one line with exit code 2.

The scene is two inertias J1 = 2, J2 = 3 kg m^2 on a torsional shaft k = 1e4 N m/rad with a
damper c = 30 N m s/rad, free otherwise; torque on J1. Closed form of the shaft torque per
unit input torque (see tests/dynamics/test_frf.py): with z = k + i w c,
T_s / T = J2 z / (z (J1 + J2) - w^2 J1 J2).
"""
from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

from assembly.app.cli import main
from assembly.app.report.links import folder_problems

J1, J2, K, C = 2.0, 3.0, 1.0e4, 30.0

SCENE = f"""
name = "two inertias"

[[bodies]]
name = "a"
mass = 10.0
polar_inertia = {J1}

[[bodies]]
name = "b"
mass = 10.0
polar_inertia = {J2}
position = [0.0, 0.0, 1.0]

[[bearings]]
body = "a"
k_radial = inf
k_axial = inf
k_tilt = inf

[[bearings]]
body = "b"
k_radial = inf
k_axial = inf
k_tilt = inf

[[shafts]]
name = "s"
body1 = "a"
body2 = "b"
k_torsion = {K}
c_torsion = {C}
"""


@pytest.fixture
def scene(tmp_path):
    p = tmp_path / "two.toml"
    p.write_text(SCENE)
    return str(p)


def _closed(f):
    w = 2 * np.pi * np.asarray(f)
    z = K + 1j * w * C
    return J2 * z / (z * (J1 + J2) - w ** 2 * J1 * J2)


def test_json_prints_one_object(scene, capsys):
    assert main(["frf", scene, "--input", "torque:a", "--output", "torque:s", "--output", "motion:b:rz",
                 "--fmin", "1", "--fmax", "50", "--points", "7", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    f = np.array(data["frequency_hz"])
    assert f.tolist() == np.linspace(1.0, 50.0, 7).tolist()
    assert set(data["outputs"]) == {"torque:s", "motion:b:rz"}
    want = _closed(f)
    got = data["outputs"]["torque:s"]
    assert np.allclose(got["magnitude"], np.abs(want), rtol=1e-9, atol=0)
    assert np.allclose(got["phase_deg"], np.degrees(np.angle(want)), rtol=0, atol=1e-7)
    assert data["units"]["torque:s"] == "N m/(N m)" and data["units"]["frequency"] == "Hz"
    assert data["natural_hz"] == pytest.approx([math.sqrt(K * (J1 + J2) / (J1 * J2)) / (2 * math.pi)], rel=1e-9)


def test_out_writes_csv_json_plots_index(scene, tmp_path, capsys):
    out = tmp_path / "res"
    assert main(["frf", scene, "--input", "torque:a", "--output", "torque:s", "--output", "motion:a:spin",
                 "--fmin", "0.5", "--fmax", "100", "--points", "50", "--log", "--out", str(out)]) == 0
    names = {p.name for p in out.iterdir()}
    assert {"frf.csv", "frf.json", "bode_01.png", "bode_02.png", "index.html"} <= names
    rows = list(csv.reader(open(out / "frf.csv")))
    assert len(rows) == 51 and rows[0][0] == "frequency_hz" and len(rows[0]) == 1 + 2 * 4
    f = float(rows[1][0])
    assert float(rows[1][3]) == pytest.approx(abs(_closed(f)), rel=1e-8)     # magnitude column of torque:s
    assert "bode_02.png" in (out / "index.html").read_text()
    assert folder_problems(out) == []      # the shared style, the navigation, every link and anchor
    assert json.loads((out / "frf.json").read_text())["input"] == "torque:a"
    assert "index.html" in capsys.readouterr().out


@pytest.mark.parametrize("args,named", [
    (["--input", "torque:nobody", "--output", "torque:s"], "--input"),
    (["--input", "torque:a", "--output", "force:nomesh"], "--output"),
    (["--input", "torque:a", "--output", "torque:s", "--fmin", "10", "--fmax", "10"], "--fmax"),
    (["--input", "torque:a", "--output", "torque:s", "--fmin", "-1"], "--fmin"),
    (["--input", "torque:a", "--output", "torque:s", "--points", "1"], "--points"),
    (["--input", "torque:a", "--output", "torque:s", "--fmin", "0", "--log"], "--fmin"),
    (["--input", "torque:a", "--output", "torque:s", "--fmin", "0"], "frequency_hz"),
    (["--input", "torque:a", "--output", "torque:s", "--modes-hz", "0"], "--modes-hz"),
    (["--input", "torque:a", "--output", "torque:s", "--modes-hz", "-5"], "--modes-hz"),
    (["--input", "torque:a", "--output", "stress:a:0,0,0"], "--output"),
    (["--input", "mesh:nomesh", "--output", "torque:s"], "--input"),
    (["--input", "torque:a", "--output", "torque:s", "--method", "exact"], "--method"),
])
def test_bad_input_is_one_line_exit_2(scene, tmp_path, capsys, args, named):
    out = tmp_path / "never"
    assert main(["frf", scene, *args, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("flexgear: error:") and named in err[0]
    assert not out.exists()


def test_documented_command_runs(tmp_path, capsys):
    # the first command of docs/frf.md (rigid 5 MW scene), as written, into a temporary folder
    import re
    import shlex
    from pathlib import Path

    doc = (Path(__file__).resolve().parents[2] / "docs" / "frf.md").read_text(encoding="utf-8")
    block = re.search(r"```sh\n(.*?)```", doc, re.DOTALL).group(1)
    first = block.replace("\\\n", " ").splitlines()[0]
    argv = shlex.split(first)[1:]                                     # drop .venv/bin/flexgear
    assert argv[:2] == ["frf", "nrel5mw"]
    argv[argv.index("--out") + 1] = str(tmp_path / "frf")
    assert main(argv) == 0
    data = json.loads((tmp_path / "frf" / "frf.json").read_text())
    assert set(data["outputs"]) == {"torque:ls_shaft", "force:stage1.sun-planet0"}
    assert len(data["frequency_hz"]) == 4000 and data["units"]["torque:ls_shaft"] == "N m/(N m)"
