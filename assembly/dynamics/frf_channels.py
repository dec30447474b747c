"""Inputs and outputs of a frequency response, parsed once into rows on the independent
coordinates ``q`` of an assembled model (``z = T q``).

Inputs (a unit load; its load vector ``T' P' w`` by virtual work, as
:func:`assembly.analysis.load_cases.load_vector` does, ``P`` the body's motion at the load point):

* ``torque:BODY[:INTERFACE]``: a couple of 1 N m about the body's own axis;
* ``force:BODY[:INTERFACE]:x|y|z``: 1 N along a global axis;
* ``moment:BODY[:INTERFACE]:x|y|z``: 1 N m about a global axis;
* ``mesh:MESH``: a pair of opposite 1 N forces along the line of action on the two gears
  (its load vector is the mesh deflection row: the forcing ``k e`` of a transmission error
  ``e``, positive as the mesh force of ``force:MESH``).

The load point is the interface master when one is named, else the body's axis point (a
flexible body: its position), :func:`assembly.analysis.load_cases.load_point`.

Outputs (one row per output, or two: ``out = (r_k + i omega r_c) q``):

* ``motion:BODY[:INTERFACE]:x|y|z|rx|ry|rz|spin``: the motion (m, rad; global axes; ``spin``
  about the body's own axis) at the same point an input of that body would act on -- the
  work-conjugate of that input, so ``H`` between such pairs is reciprocal;
* ``acceleration:BODY[:INTERFACE]:x|..|spin``: the second time derivative of that motion
  (m/s^2, rad/s^2);
* ``torque:SHAFT``: the section torque of a shaft element, ``(k + i omega c) e`` of its
  strain rows, taken about body1's axis (positive when body1 is twisted ahead of body2, as
  the static report, :mod:`assembly.analysis.reactions`); a beam shaft of several elements: its
  first element (at body1), or name an element ``SHAFT:A-B``;
* ``torque:BODY:INTERFACE``: the torque the body passes through an interface to the springs
  attached there (shafts, bearings, meshes), about its own axis -- a carrier's output torque
  without a shaft of its own: equal to a shaft's section torque where a shaft alone is
  attached (body1 the body);
* ``force:MESH``: the mesh force along the line of action, ``(k + i omega c) delta``
  (positive: the ``drive_sign`` flank in compression);
* ``force:BEARING[:x|y|z|rx|ry|rz]``: the force (N) or moment (N m) the bearing exerts on
  its body, in the bearing's axes, ``-(k + i omega c) e`` of that direction; without a
  direction, every direction that has a spring or damper. A rigid direction is a constraint,
  whose reaction no spring carries: asking for it is an error;
* ``stress:BODY:X,Y,Z``: von Mises stress (Pa) of a flexible body at the FE stress node
  nearest to the global point (X, Y, Z) in m (refused farther than :data:`STRESS_SNAP` of the
  body's size from every node): the six stress components, each linear in q by
  back-expansion (:meth:`assembly.model.flexible.FlexibleBodyModel.stress_rows`), are combined
  after the solve into the peak von Mises stress over one cycle
  (:func:`von_mises_peak`); a real amplitude, its phase reported as 0.

Internal loads (section loads) come from the element springs and dampers, never from
accelerations, plus each element's share of the scene's ``[damping]``
(:mod:`assembly.dynamics.damping`: Rayleigh beta as the element's ``beta k``; modal ratios
and alpha distributed mode by mode in proportion to the element's strain), so that every
body's balance holds with them. Unknown
names raise :class:`assembly.errors.SceneError` naming the argument and listing what exists.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..analysis.lever_arms import axis_line
from ..arguments import nearest
from ..errors import SceneError
from ..model.probes import body_point, point_vector, strain_rows, unit_wrench
from ..scene.tables import DOF_NAMES

AXES = ("x", "y", "z")
MOTIONS = DOF_NAMES + ("spin",)
VOIGT_NAMES = ("xx", "yy", "zz", "yz", "xz", "xy")
#: A stress point farther than this fraction of the body's bounding-box diagonal from every
#: FE stress node is refused (it lies off the body).
STRESS_SNAP = 0.02


@dataclass(frozen=True)
class Channel:
    """One input or output: ``name``, ``unit`` (SI) and its rows on q -- an input's load
    vector ``k_row`` (per unit load), an output's ``(k_row + i omega c_row) q`` (``c_row``
    None: no frequency-dependent part)."""

    name: str
    unit: str
    k_row: np.ndarray
    c_row: Optional[np.ndarray] = None
    group: Optional[str] = None     # a stress component: the von Mises output it feeds
    #: a section load (an element's force or a stress): it carries its share of the scene's
    #: damping (:mod:`assembly.dynamics.damping`) and vanishes in every rigid-body mode
    section: bool = False
    #: 0: the output is ``(k_row + i omega c_row) q``; 2: its second time derivative (an
    #: ``acceleration:`` output: the ``motion:`` rows applied to q'')
    derivative: int = 0


def input_channel(model, name: str, arg: str = "input") -> Channel:
    """The unit load vector on q of input ``name`` (module notes)."""
    kind, _, rest = name.partition(":")
    if kind == "torque" and rest:
        body, iface = body_point(model, rest, arg, name)
        return Channel(name, "N m", point_vector(model, body, iface, unit_wrench(model, body, "spin")))
    if kind in ("force", "moment") and rest:
        where, _, axis = rest.rpartition(":")
        if axis not in AXES or not where:
            raise SceneError(arg, name, f"{kind} input: {kind}:BODY[:INTERFACE]:x|y|z (global axes)")
        body, iface = body_point(model, where, arg, name)
        what = axis if kind == "force" else "r" + axis
        return Channel(name, "N" if kind == "force" else "N m", point_vector(model, body, iface,
                                                                               unit_wrench(model, body, what)))
    if kind == "mesh" and rest:
        el = next((e for e in model.elements if e.kind == "mesh" and e.name == rest), None)
        if el is None:
            raise SceneError(arg, name, f"no mesh {rest!r}; meshes: {_names(model, 'mesh')}"
                                        f"{nearest(rest, _names(model, 'mesh'))}")
        return Channel(name, "N", strain_rows(model, el)[0])
    raise SceneError(arg, name, "inputs are torque:BODY[:INTERFACE], force:BODY[:INTERFACE]:x|y|z, "
                                f"moment:BODY[:INTERFACE]:x|y|z, mesh:MESH; bodies: {sorted(model.bodies)}")


def output_channels(model, name: str, arg: str = "outputs") -> list[Channel]:
    """The output rows of ``name`` (one channel; a bearing without a direction: one per
    direction, named ``force:BEARING:d``)."""
    kind, _, rest = name.partition(":")
    if kind in ("motion", "acceleration") and rest:
        where, _, what = rest.rpartition(":")
        if what not in MOTIONS or not where:
            raise SceneError(arg, name, f"{kind} output: {kind}:BODY[:INTERFACE]:{'|'.join(MOTIONS)}")
        body, iface = body_point(model, where, arg, name)
        unit = "m" if what in AXES else "rad"
        order = 2 if kind == "acceleration" else 0
        return [Channel(name, unit + ("/s^2" if order else ""),
                        point_vector(model, body, iface, unit_wrench(model, body, what)), derivative=order)]
    if kind == "stress" and rest:
        return _stress_channels(model, rest, arg, name)
    elements = {el.name: el for el in model.elements}
    if kind == "torque" and rest:
        el = elements.get(rest) or next((e for e in model.elements if e.kind == "shaft"
                                          and e.name.startswith(rest + ":")), None)
        body, _, iface = rest.rpartition(":")
        if (el is None or el.kind != "shaft") and body in model.bodies and iface:
            return [_interface_channel(model, body, iface, arg, name)]
        if el is None or el.kind != "shaft":
            raise SceneError(arg, name, f"no shaft {rest!r}; shafts: {_names(model, 'shaft')}"
                                        f"{nearest(rest, _names(model, 'shaft'))}")
        a1 = model.bodies[el.bodies[0]].axes[:, 2]
        return [_element_channel(model, el, el.B[:, 3:6] @ a1, name, "N m")]
    if kind == "force" and rest:
        el = elements.get(rest)
        if el is not None and el.kind == "mesh":
            return [_element_channel(model, el, np.ones(1), name, "N")]
        return _bearing_channels(model, rest, elements, arg, name)
    raise SceneError(arg, name, "outputs are motion:BODY[:INTERFACE]:DOF, acceleration:BODY[:INTERFACE]:DOF, "
                                "torque:SHAFT, torque:BODY:INTERFACE, force:MESH, "
                                "force:BEARING[:x|y|z|rx|ry|rz], stress:BODY:X,Y,Z")


def _interface_channel(model, body: str, iface: str, arg: str, name: str) -> Channel:
    """``torque:BODY:INTERFACE``: the torque ``body`` passes through ``iface`` to what is attached
    there, about its own axis -- the sum over the springs attached at that interface of ``(k +
    i omega c) e`` weighted by each row's moment about the axis line, ``b . [a x (p - c); a]`` (a
    the body's axis through c, p the spring's point): a shaft there gives its own section torque."""
    c, a = axis_line(model.bodies[body])
    parts = []
    for el in model.elements:
        for i, (b, f) in enumerate(zip(el.bodies, el.interfaces)):
            if b == body and f == iface:
                g = np.concatenate([np.cross(a, np.asarray(el.point, float) - c), a])
                parts.append((el, el.B[:, 6 * i:6 * i + 6] @ g))
    if not parts:
        have = sorted({f for el in model.elements for b, f in zip(el.bodies, el.interfaces) if b == body and f})
        raise SceneError(arg, name, f"no spring of {body!r} is attached at interface {iface!r}; its interfaces "
                                    f"with springs: {have}")
    rows = [_element_channel(model, el, w, name, "N m") for el, w in parts]
    k_row = sum(ch.k_row for ch in rows)
    c_rows = [ch.c_row for ch in rows if ch.c_row is not None]
    return Channel(name, "N m", k_row, sum(c_rows) if c_rows else None, section=True)


def _stress_channels(model, rest: str, arg: str, name: str) -> list[Channel]:
    """Six stress-component rows (Pa, body axes) of ``stress:BODY:X,Y,Z``, grouped under ``name``."""
    body, _, xyz = rest.rpartition(":")
    try:
        point = np.array([float(v) for v in xyz.split(",")])
    except ValueError:
        point = np.zeros(0)
    if point.shape != (3,) or not np.all(np.isfinite(point)):
        raise SceneError(arg, name, "stress output: stress:BODY:X,Y,Z (a global point in m, e.g. "
                                    "stress:stage1.carrier:0.1,0.45,0.2)")
    flexible = sorted(b for b, bm in model.bodies.items() if bm.flexible)
    if body not in model.bodies or not model.bodies[body].flexible:
        raise SceneError(arg, name, f"{body!r} is not a flexible body (stress needs its FE mesh); "
                                    f"flexible bodies: {flexible}")
    bm = model.bodies[body]
    rows, node, dist = bm.stress_rows(point)
    nodes = bm.nodes_global()
    size = float(np.linalg.norm(nodes.max(axis=0) - nodes.min(axis=0)))
    if dist > STRESS_SNAP * size:
        raise SceneError(arg, name, f"the point lies {dist:.4g} m from the nearest FE node of {body!r} "
                                    f"({', '.join(f'{v:.4g}' for v in node)}): off the body")
    T = model.T[model.body_slice(body), :].toarray()
    return [Channel(f"{name}:s_{c}", "Pa", r @ T, None, group=name, section=True)
            for c, r in zip(VOIGT_NAMES, rows)]


def von_mises_peak(S: np.ndarray) -> np.ndarray:
    """Largest von Mises stress over one cycle of the harmonic stress ``Re(S e^{i w t})``
    (``S`` (..., 6) complex, Voigt order xx, yy, zz, yz, xz, xy): with ``a, b`` the real and
    imaginary parts and ``Q`` the von Mises quadratic form, ``Q(t) = Q(a) cos^2 + Q(b) sin^2
    - 2 Q(a, b) sin cos`` peaks at ``(A + B)/2 + sqrt(((A - B)/2)^2 + Q(a, b)^2)``."""
    def q(x, y):
        n = (x[..., 0] * y[..., 0] + x[..., 1] * y[..., 1] + x[..., 2] * y[..., 2]
             - 0.5 * (x[..., 0] * y[..., 1] + x[..., 1] * y[..., 0] + x[..., 1] * y[..., 2]
                      + x[..., 2] * y[..., 1] + x[..., 2] * y[..., 0] + x[..., 0] * y[..., 2]))
        return n + 3.0 * (x[..., 3] * y[..., 3] + x[..., 4] * y[..., 4] + x[..., 5] * y[..., 5])
    a, b = S.real, S.imag
    A, B, Cab = q(a, a), q(b, b), q(a, b)
    return np.sqrt(np.maximum(0.5 * (A + B) + np.sqrt(0.25 * (A - B) ** 2 + Cab ** 2), 0.0))


def _names(model, kind: str) -> list:
    return [el.name for el in model.elements if el.kind == kind]


def _bearing_channels(model, rest: str, elements: dict, arg: str, name: str) -> list[Channel]:
    el, direction = elements.get(rest), None
    if el is None:
        head, _, direction = rest.rpartition(":")
        el = elements.get(head)
    if el is None or el.kind != "bearing":
        raise SceneError(arg, name, f"no mesh or bearing {rest!r}; meshes: {_names(model, 'mesh')}; "
                                    f"bearings: {_names(model, 'bearing')}"
                                    f"{nearest(rest, _names(model, 'mesh') + _names(model, 'bearing'))}")
    dirs = bearing_directions(model, el)
    if not dirs:
        raise SceneError(arg, name, f"bearing {el.name!r} has no spring or damper (every direction rigid or "
                                    "free): no spring carries its load")
    if direction is not None and direction not in DOF_NAMES:
        raise SceneError(arg, name, f"bearing direction must be one of {list(DOF_NAMES)}")
    if direction is not None and direction not in dirs:
        raise SceneError(arg, name, f"bearing {el.name!r} has no spring or damper in {direction} (a rigid "
                                    f"direction is a constraint; no spring carries its reaction); it has {dirs}")
    want = dirs if direction is None else [direction]
    out = []
    for d in want:
        weights = -(np.array(dirs) == d).astype(float)
        label = name if direction is not None else f"{name}:{d}"
        out.append(_element_channel(model, el, weights, label, "N m" if d.startswith("r") else "N"))
    return out


def bearing_directions(model, el) -> list:
    """Directions (local names) of the rows of a bearing element: those with a spring or a
    damper, as :func:`assembly.mechanics.elements.relative_spring` keeps them."""
    br = model.scene.bearings[el.item[1]]
    k = br.diagonal()
    keep = ((k > 0) & ~np.isinf(k)) | (br.damping_diagonal() > 0)
    return [d for d, on in zip(DOF_NAMES, keep) if on]


def _element_channel(model, el, weights: np.ndarray, name: str, unit: str) -> Channel:
    """``sum_j weights_j (k_j + i omega c_j) e_j`` with ``e = B A T q`` the element's
    strains (``A`` its attachment operator)."""
    E = strain_rows(model, el)
    k_row = (weights * el.k) @ E
    c_row = None if el.c is None else (weights * el.c) @ E
    return Channel(name, unit, k_row, c_row, section=True)


def output_rows(outs: list) -> tuple[np.ndarray, np.ndarray]:
    """``(Ok, Oc)``: the outputs' stiffness and damper rows stacked (n_out x n_q; zero damper
    rows where an output has none), the output being ``(Ok + i omega Oc) q``."""
    Ok = np.array([c.k_row for c in outs])
    Oc = np.array([np.zeros_like(c.k_row) if c.c_row is None else c.c_row for c in outs])
    return Ok, Oc
