"""Band-aware results: modes outside DISPLAY_BAND_FACTOR x band flagged and left out of the
text/HTML tables, ``run --modes`` selections, modal stress scaling and stress image labels."""
import csv
import json
import os
from pathlib import Path
from types import SimpleNamespace

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

import numpy as np
import pytest

from assembly.analysis.modal import solve_modes
from assembly.app.args import parse_modes
from assembly.app.cli import main
from assembly.app.errors import UsageError
from assembly.app.report.pipeline import ModeSelectionError, RunOptions, run_pipeline
from assembly.app.report.tables import in_band, modes_table
from assembly.model.assemble import assemble
from assembly.scene.schema import SCENE_DIR, load_scene
from assembly.scene.tables import DISPLAY_BAND_FACTOR

SHIPPED = SCENE_DIR / "lin_parker_n4.toml"   # rigid planetary stage: 21 modes, no flexible body
SIZE = (320, 240)


@pytest.fixture(scope="module")
def straddling(tmp_path_factory):
    """The stage with band_hz set so that DISPLAY_BAND_FACTOR x band falls midway between
    two of its elastic frequencies (band_hz changes no frequency of a rigid model)."""
    f = np.sort(solve_modes(assemble(load_scene(SHIPPED))).frequencies_hz)
    k = len(f) // 2
    band = float(0.5 * (f[k] + f[k + 1]) / DISPLAY_BAND_FACTOR)
    p = tmp_path_factory.mktemp("band") / "straddle.toml"
    p.write_text(f"band_hz = {band!r}\n" + SHIPPED.read_text())
    return p, band, f, k


def test_modes_outside_the_band_are_flagged_and_left_out_of_the_tables(straddling, tmp_path):
    path, band, f, k = straddling
    res = solve_modes(assemble(load_scene(path)))
    assert list(in_band(res)) == [True] * (k + 1) + [False] * (len(f) - k - 1)
    text = modes_table(res)
    rows = [ln for ln in text.splitlines() if ln[:4].strip().isdigit()]
    assert [int(r.split()[0]) for r in rows] == list(range(1, k + 2))
    assert f"{len(f) - k - 1} modes above {DISPLAY_BAND_FACTOR * band:.0f} Hz" in text
    assert len(modes_table(res, all_modes=True).splitlines()) == len(text.splitlines()) + len(f) - k - 2

    out = tmp_path / "r"
    run_pipeline(str(path), out, RunOptions(n_modes=len(f), images=False, compare=False))
    csv_rows = list(csv.DictReader(open(out / "modes.csv")))      # every mode, flagged
    assert [r["in_band"] for r in csv_rows] == ["1"] * (k + 1) + ["0"] * (len(f) - k - 1)
    data = json.loads((out / "modes.json").read_text())
    assert [m["in_band"] for m in data["modes"]] == [r["in_band"] == "1" for r in csv_rows]
    assert data["band_hz"] == band and data["n_outside_band"] == len(f) - k - 1
    html = (out / "index.html").read_text()
    assert f"band_hz = {band:.0f} Hz" in html and f"{len(f) - k - 1} modes above" in html
    # images (and modal stresses) default to the elastic modes in the band
    man = json.loads((out / "flexgear_run.json").read_text())
    assert "mode-shape images" in man["timings_s"]


def test_parse_modes():
    assert parse_modes("12") == (12, None)
    assert parse_modes("7,9,12-14") == (None, (7, 9, 12, 13, 14))
    assert parse_modes("7,") == (None, (7,))
    for bad in ("7,x", "0,3", "5-3", ",", "-2"):
        with pytest.raises(UsageError):
            parse_modes(bad)


def test_run_modes_selection_draws_those_modes(tmp_path):
    out = tmp_path / "sel"
    ctx = run_pipeline(str(SHIPPED), out, RunOptions(mode_numbers=(7, 9), compare=False, window_size=SIZE))
    assert sorted(p.name for p in (out / "images").glob("mode_*.png")) == ["mode_007.png", "mode_009.png"]
    assert ctx.drawn_modes() == [6, 8]


def test_bad_mode_selections_are_one_line_usage_errors(tmp_path, capsys):
    out = tmp_path / "bad"
    with pytest.raises(ModeSelectionError):
        run_pipeline(str(SHIPPED), out, RunOptions(mode_numbers=(7, 22), images=False, compare=False))
    for sel in ("7,22", "7,x"):
        assert main(["run", str(SHIPPED), "--out", str(out), "--modes", sel, "-q"]) == 2
        err = capsys.readouterr().err
        assert err.startswith("flexgear: error: --modes") and err.count("\n") == 1
    assert not out.exists()


def test_no_images_says_what_it_skipped(tmp_path, capsys):
    out = tmp_path / "noimg"
    assert main(["run", str(SHIPPED), "--out", str(out), "--modes", "2", "--no-images", "--no-compare"]) == 0
    err = [ln for ln in capsys.readouterr().err.splitlines() if "--no-images" in ln]
    assert len(err) == 1 and "2 mode-shape images" in err[0]
    assert ("--no-images: skipped the overview, 2 mode-shape images and 2 mode animations;"
            in (out / "index.html").read_text())


def test_colour_bar_maximum_is_the_title_maximum():
    from assembly.app.render.fe import stress_scale
    from cms.stress import NodalStress, von_mises
    # uniaxial stress s e_x e_x: von Mises = |s| (von Mises 1913); the largest at node 2
    s = np.array([10e6, -30e6, 50e6, 20e6])
    sigma = np.zeros((4, 3, 3))
    sigma[:, 0, 0] = s
    st = NodalStress(sigma, von_mises(sigma), np.zeros((4, 3)), np.eye(4, 3))
    body = SimpleNamespace(origin=np.zeros(3), axes=np.eye(3))
    sc = stress_scale(body, st, "t")
    assert sc["clim"] == (0.0, sc["vmax"]) and sc["vmax"] == pytest.approx(50.0, rel=1e-12)  # MPa
    assert f"max over all nodes {sc['vmax']:.4g} MPa" in sc["text"]
    assert list(sc["point"]) == [0.0, 0.0, 1.0]


@pytest.mark.slow
def test_modal_stress_scaling_and_bodies_without_strain_energy():
    from assembly.analysis.modal_stress import MODAL_PEAK_DISPLACEMENT_M, modal_amplitudes, peak_displacement
    scene = Path(__file__).parent.parent / "support" / "data" / "shaft_torsion.toml"
    res = solve_modes(assemble(load_scene(scene)))
    m = res.model
    i = res.n_rigid                                   # first elastic mode
    a, = modal_amplitudes(res, [i])
    assert peak_displacement(m, a.factor * res.abs_shapes[:, i]) == pytest.approx(MODAL_PEAK_DISPLACEMENT_M,
                                                                                     rel=1e-12)
    assert a.carrier == "shaft" and a.skipped == ()
    # a rigid translation of the shaft strains the springs holding it but not the shaft:
    # rigid motions lie in the null space of a free-free stiffness (Craig & Kurdila 2006,
    # Fundamentals of Structural Dynamics, ch. 14), so the shaft is skipped
    z = np.zeros(m.K_abs.shape[0])
    z[m.body_slice("shaft")] = m.bodies["shaft"].rigid_local[:, 0]
    fake = SimpleNamespace(model=m, abs_shapes=np.column_stack([res.abs_shapes[:, i], z]))
    b, = modal_amplitudes(fake, [1])
    assert b.skipped == ("shaft",) and b.carrier is None
