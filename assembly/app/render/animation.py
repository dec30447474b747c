"""Animated mode shapes: the still mode image's drawing moved through one period (GIF).

Frame k of N shows the drawn deformation at phase ``cos(2 pi k / N)`` (= ``sin(2 pi (t + 1/4))``
at ``t = k / N`` of the period) times that of the still image
(:meth:`assembly.app.render.renderer.AssemblyRenderer.render_mode`): frame 0 is the still's
deformation, frame N/2 its mirror. The view, the deformation scale and the colour
normalisation are the still's: the colour is the displacement at that instant over the
largest drawn (colour bar 0 to 1, "displacement / largest"), so the colours fade through
the zero crossings.

Cheap by construction: the frames are drawn with the renderer's one plotter (no new OpenGL
context) at :data:`ANIMATION_SCALE` of its window, the actors are added once and only the
moving meshes' points and colours change from frame to frame, and frames k and N - k (the
same phase) are rendered once. Pillow writes the GIF with one palette for every frame (made
from frame 0, which holds every colour of the drawing). pyvista is imported lazily.
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .plotter import load_pyvista
from .views import place_camera

#: Frames per period, the period shown (s) and the frame size as a fraction of the still's.
FRAMES = 12
PERIOD_S = 1.2
ANIMATION_SCALE = 0.4
#: Font sizes of the frames' title and colour-bar labels, as a fraction of the still's.
TEXT_SCALE = 0.6


def frame_phases(n_frames: int = FRAMES) -> np.ndarray:
    """Deformation factor of each frame: ``cos(2 pi k / n_frames)``, k = 0 .. n_frames - 1."""
    return np.cos(2 * np.pi * np.arange(n_frames) / n_frames)


@dataclass(frozen=True)
class ModeAnimation:
    """One written animation: its file, the mode (0-based), each frame's phase, how many
    distinct frames were rendered, the frame size (pixels) and the seconds it took."""

    path: Path
    mode: int
    phases: tuple
    rendered: int
    size: tuple
    seconds: float


def animation_size(window_size) -> tuple:
    """Frame size (pixels) for a renderer of ``window_size``: the same aspect, so the still's
    view frames the same part of the drawing."""
    return tuple(max(2, int(round(ANIMATION_SCALE * v))) for v in window_size)


@dataclass(frozen=True)
class Mover:
    """One moving mesh of a mode drawing as it is handed to the renderer: its points are
    ``base + phase * step`` (``base``: undeformed; ``step``: the still's displacement as
    drawn) and its colours ``|phase| * colour`` (None: a mesh of one colour)."""

    mesh: object
    base: np.ndarray
    step: np.ndarray
    colour: np.ndarray | None

    def at(self, phase: float) -> tuple:
        """(points (n, 3), colours or None) at ``phase``."""
        return self.base + phase * self.step, None if self.colour is None else abs(phase) * self.colour


#: Point array of a drawing's colours (:meth:`AssemblyRenderer.mode_meshes`).
COLOUR = "normalised displacement"


def _merged_lines(meshes: list):
    """One line mesh (pyvista PolyData) holding the points and lines of ``meshes``, in order
    (one actor to draw and move instead of one per spring)."""
    pv = load_pyvista()
    pts, lines, off = [], [], 0
    for m in meshes:
        cells = np.array(m.lines, dtype=np.int64)
        k = 0
        while k < len(cells):                    # [n, i_1 .. i_n, n, ...]: shift the indices
            cells[k + 1:k + 1 + cells[k]] += off
            k += cells[k] + 1
        pts.append(np.asarray(m.points, float))
        lines.append(cells)
        off += m.n_points
    out = pv.PolyData(np.vstack(pts))
    out.lines = np.concatenate(lines)
    return out


def movers(still: dict, rest: dict) -> dict:
    """{kind: [(Mover, add_mesh keyword arguments)]} from a mode drawing's meshes at phase 1
    (``still``) and 0 (``rest``) (:meth:`AssemblyRenderer.mode_meshes`). A body's normals are
    computed once, on the still's shape, its sharp edges split as the still's are (points
    duplicated: ``pyvistaOriginalPointIds``), so a frame only moves points. Springs and index
    marks of one look are merged into one line mesh each."""
    out: dict = {}
    for kind, items in still.items():
        out[kind] = []
        pairs = [(m1, m0, kw) for (m1, kw), (m0, _) in zip(items, rest[kind])]
        if kind in ("springs", "marks"):
            looks: dict = {}
            for m1, m0, kw in pairs:
                looks.setdefault(tuple(sorted(kw.items())), []).append((m1, m0))
            pairs = [(_merged_lines([a for a, _ in group]), _merged_lines([b for _, b in group]), dict(look))
                     for look, group in looks.items()]
        for m1, m0, kw in pairs:
            kw = dict(kw)
            p0 = np.asarray(m0.points, float)
            if kw.pop("split_sharp_edges", False):
                m1 = m1.compute_normals(split_vertices=True, feature_angle=kw.pop("feature_angle", 30.0))
                p0 = p0[np.asarray(m1.point_data["pyvistaOriginalPointIds"])]
            colour = np.array(m1.point_data[COLOUR]) if COLOUR in m1.point_data else None
            out[kind].append((Mover(m1, p0, np.asarray(m1.points, float) - p0, colour), kw))
    return out


def _show(moving: dict, phase: float) -> None:
    """Every moving mesh set to ``phase`` (points and colours written into its arrays)."""
    for items in moving.values():
        for mv, _ in items:
            pts, colour = mv.at(phase)
            mv.mesh.points[:] = pts
            mv.mesh.GetPoints().Modified()
            if colour is not None:
                mv.mesh.point_data[COLOUR][:] = colour
                mv.mesh.GetPointData().GetArray(COLOUR).Modified()
            mv.mesh.Modified()


def animate_modes(rnd, result, jobs, n_frames: int = FRAMES, period_s: float = PERIOD_S) -> list:
    """Write the GIF of each ``(mode, path, title)`` of ``jobs`` (mode: 0-based index into
    ``result``) drawn by ``rnd`` (an :class:`~assembly.app.render.renderer.AssemblyRenderer`):
    ``n_frames`` frames over one period shown in ``period_s`` seconds, looping, with the
    still's framing (the mode's dominant bodies) and ``title`` at the top. The renderer's
    plotter is switched to the frame size without anti-aliasing (MSAA would double the
    cost of a frame) and back. Returns a :class:`ModeAnimation` per job."""
    jobs = list(jobs)
    if not jobs:
        return []
    pl = rnd.plotter()
    samples = pl.ren_win.GetMultiSamples()
    pl.disable_anti_aliasing()
    pl.window_size = list(animation_size(rnd.window_size))
    try:
        return [_animate(rnd, result, mode, path, title, n_frames, period_s) for mode, path, title in jobs]
    finally:
        pl.close()
        pl.window_size = list(rnd.window_size)
        if samples:
            pl.enable_anti_aliasing("msaa", multi_samples=samples)


def _animate(rnd, result, mode: int, path, title: str, n_frames: int, period_s: float) -> ModeAnimation:
    """One job of :func:`animate_modes`, the renderer's plotter already at the frame size."""
    from PIL import Image

    t0 = time.perf_counter()
    phases = frame_phases(n_frames)
    drawing = rnd.mode_drawing(result, mode)
    moving = movers(rnd.mode_meshes(result, drawing, 1.0), rnd.mode_meshes(result, drawing, 0.0))
    shots: dict = {}
    pl = rnd.plotter()
    size = tuple(pl.window_size)
    try:
        _show(moving, float(phases[0]))
        rnd.draw_mode(pl, drawing, {k: [(mv.mesh, kw) for mv, kw in v] for k, v in moving.items()},
                      text_scale=TEXT_SCALE)
        if title:
            pl.add_text(title, position="upper_left", font_size=round(15 * TEXT_SCALE), color="black")
        place_camera(pl, drawing.view)
        pl.suppress_rendering = False
        frames = []
        for k, ph in enumerate(phases):
            key = min(k, n_frames - k)             # frames k and N - k: the same phase
            if key not in shots:
                _show(moving, float(ph))
                pl.render()
                shots[key] = Image.fromarray(pl.screenshot(None, return_img=True))
            frames.append(shots[key])
    finally:
        pl.close()
    palette = frames[0].quantize(colors=256, method=Image.Quantize.MEDIANCUT)
    cache = {id(f): f.quantize(palette=palette, dither=Image.Dither.NONE) for f in shots.values()}
    gif = [cache[id(f)] for f in frames]
    tmp = Path(path).with_name(Path(path).name + ".tmp")
    gif[0].save(tmp, format="GIF", save_all=True, append_images=gif[1:], loop=0,
                duration=int(round(1000 * period_s / n_frames)))
    tmp.replace(path)
    return ModeAnimation(Path(path), mode, tuple(float(p) for p in phases), len(shots), size,
                         time.perf_counter() - t0)
