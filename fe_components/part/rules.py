"""Geometric interface rules of a user's part, on sample points of its faces (numpy only).

A face (a CAD surface, or a boundary triangle of a mesh file) belongs to a rule when every
one of its sample points satisfies the rule within ``tol`` (m). Masters computed from the
selected faces: the area centroid; for a cylinder rule, that centroid projected onto the
axis (a bearing seat or pin bore is held on its axis).
"""
from __future__ import annotations

import numpy as np

from .file import InterfaceRule


def _unit(v) -> np.ndarray:
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def _in_box(rule: InterfaceRule, pts: np.ndarray, tol: float) -> np.ndarray:
    if rule.box_min is None:
        return np.ones(pts.shape[0], bool)
    lo, hi = np.asarray(rule.box_min) - tol, np.asarray(rule.box_max) + tol
    return np.all((pts >= lo) & (pts <= hi), axis=(1, 2))


def _cylinder_coords(rule: InterfaceRule, pts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(distance from the axis, position along it from axis_point) of each point (m)."""
    a = _unit(rule.axis)
    d = pts - np.asarray(rule.axis_point, float)
    s = d @ a
    return np.linalg.norm(d - s[..., None] * a, axis=-1), s


def faces_match(rule: InterfaceRule, pts: np.ndarray, tol: float) -> np.ndarray:
    """Which faces, each sampled by ``k`` points (``pts``: (n_faces, k, 3) [m]), belong to
    the geometric ``rule``: (n_faces,) bool."""
    pts = np.asarray(pts, float)
    if rule.select == "group":
        raise ValueError("a group rule selects by name, not by geometry")
    ok = _in_box(rule, pts, tol)
    if rule.select == "plane":
        ok &= np.all(np.abs((pts - np.asarray(rule.point, float)) @ _unit(rule.normal)) < tol, axis=1)
    elif rule.select == "cylinder":
        r, s = _cylinder_coords(rule, pts)
        if rule.span is not None:
            ok &= (s.min(axis=1) > rule.span[0] - tol) & (s.max(axis=1) < rule.span[1] + tol)
        if rule.outer_radius is None:
            ok &= np.all(np.abs(r - rule.radius) < tol, axis=1)
        else:  # a band between two radii: lateral faces only (a face normal to the axis spans no length)
            ok &= np.all((r > rule.radius - tol) & (r < rule.outer_radius + tol), axis=1) & (np.ptp(s, axis=1) > tol)
    return ok


def computed_master(rule: InterfaceRule, centroid: np.ndarray) -> np.ndarray:
    """Master position (m) of ``rule`` from the area centroid of its selected faces."""
    c = np.asarray(centroid, float)
    if rule.master is not None:
        return np.asarray(rule.master, float)
    if rule.select == "cylinder":
        a = _unit(rule.axis)
        p = np.asarray(rule.axis_point, float)
        return p + ((c - p) @ a) * a
    return c


def unreached(master: np.ndarray, lo: np.ndarray, hi: np.ndarray, part_size: float) -> float | None:
    """Distance (m) from ``master`` to the bounding box ``lo``..``hi`` of its interface's
    faces when it exceeds a tenth of the part's size (the part does not reach it), else None."""
    gap = float(np.linalg.norm(np.maximum(0.0, np.maximum(lo - master, master - hi))))
    return gap if gap > 0.1 * part_size else None
