"""The housing's motion and gravity as loads on every body: d'Alembert forces of the frame.

The model's coordinates are measured from the housing (the bearings' and shafts' frame), so a
prescribed housing motion -- a nacelle's translation and rotation ``a_h(t) = [a; alpha]`` at a
reference point ``p0`` (6 values, global axes) -- moves every mass point with it, and in the
housing's frame each body feels the inertia load of that rigid motion:

    f_z = -M_abs r a_h,   f_q = T' f_z,

``r`` (n_abs x 6) the housing's rigid-body field on the absolute coordinates z (a rigid body:
the rigid transfer from ``p0`` to its centre of mass; a flexible body: its own rigid motions
about its centre of mass in its axes, ``rigid_local``, driven by that transfer -- for a
Craig-Bampton superelement its master nodes moved rigidly and its fixed-interface modes 0),
``T`` the map z = T q, so that ``f_q`` is the virtual work of ``f_z`` on q (a DOF
held to the housing takes its share as a reaction). Gravity is the same load with ``a_h =
[-g; 0]``: ``g`` the gravity vector in the model's axes (the shaft tilt turns it).

Terms kept: the frame's translational and angular accelerations; left out: the centrifugal and
Coriolis terms of the frame's angular *velocity* (second order in a nacelle's small rotations)
and the frame's motion's effect on the stiffness.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import SceneError
from ..mechanics.kinematics import block_rotation, rigid_transfer


def housing_field(model, origin=(0.0, 0.0, 0.0)) -> np.ndarray:
    """``r`` (n_abs x 6): every absolute coordinate's motion under a unit rigid motion of the
    housing at ``origin`` (module notes)."""
    r = np.zeros((model.n_abs, 6))
    for name, body in model.bodies.items():
        to_body = rigid_transfer(body.position, origin)     # the motion at the body's centre of mass
        rigid_local = getattr(body, "rigid_local", None)
        if rigid_local is None:                             # a rigid body: its 6 DOFs there, global axes
            r[model.body_slice(name)] = to_body
        else:                                               # its rigid motions about it, in its own axes
            r[model.body_slice(name)] = np.asarray(rigid_local) @ (block_rotation(body.axes).T @ to_body)
    return r


def frame_loads(model, origin=(0.0, 0.0, 0.0)) -> np.ndarray:
    """``L`` (n_q x 6) with ``f_q = L a_h``: the inertia load of a housing acceleration ``a_h``
    (module notes)."""
    r = housing_field(model, origin)
    return -(model.T.T @ (model.M_abs @ r))


def tilted(g, tilt_deg: float) -> np.ndarray:
    """Gravity ``g`` (m/s^2, model axes) turned by the shaft ``tilt_deg`` about the model's x axis."""
    c, s = math.cos(math.radians(tilt_deg)), math.sin(math.radians(tilt_deg))
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]) @ np.asarray(g, float)


def gravity_load(model, g=(0.0, -9.80665, 0.0), tilt_deg: float = 0.0) -> np.ndarray:
    """``f_q`` (n_q,) of gravity ``g`` (m/s^2, model axes) turned by the shaft ``tilt_deg`` about
    the model's x axis (module notes: the load of a housing accelerating at ``-g``)."""
    return frame_loads(model) @ np.concatenate([-tilted(g, tilt_deg), np.zeros(3)])


#: Standard gravity (m/s^2).
STANDARD_GRAVITY = 9.80665


def scene_gravity(model, turbine) -> np.ndarray | None:
    """The gravity load on q of a scene's ``[turbine]`` table (``gravity`` true: standard gravity
    along -y turned by its ``tilt``), or None. A tilt left to an OpenFAST deck is refused here:
    the deck is read by time-domain runs only (:mod:`assembly.dynamics.turbine_run`)."""
    if turbine is None or not turbine.gravity:
        return None
    if turbine.tilt is None and turbine.openfast is not None:
        raise SceneError("turbine.tilt", None, "missing: a static run takes the shaft tilt from the scene "
                                               "(the deck's ShftTilt is read by simulate only)")
    return gravity_load(model, (0.0, -STANDARD_GRAVITY, 0.0), math.degrees(turbine.tilt or 0.0))


def body_weights(model, turbine) -> list:
    """[(body, centre of mass (3,), wrench (6,) N, N m there)]: the resultant of the scene's
    gravity load (:func:`scene_gravity`; [] without) on each body's coordinates -- its mass
    matrix's, so a beam shaft's mass lumped on the bodies it joins is in it -- for the static
    report's applied loads and equilibrium check. A body held to the housing in every direction
    is left out: its weight goes into the housing, not into the model."""
    if scene_gravity(model, turbine) is None:
        return []
    g = tilted((0.0, -STANDARD_GRAVITY, 0.0), math.degrees(turbine.tilt or 0.0))
    Fz = -(model.M_abs @ (housing_field(model) @ np.concatenate([-g, np.zeros(3)])))
    T = model.T
    out = []
    for name, body in model.bodies.items():
        sl = model.body_slice(name)
        if np.count_nonzero(T[sl].toarray() if hasattr(T, "toarray") else T[sl]) == 0:
            continue
        rigid_local = getattr(body, "rigid_local", None)
        w = Fz[sl] if rigid_local is None else block_rotation(body.axes) @ (np.asarray(rigid_local).T @ Fz[sl])
        out.append((name, np.asarray(body.position, float), np.asarray(w, float)))
    return out
