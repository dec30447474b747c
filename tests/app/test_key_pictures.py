"""Key pictures of a run: overview with one label per stage, the global torsional mode, a
stage-local mode (fixed file names, docs/output.md). Rigid scenes only (fast)."""
import os

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

import numpy as np
import pytest

from assembly import assemble, classify_modes, load_scene, solve_modes
from assembly.app.render.renderer import AssemblyRenderer
from assembly.app.render.shafts import hermite_centreline
from assembly.app.render.shapes import body_shapes, pitch_radii
from assembly.app.render.twist import referred_angles
from assembly.app.report.key_modes import global_torsional_mode, stage_local_mode
from assembly.app.report.pipeline import RunOptions, run_pipeline

SIZE = (480, 360)


@pytest.fixture(scope="module")
def nrel():
    sc = load_scene("nrel5mw.toml")
    m = assemble(sc)
    r = solve_modes(m)
    return sc, m, r, classify_modes(r)


def test_run_writes_the_named_pictures(tmp_path):
    # two_stage_quill: a helical parallel stage driving a planetary stage through a quill;
    # unheld, so its first elastic mode twists the whole chain (global, rotational).
    ctx = run_pipeline("two_stage_quill.toml", tmp_path / "out", RunOptions(n_modes=1, compare=False,
                                                                            window_size=SIZE))
    for rel in ("images/overview.png", "images/global_torsional.png", "images/stage_local.png"):
        assert (tmp_path / "out" / rel).is_file(), rel
    html = (tmp_path / "out" / "index.html").read_text()
    # shown first: before the mode table
    assert html.index("images/global_torsional.png") < html.index("Natural frequencies and mode table")
    assert [rel for rel, _ in ctx.key_images] == ["images/overview.png", "images/global_torsional.png",
                                                  "images/stage_local.png"]


def test_global_torsional_is_the_lowest_rotational_global_mode(nrel):
    # By construction the free drivetrain's lowest torsional mode is the rotor (3.9e7 kg m^2)
    # against the generator (534 kg m^2 x 96.35^2 = 5.0e6 kg m^2 on the rotor side) through
    # the main shaft: the chain's only rigid-body mode removed, the two-inertia mode is the
    # lowest rotational global one; every lower elastic mode is held by one stage.
    sc, m, r, infos = nrel
    i = global_torsional_mode(infos, r.n_rigid)
    mi = infos[i]
    assert mi.mode_class == "rotational" and mi.scope == "global"
    lower = [x for x in infos[r.n_rigid:i]]
    assert all(not (x.mode_class == "rotational" and x.scope == "global") for x in lower)
    assert {b for b, _ in mi.dominant_bodies} == {"generator", "rotor"}
    # Two inertias on a spring: the referred angles of rotor and generator are opposite (zero
    # net angular momentum of a free two-mass mode).
    angles, ref = referred_angles(m, r.abs_shapes[:, i])
    assert ref == "rotor" and np.sign(angles["rotor"]) == -np.sign(angles["generator"])


def test_stage_local_mode_is_held_by_a_planetary_stage(nrel):
    sc, m, r, infos = nrel
    i = stage_local_mode(infos, r.n_rigid, m.scene)
    mi = infos[i]
    assert mi.scope in ("stage1", "stage2") and mi.mode_class in ("rotational", "translational")
    assert all(not (x.scope in ("stage1", "stage2") and x.mode_class in ("rotational", "translational"))
               for x in infos[r.n_rigid:i])


def test_overview_has_one_label_per_stage_and_a_capped_rotor(nrel, tmp_path):
    sc, m, r, infos = nrel
    rnd = AssemblyRenderer(m, window_size=SIZE)
    rnd.render_overview(tmp_path / "ov.png")
    stages = {b.stage for b in m.scene.bodies}
    assert len(rnd.labels_drawn) == len(stages) == 5
    shapes = body_shapes(m)
    rotor = shapes["rotor"]
    # sqrt(2 J / m) of the lumped rotor: sqrt(2 x 38759236 / 110000) = 26.55 m, capped at the
    # largest pitch radius, the stage-1 ring's: at least its base radius 56 x 0.045 m x cos 20 deg / 2
    # = 1.184 m, and below the NREL 5 MW hub radius 1.5 m (Jonkman et al. 2009, hub diameter 3 m).
    assert rotor.equivalent_radius == pytest.approx(np.sqrt(2 * 38759236.0 / 110000.0), rel=1e-9)
    assert rotor.r_outer == max(abs(v) for v in pitch_radii(m.scene).values())
    assert 56 * 0.045 * np.cos(np.radians(20.0)) / 2 <= rotor.r_outer < 1.5


def test_hermite_centreline_follows_a_rigid_rotation():
    # A rigid rotation theta about z at node a moves the point at distance L on x by
    # theta x (L e_x) = theta L e_y; Hermite reproduces a rigid motion exactly (cubic basis).
    L, th = 2.0, 1e-3
    a, b = np.zeros(3), np.array([L, 0.0, 0.0])
    ma = np.array([0, 0, 0, 0, 0, th])
    mb = np.array([0, th * L, 0, 0, 0, th])
    P, w = hermite_centreline(a, b, ma, mb, n=5)
    assert np.allclose(w[:, 1], th * P[:, 0], rtol=0, atol=1e-15)
    assert np.allclose(w[:, [0, 2]], 0.0)
