"""A ``modes`` study follows modes by shape: a column is one mode across the variants, with its
class, through a crossing where the sorted columns swap; modes kept by class or band.

Scene: two torsional bodies, each on its own torsion spring to the housing, not joined -- two
decoupled oscillators f = sqrt(k / J) / 2 pi (Rao, Mechanical Vibrations, sec. 2.2): a (J = 1e-3)
on k_a swept 5e3 -> 2e4 N m/rad, b (J = 2e-3) on 2e4: f_b = 503.3 Hz, met by f_a at k_a = 1e4.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.app.report.links import folder_problems, read_page
from assembly.app.study.engine import run_study
from assembly.app.study.file import read_study
from assembly.errors import SceneError

SCENE = """
name = "two oscillators"
fidelity = "torsional"
[[bodies]]
name = "a"
mass = 1.0
polar_inertia = 1.0e-3
[[bodies]]
name = "b"
mass = 1.0
polar_inertia = 2.0e-3
position = [1.0, 0.0, 0.0]
[[bearings]]
body = "a"
k_radial = 1.0e8
k_axial = 1.0e8
k_tilt = 1.0e5
k_torsion = 5.0e3
[[bearings]]
body = "b"
k_radial = 1.0e8
k_axial = 1.0e8
k_tilt = 1.0e5
k_torsion = 2.0e4
"""
STUDY = """
scene = "osc.toml"
analysis = "modes"
[keep]
modes = 2
{keep}
[[parameters]]
path = "bearings[0].k_torsion"
values = [5.0e3, 7.5e3, 1.0e4, 1.25e4, 1.5e4, 2.0e4]
"""


def _rows(tmp_path, keep: str = ""):
    (tmp_path / "osc.toml").write_text(SCENE, encoding="utf-8")
    (tmp_path / "study.toml").write_text(STUDY.format(keep=keep), encoding="utf-8")
    return run_study(read_study(str(tmp_path / "study.toml")), "serial")


def test_a_column_follows_one_mode_through_the_crossing(tmp_path):
    rows = _rows(tmp_path)
    k = np.array([r["bearings[0].k_torsion"] for r in rows])
    f_a = np.sqrt(k / 1e-3) / (2 * math.pi)
    f_b = math.sqrt(2e4 / 2e-3) / (2 * math.pi)
    # the first variant's mode 1 is a's (355.9 Hz), mode 2 b's: each column stays on its body
    col_a = [c for c in rows[0] if c.startswith("mode1_hz[")][0]
    col_b = [c for c in rows[0] if c.startswith("mode2_hz[")][0]
    assert [r[col_a] for r in rows] == pytest.approx(f_a, rel=1e-9)
    assert [r[col_b] for r in rows] == pytest.approx([f_b] * len(rows), rel=1e-9)
    assert all(r[col_a.replace("_hz", "_mac")] > 0.999 for r in rows)
    # the sorted columns swap past the crossing (k_a > 1e4): f1 is then b's
    assert rows[-1]["f1_hz"] == pytest.approx(f_b, rel=1e-9) and rows[-1][col_a] == pytest.approx(f_a[-1], rel=1e-9)


def test_modes_kept_by_band(tmp_path):
    # the first variant's band 400-600 Hz holds b's mode alone (a's is 355.9 Hz there)
    rows = _rows(tmp_path, "band_hz = [400.0, 600.0]")
    cols = [c for c in rows[0] if c.startswith("mode") and "_hz[" in c]
    assert cols == [c for c in cols if c.startswith("mode2_hz[")] and len(cols) == 1


@pytest.mark.parametrize("keep,field", [("band_hz = [600.0, 400.0]", "keep.band_hz"),
                                        ("band_hz = [1.0e5, 2.0e5]", "keep.band_hz"),
                                        ('classes = ["no such class"]', "keep.classes[0]"),
                                        ('classes = ["planet", "rotatonal"]', "keep.classes[1]"),
                                        ("classes = []", "keep.classes"),
                                        ("track = false\nband_hz = [1.0, 2.0]", "keep.track"),
                                        ('track = "yes"', "keep.track")])
def test_what_cannot_be_followed_is_refused_before_it_runs(tmp_path, keep, field):
    with pytest.raises(SceneError) as e:
        _rows(tmp_path, keep)
    assert e.value.path == field


def test_sensitivity_of_a_power_law_is_its_exponent(tmp_path):
    # f_a = sqrt(k_a / J) / 2 pi: d ln f_a / d ln k_a = 1/2 exactly; f_b does not depend on k_a: 0
    from assembly.app.study.sensitivity import sensitivities
    rows = _rows(tmp_path)
    col_a = [c for c in rows[0] if c.startswith("mode1_hz[")][0]
    col_b = [c for c in rows[0] if c.startswith("mode2_hz[")][0]
    (a, b) = sensitivities(rows, ["bearings[0].k_torsion"], [col_a, col_b])
    assert a["elasticity"]["bearings[0].k_torsion"] == pytest.approx(0.5, abs=1e-9)
    assert a["r2"] == pytest.approx(1.0, abs=1e-9)
    assert b["elasticity"]["bearings[0].k_torsion"] == pytest.approx(0.0, abs=1e-9)


def test_the_study_folder_has_its_sensitivity_table(tmp_path):
    import csv

    from assembly.app.cli import main
    _rows(tmp_path)                                       # writes the scene and the study
    assert main(["study", str(tmp_path / "study.toml"), "--out", str(tmp_path / "out"), "-q", "--serial"]) == 0
    table = {r["result"]: r for r in csv.DictReader(open(tmp_path / "out" / "sensitivity.csv", encoding="utf-8"))}
    col_a = [c for c in table if c.startswith("mode1_hz[")][0]
    assert float(table[col_a]["dln/dln[bearings[0].k_torsion]"]) == pytest.approx(0.5, abs=1e-6)
    assert "Sensitivities" in (tmp_path / "out" / "index.html").read_text(encoding="utf-8")
    assert "#s-sensitivities" in read_page((tmp_path / "out" / "index.html").read_text(encoding="utf-8")).nav
    assert folder_problems(tmp_path / "out") == []     # the shared style, the navigation, links and anchors


def test_a_two_parameter_study_draws_its_results_over_both(tmp_path):
    from assembly.app.cli import main
    (tmp_path / "osc.toml").write_text(SCENE, encoding="utf-8")
    (tmp_path / "study.toml").write_text(STUDY.format(keep="") + """
[[parameters]]
path = "bearings[1].k_torsion"
values = [1.5e4, 2.5e4]                 # b: 435.9, 562.7 Hz; not repeated with a in the first variant
""", encoding="utf-8")
    out = tmp_path / "out"
    assert main(["study", str(tmp_path / "study.toml"), "--out", str(out), "-q", "--serial"]) == 0
    names = {p.name for p in out.iterdir()}
    assert any(n.startswith("mode1_hz") and n.endswith("_map.png") for n in names), names
    assert any(n.startswith("tracked_modes_vs_") for n in names)
    assert not any("_mac" in n for n in names)                  # MACs are in the table, not drawn


def test_a_partner_below_the_mac_threshold_is_no_longer_that_mode(tmp_path):
    """Lin & Parker's planet bearings swept over five decades reshape the modes: where the
    base mode's best partner has MAC below MAC_THRESHOLD the frequency cell stays empty (the
    MAC cell says why); above it the frequency is given."""
    from assembly.analysis.tracking import MAC_THRESHOLD

    (tmp_path / "s.toml").write_text('name = "wide"\nscene = "lin_parker_n4.toml"\nanalysis = "modes"\n'
                                     "[keep]\nmodes = 6\n[[parameters]]\n"
                                     'path = "stages[0].planets.bearing.k_radial"\nlog_range = [1.0e6, 1.0e11, 6]\n',
                                     encoding="utf-8")
    rows = run_study(read_study(str(tmp_path / "s.toml")), "serial")
    macs = [(r, k) for r in rows for k in r if "_mac[" in k]
    assert any(r[k] < MAC_THRESHOLD for r, k in macs)        # the sweep does lose modes
    for r, k in macs:
        assert 0.0 <= r[k] <= 1.0
        hz = k.replace("_mac[", "_hz[")
        assert (r.get(hz) is not None) == (r[k] >= MAC_THRESHOLD)


def test_collinear_parameters_and_mac_columns_have_no_sensitivity():
    """f = k^(1/2): with m = 2 k (or m = k^2) beside k, any split of the slope between them
    fits (rank-deficient): no elasticity is given; with m independent, f = k^(1/2) m^(-1/2)
    gives 1/2 and -1/2 (exact power law, to 1e-9); a MAC column gets no row."""
    from assembly.app.study.sensitivity import sensitivities

    ks = [1.0, 2.0, 4.0, 8.0, 16.0]
    for m_of in (lambda k: 2.0 * k, lambda k: k * k):
        rows = [{"status": "ok", "k": k, "m": m_of(k), "f": k ** 0.5} for k in ks]
        (row,) = sensitivities(rows, ["k", "m"], ["f"])
        assert row["elasticity"] == {"k": None, "m": None}
    rows = [{"status": "ok", "k": k, "m": m, "f": (k / m) ** 0.5, "mode1_mac[rotational]": 0.9 + 0.01 * k}
            for k in ks for m in (1.0, 3.0)]
    table = sensitivities(rows, ["k", "m"], ["f", "mode1_mac[rotational]", "n_rigid"])
    assert [t["result"] for t in table] == ["f"]
    assert table[0]["elasticity"]["k"] == pytest.approx(0.5, abs=1e-9)
    assert table[0]["elasticity"]["m"] == pytest.approx(-0.5, abs=1e-9)
