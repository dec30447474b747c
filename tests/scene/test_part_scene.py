"""The shipped example with a user's CAD carrier (planetary_step_carrier.toml): the STEP
carrier reduced and coupled into the Lin & Parker stage, checked against its CAD and its
unreduced FE model, and the scene's file path rules."""
from __future__ import annotations

import math
import shutil

import numpy as np
import pytest

from assembly import assemble, load_scene, solve_modes
from assembly.errors import SceneError
from assembly.scene.schema import SCENE_DIR
from fe_components.part.file import PartFile
from fe_components.part.read import part_geometry

pytestmark = pytest.mark.slow   # meshes and reduces the carrier (about 15 s cold)

SCENE = SCENE_DIR / "planetary_step_carrier.toml"
N_CMP = 12


@pytest.fixture(scope="module")
def scene():
    return load_scene(SCENE)


@pytest.fixture(scope="module")
def reduced(scene):
    return solve_modes(assemble(scene), n_modes=40)


def test_the_file_path_is_relative_to_the_scene(scene):
    comp = scene.stages[0].carrier.component
    assert isinstance(comp, PartFile)
    assert comp.path == SCENE_DIR / "parts" / "carrier_windows.step"


def test_carrier_mass_and_pins_come_from_the_cad(scene):
    """The carrier body's mass is the CAD solid's (steel, 7850 kg/m^3) to 1e-3, and each
    pin master sits at its planet's centre on the carrier radius (r_s + r_p) / cos(alpha)."""
    model = assemble(scene)
    carrier = model.bodies["stage.carrier"]
    geo = part_geometry(scene.stages[0].carrier.component)
    assert abs(carrier.mass - 7850.0 * geo.volume) / carrier.mass < 1e-3
    st = scene.stages[0]
    Rc = (0.0387 + 0.0502) / math.cos(math.radians(24.6))     # Lin & Parker base radii, alpha = 24.6 deg
    assert st.carrier_radius() == pytest.approx(Rc, rel=1e-12)
    for n, psi in enumerate(st.planet_angles()):
        pos, _ = carrier.masters[f"pin_{n}"]
        assert np.allclose(pos, [Rc * math.cos(psi), Rc * math.sin(psi), 0.0], atol=1e-9)


def test_reduced_stage_has_the_spin_and_checks_itself(reduced):
    """The carrier's bearing leaves the stage's spin free (one rigid-body mode: sun, carrier
    and ring torsionally free to the housing except the ring's torsion spring, which holds
    the ring only), and every mode's eigen-residual is small."""
    assert reduced.n_rigid == 1
    assert reduced.max_residual < 1e-8


def test_reduced_against_the_unreduced_fe_model(scene, reduced):
    """Craig-Bampton (cutoff 1.5 x band, residual vectors) against every FE DOF of the
    carrier kept: the in-band coupled frequencies bound the full model's from above (Ritz)
    and agree to 1e-3 (the convergence study of docs/benchmarks.md gives < 1e-4 % for the
    built-in carrier at this cutoff)."""
    full = solve_modes(assemble(scene, full_fe=True), n_modes=N_CMP + 4)
    f_full = full.frequencies_hz[full.n_rigid:full.n_rigid + N_CMP]
    f_red = reduced.frequencies_hz[reduced.n_rigid:reduced.n_rigid + N_CMP]
    assert np.all(f_red >= f_full * (1 - 1e-8))
    assert np.max(f_red / f_full - 1) < 1e-3


def test_moving_the_part_file_keeps_working(tmp_path):
    """The scene and its part copied elsewhere: the relative path follows the scene file."""
    (tmp_path / "parts").mkdir()
    shutil.copy(SCENE, tmp_path / SCENE.name)
    shutil.copy(SCENE_DIR / "parts" / "carrier_windows.step", tmp_path / "parts")
    moved = load_scene(tmp_path / SCENE.name)
    assert moved.stages[0].carrier.component.path == tmp_path / "parts" / "carrier_windows.step"
    assert moved.stages[0].carrier.component.content_sha256 == \
        load_scene(SCENE).stages[0].carrier.component.content_sha256


def test_a_missing_part_file_names_its_scene_path(tmp_path):
    shutil.copy(SCENE, tmp_path / SCENE.name)
    with pytest.raises(SceneError) as exc:
        load_scene(tmp_path / SCENE.name)
    assert exc.value.path == "stages[0].carrier.component.file"
    assert "carrier_windows.step" in str(exc.value) and "cannot read" in str(exc.value)


def test_run_draws_the_step_carrier(tmp_path):
    """flexgear run on the example: mode-shape and stress images of the user's carrier (the
    load case and each mode), all referenced from index.html."""
    from PIL import Image

    from assembly.app.cli import main
    from assembly.app.report.html import missing_references
    out = tmp_path / "out"
    assert main(["run", str(SCENE), "--out", str(out), "--quiet", "--modes", "2"]) == 0
    imgs = sorted(p.name for p in (out / "images").glob("stress_*.png"))
    assert imgs == ["stress_stage.carrier_load.png", "stress_stage.carrier_mode_002.png",
                    "stress_stage.carrier_mode_003.png"]
    assert (out / "images" / "mode_002.png").exists()
    a = np.asarray(Image.open(out / "images" / imgs[1]).convert("L"), float)
    assert a.std() > 5                     # a picture, not a blank frame
    assert missing_references(out / "index.html") == []
