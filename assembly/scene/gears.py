"""Gear numbers from teeth: a scene's meshes and planetary stages take base radii, working
pressure angles and helix from the gears' teeth (ISO 21771, :mod:`fe_components.gear_pair`),
once, when the scene is built (:func:`resolve`, called by :class:`assembly.scene.tables.Scene`).

* A body's teeth: ``Body.teeth`` or its pinion / wheel component's ``teeth`` -- one
  definition: given both, they must be equal (:func:`body_teeth`).
* A mesh between two gears with teeth: ``base_radius1/2`` (negative for the gear whose body
  is ``internal``), ``pressure_angle`` (working transverse, from the profile shifts) and
  ``helix_angle`` (gear 1's) are derived; normal modules and normal pressure angles must be
  equal and the helix angles opposite (external) or equal (internal). A gear with teeth on
  a mesh with typed numbers: its typed base radius must be its teeth's.
* A stage with ``normal_module``: :func:`stage_from_teeth`.
* Mesh stiffness left out: between gears with teeth, and on a stage with ``normal_module``
  (and ``face_width``), the ISO 6336-1 method B mean mesh stiffness c_gamma_alpha b of solid
  gears (:mod:`fe_components.mesh_stiffness`), b the smaller face width and eps_alpha the
  pair's transverse contact ratio; elsewhere it must be given. :func:`iso_stiffnesses` lists
  the derived ones.
* Tip circles carry the ISO 21771 tip alteration k of the gear's external pair
  (:func:`fe_components.gear_pair.tip_alteration`): a stage's sun and planets take the
  sun-planet k, its ring none; a body takes the k of its external meshes (the smallest, if
  it has several: the shortest tip keeps at least the standard bottom clearance in each;
  :func:`body_tip_alterations`), a body with internal teeth none. The contact ratio (so the
  ISO 6336-1 stiffness), the gear blank and the pointed-teeth check use these tips.
* Pointed teeth (tip thickness s_a <= 0, :func:`fe_components.gear_pair.tip_thickness`) are
  refused naming the profile shift (:func:`refuse_pointed`).
* A body, stage member or planets table with teeth and without mass and polar inertia
  takes them from its gear blank (:func:`with_blank_mass`).

Typed numbers keep working; given together with teeth they must agree to
:data:`AGREEMENT` (relative), else the scene is refused naming the typed field, its value,
the derived value and the teeth it comes from. The derived numbers replace the typed ones,
so a resolved scene resolves to itself. Then :func:`assembly.scene.placement.place_bodies` puts
the bodies meshes ``place``, and fills the scene-level default fidelity.
"""
from __future__ import annotations

import dataclasses
import logging
import math

from fe_components.errors import GeometryError
from fe_components.gear_blank import blank_mass_properties
from fe_components.gear_pair import (
    base_helix_angle,
    base_radius,
    pair_geometry,
    pair_mismatch,
    shift_sum_for_centre_distance,
    tip_alteration,
    tip_thickness,
    transverse_contact_ratio,
    working_centre_distance,
    working_pressure_angle,
)
from fe_components.mesh_stiffness import mesh_stiffness
from fe_components.params import PinionParams, WheelParams, check_face_per_module

from ..errors import SceneError
from .mesh_excitation import mesh_variation
from .schema import as_written, keep_degrees

#: Relative agreement required between a typed gear number and the one its teeth give:
#: the centre-distance check of :mod:`assembly.scene.validate` holds geometry to the same 1e-6.
AGREEMENT = 1e-6
#: Largest difference between a stage's planet-ring and sun-planet working centre distances,
#: in normal modules. A centre-distance difference da changes the normal backlash of the
#: ring mesh by 2 da sin(alpha_wt) (ISO 21771 / ISO/TR 10064-2): at 0.01 m_n that is under
#: 0.01 m_n, within any backlash allowance, so the teeth still mesh as designed. (The 5 MW
#: reference gearbox of Nejad et al. 2016, Table V: 4.7 um and 2.7 um, i.e. 1e-4 m_n.)
RING_CENTRE_TOLERANCE = 0.01
#: What a stiffness derived from teeth is called in logs and reports.
ISO_SOURCE = "ISO 6336-1 method B"

log = logging.getLogger(__name__)

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


def refuse_pointed(n_teeth: int, normal_module: float, pressure_angle: float, helix_angle: float,
                   profile_shift: float, internal: bool, path: str, tip_alteration: float = 0.0) -> None:
    """SceneError naming ``path`` (the profile shift) when the teeth are pointed: tip
    thickness s_a <= 0 (ISO 21771, :func:`fe_components.gear_pair.tip_thickness`) on the tip
    circle with tip alteration coefficient ``tip_alteration`` (<= 0)."""
    s_a = tip_thickness(n_teeth, normal_module, pressure_angle, helix_angle, profile_shift, internal,
                        tip_alteration)
    if s_a <= 0:
        raise SceneError(path, profile_shift,
                         f"teeth are pointed: tip thickness s_a = {s_a:.4g} m <= 0 ({n_teeth} "
                         f"{'internal ' if internal else ''}teeth, normal_module = {normal_module:g} m); give a "
                         f"{'larger' if internal else 'smaller'} profile shift")


def with_blank_mass(obj, path: str, gear, internal: bool, tip_alteration: float = 0.0):
    """``obj`` (a Body, stage Member or Planets) with ``mass``, ``polar_inertia`` and, unless
    given, ``transverse_inertia`` from its gear blank when it leaves out mass and inertia;
    ``gear``: (n_teeth, normal_module m, helix_angle rad, profile_shift, face_width m or
    None) of its teeth, or None (no teeth, or a component gives its mass); ``tip_alteration``
    its tip alteration coefficient k (<= 0). A ``blank`` table is refused where it would
    not be used."""
    given = [f for f in ("mass", "polar_inertia", "inertia_tensor") if getattr(obj, f, None) is not None]
    if obj.blank is not None and (gear is None or given):
        why = f"{path}.{given[0]} is given" if gear is not None else "no teeth of its own (or a component)"
        raise SceneError(f"{path}.blank", "table", f"unused: a gear blank gives mass and inertia from teeth "
                                                   f"when they are left out, and here {why}")
    if gear is None or given:
        return obj
    try:
        props = blank_mass_properties(*gear, internal=internal, blank=obj.blank, tip_alteration=tip_alteration)
    except GeometryError as err:
        raise SceneError(f"{path}.blank.{err.parameter}", err.value, err.reason) from None
    jt = obj.transverse_inertia if obj.transverse_inertia is not None else props.transverse_inertia
    return keep_degrees(obj, dataclasses.replace(obj, mass=props.mass, polar_inertia=props.polar_inertia,
                                                 transverse_inertia=jt))


def blank_body(b, path: str, tip_alteration: float = 0.0):
    """A body whose own ``teeth`` (no component) give its mass properties
    (:func:`with_blank_mass`), tip alteration coefficient ``tip_alteration`` (<= 0)."""
    t = b.teeth
    gear = (t.n_teeth, t.normal_module, t.helix_angle, t.profile_shift, t.face_width) \
        if t is not None and b.component is None else None
    return with_blank_mass(b, path, gear, b.internal, tip_alteration)


def body_tip_alterations(meshes, teeth: dict, bodies: dict) -> dict:
    """Body name -> tip alteration coefficient k (<= 0) of its tips: the smallest k of the
    external meshes it is in (ISO 21771, :func:`fe_components.gear_pair.tip_alteration`);
    bodies in no external mesh between teeth take none. ``teeth``: body name -> (path,
    GearTeeth); ``bodies``: name -> Body. Pairs that cannot mesh are left out here and
    refused by :func:`mesh_from_teeth`."""
    out = {}
    for m in meshes:
        g1, g2 = teeth.get(m.gear1), teeth.get(m.gear2)
        if g1 is None or g2 is None or any(bodies[n].internal for n in (m.gear1, m.gear2) if n in bodies):
            continue
        t1, t2 = g1[1], g2[1]
        if pair_mismatch(t1, t2) is not None:
            continue
        try:
            k = tip_alteration(t1.n_teeth, t2.n_teeth, t1.profile_shift, t2.profile_shift, t1.normal_module,
                               t1.pressure_angle, t1.helix_angle)
        except ValueError:
            continue
        for name in (m.gear1, m.gear2):
            out[name] = min(out.get(name, 0.0), k)
    return out


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
    :func:`assembly.mechanics.elements.line_of_action`)."""
    b = base_helix_angle(t.pressure_angle, t.helix_angle)
    return b if internal else -b


def mesh_from_teeth(m, path: str, teeth: dict, bodies: dict, tips: dict | None = None):
    """The mesh with its gear numbers from the teeth of its gears (``teeth``: body name ->
    (path, GearTeeth); ``bodies``: name -> Body of the scene's own bodies; ``tips``: body
    name -> tip alteration coefficient, :func:`body_tip_alterations`, default computed)."""
    if tips is None:
        tips = body_tip_alterations((m,), teeth, bodies)
    g1, g2 = teeth.get(m.gear1), teeth.get(m.gear2)
    b1, b2 = bodies.get(m.gear1), bodies.get(m.gear2)
    int1, int2 = bool(b1 and b1.internal), bool(b2 and b2.internal)
    if int1 and int2:
        raise SceneError(f"{path}.gear2", m.gear2, "two internal gears cannot mesh")
    derived, geometry = {}, None
    if g1 is not None and g2 is not None:
        (p1, t1), (p2, t2) = g1, g2
        ext, inn, pe, pi = (t2, t1, p2, p1) if int1 else (t1, t2, p1, p2)
        bad = pair_mismatch(ext, inn, int1 or int2)
        if bad is not None:
            f, ve, vi, why = bad
            pa, va = as_written(inn, f, f"{pi}.{f}", vi)
            pb, vb = as_written(ext, f, f"{pe}.{f}", ve)
            raise SceneError(pa, va, f"{why}: {pb} = {vb} ({path} joins {m.gear1} and {m.gear2})")
        n_ext, n_inn = (m.gear2, m.gear1) if int1 else (m.gear1, m.gear2)
        try:
            g = pair_geometry(ext, inn, int1 or int2, (tips.get(n_ext, 0.0), tips.get(n_inn, 0.0)))
        except ValueError as exc:
            raise SceneError(f"{pi}.profile_shift", inn.profile_shift, str(exc)) from None
        geometry = g
        r_ext, r_inn = g.base_radius1, g.base_radius2
        derived = {"base_radius1": r_inn if int1 else r_ext, "base_radius2": r_ext if int1 else r_inn,
                   "pressure_angle": g.working_pressure_angle, "helix_angle": mesh_helix(t1, int1)}
        if m.stiffness is None:
            derived["stiffness"] = _iso_stiffness(
                path, ext.n_teeth, inn.n_teeth, ext.profile_shift, inn.profile_shift, ext.helix_angle,
                ext.pressure_angle, g.contact_ratio, min(t1.face_width, t2.face_width), int1 or int2)
        source = f"{_teeth_text(p1, t1)} and {_teeth_text(p2, t2)}"
        sources = dict.fromkeys(derived, source)
    else:
        if m.stiffness is None:
            name = m.gear2 if g1 is not None else m.gear1
            raise SceneError(f"{path}.stiffness", None, f"missing: give it (N/m), or teeth on both gears for the "
                                                        f"{ISO_SOURCE} value ({name!r} has none)")
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
    if m.variation is not None:
        derived["variation"] = mesh_variation(m, path, teeth, geometry)
    return keep_degrees(m, dataclasses.replace(m, **derived)) if derived else m


def _iso_stiffness(path: str, z1, z2, x1, x2, helix, pressure_angle, contact_ratio, face_width, internal):
    """The ISO 6336-1 mesh stiffness (N/m) of the pair (:func:`fe_components.mesh_stiffness.mesh_stiffness`),
    logged with the scene path it fills."""
    k = mesh_stiffness(z1, z2, x1, x2, helix, pressure_angle, contact_ratio, face_width, internal)
    log.info("%s: %.6g N/m from %s (z %d / %d, eps_alpha %.4g, b %.6g m)", path, k, ISO_SOURCE, z1, z2,
             contact_ratio, face_width)
    return k


def iso_stiffnesses(scene) -> list:
    """(scene path, N/m) of every mesh stiffness of ``scene`` derived from teeth (ISO 6336-1)
    because the user left it out: ``meshes[i].stiffness``, ``stages[i].k_mesh_sun`` /
    ``k_mesh_ring``."""
    out = [(f"meshes[{i}].stiffness", m.stiffness)
           for i, (given, m) in enumerate(zip(scene.as_given("meshes"), scene.meshes)) if given.stiffness is None]
    for i, (given, st) in enumerate(zip(scene.as_given("stages"), scene.stages)):
        out += [(f"stages[{i}].{f}", getattr(st, f)) for f in ("k_mesh_sun", "k_mesh_ring")
                if getattr(given, f) is None]
    return out


def stage_from_teeth(st, path: str):
    """The stage with base radii, working pressure angles (and so its carrier radius) from
    ``normal_module``, ``normal_pressure_angle``, ``helix_angle`` and the members' ``teeth``
    and ``profile_shift``; a stage without ``normal_module`` must type them."""
    members = (("sun", st.sun), ("planets", st.planets), ("ring", st.ring))
    if st.carrier.teeth is not None:
        raise SceneError(f"{path}.carrier.teeth", st.carrier.teeth, "a carrier has no teeth")
    with_blank_mass(st.carrier, f"{path}.carrier", None, False)   # refuses a blank table
    if st.normal_module is None:
        for role, m in members:
            if m.teeth is not None:
                raise SceneError(f"{path}.{role}.teeth", m.teeth, "teeth need the stage's normal_module (m) "
                                                                  "and normal_pressure_angle")
            with_blank_mass(m, f"{path}.{role}", None, False)   # refuses a blank table
        for f in ("normal_pressure_angle", "face_width"):
            if getattr(st, f) is not None:
                raise SceneError(f"{path}.{f}", getattr(st, f), "needs normal_module")
        for f in ("pressure_angle_sun", "pressure_angle_ring"):
            if getattr(st, f) is None:
                raise SceneError(f"{path}.{f}", None, "missing: give it (transverse, rad or _deg), or the "
                                                      "stage's normal_module and the members' teeth")
        if st.planets.base_radius is None:
            raise SceneError(f"{path}.planets.base_radius", None, "missing required field (m, > 0)")
        for f in ("k_mesh_sun", "k_mesh_ring"):
            if getattr(st, f) is None:
                raise SceneError(f"{path}.{f}", None, f"missing: give it (N/m), or the stage's normal_module, "
                                                      f"face_width and the members' teeth for the {ISO_SOURCE} value")
        return st
    if st.normal_pressure_angle is None:
        raise SceneError(f"{path}.normal_pressure_angle", None, "missing: a stage with normal_module needs it")
    if st.face_width is not None:
        check_face_per_module(st.face_width, st.normal_module, f"{path}.face_width", f"{path}.normal_module",
                              SceneError)
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
    # ISO 21771 tip alteration of the sun-planet pair, on the sun and the planets' tips (the
    # planets' one tip circle serves the ring mesh too); the ring, internal, takes none
    k_sp = tip_alteration(zs, zp, xs, xp, m_n, a_n, beta)
    tips = {"sun": k_sp, "planets": k_sp, "ring": 0.0}
    for role, m in members:
        refuse_pointed(m.teeth, m_n, a_n, beta, m.profile_shift, role == "ring", f"{path}.{role}.profile_shift",
                       tips[role])
    ring_closes(st, path, a_sp)
    rbs, rbp, rbr = (base_radius(z, m_n, a_n, beta) for z in (zs, zp, zr))
    alpha_ring = math.acos((rbr - rbp) / a_sp)   # the ring mesh works at the carrier radius
    source = (f"{path} (normal_module = {m_n:g} m, teeth {zs} / {zp} / {zr}, "
              f"profile_shift {xs:g} / {xp:g} / {xr:g})")
    new = {}
    for role, m, r in (("sun", st.sun, rbs), ("planets", st.planets, rbp), ("ring", st.ring, rbr)):
        if m.base_radius is not None and _differs(m.base_radius, r):
            _refuse_typed(m, "base_radius", f"{path}.{role}", r, source)
        new[role] = _member_blank(st, f"{path}.{role}", keep_degrees(m, dataclasses.replace(m, base_radius=r)),
                                  role == "ring", path, tips[role])
    for f, a in (("pressure_angle_sun", alpha_sun), ("pressure_angle_ring", alpha_ring)):
        if getattr(st, f) is not None and _differs(getattr(st, f), a):
            _refuse_typed(st, f, path, a, source)
        new[f] = a
    if st.k_mesh_sun is None or st.k_mesh_ring is None:
        if st.face_width is None:
            missing = "k_mesh_sun" if st.k_mesh_sun is None else "k_mesh_ring"
            raise SceneError(f"{path}.face_width", None, f"missing: {missing} left out is the {ISO_SOURCE} "
                                                         f"value, which needs the face width (m); or give {missing}")
        pairs = {"k_mesh_sun": (zs, zp, xs, xp, False), "k_mesh_ring": (zp, zr, xp, xr, True)}
        for (f, (z1, z2, x1, x2, internal)), eps in zip(pairs.items(), stage_contact_ratios(st)):
            if getattr(st, f) is None:
                new[f] = _iso_stiffness(f"{path}.{f}", z1, z2, x1, x2, beta, a_n, eps, st.face_width, internal)
    return keep_degrees(st, dataclasses.replace(st, **new))


def stage_contact_ratios(st) -> tuple[float, float]:
    """Transverse contact ratios (sun-planet, planet-ring) of a stage with teeth and
    ``normal_module``: the sun and planet tips with the sun-planet pair's ISO 21771 tip
    alteration (the planets' one tip circle serves the ring mesh too), the ring's unaltered."""
    m_n, a_n, beta = st.normal_module, st.normal_pressure_angle, st.helix_angle
    (zs, xs), (zp, xp), (zr, xr) = ((m.teeth, m.profile_shift) for m in (st.sun, st.planets, st.ring))
    k_sp = tip_alteration(zs, zp, xs, xp, m_n, a_n, beta)
    return (transverse_contact_ratio(zs, zp, xs, xp, m_n, a_n, beta, (k_sp, k_sp)),
            transverse_contact_ratio(zp, -zr, xp, xr, m_n, a_n, beta, (k_sp, 0.0)))


def ring_closes(st, path: str, a_sp: float) -> None:
    """The planet-ring pair of stage ``st`` (with teeth) must work at the carrier radius
    ``a_sp`` (m, the sun-planet working centre distance) to :data:`RING_CENTRE_TOLERANCE`
    normal modules. Refused naming the ring's teeth, or its profile shift when no working
    pressure angle exists and a ring shift in (-1, 1) would close the stage; the message says
    which ring shift (ISO 21771, :func:`~fe_components.gear_pair.shift_sum_for_centre_distance`)."""
    (zp, xp), (zr, xr) = (st.planets.teeth, st.planets.profile_shift), (st.ring.teeth, st.ring.profile_shift)
    m_n, a_n, beta = st.normal_module, st.normal_pressure_angle, st.helix_angle
    x_sum = shift_sum_for_centre_distance(zp, -zr, a_sp, m_n, a_n, beta)
    x_need = None if x_sum is None or not -1.0 < x_sum - xp < 1.0 else x_sum - xp
    hint = (f"a ring profile_shift of {x_need:.4f} would close it" if x_need is not None else
            f"no ring profile_shift in (-1, 1) closes it with {zr} ring and {zp} planet teeth")
    try:
        a_pr = working_centre_distance(zp, -zr, xp, xr, m_n, a_n, -beta)
    except ValueError as exc:
        p, v = (f"{path}.ring.profile_shift", xr) if x_need is not None else (f"{path}.ring.teeth", zr)
        raise SceneError(p, v, f"the planet-ring pair has no working pressure angle with the planets' "
                               f"profile_shift {xp:g}: {exc}; {hint}") from None
    tol = RING_CENTRE_TOLERANCE * m_n
    if abs(a_pr - a_sp) > tol:
        raise SceneError(f"{path}.ring.teeth", zr,
                         f"planet-ring working centre distance {a_pr:.9g} m differs from the sun-planet one "
                         f"{a_sp:.9g} m (the carrier radius) by {abs(a_pr - a_sp):.3g} m, more than the "
                         f"tolerance {tol:.3g} m ({RING_CENTRE_TOLERANCE:g} normal modules): the stage does "
                         f"not close; {hint}")


def _member_blank(st, path: str, m, internal: bool, stage_path: str, tip_alteration: float):
    """Stage member ``m`` (sun, planets or ring of stage ``st`` with ``normal_module``) with
    mass properties from its gear blank when it leaves them out (:func:`with_blank_mass`);
    the blank's length is the stage's ``face_width`` unless ``m.blank`` gives one; its tip
    alteration coefficient ``tip_alteration``."""
    leaves_out = m.mass is None and m.polar_inertia is None and getattr(m, "component", None) is None
    if leaves_out and st.face_width is None and (m.blank is None or m.blank.length is None):
        raise SceneError(f"{stage_path}.face_width", None,
                         f"missing: {path} leaves out mass and polar_inertia, which its gear blank gives "
                         f"from the teeth and the face width (m)")
    gear = (m.teeth, st.normal_module, st.helix_angle, m.profile_shift, st.face_width) \
        if getattr(m, "component", None) is None else None
    return with_blank_mass(m, path, gear, internal, tip_alteration)


def resolve(scene) -> dict:
    """The scene's ``bodies``, ``meshes`` and ``stages`` with the scene's default fidelity
    filled in, gear numbers from teeth, bodies placed by meshes and stages on the axes of
    the bodies they are coaxial with (a dict of the changed fields, for the constructor to
    set)."""
    from .placement import place_bodies, place_stages
    default = scene.fidelity or "rigid"

    def fid(obj):
        return obj if obj.fidelity is not None else keep_degrees(obj, dataclasses.replace(obj, fidelity=default))

    bodies = tuple(fid(b) for b in scene.bodies)
    teeth = {b.name: t for i, b in enumerate(bodies) if (t := body_teeth(b, f"bodies[{i}]")) is not None}
    own = {b.name: b for b in bodies}
    tips = body_tip_alterations(scene.meshes, teeth, own)
    bodies = tuple(blank_body(b, f"bodies[{i}]", tips.get(b.name, 0.0)) for i, b in enumerate(bodies))
    for b in bodies:
        if b.name in teeth:
            p, g = teeth[b.name]
            refuse_pointed(g.n_teeth, g.normal_module, g.pressure_angle, g.helix_angle, g.profile_shift,
                           b.internal, f"{p}.profile_shift", tips.get(b.name, 0.0))
    own = {b.name: b for b in bodies}
    meshes = tuple(mesh_from_teeth(m, f"meshes[{i}]", teeth, own, tips) for i, m in enumerate(scene.meshes))
    stages = tuple(stage_from_teeth(dataclasses.replace(st, **{r: fid(getattr(st, r)) for r in
                                                               ("sun", "ring", "carrier", "planets")}),
                                    f"stages[{i}]") for i, st in enumerate(scene.stages))
    stages = tuple(keep_degrees(old, new) for old, new in zip(scene.stages, stages))
    bodies = place_bodies(bodies, meshes)
    return {"bodies": bodies, "meshes": meshes, "stages": place_stages(stages, bodies)}
