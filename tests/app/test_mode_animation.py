"""Animated mode shapes (:mod:`assembly.app.render.animation`): the GIF has the stated frame
count over one period, its frames move, frame 0 is the still image's deformation and frame
N/2 its mirror (checked on the coordinates handed to the renderer, not on pixels), and a run
whose drawn modes all lie outside the band writes no animation and says so.

Scene: lin_parker_n4 (rigid planetary stage, no beam shafts: every moving point is a body
surface point, an index mark or a spring), drawn small (the frames are ANIMATION_SCALE of it).
"""
import os

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

import numpy as np
import pytest

from assembly import assemble, load_scene, solve_modes
from assembly.app.render.animation import FRAMES, animate_modes, animation_size, frame_phases, movers
from assembly.app.render.renderer import AssemblyRenderer
from assembly.app.render.views import DEFORMATION_FRACTION
from assembly.app.report.pipeline import DEFAULT_STEPS, RunOptions, run_pipeline
from assembly.scene.schema import SCENE_DIR

SCENE = SCENE_DIR / "lin_parker_n4.toml"
SIZE = (320, 240)


@pytest.fixture(scope="module")
def stage():
    m = assemble(load_scene(SCENE))
    r = solve_modes(m)
    return m, r, AssemblyRenderer(m, window_size=SIZE)


def test_phases_one_period_from_the_still_to_its_mirror():
    # cos(2 pi k / N): frame 0 the still (1), frame N/4 undeformed (0), frame N/2 the mirror (-1),
    # frames k and N - k alike (cos is even)
    ph = frame_phases(FRAMES)
    assert len(ph) == FRAMES and 12 <= FRAMES <= 16 and FRAMES % 4 == 0
    assert ph[0] == 1.0 and ph[FRAMES // 2] == -1.0 and abs(ph[FRAMES // 4]) < 1e-15
    assert np.allclose(ph[1:], ph[1:][::-1], rtol=0, atol=1e-15)


def test_frame_coordinates_are_the_still_and_its_mirror(stage):
    m, r, rnd = stage
    mode = r.n_rigid
    drawing = rnd.mode_drawing(r, mode)
    still, rest = rnd.mode_meshes(r, drawing, 1.0), rnd.mode_meshes(r, drawing, 0.0)
    moving = movers(still, rest)
    ph = frame_phases(FRAMES)
    largest = 0.0
    for kind, items in moving.items():
        if kind in ("springs", "marks"):   # merged into one line mesh per look: the same points
            assert sum(mv.mesh.n_points for mv, _ in items) == sum(m.n_points for m, _ in still[kind]) > 0
            pairs = [(mv, mv.base + mv.step, mv.base) for mv, _ in items]
        else:
            assert len(items) == len(still[kind]) and (items or kind == "tubes")   # no beam shaft here
            ids = [np.asarray(mv.mesh.point_data["pyvistaOriginalPointIds"]) if kind == "bodies"
                   else np.arange(mv.mesh.n_points) for mv, _ in items]   # a body's sharp edges: split
            pairs = [(mv, np.asarray(m1.points)[i], np.asarray(m0.points)[i])
                     for (mv, _), (m1, _), (m0, _), i in zip(items, still[kind], rest[kind], ids)]
        for mv, drawn, base in pairs:
            first, c_first = mv.at(ph[0])
            half, c_half = mv.at(ph[FRAMES // 2])
            # frame 0: the still's coordinates (m; the drawing spans ~1 m); frame N/2: the same
            # displacement reversed
            assert np.allclose(first, drawn, rtol=0, atol=1e-12)
            assert np.allclose(half - base, -(first - base), rtol=0, atol=1e-12)
            if c_first is not None:        # colour: |displacement| / largest, alike at +-1, 0 at rest
                assert np.array_equal(c_first, c_half)
                assert not np.any(mv.at(ph[FRAMES // 4])[1] > 1e-15)
            if kind == "bodies":
                largest = max(largest, float(np.linalg.norm(first - base, axis=1).max()))
    # the still's scale: the largest drawn displacement is DEFORMATION_FRACTION of the framed size
    assert largest == pytest.approx(DEFORMATION_FRACTION * drawing.view.size, rel=1e-9)


def test_gif_has_the_frames_and_they_move(stage, tmp_path):
    from PIL import Image

    m, r, rnd = stage
    modes = [r.n_rigid]
    before = np.asarray(Image.open(rnd.render_mode(r, r.n_rigid + 1, tmp_path / "before.png", title="t")))
    out = animate_modes(rnd, r, [(i, tmp_path / f"m{i}.gif", f"mode {i + 1}") for i in modes])
    assert [a.mode for a in out] == modes
    for a in out:
        assert a.rendered == FRAMES // 2 + 1        # frames k and N - k drawn once
        with Image.open(a.path) as im:
            assert im.n_frames == FRAMES and im.size == animation_size(SIZE)
            frames = []
            for k in range(FRAMES):
                im.seek(k)
                frames.append(np.asarray(im.convert("RGB"), dtype=int))
        assert os.path.getsize(a.path) < 1_000_000
        for k in range(1, FRAMES):               # the shape moves from frame to frame ...
            assert np.abs(frames[k] - frames[k - 1]).max() > 0, k
        for k in range(1, FRAMES // 2):          # ... and comes back the way it went
            assert np.array_equal(frames[k], frames[FRAMES - k])
    # the renderer is back at its size, anti-aliased: a still after the animations is unchanged
    after = np.asarray(Image.open(rnd.render_mode(r, r.n_rigid + 1, tmp_path / "after.png", title="t")))
    assert tuple(rnd.plotter().window_size) == SIZE and np.array_equal(before, after)


def test_no_mode_in_the_band_no_animation(tmp_path):
    # band_hz so low that the display limit (DISPLAY_BAND_FACTOR x band) is below the first
    # elastic frequency (hundreds of Hz): only the rigid-body mode is in the band
    p = tmp_path / "low_band.toml"
    p.write_text("band_hz = 1.0\n" + SCENE.read_text())
    steps = [s for s in DEFAULT_STEPS if s.name in ("load scene", "assemble", "eigen solve", "mode-shape images",
                                                    "index.html")]
    ctx = run_pipeline(str(p), tmp_path / "out", RunOptions(compare=False, window_size=(160, 120)), steps=steps)
    assert ctx.animated_modes() == [] and ctx.animations == []
    assert not (tmp_path / "out" / "animations").exists()
    note = "no mode animations: no elastic mode drawn is in the band"
    assert any(n.startswith(note) for n in ctx.notes)
    html = (tmp_path / "out" / "index.html").read_text()
    assert note in html and "Mode animations</h2>" not in html
