"""Stage labels of the overview image: one callout per stage, placed clear of the drawing.

Bodies are grouped by their scene ``stage`` label (a body without one is its own group);
each group gets one text label, e.g. ``"stage1 (planetary)"``, on a leader line from the
middle of its bodies' top (or bottom) edge in the image to a row of labels above (or
below) the whole drawing. Labels are placed greedily from left to right into the first row
whose labels they do not overlap (rows nearest the drawing first; above for a group in the
upper half of the drawing, else below first), so neighbouring stages of a long drivetrain
do not write over each other. Pure numpy.
"""
from __future__ import annotations

import numpy as np

#: Width of one character of a label (pixels per point of font size), an estimate for the
#: overlap test, and the gap between label rows (pixels).
CHAR_WIDTH = 0.95
ROW_GAP_PX = 10
#: Height of a label row (pixels per point of font size).
ROW_HEIGHT = 2.0


def stage_groups(scene, gears) -> dict:
    """Group key -> (label text, body names), in scene order. ``gears``: names of the
    bodies with gear geometry. The text names the kind of stage: planetary (it has planets),
    parallel (gears, no planets), lumped (a rotor body, drawn as a hub)."""
    groups: dict = {}
    for b in scene.bodies:
        groups.setdefault(b.stage or b.name, []).append(b)
    out = {}
    for key, bodies in groups.items():
        roles = {b.role for b in bodies}
        if "planet" in roles:
            kind = "planetary"
        elif any(b.name in gears for b in bodies):
            kind = "parallel" if len(bodies) > 1 else ""
        elif "rotor" in roles:
            kind = "lumped"
        else:
            kind = ""
        text = f"{key} ({kind})" if kind and bodies[0].stage else key
        out[key] = (text, [b.name for b in bodies])
    return out


def place_labels(boxes: dict, texts: dict, font_size: int, lo: float, hi: float) -> dict:
    """Key -> (x, y, side) in pixels for each group's label: ``boxes`` maps a key to its
    bodies' pixel box (x_min, x_max, y_min, y_max); ``lo``/``hi``: the drawing's lowest and
    highest pixel row. ``side`` is +1 (row above) or -1 (below); y is the label's
    baseline row, x its centre."""
    row_h = font_size * ROW_HEIGHT + ROW_GAP_PX
    rows: dict = {}   # (side, k) -> [(x0, x1)]
    out = {}
    order = sorted(boxes, key=lambda k: 0.5 * (boxes[k][0] + boxes[k][1]))
    for key in order:
        x0, x1, y0, y1 = boxes[key]
        xc = 0.5 * (x0 + x1)
        half = 0.5 * CHAR_WIDTH * font_size * len(texts[key]) + 4
        sides = (1, -1) if y0 + y1 >= lo + hi else (-1, 1)   # the nearer edge of the drawing first
        for k in range(len(order)):
            hit = None
            for side in sides:
                taken = rows.setdefault((side, k), [])
                if all(xc + half < a or xc - half > b for a, b in taken):
                    hit = side
                    break
            if hit is not None:
                rows[(hit, k)].append((xc - half, xc + half))
                y = hi + ROW_GAP_PX + k * row_h if hit > 0 else lo - ROW_GAP_PX - (k + 1) * row_h
                out[key] = (xc, y, hit)
                break
    return out


def pixel_box(points, right, up, focal, ppm: float, window_size) -> tuple:
    """Pixel box (x_min, x_max, y_min, y_max) of ``points`` (n, 3) in a parallel projection
    seen with ``right``/``up`` about ``focal`` at ``ppm`` pixels per metre."""
    W, H = window_size
    d = np.asarray(points, float).reshape(-1, 3) - focal
    x, y = W / 2 + (d @ right) * ppm, H / 2 + (d @ up) * ppm
    return float(x.min()), float(x.max()), float(y.min()), float(y.max())
