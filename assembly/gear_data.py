"""Gear numbers from teeth: a scene's meshes and planetary stages take base radii, working
pressure angles and helix from the gears' teeth (ISO 21771, :mod:`fe_components.gear_pair`),
once, when the scene is built (:func:`resolve`, called by :class:`assembly.scene.Scene`).

* A body's teeth: ``Body.teeth`` or its pinion / wheel component's ``teeth`` -- one
  definition: given both, they must be equal (:func:`body_teeth`).
* A mesh between two gears with teeth: ``base_radius1/2`` (negative for the gear whose body
  is ``internal``), ``pressure_angle`` (working transverse, from the profile shifts) and
  ``helix_angle`` (gear 1's) are derived; normal modules and normal pressure angles must be
  equal and the helix angles opposite (external) or equal (internal). A gear with teeth on
  a mesh with typed numbers: its typed base radius must be its teeth's.
* A stage with ``normal_module``: :func:`stage_from_teeth`.

Typed numbers keep working; given together with teeth they must agree to
:data:`AGREEMENT` (relative), else the scene is refused naming the typed field, its value,
the derived value and the teeth it comes from. The derived numbers replace the typed ones,
so a resolved scene resolves to itself. Then :func:`assembly.placement.place_bodies` puts
the bodies meshes ``place``, and fills the scene-level default fidelity.
"""
from __future__ import annotations

import dataclasses
import math

from fe_components.gear_pair import (base_helix_angle, base_radius, pair_geometry, pair_mismatch,
                                     working_centre_distance, working_pressure_angle)
from fe_components.params import PinionParams, WheelParams

from .errors import SceneError
from .schema import as_written, keep_degrees

#: Relative agreement required between a typed gear number and the one its teeth give:
#: the centre-distance check of :mod:`assembly.validate` holds geometry to the same 1e-6.
AGREEMENT = 1e-6
#: Largest difference between a stage's planet-ring and sun-planet working centre distances,
#: in normal modules. A centre-distance difference da changes the normal backlash of the
#: ring mesh by 2 da sin(alpha_wt) (ISO 21771 / ISO/TR 10064-2): at 0.01 m_n that is under
#: 0.01 m_n, within any backlash allowance, so the teeth still mesh as designed. (The 5 MW
#: reference gearbox of Nejad et al. 2016, Table V: 4.7 um and 2.7 um, i.e. 1e-4 m_n.)
RING_CENTRE_TOLERANCE = 0.01

def body_teeth(b, path: str):
    """(path of the teeth table, GearTeeth) of a body, or None: ``Body.teeth``, or its
    pinion / wheel component's ``teeth``; both given must be equal."""
    own = (f"{path}.teeth", b.teeth) if b.teeth is not None else None
    comp = None
    if isinstance(b.component, (PinionParams, WheelParams)):
        comp = (f"{path}.component.teeth", b.component.teeth)
    if comp is not None and b.internal:
        raise SceneError(f"{path}.internal", True, "a pinion or wheel component has external teeth")
    if own is None:
        return comp
    if comp is not None and comp[1] != own[1]:
        f = next(f.name for f in dataclasses.fields(own[1]) if getattr(own[1], f.name) != getattr(comp[1], f.name))
        p, v = as_written(own[1], f, f"{own[0]}.{f}")
        pc, vc = as_written(comp[1], f, f"{comp[0]}.{f}")
        raise SceneError(p, v, f"differs from {pc} = {vc}: give the teeth once, on the body or in its component")
    return own


def _differs(typed: float, derived: float, absolute: bool = False) -> bool:
    return abs(typed - derived) > (AGREEMENT if absolute else AGREEMENT * abs(derived))


def _refuse_typed(obj, field: str, path: str, derived: float, source: str):
    """The typed ``obj.field`` disagrees with ``derived``: SceneError naming both."""
    p, v = as_written(obj, field, f"{path}.{field}")
    shown = f"{math.degrees(derived):.9g} deg" if p.endswith("_deg") else f"{derived:.9g}"
    raise SceneError(p, v, f"differs from {shown} derived from {source} (relative tolerance {AGREEMENT:g}); "
                           f"leave it out to use the teeth, or correct the teeth")


def _teeth_text(path: str, t) -> str:
    return (f"{path} (n_teeth = {t.n_teeth}, normal_module = {t.normal_module:g} m, "
            f"profile_shift = {t.profile_shift:g})")


def mesh_helix(t, internal: bool) -> float:
    """``GearMesh.helix_angle`` (the line of action's helix, rad) from gear 1's teeth: the
    flank normal of an external gear whose teeth turn positively about +z along +z
    (``GearTeeth.helix_angle`` > 0, right hand) lies in the plane of action at minus the
    base helix angle beta_b; of an internal gear 1, at +beta_b (ISO 21771 involute helicoid;
    :func:`assembly.elements.line_of_action`)."""
    b = base_helix_angle(t.pressure_angle, t.helix_angle)
    return b if internal else -b


def mesh_from_teeth(m, path: str, teeth: dict, bodies: dict):
    """The mesh with its gear numbers from the teeth of its gears (``teeth``: body name ->
    (path, GearTeeth); ``bodies``: name -> Body of the scene's own bodies)."""
    g1, g2 = teeth.get(m.gear1), teeth.get(m.gear2)
    b1, b2 = bodies.get(m.gear1), bodies.get(m.gear2)
    int1, int2 = bool(b1 and b1.internal), bool(b2 and b2.internal)
    if int1 and int2:
        raise SceneError(f"{path}.gear2", m.gear2, "two internal gears cannot mesh")
    derived = {}
    if g1 is not None and g2 is not None:
        (p1, t1), (p2, t2) = g1, g2
        ext, inn, pe, pi = (t2, t1, p2, p1) if int1 else (t1, t2, p1, p2)
        bad = pair_mismatch(ext, inn, int1 or int2)
        if bad is not None:
            f, ve, vi, why = bad
            pa, va = as_written(inn, f, f"{pi}.{f}", vi)
            pb, vb = as_written(ext, f, f"{pe}.{f}", ve)
            raise SceneError(pa, va, f"{why}: {pb} = {vb} ({path} joins {m.gear1} and {m.gear2})")
        try:
            g = pair_geometry(ext, inn, int1 or int2)
        except ValueError as exc:
            raise SceneError(f"{pi}.profile_shift", inn.profile_shift, str(exc)) from None
        r_ext, r_inn = g.base_radius1, g.base_radius2
        derived = {"base_radius1": r_inn if int1 else r_ext, "base_radius2": r_ext if int1 else r_inn,
                   "pressure_angle": g.working_pressure_angle, "helix_angle": mesh_helix(t1, int1)}
        source = f"{_teeth_text(p1, t1)} and {_teeth_text(p2, t2)}"
        sources = dict.fromkeys(derived, source)
    else:
        sources = {}
        for k, (g, internal) in enumerate(((g1, int1), (g2, int2)), start=1):
            if g is not None:
                derived[f"base_radius{k}"] = -g[1].base_radius if internal else g[1].base_radius
                sources[f"base_radius{k}"] = _teeth_text(*g)
        if m.helix_angle is None:
            # gear 1's hand is gear 2's on an internal pair, the other one on an external pair
            derived["helix_angle"] = (mesh_helix(g1[1], int1) if g1 is not None else
                                      mesh_helix(g2[1], not int2) if g2 is not None else 0.0)
        for k, name in ((1, m.gear1), (2, m.gear2)):
            if getattr(m, f"base_radius{k}") is None:
                raise SceneError(f"{path}.base_radius{k}", None,
                                 f"missing: give it (m), or teeth on both gears ({name!r} has none)")
        if m.pressure_angle is None:
            raise SceneError(f"{path}.pressure_angle", None,
                             "missing: give it (transverse, rad or _deg), or teeth on both gears")
    for f, value in derived.items():
        typed = getattr(m, f)
        if typed is not None and f in sources and _differs(typed, value, absolute=f == "helix_angle"):
            _refuse_typed(m, f, path, value, sources[f])
    return keep_degrees(m, dataclasses.replace(m, **derived)) if derived else m


def stage_from_teeth(st, path: str):
    """The stage with base radii, working pressure angles (and so its carrier radius) from
    ``normal_module``, ``normal_pressure_angle``, ``helix_angle`` and the members' ``teeth``
    and ``profile_shift``; a stage without ``normal_module`` must type them."""
    members = (("sun", st.sun), ("planets", st.planets), ("ring", st.ring))
    if st.carrier.teeth is not None:
        raise SceneError(f"{path}.carrier.teeth", st.carrier.teeth, "a carrier has no teeth")
    if st.normal_module is None:
        for role, m in members:
            if m.teeth is not None:
                raise SceneError(f"{path}.{role}.teeth", m.teeth, f"teeth need the stage's normal_module (m) "
                                                                  f"and normal_pressure_angle")
        if st.normal_pressure_angle is not None:
            raise SceneError(f"{path}.normal_pressure_angle", st.normal_pressure_angle, "needs normal_module")
        for f in ("pressure_angle_sun", "pressure_angle_ring"):
            if getattr(st, f) is None:
                raise SceneError(f"{path}.{f}", None, "missing: give it (transverse, rad or _deg), or the "
                                                      "stage's normal_module and the members' teeth")
        if st.planets.base_radius is None:
            raise SceneError(f"{path}.planets.base_radius", None, "missing required field (m, > 0)")
        return st
    if st.normal_pressure_angle is None:
        raise SceneError(f"{path}.normal_pressure_angle", None, "missing: a stage with normal_module needs it")
    for role, m in members:
        if m.teeth is None:
            raise SceneError(f"{path}.{role}.teeth", None,
                             "missing: a stage with normal_module needs teeth on sun, planets and ring")
    m_n, a_n, beta = st.normal_module, st.normal_pressure_angle, st.helix_angle
    (zs, xs), (zp, xp), (zr, xr) = ((m.teeth, m.profile_shift) for _, m in members)
    try:
        a_sp = working_centre_distance(zs, zp, xs, xp, m_n, a_n, beta)
        alpha_sun = working_pressure_angle(zs, zp, xs, xp, a_n, beta)
    except ValueError as exc:
        raise SceneError(f"{path}.planets.profile_shift", xp, f"with the sun's: {exc}") from None
    try:
        a_pr = working_centre_distance(zp, -zr, xp, xr, m_n, a_n, -beta)
    except ValueError as exc:
        raise SceneError(f"{path}.ring.profile_shift", xr, f"with the planets': {exc}") from None
    tol = RING_CENTRE_TOLERANCE * m_n
    if abs(a_pr - a_sp) > tol:
        raise SceneError(f"{path}.ring.teeth", zr,
                         f"planet-ring working centre distance {a_pr:.9g} m differs from the sun-planet one "
                         f"{a_sp:.9g} m (the carrier radius) by {abs(a_pr - a_sp):.3g} m, more than the "
                         f"tolerance {tol:.3g} m ({RING_CENTRE_TOLERANCE:g} normal modules): change the teeth "
                         f"or profile shifts")
    rbs, rbp, rbr = (base_radius(z, m_n, a_n, beta) for z in (zs, zp, zr))
    alpha_ring = math.acos((rbr - rbp) / a_sp)   # the ring mesh works at the carrier radius
    source = (f"{path} (normal_module = {m_n:g} m, teeth {zs} / {zp} / {zr}, "
              f"profile_shift {xs:g} / {xp:g} / {xr:g})")
    new = {}
    for role, m, r in (("sun", st.sun, rbs), ("planets", st.planets, rbp), ("ring", st.ring, rbr)):
        if m.base_radius is not None and _differs(m.base_radius, r):
            _refuse_typed(m, "base_radius", f"{path}.{role}", r, source)
        new[role] = keep_degrees(m, dataclasses.replace(m, base_radius=r))
    for f, a in (("pressure_angle_sun", alpha_sun), ("pressure_angle_ring", alpha_ring)):
        if getattr(st, f) is not None and _differs(getattr(st, f), a):
            _refuse_typed(st, f, path, a, source)
        new[f] = a
    return keep_degrees(st, dataclasses.replace(st, **new))


def resolve(scene) -> dict:
    """The scene's ``bodies``, ``meshes`` and ``stages`` with the scene's default fidelity
    filled in, gear numbers from teeth and bodies placed by meshes (a dict of the changed
    fields, for the constructor to set)."""
    from .placement import place_bodies
    default = scene.fidelity or "rigid"

    def fid(obj):
        return obj if obj.fidelity is not None else keep_degrees(obj, dataclasses.replace(obj, fidelity=default))

    bodies = tuple(fid(b) for b in scene.bodies)
    teeth = {}
    for i, b in enumerate(bodies):
        t = body_teeth(b, f"bodies[{i}]")
        if t is not None:
            teeth[b.name] = t
    own = {b.name: b for b in bodies}
    meshes = tuple(mesh_from_teeth(m, f"meshes[{i}]", teeth, own) for i, m in enumerate(scene.meshes))
    stages = tuple(stage_from_teeth(dataclasses.replace(st, **{r: fid(getattr(st, r)) for r in
                                                               ("sun", "ring", "carrier", "planets")}),
                                    f"stages[{i}]") for i, st in enumerate(scene.stages))
    stages = tuple(keep_degrees(old, new) for old, new in zip(scene.stages, stages))
    return {"bodies": place_bodies(bodies, meshes), "meshes": meshes, "stages": stages}
