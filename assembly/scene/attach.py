"""Where springs attach: body positions, or interface master nodes of component bodies.

A component body's local point ``x`` sits at ``position + R x`` with ``R = axis_frame(axis)``
(local z = the body's axis).

Master positions come from the component geometry alone (no meshing), so a scene is
validated -- and its rigid and torsional variants attach their springs at the very same
points as the flexible one -- before anything is meshed.
"""
from __future__ import annotations

import numpy as np

from ..errors import SceneError
from ..mechanics.kinematics import axis_frame


def local_masters(params) -> dict:
    """Interface name -> master position in the component's local axes (m); no meshing."""
    from fe_components.geometry import interface_defs
    return {d.name: np.asarray(d.master, float) for d in interface_defs(params)}


def placement(body):
    """(origin (3,), R (3x3)) mapping local component points to global: x_g = o + R x."""
    return np.asarray(body.position, float), axis_frame(body.axis)


def global_masters(body) -> dict:
    """Interface name -> global master position (m) of a placed component body."""
    o, R = placement(body)
    return {k: o + R @ v for k, v in local_masters(body.component).items()}


def component_masters(scene) -> dict:
    """Body name -> {interface: global master position (m)} for bodies with a component."""
    out = {}
    for b in scene.bodies:
        if b.component is not None:
            out[b.name] = global_masters(b)
    return out


def interface_point(body, interface, masters: dict, path: str, default_interface=None):
    """Global attachment point on ``body`` and the interface used (None for plain bodies)."""
    if body.component is None:
        if interface is not None:
            raise SceneError(path, interface, f"body {body.name!r} has no component, hence no interfaces")
        return np.asarray(body.position, float), None
    have = masters[body.name]
    name = interface or default_interface
    if name is None:
        raise SceneError(path, None, f"body {body.name!r} is a component: name one of its interfaces "
                                     f"{sorted(have)}")
    if name not in have:
        raise SceneError(path, name, f"no such interface on {body.name!r}; have {sorted(have)}")
    return have[name], name


def mesh_centers(mesh, b1, b2, masters: dict, path: str):
    """Gear centres (global) and interfaces of a mesh; explicit centre1/2 win."""
    p1, i1 = interface_point(b1, mesh.interface1, masters, f"{path}.interface1", "gear_mesh")
    p2, i2 = interface_point(b2, mesh.interface2, masters, f"{path}.interface2", "gear_mesh")
    c1 = np.asarray(mesh.center1, float) if mesh.center1 is not None else p1
    c2 = np.asarray(mesh.center2, float) if mesh.center2 is not None else p2
    return c1, c2, i1, i2


def bearing_point(br, body, masters: dict, path: str):
    p, iface = interface_point(body, br.interface, masters, f"{path}.interface")
    if br.position is not None:
        p = np.asarray(br.position, float)
    return p, iface


def shaft_points(s, b1, b2, masters: dict, path: str):
    p1, i1 = interface_point(b1, s.interface1, masters, f"{path}.interface1")
    p2, i2 = interface_point(b2, s.interface2, masters, f"{path}.interface2")
    point = np.asarray(s.position, float) if s.position is not None else 0.5 * (p1 + p2)
    return point, i1, i2
