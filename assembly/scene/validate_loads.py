"""Rules of the static load cases (``[load]`` / ``[[loads]]``): the torque case's bodies
and interfaces, point loads (``forces``) and per-case supports (``supports``).

Fidelity does not enter: a component body takes an ``interface`` (its master node) and a
plain body a ``point`` at any fidelity, so a scene's torsional, rigid and flexible
variants accept the same load cases. Whether a case's held model can still move is decided
at the solve (:func:`assembly.analysis.static.solve_static_cases`), from the structure of the
springs.
"""
from __future__ import annotations

from ..errors import SceneError
from .attach import interface_point
from .tables import DOF_NAMES, HOUSING, LoadCase

_TORQUE_FIELDS = ("input", "output", "torque")


def check_load(load: LoadCase, path: str, names: dict, masters: dict) -> None:
    """One load case: a torque case complete or absent, something applied, and every
    point load and support valid."""
    given = [f for f in _TORQUE_FIELDS if getattr(load, f) is not None]
    if given and len(given) < len(_TORQUE_FIELDS):
        missing = next(f for f in _TORQUE_FIELDS if getattr(load, f) is None)
        raise SceneError(f"{path}.{missing}", None, f"a torque case needs input, output and torque together "
                                                   f"(given: {given}); give all three or none")
    if given:
        _check_torque_case(load, path, names, masters)
    else:
        for role in ("input", "output"):
            if getattr(load, f"{role}_interface") is not None:
                raise SceneError(f"{path}.{role}_interface", getattr(load, f"{role}_interface"),
                                 f"no {role} body: the interface belongs to a torque case")
        if not load.forces:
            raise SceneError(f"{path}.forces", [], "the case applies nothing: give input, output and torque, "
                                                   "or [[loads.forces]]")
    for j, pl in enumerate(load.forces):
        p = f"{path}.forces[{j}]"
        body = _body(pl.body, f"{p}.body", names)
        _check_where(body, pl.interface, pl.point, p, masters)
        if not any(pl.force) and not any(pl.moment):
            raise SceneError(f"{p}.force", list(pl.force), "force and moment are both zero: the load does nothing")
    for j, su in enumerate(load.supports):
        p = f"{path}.supports[{j}]"
        body = _body(su.body, f"{p}.body", names)
        _check_where(body, su.interface, None, p, masters)
        if not su.dofs:
            raise SceneError(f"{p}.dofs", [], f"hold at least one of {list(DOF_NAMES)}")
        for i, d in enumerate(su.dofs):
            if d not in DOF_NAMES:
                raise SceneError(f"{p}.dofs[{i}]", d, f"must be one of {list(DOF_NAMES)}")
            if d in su.dofs[:i]:
                raise SceneError(f"{p}.dofs[{i}]", d, "given twice")


def _check_torque_case(load: LoadCase, path: str, names: dict, masters: dict) -> None:
    """Two different bodies (torque range: the field rule), the output riding in the
    housing frame (it is held relative to the housing), and the interface where the torque
    enters / the output is held on a component body."""
    for f in ("input", "output"):
        _body(getattr(load, f), f"{path}.{f}", names)
    if load.input == load.output:
        raise SceneError(f"{path}.output", load.output, "input and output must differ")
    out = names[load.output]
    if out.frame != HOUSING:
        raise SceneError(f"{path}.output", load.output, f"the reacting body rides in {out.frame!r}'s frame; it is "
                                                        "held against the housing, so it must ride in the housing frame")
    for role in ("input", "output"):
        body, iface = names[getattr(load, role)], getattr(load, f"{role}_interface")
        if body.component is not None and iface is None:
            raise SceneError(f"{path}.{role}_interface", None, f"{body.name} is a component: name the interface "
                             + ("the torque enters at" if role == "input" else "it is held at")
                             + f"; have {sorted(masters[body.name])}")
        if iface is not None:
            interface_point(body, iface, masters, f"{path}.{role}_interface")


def _body(name, path: str, names: dict):
    if name not in names:
        raise SceneError(path, name, f"no body of that name; have {sorted(names)}")
    return names[name]


def _check_where(body, interface, point, path: str, masters: dict) -> None:
    """A component body is loaded or held at a named interface (its master node), a plain
    body at a point (default its position); never both."""
    if interface is not None and point is not None:
        raise SceneError(f"{path}.point", list(point), "give either point or interface, not both")
    if body.component is not None:
        if point is not None:
            raise SceneError(f"{path}.point", list(point), f"{body.name} is a component: load it at one of its "
                                                           f"interfaces {sorted(masters[body.name])}, not at a point")
        if interface is None:
            raise SceneError(f"{path}.interface", None, f"{body.name} is a component: name one of its interfaces "
                                                        f"{sorted(masters[body.name])}")
    interface_point(body, interface, masters, f"{path}.interface")

