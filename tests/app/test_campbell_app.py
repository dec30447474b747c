"""``flexgear campbell``: files written, one JSON object, and bad input as one line with exit 2."""
from __future__ import annotations

import csv
import json

import pytest

from assembly.app.cli import main
from assembly.app.report.links import folder_problems
from tests.support.campbell_scene import campbell_scene


@pytest.fixture()
def scene(tmp_path):
    p = tmp_path / "pair_planetary.toml"
    p.write_text(campbell_scene())
    return str(p)


def test_out_writes_image_table_and_json(scene, tmp_path, capsys):
    out = tmp_path / "cb"
    assert main(["campbell", scene, "--speed-range", "0", "3000", "--rated-rpm", "1500", "--out", str(out)]) == 0
    png = (out / "campbell.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10_000
    rows = list(csv.DictReader(open(out / "crossings.csv")))
    data = json.loads((out / "campbell.json").read_text())
    assert len(rows) == len(data["crossings"]) > 0
    assert {r["excitable"] for r in rows} >= {"yes", "no"}       # Z_s = 20, N = 4: some ruled out
    assert data["rated_rpm"] == 1500.0 and data["units"] == {"speed": "rpm", "frequency": "Hz"}
    assert "crossings" in capsys.readouterr().out
    assert folder_problems(out) == []      # index.html: the shared style, the navigation, every link and anchor


def test_json_prints_one_object(scene, capsys):
    assert main(["campbell", scene, "--speed-range", "0", "500", "--json", "--gyroscopic", "--points", "3"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["gyroscopic"] and len(data["frequencies_hz"]) == 3 and data["reference"] == "pinion"


HELD = """
name = "held"
[[bodies]]
name = "disc"
mass = 1.0
polar_inertia = 1.0
role = "rotor"
[[bearings]]
body = "disc"
k_radial = 1.0e8
k_axial = 1.0e8
k_tilt = 1.0e5
k_torsion = 1.0e5
"""


@pytest.mark.parametrize("args, named", [
    (["--speed-range", "100", "10"], "--speed-range"),
    (["--speed-range", "-5", "10"], "--speed-range"),
    (["--speed-range", "0", "10", "--reference", "nope"], "--reference"),
    (["--speed-range", "0", "10", "--points", "1"], "--points"),
    (["--speed-range", "0", "10", "--rated-rpm", "-1"], "--rated-rpm"),
    (["--speed-range", "0", "10", "HELD"], "SCENE"),
])
def test_bad_input_is_one_line_exit_2(scene, tmp_path, capsys, args, named):
    if "HELD" in args:
        held = tmp_path / "held.toml"
        held.write_text(HELD)
        args = [a for a in args if a != "HELD"]
        scene = str(held)
    assert main(["campbell", scene, *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"flexgear: error: {named}")
