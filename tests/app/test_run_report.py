"""run_report: the `flexgear run` pipeline from Python, on a Scene object or a file."""
import json

import pytest

from assembly.app import run_report
from assembly.app.output import MANIFEST
from assembly.errors import SceneError
from assembly.scene.schema import load_scene, scene_from_dict


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
    # eigenvalue of K + dK, dK positive semi-definite, is >= that of K for the same M); the
    # rigid-body modes (round-off frequencies, ~1e-4 Hz) are compared by count only
    r = plain.result.n_rigid
    assert ctx.result.n_rigid == r
    assert all(a >= b * (1 - 1e-9) for a, b in zip(ctx.result.frequencies_hz[r:], plain.result.frequencies_hz[r:]))


def test_run_report_refuses_unknown_option(tmp_path):
    with pytest.raises(SceneError, match="n_modes"):
        run_report("lin_parker_n3.toml", tmp_path / "out", modes=3)
    assert not (tmp_path / "out").exists()


def test_report_notes_the_mesh_stiffness_from_iso_6336(tmp_path):
    # two spur gears with teeth on rigid-in-torsion-free bearings, the mesh stiffness left out
    teeth = dict(normal_module=0.004, pressure_angle_deg=20.0, face_width=0.04)
    bearing = dict(k_radial=1e9, k_axial=1e9, k_tilt=1e7)
    scene = scene_from_dict({
        "name": "iso pair",
        "bodies": [{"name": "pinion", "mass": 2.0, "polar_inertia": 2e-3, "teeth": dict(n_teeth=20, **teeth)},
                   {"name": "wheel", "mass": 8.0, "polar_inertia": 3e-2, "teeth": dict(n_teeth=40, **teeth)}],
        "bearings": [dict(body="pinion", **bearing), dict(body="wheel", **bearing)],
        "meshes": [{"gear1": "pinion", "gear2": "wheel", "place": "gear2"}]})
    ctx = run_report(scene, tmp_path / "out", n_modes=2, images=False, compare=False)
    k = scene.meshes[0].stiffness
    note = next(n for n in ctx.notes if "ISO 6336-1" in n)
    assert f"meshes[0].stiffness = {k:.4g} N/m" in note
    assert "ISO 6336-1" in (tmp_path / "out" / "index.html").read_text()
