"""Mode-shape images (pyvista off-screen): size, not blank, deterministic, mode-dependent.

Blank-frame floor: the central band of the image (rows 15-85 %) holds only the drawn
assembly; the title sits above it and the scale bar / colour bar below. A frame without
bodies is plain white there (standard deviation 0). Measured images of the shipped scenes
have a grey-level standard deviation of 75-95 (0-255 scale) and 25-35 % non-white pixels
in that band; the floors (20 grey levels, 5 % non-white) lie far below the real images and
far above an empty frame.
"""
import os

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

import numpy as np
import pytest

from assembly import assemble, classify_modes, load_scene, solve_modes
from assembly.app.render.renderer import AssemblyRenderer, mode_title
from assembly.app.render.shapes import body_shapes, pitch_radii, rigid_displacement
from assembly.app.render.springs import spring_glyphs

SIZE = (480, 360)
STD_FLOOR = 20.0 / 255
NONWHITE_FLOOR = 0.05


def _read(path):
    import matplotlib.image as mpimg

    return mpimg.imread(str(path))[..., :3]


def _central(a):
    h = a.shape[0]
    return a[int(0.15 * h):int(0.85 * h)]


@pytest.fixture(scope="module")
def planetary():
    sc = load_scene("lin_parker_n4.toml")
    m = assemble(sc)
    r = solve_modes(m)
    return sc, m, r, classify_modes(r), AssemblyRenderer(m, window_size=SIZE)


def test_mode_images_size_not_blank_and_mode_dependent(planetary, tmp_path):
    sc, m, r, infos, rnd = planetary
    i1, i2 = r.n_rigid, r.n_rigid + 5   # translational pair vs a different class
    p1 = rnd.render_mode(r, i1, tmp_path / "a.png", title=mode_title(sc.name, infos[i1]))
    p2 = rnd.render_mode(r, i2, tmp_path / "b.png", title=mode_title(sc.name, infos[i2]))
    a, b = _read(p1), _read(p2)
    assert a.shape == b.shape == (SIZE[1], SIZE[0], 3)
    for img in (a, b):
        c = _central(img)
        assert c.std() > STD_FLOOR
        assert (c.min(axis=2) < 0.9).mean() > NONWHITE_FLOOR
    # A different mode gives a visibly different picture (not just a different title).
    assert np.abs(_central(a) - _central(b)).mean() > 0.01


def test_images_are_deterministic(planetary, tmp_path):
    sc, m, r, infos, rnd = planetary
    i = r.n_rigid + 2
    p1 = rnd.render_mode(r, i, tmp_path / "1.png", title="t")
    p2 = AssemblyRenderer(m, window_size=SIZE).render_mode(r, i, tmp_path / "2.png", title="t")
    assert np.array_equal(_read(p1), _read(p2))


def test_overview_and_torsional_scene(tmp_path):
    sc = load_scene("peeters_parallel_torsional.toml")
    m = assemble(sc)
    r = solve_modes(m)
    rnd = AssemblyRenderer(m, window_size=SIZE)
    ov = _read(rnd.render_overview(tmp_path / "ov.png", title=sc.name))
    md = _read(rnd.render_mode(r, 1, tmp_path / "m.png", title="mode 2"))
    for img in (ov, md):
        assert img.shape == (SIZE[1], SIZE[0], 3)
        assert _central(img).std() > STD_FLOOR


def test_geometry_rules():
    sc = load_scene("lin_parker_n4.toml")
    m = assemble(sc)
    shapes = body_shapes(m)
    rp = pitch_radii(m.scene)
    # Gears drawn at their pitch radius |r_b| / cos(alpha); the ring is an annulus.
    assert shapes["stage.sun"].r_outer == pytest.approx(0.0387 / np.cos(np.radians(24.6)))
    assert shapes["stage.ring"].kind == "ring" and rp["stage.ring"] < 0
    assert shapes["stage.ring"].r_inner == pytest.approx(0.1391 / np.cos(np.radians(24.6)))
    # The carrier carries the planets: a plate behind them, equivalent radius sqrt(2 J / m).
    car = shapes["stage.carrier"]
    assert car.kind == "plate"
    assert car.r_outer == pytest.approx(np.sqrt(2 * 6.013133110841227e-2 / 5.43))
    assert car.axial_offset + car.width / 2 < shapes["stage.planet0"].axial_offset - shapes["stage.planet0"].width / 2
    glyphs = spring_glyphs(m, shapes)
    assert len(glyphs) == len(m.elements)
    assert sum(g.ground for g in glyphs) == 3   # sun, ring, carrier bearings to the housing


def test_width_from_transverse_inertia():
    from assembly.app.render.shapes import width_from_inertia
    from assembly.scene.tables import Body

    r, L, mass = 0.05, 0.08, 3.0
    jp = mass * r ** 2 / 2
    jt = mass * (3 * r ** 2 + L ** 2) / 12
    b = Body(name="c", mass=mass, polar_inertia=jp, transverse_inertia=jt)
    assert width_from_inertia(b, r, 0.35) == pytest.approx(L)
    thin = Body(name="d", mass=mass, polar_inertia=jp)  # default J_t = J_p / 2: no length
    assert width_from_inertia(thin, r, 0.35) == pytest.approx(0.35 * r)


def test_rigid_displacement_small_rotation():
    z = np.array([1.0, 0, 0, 0, 0, 2.0])
    d = rigid_displacement(z, np.zeros(3), np.array([[1.0, 0, 0]]))
    assert np.allclose(d, [[1.0, 2.0, 0.0]])


@pytest.mark.parametrize("side", [False, True])
def test_frame_view_fits_the_focus_box(side):
    """The framed box lies inside the drawing band of the image (below the title, above
    the colour bar) and fills a good part of it, for the oblique and the side view."""
    from assembly.app.render.views import FILL_H, FILL_V, frame_view, project

    W, H = 1200, 900
    lo, hi = np.array([0.30, -0.05, 0.10]), np.array([0.42, 0.07, 0.16])   # a small pinion far off-centre
    axis = np.array([0.0, 0.0, 1.0])
    v = frame_view(lo, hi, axis, (W, H), side=side, across=np.array([1.0, 0.0, 0.0]))
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    px = project(v, corners, (W, H))
    assert px[:, 0].min() >= 0 and px[:, 0].max() <= W
    band = (0.5 - 0.5 * FILL_V) * H, (0.5 + 0.5 * FILL_V) * H + 0.04 * H
    assert px[:, 1].min() >= 0.5 * (1 - FILL_V) * H - 0.04 * H - 1 and px[:, 1].max() <= band[1]
    fill = max(np.ptp(px[:, 0]) / (FILL_H * W), np.ptp(px[:, 1]) / (FILL_V * H))
    assert 0.5 < fill <= 1.0
    if side:   # looking across the shafts: the axis lies (nearly) in the image plane
        assert abs(v.direction @ axis) < 0.35
    else:
        assert v.direction @ axis > 0.7


def test_a_mode_image_never_frames_what_the_ring_surrounds(planetary):
    sc, m, r, infos, rnd = planetary
    for i in range(r.n_rigid, r.n_rigid + 8):
        focus = rnd.focus_bodies(r, i)
        assert focus == tuple(b for b, _ in infos[i].dominant_bodies)
        view, hidden = rnd.mode_frame(focus)
        assert hidden == ()   # one stage: nothing left out
        if "stage.ring" not in focus:   # the ring surrounds the stage: a zoom would cut it
            assert view is rnd.view


def test_a_small_body_is_framed_when_that_magnifies_it_enough():
    """kahraman_beta20's pinion is small beside its gear: a mode held by it is framed on it
    exactly when that magnifies it MIN_ZOOM times over the whole drawing."""
    from assembly.app.render.renderer import MIN_ZOOM
    from assembly.app.render.views import frame_view

    m = assemble(load_scene("kahraman_beta20.toml"))
    rnd = AssemblyRenderer(m, window_size=SIZE)
    for name in m.bodies:
        zoom = frame_view(*_box(m, rnd, (name,)), rnd.shapes[name].axes[:, 2], SIZE, False, None)
        view, hidden = rnd.mode_frame((name,))
        assert hidden == ()
        if rnd.view.parallel_scale >= MIN_ZOOM * zoom.parallel_scale:
            assert view.parallel_scale == pytest.approx(zoom.parallel_scale, rel=1e-12)
        else:
            assert view is rnd.view


def test_mode_scale_and_caption(planetary):
    sc, m, r, infos, rnd = planetary
    from assembly.app.render.renderer import mode_caption
    from assembly.app.render.surfaces import body_actor
    i = r.n_rigid + 5
    view = rnd.mode_view(rnd.focus_bodies(r, i))
    scale, dmax = rnd.mode_scale(r, i, view.size)
    # The colour bar's 1 is the largest displacement over every drawn surface point, drawn as
    # DEFORMATION_FRACTION of the framed size (the caption's length).
    d = max(float(np.max(body_actor(m, n, r.abs_shapes[m.body_slice(n), i], 0.0).point_data["displacement_m"]))
            for n in m.bodies)
    assert dmax == pytest.approx(d, rel=1e-12)
    from assembly.app.render.views import DEFORMATION_FRACTION
    assert scale * dmax == pytest.approx(DEFORMATION_FRACTION * view.size, rel=1e-12)
    text = mode_caption(scale, view.size, ("sun",), True)
    assert f"drawn as {1e3 * DEFORMATION_FRACTION * view.size:.3g} mm" in text and "modal mass" not in text


def _box(m, rnd, names):
    from assembly.app.render.surfaces import reference_surface
    P = np.vstack([np.asarray(reference_surface(m, n, rnd.shapes).points) for n in names])
    return P.min(axis=0), P.max(axis=0)


def test_a_stage_mode_of_a_stacked_box_is_seen_from_the_front_without_the_other_stages():
    """The quill drive's stages lie one behind the other along the shaft: the whole box is seen
    from the side, where the ring hides the planets. A mode held by the planetary stage is
    seen along the shaft with the bodies outside the stage's axial span (the helical pair)
    left out; a mode of the whole box or of the helical pair keeps the side view and every
    body."""
    sc = load_scene("two_stage_quill.toml")
    m = assemble(sc)
    rnd = AssemblyRenderer(m, window_size=SIZE)
    axis = rnd.shapes["planetary.sun"].axes[:, 2]
    assert abs(rnd.view.direction @ axis) < 0.35            # the box: side view
    focus = ("planetary.planet0", "planetary.planet1", "planetary.carrier")
    view, hidden = rnd.mode_frame(focus)
    assert view.direction @ axis > 0.7                        # the stage: along the shaft
    assert set(hidden) == {"pinion", "wheel"}
    z = {n: rnd.shapes[n].position @ axis for n in m.bodies}
    stage = [z[n] for n in m.bodies if n.startswith("planetary.")]
    assert all(not min(stage) - 1e-9 <= z[n] <= max(stage) + 1e-9 for n in hidden)
    whole, none = rnd.mode_frame(tuple(m.bodies))
    assert none == () and whole is rnd.view
    # A mode of the helical pair (no planets there) keeps the side view and every body.
    view, hidden = rnd.mode_frame(("wheel",))
    assert hidden == () and abs(view.direction @ axis) < 0.35


def test_a_plain_gear_with_teeth_is_drawn_its_face_width_long():
    # the quill drive's pinion has teeth (face width 60 mm) and no component: drawn 60 mm long,
    # not the length its mass and inertia would give a solid cylinder
    scene = load_scene("two_stage_quill")
    sh = body_shapes(assemble(scene))["pinion"]
    assert sh.kind == "gear" and sh.width == pytest.approx(scene.body("pinion").teeth.face_width, rel=1e-12)
