"""run_report: the `flexgear run` pipeline from Python, on a Scene object or a file."""
import json

import pytest

from assembly.app import run_report
from assembly.app.output import MANIFEST
from assembly.schema import load_scene


def test_run_report_on_an_edited_scene_object(tmp_path):
    # k_torsion of the ring's bearing x 4 (a design-study change made in Python, never saved)
    scene = load_scene("lin_parker_n3.toml")
    k = scene.get_value("stages.stage.ring.bearing.k_torsion")
    edited = scene.with_value("stages.stage.ring.bearing.k_torsion", 4 * k)
    ctx = run_report(edited, tmp_path / "out", n_modes=2, images=False)
    assert ctx.scene is edited and ctx.out_dir == (tmp_path / "out").absolute()
    manifest = json.loads((tmp_path / "out" / MANIFEST).read_text())
    assert "Python scene object" in manifest["scene_source"]
    assert (tmp_path / "out" / "modes.csv").exists() and (tmp_path / "out" / "index.html").exists()
    # the same scene from its file gives the same frequencies as the object
    plain = run_report("lin_parker_n3.toml", tmp_path / "plain", n_modes=2, images=False, compare=False)
    assert plain.scene == scene
    assert ctx.result.frequencies_hz.shape == plain.result.frequencies_hz.shape
    # a stiffer ring mount cannot lower any frequency (Courant-Fischer min-max: the k-th
    # eigenvalue of K + dK, dK positive semi-definite, is >= that of K for the same M)
    assert all(a >= b * (1 - 1e-9) for a, b in zip(ctx.result.frequencies_hz, plain.result.frequencies_hz))


def test_run_report_refuses_unknown_option(tmp_path):
    with pytest.raises(TypeError, match="n_modes"):
        run_report("lin_parker_n3.toml", tmp_path / "out", modes=3)
    assert not (tmp_path / "out").exists()
