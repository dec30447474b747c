"""Mode-shape images of an assembled drivetrain (PNG, pyvista off-screen).

Every body is drawn where it is, as a solid of its geometry moved by its mode shape
(:mod:`assembly.app.render.shapes`: gears as toothed discs, other bodies as equivalent
cylinders, a planet carrier as a plate behind the bodies it carries). Bearings, shafts and
gear meshes are zig-zag springs between their attachment points
(:mod:`assembly.app.render.springs`: a bearing to the housing ends on a fixed ground point;
a mesh spring lies along the line of action at the contact point, on the front face so it
stays visible). A faint grey ghost shows the undeformed assembly.

Deformation scale: each mode is drawn with the scale that makes its largest displacement
:data:`assembly.app.render.views.DEFORMATION_FRACTION` of the assembly's size (bounding-box
diagonal); the colour is the displacement magnitude over the largest (a mode shape has no
physical size). The camera (parallel projection, :mod:`assembly.app.render.views`), window size
and colours depend only on the undeformed assembly, so images are identical from run to run.

Flexible bodies
---------------
A flexible body (``bm.flexible``) is drawn as its own FE surface moved by the back-expanded
displacement (:mod:`assembly.app.render.surfaces`); springs attach through
``motion_at(point)``, which every body model provides.

pyvista/VTK are imported lazily inside the functions (never at import of this module).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...mechanics.kinematics import axis_frame, rigid_transfer
from .labels import CHAR_WIDTH, ROW_HEIGHT, pixel_box, place_labels, stage_groups
from .plotter import kept_plotter, load_pyvista, save_png
from .shafts import shaft_segments, shaft_tube
from .shapes import assembly_size, body_shapes, index_mark, pitch_radii, rigid_displacement, rigid_part, solid_surface
from .springs import spring_glyphs, spring_points
from .surfaces import body_actor, reference_surface
from .twist import referred_angles, twist_arrows
from .views import (
    DEFORMATION_FRACTION,
    WINDOW_SIZE,
    View,
    assembly_view,
    fit_view,
    frame_view,
    place_camera,
    view_axes,
    wants_side_view,
)

#: Overview: stage colours, beam shaft colour, label font (points) and margin (fraction of
#: the assembly size) around the drawing and its labels.
PALETTE = ("#4c72b0", "#dd8452", "#55a868", "#c44e52", "#8172b3", "#937860", "#da8bc3", "#8c8c8c",
           "#ccb974", "#64b5cd")
BEAM_COLOR = "#a0a4aa"
LABEL_FONT = 12
OVERVIEW_MARGIN = 0.04
#: Twist arrows: turning with the reference body, against it.
TWIST_COLORS = ("#d62728", "#1f5fbf")
#: The undeformed ghost and index marks; springs by kind; the colour map of the displacement.
GHOST_COLOR = "#6a6a6a"
BEARING_COLOR = "#303030"
MESH_COLOR = "#c03000"
SHAFT_COLOR = "#1f4e99"
CMAP = "viridis"
#: Opacity of the bodies drawn as context (not among a mode's dominant bodies).
CONTEXT_OPACITY = 0.25
#: The colour bar of a mode image (fractions of the window: left edge, bottom, width, height),
#: its labels 0 / 0.5 / 1 drawn below it and its title above.
BAR_X, BAR_Y, BAR_W, BAR_H = 0.55, 0.06, 0.4, 0.05
#: A mode image frames its dominant bodies only when that magnifies them at least this much
#: over the whole drawing: a smaller zoom gains little and cuts the faint context bodies at
#: the title and the colour bar.
MIN_ZOOM = 2.0
#: A carrier seen along the shaft is drawn at most this opaque (its cheek covers the planets).
CARRIER_OPACITY = 0.45
#: Text drawn over the picture sits on a white band of this opacity (legible over a body).
TEXT_BACKING = 0.8


def _backed(actor):
    """``actor`` (a pyvista text) on a white, slightly transparent band."""
    prop = actor.GetTextProperty() if hasattr(actor, "GetTextProperty") else None
    if prop is not None:
        prop.SetBackgroundColor(1.0, 1.0, 1.0)
        prop.SetBackgroundOpacity(TEXT_BACKING)
    return actor


def _nice_length(x: float) -> float:
    """Largest 1-2-5 x 10^k not above ``x``."""
    e = math.floor(math.log10(x))
    for m in (5, 2, 1):
        if m * 10 ** e <= x:
            return m * 10 ** e
    return 10 ** e


def _format_length(L: float) -> str:
    if L >= 1:
        return f"{L:g} m"
    if L >= 1e-3:
        return f"{L * 1e3:g} mm"
    return f"{L * 1e6:g} um"


class AssemblyRenderer:
    """Renders mode shapes (and an overview) of one assembled model with a fixed camera.

    Build once per model; :meth:`render_mode` writes one PNG per call.
    """

    def __init__(self, model, window_size=WINDOW_SIZE):
        self.model = model
        self.window_size = tuple(int(v) for v in window_size)
        self.shapes = body_shapes(model)
        self.glyphs = spring_glyphs(model, self.shapes)
        self.segments = shaft_segments(model)
        ends = [p for g in self.glyphs for p in (g.a, g.b)] + [p for sg in self.segments for p in (sg.a, sg.b)]
        self._ends = ends
        self.view = assembly_view(self.shapes, self.window_size, ends)
        self._cache: dict = {}
        self._pl = None
        self._roles = {b.name: b.role for b in model.scene.bodies}

    def close(self) -> None:
        """Release the plotter (its OpenGL context); the renderer can still draw after."""
        if self._pl is not None:
            self._pl.release()
            self._pl = None

    # -- helpers -------------------------------------------------------------------
    def plotter(self):
        """The renderer's one off-screen plotter, cleared: a new plotter per image costs a new
        OpenGL context and shader compilation. Actors are added with rendering suppressed;
        :meth:`_finish` renders once. Its ``close()`` only clears (see :meth:`close`)."""
        if self._pl is None:
            self._pl = kept_plotter(load_pyvista(), self.window_size)
            # FXAA is not supported with EGL; MSAA (4 samples) draws as smooth edges as SSAA here
            # in half the time (SSAA renders every image at twice the size)
            self._pl.enable_anti_aliasing("msaa", multi_samples=4)
        pl = self._pl
        pl.clear()
        pl.set_background("white")
        pl.suppress_rendering = True
        return pl

    def ghost(self, pl, hidden=()):
        """Undeformed outline (feature edges) of every body but ``hidden``, thin grey lines,
        and their index marks; made once per ``hidden`` set, as one mesh each (one actor to add
        and draw, not one per body)."""
        key = ("ghost", tuple(hidden))
        if key not in self._cache:
            pv = load_pyvista()
            edges = []
            for name in self.model.bodies:
                if name not in hidden:
                    ref = reference_surface(self.model, name, self.shapes, self._cache)
                    edges.append(ref.extract_feature_edges(feature_angle=40, boundary_edges=True,
                                                           non_manifold_edges=False, manifold_edges=False))
            marks = [pv.Line(*index_mark(sh)) for name, sh in self.shapes.items()
                     if not self.model.bodies[name].flexible and name not in hidden]
            self._cache[key] = [pv.merge(group, merge_points=False) if group else None for group in (edges, marks)]
        edges, marks = self._cache[key]
        if edges is not None:
            pl.add_mesh(edges, color=GHOST_COLOR, line_width=1, lighting=False)
        if marks is not None:
            pl.add_mesh(marks, color=GHOST_COLOR, line_width=3)

    def _motion(self, shape_of):
        """``motion(body, point)`` -> [u, theta] (m, rad; global) at ``point`` of ``body``
        in the mode shape ``shape_of`` (a flexible body's interface master when ``point`` is
        one, else its rigid-equivalent motion)."""
        def motion(body, p):
            bm = self.model.bodies[body]
            z = shape_of(body)
            if z is None:
                return np.zeros(6)
            if bm.flexible:
                try:
                    return np.asarray(bm.motion_at(p) @ np.asarray(z, float), float).ravel()
                except (ValueError, KeyError):
                    pass
            return rigid_transfer(p, bm.position) @ rigid_part(bm, z)
        return motion

    def _tubes(self, shape_of, scale, hidden=()):
        """Beam shaft tubes (pyvista) moved by ``scale`` x the mode ``shape_of`` (None:
        undeformed), but those ending on a ``hidden`` body."""
        motion = None if shape_of is None else self._motion(shape_of)
        return [shaft_tube(sg, motion, scale) for sg in self.segments
                if sg.body_a not in hidden and sg.body_b not in hidden]

    def _scale_bar(self, pl, view=None):
        pv = load_pyvista()
        v = view or self.view
        right = np.cross(v.up, v.direction)
        L = _nice_length(0.2 * v.size)
        W, H = self.window_size
        # Pixel (x, y from bottom-left) -> point in the focal plane (parallel projection).
        px = lambda x, y: (v.focal + right * ((x - W / 2) / (H / 2) * v.parallel_scale)
                           + v.up * ((y - H / 2) / (H / 2) * v.parallel_scale))
        p0 = px(40, 45)
        p1 = p0 + right * L
        pl.add_mesh(pv.Line(p0, p1), color="black", line_width=4)
        for q in (p0, p1):
            pl.add_mesh(pv.Line(q - v.up * 0.012 * v.parallel_scale, q + v.up * 0.012 * v.parallel_scale),
                        color="black", line_width=4)
        _backed(pl.add_text(f"{_format_length(L)} (geometry scale)", position=(40, 55), font_size=11, color="black"))

    def _finish(self, pl, path, view=None):
        """Scale bar, the camera (the assembly's unless ``view``), and the PNG written to ``path``."""
        view = view or self.view
        self._scale_bar(pl, view)
        place_camera(pl, view)
        pl.suppress_rendering = False
        pl.render()
        save_png(pl, path)

    def _springs(self, pl, shape_of, scale, view=None, hidden=()):
        for m, kw in self._spring_lines(shape_of, scale, view or self.view, hidden):
            pl.add_mesh(m, **kw)
        self._ground(pl, hidden)

    def _spring_lines(self, shape_of, scale, view, hidden=()) -> list:
        """(zig-zag line, add_mesh keyword arguments) of every spring not ending on a ``hidden``
        body, its ends moved by ``scale`` x the mode ``shape_of``, coloured by kind."""
        pv = load_pyvista()
        colors = {"bearing": BEARING_COLOR, "mesh": MESH_COLOR, "shaft": SHAFT_COLOR}
        return [(pv.lines_from_points(spring_points(self.model, g, shape_of, scale, view)[0]),
                 dict(color=colors.get(g.kind, BEARING_COLOR), line_width=4, render_lines_as_tubes=True))
                for g in self.glyphs if g.body_a not in hidden and g.body_b not in hidden]

    def _ground(self, pl, hidden=()):
        """Ground: a small cube (sized on the assembly) at the housing end of each spring not
        ending on a ``hidden`` body; made once per ``hidden`` set, as one mesh."""
        key = ("ground", tuple(hidden))
        if key not in self._cache:
            pv = load_pyvista()
            e = 0.025 * self.view.size
            cubes = [pv.Cube(center=g.b, x_length=e, y_length=e, z_length=e) for g in self.glyphs
                     if g.ground and g.body_a not in hidden and g.body_b not in hidden]
            self._cache[key] = pv.merge(cubes, merge_points=False) if cubes else None
        if self._cache[key] is not None:
            pl.add_mesh(self._cache[key], color="#606060")

    # -- public ----------------------------------------------------------------------
    def _label_layout(self, groups: dict, view, font: int) -> dict:
        """Key -> (label text, x, y, side, box) in pixels of ``view`` (render_labels)."""
        right = np.cross(view.up, view.direction)
        ppm = self.window_size[1] / 2 / view.parallel_scale
        boxes, texts = {}, {}
        for key, (text, names) in groups.items():
            P = [np.asarray(reference_surface(self.model, n, self.shapes, self._cache).points) for n in names]
            boxes[key] = pixel_box(np.vstack(P), right, view.up, view.focal, ppm, self.window_size)
            texts[key] = text
        lo = min(b[2] for b in boxes.values())
        hi = max(b[3] for b in boxes.values())
        place = place_labels(boxes, texts, font, lo, hi)
        return {k: (texts[k], *place[k], boxes[k]) for k in place}

    def _pixel_point(self, view, x: float, y: float) -> np.ndarray:
        """Point (m) in front of the drawing that ``view`` shows at pixel (x, y)."""
        W, H = self.window_size
        right = np.cross(view.up, view.direction)
        return (view.focal + right * ((x - W / 2) / (H / 2) * view.parallel_scale)
                + view.up * ((y - H / 2) / (H / 2) * view.parallel_scale) + view.direction * view.size)

    def overview_view(self, groups: dict, font: int = LABEL_FONT) -> View:
        """The assembly's view refitted with room for the stage labels' rows."""
        v0 = self.view
        pts = [solid_surface(s, n_radial=1)[0] for s in self.shapes.values()] + [np.asarray(self._ends).reshape(-1, 3)]
        for text, x, y, side, _ in self._label_layout(groups, v0, font).values():
            half = 0.5 * CHAR_WIDTH * font * len(text) + 4
            pts.append(np.array([self._pixel_point(v0, x + dx, y + dy) for dx in (-half, half)
                                 for dy in (0.0, ROW_HEIGHT * font)]))
        first = next(iter(self.shapes.values()))
        side, across = wants_side_view(self.shapes)
        direction, up = view_axes(first.axes[:, 2], side, across)
        size = assembly_size(self.shapes)
        return fit_view(np.vstack(pts), direction, up, self.window_size, size, OVERVIEW_MARGIN * size)

    def render_overview(self, path, title: str = "") -> Path:
        """Undeformed assembly (PNG): bodies coloured per stage with one label per stage (a
        body without a stage is labelled alone: :func:`assembly.app.render.labels.stage_groups`),
        beam shafts as cylinders of their diameter, springs, a length scale, and a note on
        bodies drawn smaller than their equivalent radius (a lumped rotor drawn as a hub).
        ``self.labels_drawn`` lists the label texts drawn."""
        pv = load_pyvista()
        pl = self.plotter()
        try:
            groups = stage_groups(self.model.scene, set(pitch_radii(self.model.scene)))
            # one colour per stage; a scene of one stage gets one colour per body
            sets = list(groups.values()) if len(groups) > 1 else [(None, [n]) for n in self.model.bodies]
            colour = {n: PALETTE[k % len(PALETTE)] for k, (_, names) in enumerate(sets) for n in names}
            for name in self.model.bodies:
                ref = reference_surface(self.model, name, self.shapes, self._cache)
                pl.add_mesh(ref, color=colour.get(name, PALETTE[0]), smooth_shading=True, split_sharp_edges=True,
                            feature_angle=40.0)
            for tube in self._tubes(None, 0.0):
                pl.add_mesh(tube, color=BEAM_COLOR, smooth_shading=True)
            self._springs(pl, lambda b: None, 0.0)
            view = self.overview_view(groups)
            self.labels_drawn = []
            for text, x, y, side, box in self._label_layout(groups, view, LABEL_FONT).values():
                half = 0.5 * CHAR_WIDTH * LABEL_FONT * len(text)
                pl.add_text(text, position=(int(round(x - half)), int(round(y))), font_size=LABEL_FONT,
                            color="black")
                edge = box[3] if side > 0 else box[2]
                end = y - 2 if side > 0 else y + 0.5 * ROW_HEIGHT * LABEL_FONT + 4
                pl.add_mesh(pv.Line(self._pixel_point(view, x, edge), self._pixel_point(view, x, end)),
                            color="#404040", line_width=1)
                self.labels_drawn.append(text)
            pl.add_text(title or "assembly", position="upper_left", font_size=14, color="black")
            lines = [f"{n}: lumped mass, drawn as a hub of radius {s.r_outer:.3g} m (largest gear radius;\n"
                     f"    its equivalent solid cylinder would have sqrt(2 J / m) = {s.equivalent_radius:.3g} m)"
                     for n, s in self.shapes.items() if s.equivalent_radius > 0]
            if lines:
                pl.add_text("\n".join(lines), position=(12, self.window_size[1] - 50 - 26 * len(lines)), font_size=10,
                            color="#202020")
            beams = "beam shafts: grey cylinders of their diameter; " if self.segments else ""
            pl.add_text(f"{beams}springs: bearings (dark grey), gear meshes (red, along the line of action), "
                        "shafts (blue); grey cubes = housing", position="lower_right", font_size=11,
                        color="black")
            self._finish(pl, path, view)
        finally:
            pl.close()
        return Path(path)

    def mode_scale(self, result, mode: int, size: float | None = None, hidden=()) -> tuple[float, float]:
        """(deformation scale, largest unscaled displacement in m over every drawn surface
        point, ``hidden`` bodies' left out) of ``mode``; the scale draws that displacement as
        :data:`DEFORMATION_FRACTION` of ``size`` (m; default the assembly size)."""
        dmax = 0.0
        for name in self.model.bodies:
            if name in hidden:
                continue
            z = result.abs_shapes[self.model.body_slice(name), mode]
            dmax = max(dmax, float(np.asarray(body_actor(self.model, name, z, 0.0, self.shapes, self._cache)
                                              .point_data["displacement_m"]).max(initial=0.0)))
        for tube in self._tubes(lambda b: result.abs_shapes[self.model.body_slice(b), mode], 0.0, hidden):
            dmax = max(dmax, float(np.asarray(tube.point_data["displacement_m"]).max(initial=0.0)))
        if dmax <= 0:
            return 0.0, 0.0
        return DEFORMATION_FRACTION * (size or self.view.size) / dmax, dmax

    def focus_bodies(self, result, mode: int) -> tuple:
        """Names of the bodies holding most of ``mode``'s kinetic energy
        (:func:`assembly.analysis.classify.dominant_bodies`; all bodies for a motionless mode)."""
        from ...analysis.classify import dominant_bodies
        from ...analysis.energy import kinetic_by_body
        key = ("shares", id(result))
        if key not in self._cache:
            self._cache[key] = kinetic_by_body(result)
        names = list(self.model.bodies)
        dom = tuple(b for b, _ in dominant_bodies(self._cache[key][mode], names))
        return dom or tuple(names)

    def _twist(self, pl, result, mode: int, sign: float, view) -> str:
        """Twist arrows of ``mode`` (render_twist) added to ``pl``; returns their caption."""
        pv = load_pyvista()
        angles, ref = referred_angles(self.model, sign * result.abs_shapes[:, mode])
        if ref is not None and angles.get(ref, 0.0) < 0:   # the reference turns the positive way
            angles = {b: -a for b, a in angles.items()}
        for _, start, vec, sgn in twist_arrows(self.shapes, angles, view.direction, view.size):
            L = float(np.linalg.norm(vec))
            pl.add_mesh(pv.Arrow(start=start, direction=vec / L, tip_length=min(0.5, 0.02 * view.size / L), tip_radius=0.35 * 0.5,
                                 shaft_radius=0.12 * 0.5, scale=L),
                        color=TWIST_COLORS[sgn < 0])
        if ref is None:
            return "arrows: each body's rotation about its own axis, to one scale (no speed ratios: no rigid-body mode)"
        return (f"arrows: each body's rotation about its own axis divided by its speed ratio to {ref} (the angle "
                f"referred to the {ref} shaft),\nlongest = largest; red turns with {ref}, blue against it")

    def mode_view(self, focus) -> View:
        """Camera of a mode image whose dominant bodies are ``focus`` (:meth:`mode_frame`)."""
        return self.mode_frame(focus)[0]

    def _box(self, names, frame=None):
        """(lowest, highest) corner of the undeformed surfaces of ``names``: global axes, or
        the coordinates along the columns of ``frame``."""
        P = np.vstack([np.asarray(reference_surface(self.model, n, self.shapes, self._cache).points)
                       for n in names])
        if frame is not None:
            P = P @ frame
        return P.min(axis=0), P.max(axis=0)

    def _opacity(self, name, focus, hidden) -> float:
        """A dominant body opaque, the others faint; seen along the shaft (``hidden``: other
        stages left out) a carrier is drawn at :data:`CARRIER_OPACITY` at most: its cheek
        would cover the planets it carries."""
        o = 1.0 if name in focus else CONTEXT_OPACITY
        if hidden and self._roles.get(name) == "carrier":
            o = min(o, CARRIER_OPACITY)
        return o

    def _planetary_stage(self, focus) -> bool:
        """Whether the bodies ``focus`` all belong to one planetary stage (one with planets)."""
        by_name = {b.name: b for b in self.model.scene.bodies}
        stages = {getattr(by_name.get(n), "stage", None) for n in focus}
        if len(stages) != 1 or None in stages:
            return False
        (stage,) = stages
        return any(b.stage == stage and b.role == "planet" for b in self.model.scene.bodies)

    def _encloses(self, focus, shown, axis) -> bool:
        """Whether a drawn body other than ``focus`` surrounds the focus across the shaft
        ``axis`` (a ring round its planets): framing the focus would cut it at the edges."""
        R = axis_frame(np.asarray(axis, float))[:, :2]
        lo, hi = self._box(focus, R)
        for n in shown:
            if n not in focus:
                a, b = self._box([n], R)
                if np.all(a <= lo) and np.all(b >= hi):
                    return True
        return False

    def mode_frame(self, focus) -> tuple[View, tuple]:
        """(camera, bodies left out) of a mode image whose dominant bodies are ``focus``.

        A box whose stages lie one behind another is seen from the side
        (:func:`assembly.app.render.views.wants_side_view`); a mode held by one of its
        planetary stages is seen from the front instead, its own stage only: the bodies lying outside the
        focus's axial span (other stages, in front of or behind it) are left out, so the
        planets are not hidden behind a ring seen edge-on. The camera frames ``focus`` when
        that magnifies it at least :data:`MIN_ZOOM` times over the drawn bodies and no drawn
        body surrounds it (a ring round its planets would be cut at the title and the colour
        bar); else it frames them all (the assembly's own view when none is left out)."""
        shapes = self.shapes
        first = shapes[focus[0]]
        axis = first.axes[:, 2]
        side, across = wants_side_view(shapes)
        hidden: tuple = ()
        if side and self._planetary_stage(focus) and not wants_side_view({n: shapes[n] for n in focus})[0]:
            z = {n: float(shapes[n].position @ axis) for n in shapes}
            half = max(0.5 * shapes[n].width + abs(shapes[n].axial_offset) for n in focus)
            lo, hi = min(z[n] for n in focus) - half, max(z[n] for n in focus) + half
            hidden = tuple(n for n in shapes if n not in focus and not lo <= z[n] <= hi)
            side = False
        shown = [n for n in self.model.bodies if n not in hidden]
        whole = frame_view(*self._box(shown), axis, self.window_size, side, across) if hidden else self.view
        if len(focus) == len(shown) or self._encloses(focus, shown, axis):
            return whole, hidden
        zoom = frame_view(*self._box(focus), axis, self.window_size, side, across)
        return (zoom if whole.parallel_scale >= MIN_ZOOM * zoom.parallel_scale else whole), hidden

    def mode_drawing(self, result, mode: int, focus=None, twist: bool = False) -> ModeDrawing:
        """What every drawing of ``mode`` shares (:class:`ModeDrawing`): its sign, the dominant
        bodies ``focus`` (default :meth:`focus_bodies`), the camera and the bodies left out
        (:meth:`mode_frame`), the deformation scale (0 with ``twist``: drawn rotations would
        swell the fast discs over their arrows) and the largest displacement."""
        sign = _sign(result.abs_shapes[:, mode])
        focus = tuple(focus) if focus else self.focus_bodies(result, mode)
        view, hidden = self.mode_frame(focus)
        scale, dmax = self.mode_scale(result, mode, view.size, hidden)
        return ModeDrawing(mode, sign, focus, view, tuple(hidden), 0.0 if twist else scale, dmax)

    def mode_meshes(self, result, drawing: ModeDrawing, phase: float = 1.0) -> dict:
        """The moving parts of a mode drawing at ``phase`` x the drawn deformation (1: the
        still image; -1: its mirror): {"bodies": [...], "tubes": [...], "springs": [...],
        "marks": [...]}, each a list of (pyvista mesh, add_mesh keyword arguments). Bodies and
        tubes are coloured by the displacement at that phase over the largest drawn
        (``|phase|`` x the still's colour). Phase 0 is the undeformed drawing, made from the
        reference surfaces without evaluating the shape (a flexible body's back-expansion)."""
        pv = load_pyvista()
        scale, norm, hidden = phase * drawing.scale, drawing.dmax if drawing.dmax > 0 else 1.0, drawing.hidden
        rest = phase == 0

        def shape_of(b):
            return None if rest else drawing.sign * result.abs_shapes[self.model.body_slice(b), drawing.mode]

        out = {"bodies": [], "tubes": [], "springs": [], "marks": []}
        clim = (0.0, 1.0)                  # displacement over the largest drawn: a shape has no size
        bar = dict(title="", vertical=False, position_x=BAR_X, position_y=BAR_Y, width=BAR_W, height=BAR_H,
                   n_labels=0, color="black")
        for n in self.model.bodies:
            if n in hidden:
                continue
            if rest:
                m = reference_surface(self.model, n, self.shapes, self._cache).copy()
                m["normalised displacement"] = np.zeros(m.n_points)
            else:
                m = body_actor(self.model, n, shape_of(n), scale, self.shapes, self._cache)
                m["normalised displacement"] = abs(phase) * np.asarray(m["displacement_m"]) / norm
            out["bodies"].append((m, dict(scalars="normalised displacement", cmap=CMAP, clim=clim,
                                          show_scalar_bar=not out["bodies"], scalar_bar_args=bar,
                                          opacity=self._opacity(n, drawing.focus, hidden),
                                          smooth_shading=True, split_sharp_edges=True, feature_angle=40.0)))
        for tube in self._tubes(None if rest else shape_of, scale, hidden):
            tube["normalised displacement"] = abs(phase) * np.asarray(tube["displacement_m"]) / norm
            out["tubes"].append((tube, dict(scalars="normalised displacement", cmap=CMAP, clim=clim,
                                            show_scalar_bar=False, smooth_shading=True)))
        out["springs"] = self._spring_lines(shape_of, scale, drawing.view, hidden)
        for name, sh in self.shapes.items():
            bm = self.model.bodies[name]
            if bm.flexible or name in hidden:
                continue
            P = index_mark(sh)
            if not rest:
                P = P + scale * rigid_displacement(rigid_part(bm, shape_of(name)), bm.position, P)
            out["marks"].append((pv.Line(*P), dict(color="black", line_width=4, render_lines_as_tubes=True)))
        return out

    def draw_mode(self, pl, drawing: ModeDrawing, meshes: dict, text_scale: float = 1.0) -> None:
        """Add the moving meshes of a mode drawing (:meth:`mode_meshes`: {kind: [(mesh,
        add_mesh keyword arguments)]}) to plotter ``pl`` over the ghost, with the beam shafts'
        centre lines, the housing cubes and the colour bar's labels (placed for ``pl``'s
        window, fonts ``text_scale`` x the still's)."""
        self.ghost(pl, drawing.hidden)
        for m, kw in meshes["bodies"]:
            pl.add_mesh(m, **kw)
        W, H = pl.window_size
        for frac, label in ((0.0, "0"), (0.5, "0.5"), (1.0, "1")):   # the bar's labels, below it
            x = (BAR_X + BAR_W * frac) * W - 0.3 * 16 * text_scale * len(label)
            pl.add_text(label, position=(int(x), int(0.028 * H)), font_size=round(12 * text_scale), color="black")
        _backed(pl.add_text("displacement / largest", position=(int(BAR_X * W), int(0.115 * H)),
                            font_size=round(11 * text_scale), color="black"))
        for m, kw in meshes["tubes"]:
            pl.add_mesh(m, **kw)
        pv = load_pyvista()
        for sg in self.segments:
            if sg.body_a not in drawing.hidden and sg.body_b not in drawing.hidden:
                pl.add_mesh(pv.Line(sg.a, sg.b), color=GHOST_COLOR, line_width=1)
        for m, kw in meshes["springs"]:
            pl.add_mesh(m, **kw)
        self._ground(pl, drawing.hidden)
        for m, kw in meshes["marks"]:
            pl.add_mesh(m, **kw)

    def render_mode(self, result, mode: int, path, title: str = "", subtitle: str = "",
                    focus=None, twist: bool = False) -> Path:
        """Mode ``mode`` (0-based index into ``result``) drawn deformed over a ghost (PNG),
        framed on the bodies ``focus`` (default: the mode's dominant bodies,
        :meth:`focus_bodies`); the other bodies are drawn faint, as context. Beam shafts are
        tubes bent with their nodes (:mod:`assembly.app.render.shafts`). The colour bar
        runs from 0 to 1: the displacement over the largest drawn (a mass-normalised shape has
        no physical size; the caption states the length that largest is drawn as). ``twist``: arrows of each body's rotation
        about its axis referred to the rotor (:mod:`assembly.app.render.twist`)."""
        drawing = self.mode_drawing(result, mode, focus, twist)
        focus, view, hidden = drawing.focus, drawing.view, drawing.hidden
        pl = self.plotter()
        try:
            self.draw_mode(pl, drawing, self.mode_meshes(result, drawing))
            _backed(pl.add_text(title, position="upper_left", font_size=15, color="black"))
            text = mode_caption(drawing.scale, view.size, focus, len(focus) < len(self.model.bodies), hidden)
            if twist:
                text += "\n" + self._twist(pl, result, mode, drawing.sign, view)
            if subtitle:
                text = subtitle + "\n" + text
            _backed(pl.add_text(text, position=(12, self.window_size[1] - 85 - 24 * text.count("\n")), font_size=10,
                                color="#202020"))
            self._finish(pl, path, view)
        finally:
            pl.close()
        return Path(path)


@dataclass(frozen=True)
class ModeDrawing:
    """What every drawing of one mode shares: the mode (0-based), the sign that makes its
    largest entry positive, its dominant bodies, the camera, the bodies left out
    (:meth:`AssemblyRenderer.mode_frame`), the deformation scale (m drawn per m) and the
    largest unscaled displacement (m at modal mass 1 kg; the colour bar's 1)."""

    mode: int
    sign: float
    focus: tuple
    view: View
    hidden: tuple
    scale: float
    dmax: float


def mode_caption(scale: float, size: float, focus, faint: bool, hidden=()) -> str:
    """Caption line of a mode image: how the shape is drawn (a mode shape has no physical
    size: its largest displacement is drawn as a stated length, the colour is the displacement
    over that largest), the framed bodies, and the bodies left out (:meth:`AssemblyRenderer.mode_frame`)."""
    text = ("shape scaled: largest displacement drawn as "
            f"{1e3 * DEFORMATION_FRACTION * size:.3g} mm ({100 * DEFORMATION_FRACTION:.0f} % of the framed size); "
            "colour = displacement / largest" if scale > 0
            else "bodies drawn undeformed, coloured by displacement / largest")
    if faint:
        names = ", ".join(focus[:4]) + (f" and {len(focus) - 4} more" if len(focus) > 4 else "")
        text += "\nmost kinetic energy in " + names + "; other bodies faint"
    if hidden:
        text += f"\nseen along the shaft: {len(hidden)} bodies of other stages left out"
    return text


def _sign(v: np.ndarray) -> float:
    """+1/-1 making the largest-magnitude entry of ``v`` positive (deterministic sign)."""
    if v.size == 0:
        return 1.0
    i = int(np.argmax(np.abs(v)))
    return -1.0 if v[i] < 0 else 1.0


def mode_title(scene_name: str, info) -> str:
    """Image title: mode number, frequency (Hz), class (elastic: body and nodal diameters),
    scope (global, or the stage holding the mode) and multiplicity."""
    mult = f", x{info.multiplicity} repeated" if info.multiplicity > 1 else ""
    if getattr(info, "scope", None) == "global":
        stage = ", global"
    else:
        stage = f", stage '{info.stage}'" if info.stage and info.mode_class != "elastic" else ""
    label = getattr(info, "label", info.mode_class)
    return (f"{scene_name}\nmode {info.index + 1}: {info.frequency_hz:.2f} Hz, "
            f"{label}{stage}{mult}")
