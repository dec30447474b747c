"""How to push on and read an assembled model: the one public place that knows how a load
enters the coordinates ``q`` and how a motion or a strain is read from them.

* where a load acts (:func:`load_point`) and its load vector by virtual work, ``T' P' w``
  (:func:`point_vector`, :func:`unit_wrench`), on a body named ``BODY`` or
  ``BODY:INTERFACE`` (:func:`body_point`, :func:`interfaces`);
* what a body or an element does: a body's rotation about its own axis
  (:func:`axial_rotation`, :func:`spin_row`), an element's strains (:func:`strain_rows`).

Inputs and outputs of a frequency response (:mod:`assembly.dynamics.frf_channels`), the
loads and outputs of a time-domain run, the static load cases and the drivetrain's
kinematics all read the model through these. SI units.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from ..arguments import nearest
from ..errors import SceneError
from ..mechanics.dense import dense
from ..scene.attach import global_masters
from ..scene.tables import DOF_NAMES


def body_point(model, where: str, arg: str, name: str) -> tuple[str, Optional[str]]:
    """(body, interface) of ``where``, ``BODY`` or ``BODY:INTERFACE`` (a flexible body needs its
    interface); SceneError at the field ``arg`` with the value ``name`` that wrote it otherwise."""
    if where in model.bodies:
        if model.bodies[where].flexible:
            raise SceneError(arg, name, f"{where!r} is flexible: name one of its interfaces "
                                        f"{interfaces(model, where)} as {where}:INTERFACE")
        return where, None
    body, _, iface = where.rpartition(":")
    if body in model.bodies:
        have = interfaces(model, body)
        if iface in have:
            return body, iface
        raise SceneError(arg, name, f"body {body!r} has no interface {iface!r}; it has {have}")
    raise SceneError(arg, name, f"no body {where!r}; bodies: {sorted(model.bodies)}{nearest(where, model.bodies)}")


def interfaces(model, body: str) -> list:
    """The interfaces of ``body``: a flexible body's masters, a rigid body's component
    interfaces (none for a plain body)."""
    bm = model.bodies[body]
    if bm.flexible:
        return sorted(bm.masters)
    b = next(b for b in model.scene.bodies if b.name == body)
    return sorted(global_masters(b)) if b.component is not None else []


def load_point(model, body: str, interface: str | None = None, point=None) -> np.ndarray:
    """Where a load or support acts (m, global): the master of ``interface`` (a component
    body), else ``point``, else the body's axis point (a flexible body: its position)."""
    bm = model.bodies[body]
    if interface is not None:
        if bm.flexible:
            return np.asarray(bm.masters[interface][0], float)
        return np.asarray(global_masters(next(b for b in model.scene.bodies if b.name == body))[interface], float)
    if point is not None:
        return np.asarray(point, float)
    return np.asarray(bm.position if bm.flexible else bm.axis_point, float)


def unit_wrench(model, body: str, what: str) -> np.ndarray:
    """Unit wrench (global axes) of a direction ``x..rz`` or ``spin`` (about the axis)."""
    w = np.zeros(6)
    if what == "spin":
        w[3:] = model.bodies[body].axes[:, 2]
    else:
        w[DOF_NAMES.index(what)] = 1.0
    return w


def point_vector(model, body: str, iface: Optional[str], wrench: np.ndarray) -> np.ndarray:
    """``T' P' w``: the virtual work of the wrench ``w`` (global, at the load point) on q."""
    bm = model.bodies[body]
    P = bm.motion_at(load_point(model, body, iface), iface)
    F = np.zeros(model.n_abs)
    F[model.body_slice(body)] = np.asarray(P.T @ wrench).ravel()
    return np.asarray(model.T.T @ F).ravel()


def axial_rotation(model, Z: np.ndarray, body: str) -> np.ndarray:
    """Rotation (rad) of ``body`` about its own axis (rigid-equivalent) for columns of ``Z``
    (absolute coordinates)."""
    bm = model.bodies[body]
    return bm.axes[:, 2] @ bm.rigid_projection()[3:] @ Z[model.body_slice(body)]


def spin_row(model, body: str) -> np.ndarray:
    """Row on q of ``body``'s rotation (rad) about its own axis (:func:`assembly.analysis.load_cases.axial_rotation`
    of the columns of ``T``)."""
    return np.asarray(axial_rotation(model, model.T, body)).ravel()


def strain_rows(model, el) -> np.ndarray:
    """The element's strains on q, ``B A T`` (one row per spring direction; a mesh: its
    deflection along the line of action)."""
    return el.B @ dense(model.attachment_operator(el) @ model.T)
