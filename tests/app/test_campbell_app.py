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


def test_out_writes_the_safe_diagram_its_table_and_page(scene, tmp_path):
    # one planetary stage ("planetary", Z_s = 20, N = 4: every harmonic at k = 0)
    from assembly.app.report.html import missing_references
    out = tmp_path / "cb"
    assert main(["campbell", scene, "--speed-range", "0", "3000", "--out", str(out), "-q"]) == 0
    png = (out / "safe_planetary.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10_000
    rows = list(csv.DictReader(open(out / "safe.csv")))
    (safe,) = json.loads((out / "campbell.json").read_text())["safe"]
    assert len(rows) == len(safe["crossings"]) > 0 and {r["stage"] for r in rows} == {"planetary"}
    assert {r["index_k"] for r in rows} == {"0"} and {e["index"] for e in safe["excitations"]} == {0}
    hits = [r for r in rows if r["safe"] == "interference"]
    assert hits and all(r["class"] == "rotational" and r["campbell_excitable"] == "yes" for r in hits)
    page = (out / "index.html").read_text()
    assert "safe_planetary.png" in page and "SAFE" in page and missing_references(out / "index.html") == []
    manifest = json.loads((out / "flexgear_run.json").read_text())
    assert "safe_planetary.png" in manifest["files"] and "safe.csv" in manifest["files"]


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


def test_order_labels_at_the_right_edge_are_spread_apart_in_order():
    """spread_labels: labels closer than the gap move apart to exactly the gap, keep their
    order, stay inside the axis [0, 1]; labels already apart do not move."""
    import numpy as np

    from assembly.app.plots import spread_labels

    apart = np.array([0.1, 0.5, 0.9])
    assert np.array_equal(spread_labels(apart, 0.02), apart)
    y = np.array([0.30, 0.30, 0.305, 0.99, 1.0, 0.0])
    out = spread_labels(y, 0.05)
    order = np.argsort(y, kind="stable")
    assert np.all(np.diff(out[order]) >= 0.05 - 1e-12)        # apart by the gap, in the same order
    assert out.min() >= -1e-12 and out.max() <= 1.0 + 1e-12   # inside the axis
    assert out[5] == 0.0 and out[0] == 0.30 and out[1] == pytest.approx(0.35)   # the lowest stay
