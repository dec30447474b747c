"""The rules a scene must obey, one function each (:class:`SceneError` with the field path).

:func:`validate_scene` runs them in order: first every field on its own -- its type and
the unit and range declared on it (:func:`assembly.scene.schema.check_instance`: finite, of
physical magnitude, in range; names without control characters or path separators), so
no rule below ever compares a NaN or overflows -- and every name a field gives a body
(:func:`references_exist`, which :class:`assembly.scene.tables.Scene` runs before deriving gear
numbers from teeth and placing bodies, the steps that read the bodies named), then each
table on its own (bodies, meshes, shafts, fixed DOFs, planetary stages, flexible
options), then the scene as a whole on its stages expanded (names, sizes against each
other -- :mod:`assembly.scene.sizes` --, frames, component tables, attachment points, rigid
bearings, mesh geometry, Craig-Bampton cutoffs, load case, connectivity).
Error paths name the table the user wrote: ``stages[0].planets.count``,
``bearings[2].k_radial``, ``stages[0].carrier.component.cheek_spacing``.
"""
from __future__ import annotations

import math

import numpy as np

from fe_components.errors import GeometryError
from fe_components.params import CarrierParams, component_kind
from fe_components.part.file import PartFile

from ..errors import SceneError
from ..mechanics.kinematics import unit
from .attach import bearing_point, component_masters, mesh_centers, shaft_points
from .body_names import body_references, scene_body_names, unknown_body_reason
from .cutoffs import CB_CUTOFF_FACTOR, cutoff_source, weyl_mode_count
from .paths import body_origins, element_paths
from .planet_spacing import check_planet_assembly, check_planet_spacing
from .schema import as_written, check_instance
from .shafts import check_along_axis, check_slenderness, shaft_ends, shaft_line, station_body
from .sizes import positions_plausible
from .tables import (
    DOF_NAMES,
    HOUSING,
    MAX_MODES,
    MODE_CLASSES,
    SPLIT_DAMPINGS,
    SPLIT_STIFFNESSES,
    Bearing,
    Body,
    Fixed,
    FlexOptions,
    GearMesh,
    PlanetaryStage,
    Shaft,
)
from .validate_loads import check_load


def can_constrain(bearing: Bearing, body: Body) -> bool:
    """Whether a direction of ``bearing`` may become an exact constraint: only on a plain
    rigid body (no component), at the body's own position, to its own reference frame,
    since the independent coordinates are the body's motion relative to that frame."""
    own_frame = bearing.frame is None or bearing.frame == body.frame
    at_body = bearing.position is None or np.allclose(bearing.position, body.position, rtol=0, atol=1e-12)
    return body.component is None and own_frame and at_body


def _nonzero_axis(path, axis) -> None:
    if not any(axis):
        raise SceneError(path, list(axis), "must be a non-zero vector")


# ---------------------------------------------------------------- one table at a time
def check_flex(opts: FlexOptions, path: str) -> None:
    """Meshing and reduction options of a component body (ranges: the field rules)."""
    if opts.n_modes is not None and opts.cutoff_hz is not None:
        raise SceneError(f"{path}.n_modes", opts.n_modes, "give n_modes or cutoff_hz, not both")
    for k, v in (opts.couplings or {}).items():
        if v not in ("rbe2", "rbe3"):
            raise SceneError(f"{path}.couplings.{k}", v, "must be 'rbe2' or 'rbe3'")


def check_body(b: Body, path: str) -> None:
    """Name, mass properties (or a component that supplies them) and axis."""
    if b.name == HOUSING:
        raise SceneError(f"{path}.name", b.name, "must be a name other than 'housing'")
    if b.component is not None:
        _check_component_body(b, path)
    elif b.fidelity == "flexible":
        raise SceneError(f"{path}.fidelity", b.fidelity,
                         "a flexible body needs a 'component' table (pinion, wheel, carrier, cylinder, file)")
    elif b.flex is not None:
        raise SceneError(f"{path}.flex", "table", "only a body with a component takes flex options")
    else:
        _check_mass_properties(b, path)
    _nonzero_axis(f"{path}.axis", b.axis)


def _check_component_body(b: Body, path: str) -> None:
    """A component body: its part, carrier pins and flex options; mass properties typed
    beside the component are the values its mesh replaces (reported, never used:
    :mod:`assembly.model.body_table`), held to the plain body's rules when given."""
    if b.polar_inertia is not None and b.inertia_tensor is not None:
        raise SceneError(f"{path}.polar_inertia", b.polar_inertia, "give polar_inertia or inertia_tensor, not both")
    if b.inertia_tensor is not None:
        _check_tensor(b, path)
    check_part(b.component, f"{path}.component")
    if isinstance(b.component, CarrierParams):
        for f in ("planet_angles", "pin_pitch_radius"):
            if getattr(b.component, f) is None:
                raise SceneError(f"{path}.component.{f}", None,
                                 "missing: a carrier body needs its planet pins (planet_angles or n_planets, "
                                 "and pin_pitch_radius); only a planetary stage's carrier takes them from "
                                 "its planets")
    if b.flex is not None:
        check_flex(b.flex, f"{path}.flex")


def check_part(component, path: str) -> None:
    """A part read from a file (``kind = "file"``): read it now (size, volumes, interfaces
    found by their rules), so that a problem names its scene path before anything is meshed."""
    if isinstance(component, PartFile):
        from fe_components.part.read import part_geometry
        try:
            part_geometry(component)
        except GeometryError as err:
            raise SceneError(f"{path}.{err.parameter}", err.value, err.reason) from None


def _check_mass_properties(b: Body, path: str) -> None:
    if b.mass is None:
        raise SceneError(f"{path}.mass", None, "missing required field (kg)")
    if (b.inertia_tensor is None) == (b.polar_inertia is None):
        raise SceneError(f"{path}.polar_inertia", b.polar_inertia,
                         "give exactly one of polar_inertia or inertia_tensor")
    if b.polar_inertia is not None:
        return
    _check_tensor(b, path)


def _check_tensor(b: Body, path: str) -> None:
    J = np.asarray(b.inertia_tensor, float)
    if not np.allclose(J, J.T, rtol=1e-12, atol=0) or np.linalg.eigvalsh(J).min() <= 0:
        raise SceneError(f"{path}.inertia_tensor", b.inertia_tensor, "must be symmetric positive definite (kg m^2)")


def check_mesh(m: GearMesh, path: str) -> None:
    """Two different gears, not both internal, a non-zero centre distance, a flank."""
    if m.gear1 == m.gear2:
        raise SceneError(f"{path}.gear2", m.gear2, "a gear cannot mesh with itself")
    if m.base_radius1 < 0 and m.base_radius2 < 0:
        raise SceneError(f"{path}.base_radius2", m.base_radius2, "two internal gears cannot mesh")
    if m.base_radius1 + m.base_radius2 == 0:
        raise SceneError(f"{path}.base_radius2", m.base_radius2,
                         "internal and external base radii are equal: zero centre distance")
    _drive_sign(m, path)


def _drive_sign(obj, path: str) -> None:
    """Drive sign +-1 (a mesh or a stage)."""
    if obj.drive_sign not in (1, -1):
        raise SceneError(f"{path}.drive_sign", obj.drive_sign, "must be +1 or -1")


def check_shaft(s: Shaft, path: str) -> None:
    """Two different bodies (stiffness ranges: the field rules; a rigid joint is a bearing);
    a spring shaft gives k_torsion, a beam shaft (``diameter``) derives every k_* field and
    names itself and its stations (where the stations lie: :mod:`assembly.scene.shafts`)."""
    if s.body1 == s.body2:
        raise SceneError(f"{path}.body2", s.body2, "a shaft needs two different bodies")
    if not s.is_beam:
        if s.k_torsion is None:
            raise SceneError(f"{path}.k_torsion", None, "missing required field (N m/rad), or give the "
                                                        "shaft's diameter to derive it")
        if s.stations:
            raise SceneError(f"{path}.stations", [st.name for st in s.stations],
                             "stations sit on a beam shaft: give its diameter")
        for f in ("position1", "position2"):
            if getattr(s, f) is not None:
                raise SceneError(f"{path}.{f}", list(getattr(s, f)), "where a beam shaft ends: give its "
                                                                     "diameter, or use position for a spring shaft")
        if s.beta != 0.0:
            raise SceneError(f"{path}.beta", s.beta, "stiffness-proportional damping of a beam shaft: give "
                                                     "c_torsion, c_bending, c_axial, c_shear on a spring shaft")
        return
    for f in dict.fromkeys(Shaft.DAMPING_FIELDS):
        if getattr(s, f) != 0.0:
            raise SceneError(f"{path}.{f}", getattr(s, f), "a beam shaft is damped by beta (s, C = beta K): "
                                                           "leave this out")
    for f in ("k_torsion", "k_bending", "k_axial", "k_shear", "position"):
        if getattr(s, f) not in (None, 0.0):
            raise SceneError(f"{path}.{f}", getattr(s, f), "a shaft with a diameter derives its stiffness from "
                                                           "its section and length: leave this out")
    if s.bore_diameter >= s.diameter:
        raise SceneError(f"{path}.bore_diameter", s.bore_diameter, f"must be less than diameter = {s.diameter!r} m")
    stations_named(s, path)
    for j, st in enumerate(s.stations):
        if "." in st.name:
            raise SceneError(f"{path}.stations[{j}].name", st.name, "must be a name without '.'")
    unique_names(s.stations, f"{path}.stations")


def stations_named(s: Shaft, path: str) -> None:
    """A shaft with stations has a name: its stations become bodies <name>.<station>."""
    if s.stations and s.name is None:
        raise SceneError(f"{path}.name", None, "a shaft with stations needs a name: its stations become bodies "
                                               "<shaft name>.<station name>")


def stations_unclaimed(scene) -> None:
    """No body of the scene already bears the name a shaft's station becomes."""
    names = {b.name: i for i, b in enumerate(scene.bodies)}
    for i, s in enumerate(scene.shafts):
        for j, st in enumerate(s.stations):
            if station_body(s, st) in names:
                raise SceneError(f"shafts[{i}].stations[{j}].name", st.name,
                                 f"station body {station_body(s, st)!r} would duplicate "
                                 f"bodies[{names[station_body(s, st)]}].name")


def check_fixed(f: Fixed, path: str) -> None:
    """Known DOF names."""
    for i, d in enumerate(f.dofs):
        if d not in DOF_NAMES:
            raise SceneError(f"{path}.dofs[{i}]", d, f"must be one of {list(DOF_NAMES)}")


def check_bearing(br, path: str) -> None:
    """A bearing table (:class:`assembly.scene.tables.Bearing` or ``BearingSpec``): ``k_axial``, and
    for the radial and the tilt directions either the one stiffness of both (``k_radial``)
    or both per-direction ones (``k_radial_x`` and ``k_radial_y``), not both ways."""
    if br.k_axial is None:
        raise SceneError(f"{path}.k_axial", None, "missing required field (N/m)")
    for whole, parts in SPLIT_STIFFNESSES.items():
        unit = "N/m" if whole == "k_radial" else "N m/rad"
        given = _split_given(br, path, whole, parts, unit)
        if getattr(br, whole) is None and not given:
            raise SceneError(f"{path}.{whole}", None,
                             f"missing required field ({unit}; or both {parts[0]} and {parts[1]})")
        if getattr(br, "radial_angle", 0.0) != 0.0 and len(given) == 2 and \
                math.isinf(getattr(br, parts[0])) != math.isinf(getattr(br, parts[1])):
            raise SceneError(f"{path}.radial_angle", br.radial_angle,
                             f"a bearing turned about the body's axis cannot be rigid ({unit} inf) in "
                             f"only one of {parts[0]}, {parts[1]}: give both or neither as inf")
    _check_split_dampers(br, path)


def _check_split_dampers(br, path: str) -> None:
    """The dampers' split rule, as the stiffnesses': ``c_radial`` or both ``c_radial_x`` and
    ``c_radial_y`` (likewise tilt), not both ways; none of them: no damper there."""
    for whole, parts in SPLIT_DAMPINGS.items():
        _split_given(br, path, whole, parts, "N s/m" if whole == "c_radial" else "N m s/rad")


def _split_given(br, path: str, whole: str, parts: tuple, unit: str) -> list:
    """The per-direction fields of ``parts`` given; refuses ``whole`` given with them and one
    of the pair without the other."""
    given = [f for f in parts if getattr(br, f) is not None]
    if getattr(br, whole) is not None and given:
        raise SceneError(f"{path}.{given[0]}", getattr(br, given[0]),
                         f"give either {whole} ({whole} = {getattr(br, whole)} is given) or both "
                         f"{parts[0]} and {parts[1]}, not both ways")
    if len(given) == 1:
        other = next(f for f in parts if f not in given)
        raise SceneError(f"{path}.{other}", None, f"missing: {given[0]} needs {other} ({unit})")
    return given


# ---------------------------------------------------------------- planetary stages
def check_stage(st: PlanetaryStage, path: str) -> None:
    """A planetary stage: members, planets, meshes, and the geometry that joins them."""
    if "." in st.name:
        raise SceneError(f"{path}.name", st.name, "must be a name without '.'")
    for role in ("sun", "ring", "carrier"):
        _check_member(getattr(st, role), role, f"{path}.{role}")
    for role in ("sun", "ring"):
        if getattr(st, role).base_radius is None:
            raise SceneError(f"{path}.{role}.base_radius", None, "missing required field (m, > 0; "
                                                                 "give the ring's as positive)")
    pl = st.planets
    for f, unit in (("mass", "kg"), ("polar_inertia", "kg m^2")):
        if getattr(pl, f) is None:
            raise SceneError(f"{path}.planets.{f}", None, f"missing required field ({unit}, > 0; or the planets' "
                                                          f"teeth and the stage's normal_module and face_width)")
    check_bearing(pl.bearing, f"{path}.planets.bearing")
    if pl.outer_radius is not None and pl.outer_radius <= pl.base_radius:
        raise SceneError(f"{path}.planets.outer_radius", pl.outer_radius,
                         f"must exceed the planet base radius {pl.base_radius} m")
    _drive_sign(st, path)
    _nonzero_axis(f"{path}.axis", st.axis)
    _check_ring_radius(st, path)
    check_planet_spacing(st, path)
    check_planet_assembly(st, path)


def _check_member(m, role: str, p: str) -> None:
    if m.component is not None:
        if role != "carrier" or not isinstance(m.component, (CarrierParams, PartFile)):
            raise SceneError(f"{p}.component", component_kind(m.component),
                             "only the carrier of a planetary stage can be a component so far "
                             "(of kind 'carrier' or 'file')")
        check_part(m.component, f"{p}.component")
        for f in ("planet_angles", "pin_pitch_radius"):
            if getattr(m.component, f, None) is not None:
                raise SceneError(*as_written(m.component, f, f"{p}.component.{f}"),
                                 "set by the stage from its planets; remove it")
        # mass and polar_inertia given: the values its mesh replaces (reported, never used)
    else:
        if m.fidelity == "flexible":
            raise SceneError(f"{p}.fidelity", m.fidelity, "a flexible member needs a component table")
        if m.mass is None:
            raise SceneError(f"{p}.mass", None, "missing required field (kg, > 0)")
        if m.polar_inertia is None:
            raise SceneError(f"{p}.polar_inertia", None, "missing required field (kg m^2, > 0)")
    if m.support == "bearing" and m.bearing is None:
        raise SceneError(f"{p}.bearing", None, "support = 'bearing' needs a bearing table")
    if m.bearing is not None:
        check_bearing(m.bearing, f"{p}.bearing")
    if m.support != "bearing" and m.bearing is not None:
        raise SceneError(f"{p}.support", m.support, "a bearing table is given but support is not 'bearing'")


def _check_ring_radius(st: PlanetaryStage, path: str) -> None:
    """The ring mesh must put the planet centres where the sun mesh does."""
    pl = st.planets
    Rc = st.carrier_radius()
    want = pl.base_radius + Rc * math.cos(st.pressure_angle_ring)
    # a ring radius 1000 x off (a length in the wrong unit) that would otherwise fit
    slip = next((f"; did you mean {st.ring.base_radius * f:.9g} m ({u})?" for f, u in
                 ((1e3, "a length in mm converted to metres twice"), (1e-3, "mm where metres belong"))
                 if abs(st.ring.base_radius * f - want) <= 1e-3 * want), "")
    if st.ring.base_radius <= pl.base_radius:
        raise SceneError(f"{path}.ring.base_radius", st.ring.base_radius,
                         f"must exceed the planet base radius{slip}")
    Rc_ring = (st.ring.base_radius - pl.base_radius) / math.cos(st.pressure_angle_ring)
    if abs(Rc_ring - Rc) > 1e-6 * Rc:
        raise SceneError(f"{path}.ring.base_radius", st.ring.base_radius,
                         f"inconsistent with the sun mesh: the planet centre lies at {Rc:.6g} m, "
                         f"which needs a ring base radius of {want:.9g} m{slip}")


# ---------------------------------------------------------------- whole-scene rules
def check_damping(d, path: str = "damping") -> None:
    """``[damping]``: ``class_ratios`` keys are mode classes and its ratios lie in [0, 1)
    (the other fields: their field rules)."""
    for key, zeta in (d.class_ratios or {}).items():
        if key not in MODE_CLASSES:
            raise SceneError(f"{path}.class_ratios", key, f"must be a mode class, one of {list(MODE_CLASSES)}")
        if isinstance(zeta, bool) or not isinstance(zeta, (int, float)) or not 0.0 <= zeta < 1.0:
            where = f".{key}" if key.isidentifier() else f"[{key!r}]"
            raise SceneError(f"{path}.class_ratios{where}", zeta, "must be a damping ratio in [0, 1)")


def check_tables(scene) -> None:
    """Every field (type, unit, range), then every table on its own, in the order the user
    wrote them; between the two, the positions against the assembly's size (a unit slip:
    :mod:`assembly.scene.sizes`), which the table rules would meet as a contradiction."""
    check_instance(scene)
    positions_plausible(scene)
    if scene.damping is not None:
        check_damping(scene.damping)
    for i, st in enumerate(scene.stages):
        check_stage(st, f"stages[{i}]")
    unique_names(scene.stages, "stages")
    for key, check in (("bodies", check_body), ("bearings", check_bearing), ("meshes", check_mesh),
                       ("shafts", check_shaft), ("fixed", check_fixed)):
        for i, item in enumerate(getattr(scene, key)):
            check(item, f"{key}[{i}]")
    stations_unclaimed(scene)


def unique_names(items, path, attr="name") -> None:
    """No two items of one table share a name (unnamed items are skipped)."""
    seen = {}
    for i, it in enumerate(items):
        name = getattr(it, attr)
        if name is None:
            continue
        if name in seen:
            raise SceneError(f"{path}[{i}].{attr}", name, f"duplicate of {path}[{seen[name]}].{attr}")
        seen[name] = i


#: Stage role of a body -> the table of the stage it comes from.
def body_table(expanded, origin: dict) -> dict:
    """Name -> body; duplicate names and an empty scene are errors."""
    names = {}
    for i, b in enumerate(expanded.bodies):
        if b.name in names:
            raise SceneError(f"{origin.get(b.name, f'bodies[{i}]')}.name", b.name, "duplicate body name")
        names[b.name] = b
    if not names:
        raise SceneError("bodies", [], "a scene needs at least one body")
    return names


def stage_elements_valid(scene, expanded, origin: dict) -> None:
    """The bodies and meshes a planetary stage made obey the table rules too."""
    for b in expanded.bodies[len(scene.bodies):]:
        check_body(b, origin[b.name])
    for p, m in list(element_paths(scene, expanded, "meshes", origin, "gear1"))[len(scene.meshes):]:
        check_mesh(m, p)


def references_exist(scene) -> None:
    """Every field that names a body names one of the scene's (its own bodies, stage
    members, shaft stations; :mod:`assembly.scene.body_names`), or the housing where a frame may
    be it; a bearing joins two different bodies. Run on the tables as written, before gear
    numbers are derived and bodies placed (:class:`assembly.scene.tables.Scene` calls it first), so
    an unknown name is named with the nearest one the scene has, not met later as a gap
    in another rule (a misspelt ``gear2`` looked like a missing base radius)."""
    for i, s in enumerate(scene.shafts):    # else its stations have no names to refer to
        stations_named(s, f"shafts[{i}]")
    names = scene_body_names(scene)
    known = set(names)
    for path, name, housing in body_references(scene):
        if name not in known and not (housing and name == HOUSING):
            raise SceneError(path, name, unknown_body_reason(name, names, housing))
    for i, br in enumerate(scene.bearings):
        if br.frame is not None and br.frame == br.body:
            raise SceneError(f"bearings[{i}].frame", br.frame, "a bearing cannot join a body to itself")


def frames_form_tree(expanded, names: dict, origin: dict) -> None:
    """Reference frames form a tree rooted at the housing."""
    for b in expanded.bodies:
        seen, cur = {b.name}, b.frame
        while cur != HOUSING:
            if cur in seen:
                raise SceneError(f"{origin[b.name]}.frame", b.frame, "reference frames form a cycle")
            seen.add(cur)
            cur = names[cur].frame


def flexible_bodies_supported(expanded, origin: dict) -> None:
    """A flexible body lives in the housing frame and is held by springs, not fixed DOFs."""
    for b in expanded.bodies:
        if b.fidelity == "flexible" and b.frame != HOUSING:
            raise SceneError(f"{origin[b.name]}.frame", b.frame, "a flexible body must live in the housing frame")
    flexible = {b.name for b in expanded.bodies if b.fidelity == "flexible"}
    for f in expanded.fixed:
        if f.body in flexible:
            raise SceneError(f"{origin[f.body]}.fidelity", "flexible",
                             "fixed DOFs act on rigid bodies; hold a flexible body by a rigid bearing")


def attachments_resolve(scene, expanded, names: dict, masters: dict, origin: dict) -> None:
    """Every bearing and shaft attaches at a body point or a named interface (a stage
    member's bearing at its ``bearing_interface``); a shaft, beam or spring, runs along
    body1's axis."""
    for p, br in element_paths(scene, expanded, "bearings", origin, "body"):
        try:
            bearing_point(br, names[br.body], masters, p)
        except SceneError as err:
            if p.startswith("stages") and err.path == f"{p}.interface":
                raise SceneError(f"{p.removesuffix('.bearing')}.bearing_interface", err.value, err.reason) from None
            raise
    for i, s in enumerate(expanded.shafts):
        shaft_points(s, names[s.body1], names[s.body2], masters, f"shafts[{i}]")
        if s.is_beam:
            check_slenderness(s, i, shaft_line(s, i, names, masters)[2])
        else:   # the beam shafts' rule and tolerance (assembly.scene.shafts.check_along_axis)
            check_along_axis(s, i, *shaft_ends(s, i, names, masters))


def rigid_bearings_allowed(scene, expanded, names: dict, origin: dict) -> None:
    """An infinite bearing stiffness becomes a constraint: only where one can act
    (:func:`assembly.model.constraints.can_constrain`)."""
    for p, br in element_paths(scene, expanded, "bearings", origin, "body"):
        body = names[br.body]
        if not np.any(np.isinf(br.diagonal())) or can_constrain(br, body):
            continue
        f = next(f for f, k in zip(br.diagonal_fields(), br.diagonal()) if np.isinf(k))
        if body.component is not None:
            raise SceneError(f"{p}.{f}", getattr(br, f), "infinite stiffness is only supported for "
                             "plain rigid bodies; give a component body a finite bearing")
        raise SceneError(f"{p}.{f}", getattr(br, f), "infinite (rigid) stiffness is only supported for a "
                         "bearing at the body's position to its own frame")


#: Relative tolerance of the centre-distance check: geometry typed to 7 significant digits
#: or derived from teeth (exact to rounding, 1e-15) passes; a position off by a micrometre
#: per metre of centre distance does not.
CENTRE_DISTANCE_TOLERANCE = 1e-6


def _centre_field(m, body, which: int, origin: dict, p: str) -> str:
    """The scene field that places gear ``which`` (1 or 2) of mesh ``m``."""
    if getattr(m, f"center{which}") is not None:
        return f"{p}.center{which}"
    if body.component is not None:
        iface = getattr(m, f"interface{which}") or "gear_mesh"
        return f"{origin[body.name]}.position + its component's {iface!r} interface"
    return f"{origin[body.name]}.position"


def _gear_fields(scene, m, p: str, names: dict):
    """(radius fields, pressure-angle field as written, its value as written) of a mesh at
    path ``p``: the mesh's own fields (marked as derived when its gears carry teeth), or
    the member tables and pressure angle of the stage that made it."""
    if p.startswith("stages"):
        st = scene.stages[int(p[len("stages["):-1])]
        ring = m.gear2.endswith(".ring")
        first = "planets" if ring else "sun"
        second = "ring" if ring else "planets"
        pa, va = as_written(st, "pressure_angle_ring" if ring else "pressure_angle_sun",
                            f"{p}.pressure_angle_{'ring' if ring else 'sun'}")
        return f"{p}.{first}.base_radius, {p}.{second}.base_radius", pa, va
    mesh = scene.meshes[int(p[len("meshes["):-1])]
    pa, va = as_written(mesh, "pressure_angle", f"{p}.pressure_angle")
    radii = f"{p}.base_radius1, {p}.base_radius2"
    if all(names[g].teeth is not None or hasattr(names[g].component, "teeth") for g in (m.gear1, m.gear2)):
        radii += " (derived from the gears' teeth)"
    return radii, pa, va


def mesh_geometry(scene, expanded, names: dict, masters: dict, origin: dict) -> None:
    """Parallel gear axes and a centre distance of |r1 + r2| / cos(pressure angle), to the
    relative tolerance CENTRE_DISTANCE_TOLERANCE. The message names the fields that place
    the two gears and the radius and pressure-angle fields (as the user wrote them: in
    degrees when given under ``_deg``)."""
    for p, m in element_paths(scene, expanded, "meshes", origin, "gear1"):
        b1, b2 = names[m.gear1], names[m.gear2]
        a1, a2 = unit(b1.axis), unit(b2.axis)
        if abs(abs(a1 @ a2) - 1) > 1e-9:
            raise SceneError(f"{p}.gear2", m.gear2, "gear axes are not parallel (only parallel-axis meshes)")
        c1, c2, _, _ = mesh_centers(m, b1, b2, masters, p)
        d = c2 - c1
        C = np.linalg.norm(d - (d @ a1) * a1)
        C_want = abs(m.base_radius1 + m.base_radius2) / math.cos(m.pressure_angle)
        if abs(C - C_want) > CENTRE_DISTANCE_TOLERANCE * C_want:
            radii, pa, va = _gear_fields(scene, m, p, names)
            angle = f"{va:.9g} deg" if pa.endswith("_deg") else f"{va:.9g} rad"
            raise SceneError(pa, va,
                             f"centre distance {C:.9g} m between {m.gear1} ({_centre_field(m, b1, 1, origin, p)}) "
                             f"and {m.gear2} ({_centre_field(m, b2, 2, origin, p)}) does not match "
                             f"|r1 + r2| / cos(pressure_angle) = |{m.base_radius1:.9g} + {m.base_radius2:.9g}| m"
                             f" / cos({angle}) = {C_want:.9g} m ({radii}; {pa}) to the relative tolerance "
                             f"{CENTRE_DISTANCE_TOLERANCE:g}: move a gear, or place it by the mesh (place)")


def couplings_name_interfaces(expanded, masters: dict, origin: dict) -> None:
    """``flex.couplings`` keys name interfaces of the body's component."""
    for b in expanded.bodies:
        for key in ((b.flex.couplings or {}) if b.flex is not None else {}):
            if key not in masters.get(b.name, {}):
                raise SceneError(f"{origin[b.name]}.flex.couplings", key,
                                 f"no such interface; have {sorted(masters.get(b.name, {}))}")


def cutoffs_bounded(scene, expanded, origin: dict) -> None:
    """The Craig-Bampton cutoff of every flexible body needs at most MAX_MODES
    fixed-interface modes, judged before anything is meshed by Weyl's mode count on a
    lower bound of the component's volume (:func:`assembly.scene.cutoffs.weyl_mode_count`,
    which underestimates: only a cutoff that surely needs too many modes is refused here;
    the reduction itself stops at MAX_MODES + 1 modes for the rest)."""
    band = scene.band
    for b in expanded.bodies:
        opts = b.flex or FlexOptions()
        if b.fidelity != "flexible" or b.component is None or opts.n_modes is not None:
            continue
        # fe_components.geometry loads the part readers (gmsh, STEP, Nastran): only for a flexible body
        from fe_components.geometry import volume_lower_bound
        cutoff = opts.cutoff_hz if opts.cutoff_hz is not None else CB_CUTOFF_FACTOR * band
        volume = volume_lower_bound(b.component)
        n = weyl_mode_count(volume, opts.material, cutoff)
        if n > MAX_MODES:
            path, value = cutoff_source(origin[b.name], opts, band)
            raise SceneError(path, value, f"body {b.name!r} ({origin[b.name]}) would keep at least about "
                                          f"{n:.3g} fixed-interface modes below the cutoff {cutoff:.6g} Hz "
                                          f"(Weyl's count for {volume:.3g} m^3), more than MAX_MODES = "
                                          f"{MAX_MODES}; lower the cutoff or give flex.n_modes")


def check_loads(scene, names: dict, masters: dict) -> None:
    """``[load]`` or ``[[loads]]`` (not both), every case valid, names unique."""
    if scene.load is not None and scene.loads:
        raise SceneError("loads", [lc.name for lc in scene.loads],
                         "give either one [load] or a list [[loads]], not both")
    unique_names(scene.loads, "loads")
    for path, lc in scene.load_cases():
        check_load(lc, path, names, masters)


def everything_connected(expanded, names: dict, origin: dict) -> None:
    """Every body is held by a bearing, mesh, shaft or fixed DOF."""
    linked = set()
    for br in expanded.bearings:
        linked.add(br.body)
        other = br.frame or names[br.body].frame
        if other != HOUSING:
            linked.add(other)
    for m in expanded.meshes:
        linked.update((m.gear1, m.gear2))
    for s in expanded.shafts:
        linked.update((s.body1, s.body2))
        linked.update(station_body(s, st) for st in s.stations)
    linked.update(f.body for f in expanded.fixed)
    for b in expanded.bodies:
        if b.name not in linked:
            raise SceneError(f"{origin[b.name]}.name", b.name,
                             "body is connected to nothing (no bearing, mesh, shaft or fixed DOF)")


def validate_scene(scene) -> None:
    """Run every rule on ``scene`` (its references checked already: :func:`references_exist`
    runs before the scene's gear numbers are derived); the first one broken raises
    :class:`SceneError`."""
    check_tables(scene)
    expanded = scene.expanded()
    origin = body_origins(scene, expanded)
    names = body_table(expanded, origin)
    stage_elements_valid(scene, expanded, origin)
    frames_form_tree(expanded, names, origin)
    masters = component_masters(expanded)
    flexible_bodies_supported(expanded, origin)
    attachments_resolve(scene, expanded, names, masters, origin)
    rigid_bearings_allowed(scene, expanded, names, origin)
    mesh_geometry(scene, expanded, names, masters, origin)
    couplings_name_interfaces(expanded, masters, origin)
    cutoffs_bounded(scene, expanded, origin)
    check_loads(scene, names, masters)
    everything_connected(expanded, names, origin)
