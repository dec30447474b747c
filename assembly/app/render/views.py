"""Fixed cameras of the images: a parallel projection fitted to the undeformed drawing.

The default view looks obliquely along the shaft axis (:func:`view_axes`); a multi-stage box
whose bodies lie one behind another along the axis is seen from the side instead
(:func:`wants_side_view`). A view is fitted to the drawing's points between the title band
at the top and the colour bar and scale bar at the bottom (:data:`FILL_V`, :data:`FILL_H`),
with room around it for the drawn deformation (:data:`DEFORMATION_FRACTION` of its size).
It depends only on the undeformed assembly, so images are identical from run to run.
Pure numpy: :func:`place_camera` only sets a plotter's camera.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...mechanics.kinematics import axis_frame
from .shapes import assembly_size, solid_surface

#: Largest drawn displacement as a fraction of the assembly size (bounding-box diagonal): the
#: deformation scale of a mode image, and the room a view leaves around the drawing for it.
DEFORMATION_FRACTION = 0.10
#: Default image size (pixels).
WINDOW_SIZE = (1200, 900)
#: Vertical / horizontal fraction of the image the fitted drawing may fill (the rest:
#: title band at the top, colour bar and scale bar at the bottom).
FILL_V, FILL_H = 0.76, 0.97
#: Side view (perpendicular to the shafts) when the bodies' centres spread along the shaft
#: axis by more than this fraction of the largest body radius (stages one behind another).
SIDE_VIEW_SPREAD = 0.5


@dataclass
class View:
    """Fixed camera of an assembly: parallel projection from its bounding box."""

    focal: np.ndarray
    direction: np.ndarray  # from focal point towards the camera
    up: np.ndarray
    parallel_scale: float
    size: float


def view_axes(axis, side: bool = False, across=None) -> tuple[np.ndarray, np.ndarray]:
    """(direction from the focal point towards the camera, view-up), unit vectors.

    Oblique front view along the shaft ``axis`` (default), or a side view looking
    perpendicular to the axis and to ``across`` (the transverse direction along which the
    shafts lie apart), slightly from the front and above, so shafts appear side by side."""
    R = axis_frame(np.asarray(axis, float))
    ax, e1, e2 = R[:, 2], R[:, 0], R[:, 1]
    if side:
        a = e2 if across is None else np.asarray(across, float) - (np.asarray(across, float) @ ax) * ax
        a = a / np.linalg.norm(a) if np.linalg.norm(a) > 1e-12 else e2
        n = np.cross(ax, a)
        direction, up0 = n + 0.30 * ax + 0.25 * a, a
    else:
        direction, up0 = ax * 1.0 + e1 * 0.35 - e2 * 0.45, e2
    direction = direction / np.linalg.norm(direction)
    up = up0 - (up0 @ direction) * direction
    return direction, up / np.linalg.norm(up)


def fit_view(P: np.ndarray, direction, up, window_size, size: float, margin: float) -> View:
    """Parallel-projection view of points ``P`` (n, 3) seen along ``direction``, with
    ``margin`` (m) around them, between the title band and the colour bar."""
    right = np.cross(up, direction)
    x, y = P @ right, P @ up
    xc, yc = 0.5 * (x.min() + x.max()), 0.5 * (y.min() + y.max())
    half_w = 0.5 * (x.max() - x.min()) + margin
    half_h = 0.5 * (y.max() - y.min()) + margin
    aspect = window_size[0] / window_size[1]
    scale = max(half_h / FILL_V, half_w / aspect / FILL_H)
    focal = P.mean(axis=0)
    focal = focal + right * (xc - focal @ right) + up * (yc - focal @ up) + up * 0.04 * scale
    return View(focal, np.asarray(direction, float), np.asarray(up, float), float(scale), float(size))


def assembly_view(shapes: dict, window_size=WINDOW_SIZE, extra_points=None) -> View:
    """Oblique front view along the (first) gear axis, fitted to the undeformed bodies (and
    ``extra_points``, e.g. spring ends) plus the largest drawn displacement, leaving room
    for the title (top) and the colour bar (bottom). Side view for bodies stacked along
    the axis (:func:`wants_side_view`)."""
    first = next(iter(shapes.values()))
    side, across = wants_side_view(shapes)
    direction, up = view_axes(first.axes[:, 2], side, across)
    size = assembly_size(shapes)
    pts = [solid_surface(s, n_radial=1)[0] for s in shapes.values()]
    if extra_points is not None and len(extra_points):
        pts.append(np.asarray(extra_points, float).reshape(-1, 3))
    return fit_view(np.vstack(pts), direction, up, window_size, size, (DEFORMATION_FRACTION + 0.02) * size)


def wants_side_view(shapes: dict) -> tuple[bool, np.ndarray | None]:
    """(side view?, transverse direction along which the bodies lie apart): side view when
    the body centres spread along the shaft axis by more than :data:`SIDE_VIEW_SPREAD` x the
    largest body radius (a multi-stage box, where the front view hides stages)."""
    first = next(iter(shapes.values()))
    ax = first.axes[:, 2]
    P = np.array([s.position for s in shapes.values()])
    z = P @ ax
    T = P - np.outer(z, ax)
    T = T - T.mean(axis=0)
    across = None
    if len(P) > 1 and np.abs(T).max() > 0:
        across = np.linalg.svd(T, full_matrices=False)[2][0]
    r_max = max(s.r_outer for s in shapes.values())
    return bool(np.ptp(z) > SIDE_VIEW_SPREAD * r_max), across


def frame_view(lo, hi, axis, window_size=WINDOW_SIZE, side: bool = False, across=None) -> View:
    """Camera framing the box ``lo``..``hi`` (m, global axes; e.g. a mode's dominant
    bodies) seen obliquely along the shaft ``axis`` (or from the side: :func:`view_axes`),
    with room for a drawn displacement of :data:`DEFORMATION_FRACTION` of the box diagonal
    (the ``size`` of the returned view)."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    corners = np.array([[(lo, hi)[i][0], (lo, hi)[j][1], (lo, hi)[k][2]]
                        for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    size = float(np.linalg.norm(hi - lo))
    direction, up = view_axes(axis, side, across)
    return fit_view(corners, direction, up, window_size, size, (DEFORMATION_FRACTION + 0.02) * size)


def project(view: View, points, window_size=WINDOW_SIZE) -> np.ndarray:
    """Pixel coordinates (x right, y up from the bottom-left corner) of ``points`` (n, 3)
    in the image of ``view`` (parallel projection, as :func:`place_camera` sets it)."""
    W, H = window_size
    right = np.cross(view.up, view.direction)
    d = np.asarray(points, float).reshape(-1, 3) - view.focal
    half = H / 2 / view.parallel_scale   # pixels per metre
    return np.column_stack([W / 2 + (d @ right) * half, H / 2 + (d @ view.up) * half])


def place_camera(plotter, view: View):
    cam = plotter.camera
    cam.parallel_projection = True
    cam.focal_point = tuple(view.focal)
    cam.position = tuple(view.focal + view.direction * 10 * view.size)
    cam.up = tuple(view.up)
    cam.parallel_scale = view.parallel_scale
    cam.clipping_range = (0.01 * view.size, 30 * view.size)
