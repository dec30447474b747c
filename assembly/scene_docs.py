"""What every scene key means: one short description per field of every scene table, and
prose notes per table (sign conventions, names, placement, defaults).

Data only, keyed by class name and field name, so that the reference generator
(``assembly/app/reference.py``) can walk the scene dataclasses and look each field up here;
``tests/app/test_reference.py`` fails when a field of the code has no description here or
a description names a field that no longer exists. Every claim below was checked against
the code it describes (the module named in brackets).
"""
from __future__ import annotations

from .flexible import CUTOFF_FACTOR
from .scene import DEFAULT_BAND_HZ, HOUSING, MAX_MODES, MAX_NAME_LENGTH

#: class name -> {field name -> one-line description}.
FIELDS: dict[str, dict[str, str]] = {
    "Scene": {
        "name": f"Name of the scene (titles, output file names; at most {MAX_NAME_LENGTH} characters).",
        "description": "Free text shown in the report.",
        "bodies": "Plain bodies, one `[[bodies]]` table each.",
        "bearings": "Bearings: 6x6 diagonal springs from a body to its frame or another body.",
        "meshes": "Parallel-axis gear meshes between two bodies.",
        "shafts": "6-DOF springs between two bodies (quill shafts, shrink fits, couplings).",
        "fixed": "DOFs held at zero relative to a body's frame.",
        "stages": "Planetary stages, each expanded into bodies, bearings and meshes.",
        "band_hz": f"Frequency band of interest; sets the Craig-Bampton cutoff of flexible bodies "
                   f"(default {DEFAULT_BAND_HZ:g} Hz).",
        "load": "One static load case (torque in, reaction out); or give `[[loads]]`.",
        "loads": "Several static load cases, names unique (not together with `[load]`).",
        "fidelity": "Default fidelity of every body, member and planets table that gives none "
                    "(default rigid).",
    },
    "Body": {
        "name": f"Unique body name, not `{HOUSING}`; referred to by bearings, meshes, shafts, `[load]`.",
        "mass": "Mass of a plain body (not with a `component`).",
        "polar_inertia": "Inertia about the rotation axis, about the centre of mass.",
        "transverse_inertia": "Inertia about the two axes normal to the rotation axis (default polar/2).",
        "inertia_tensor": "Full 3x3 inertia about the centre of mass in local axes (x, y, axis), "
                          "instead of polar/transverse.",
        "position": "Centre of mass of a plain body; the component's local origin for a component body.",
        "axis": "Rotation axis (local z), any non-zero vector; local x is global x projected "
                "normal to it (global y when the axis is near x).",
        "frame": f"Body whose motion this body's DOFs are measured from (`{HOUSING}`: ground).",
        "fidelity": "torsional (1 DOF), rigid (6 DOFs) or flexible (Craig-Bampton; needs a component).",
        "stage": "Set by the planetary-stage builder (the stage name); leave unset.",
        "role": "Set by the planetary-stage builder (sun, ring, carrier, planet); leave unset.",
        "component": "FE component table chosen by `kind`; its mesh gives mass and inertia.",
        "flex": "Meshing and reduction options of a component body.",
        "teeth": "Gear teeth of a plain gear body (`[bodies.teeth]`, as a component's); a component "
                 "gear's own `teeth` serve instead (both given: must be equal).",
        "internal": "true: the teeth are internal (a ring gear; `n_teeth` stays positive).",
    },
    "FlexOptions": {
        "mesh_size": "Element size (default from the component's thinnest wall).",
        "order": "Tetrahedron order: 2 = P2 (default), 1 = P1 (locks for nu near 0.5).",
        "n_modes": f"Fixed-interface modes kept (0 = Guyan); instead of `cutoff_hz`; at most {MAX_MODES}.",
        "cutoff_hz": f"Keep fixed-interface modes below this frequency (default {CUTOFF_FACTOR:g} x `band_hz`).",
        "couplings": "Table {interface = 'rbe2' | 'rbe3'} overriding an interface's coupling.",
        "material": "Material of the component (default steel).",
        "residual_vectors": "Add the static interior response to interface motion (Dickens et al. 1997).",
    },
    "Material": {
        "E": "Young's modulus (default 210 GPa, steel).",
        "nu": "Poisson's ratio.",
        "rho": "Density.",
    },
    "PinionParams": {
        "teeth": "Gear teeth of the pinion (`[bodies.component.teeth]`).",
        "shaft": "Shaft steps from local z = 0 along +z, each [length, diameter]; the first and "
                 "last are the bearing seats `bearing_a` and `bearing_b`.",
        "gear_center": "Local z of the gear's mid-face; the face must lie between the bearing seats.",
        "bore_diameter": "Central bore through the whole shaft (0 = solid).",
    },
    "WheelParams": {
        "teeth": "Gear teeth of the wheel (`[bodies.component.teeth]`).",
        "rim_inner_diameter": "Inner diameter of the toothed rim.",
        "web_thickness": "Axial thickness of the web.",
        "hub_outer_diameter": "Outer diameter of the hub.",
        "hub_length": "Axial length of the hub (spans the web).",
        "bore_diameter": "Hub bore (interface `bore`).",
        "web_offset": "Axial offset of the web mid-plane from the gear mid-face (local z = 0).",
        "hub_offset": "Axial offset of the hub centre from the gear mid-face.",
        "n_holes": "Number of axial lightening holes in the web.",
        "hole_diameter": "Diameter of the lightening holes.",
        "hole_pitch_diameter": "Diameter of the circle of hole centres (default midway hub-rim).",
    },
    "CarrierParams": {
        "planet_angles": "Planet (pin) angles about local z from local x; or give `n_planets`. "
                         "Set by the stage for a stage carrier.",
        "pin_pitch_radius": "Radius of the pin centres (set by the stage for a stage carrier).",
        "pin_bore_diameter": "Diameter of the planet-pin bores (interfaces `pin_0`, `pin_1`, ...).",
        "cheek_diameter": "Outer diameter of both cheeks.",
        "cheek_thickness": "Axial thickness of each cheek.",
        "cheek_spacing": "Axial gap between the cheeks (the planets' face width).",
        "post_diameter": "Diameter of the posts joining the cheeks between the planets.",
        "seat_a_diameter": "Diameter of hub A (bearing seat `bearing_a`, towards -z).",
        "seat_a_length": "Length of hub A.",
        "seat_b_diameter": "Diameter of hub B (bearing seat `bearing_b`, towards +z).",
        "seat_b_length": "Length of hub B (depth of the output bore).",
        "output_bore_diameter": "Bore in hub B (interface `output_bore`).",
        "center_hole_diameter": "Central through-hole, e.g. for the sun shaft (0 = none).",
        "post_radius": "Radius of the post centres (default the pin radius).",
    },
    "CylinderParams": {
        "length": "Length along local +z from 0 (interfaces `end_a` at 0, `end_b` at `length`).",
        "diameter": "Outer diameter.",
        "bore_diameter": "Bore (0 = solid cylinder).",
    },
    "GearTeeth": {
        "n_teeth": "Number of teeth z (refused below the undercut limit).",
        "normal_module": "Normal module m_n.",
        "pressure_angle": "Normal pressure angle alpha_n.",
        "face_width": "Face width b.",
        "helix_angle": "Helix angle beta at the pitch circle: > 0 right-hand about +z, < 0 left-hand.",
        "fidelity": "'smooth' (solid annulus) or 'involute' (meshed tooth flanks).",
        "smooth_radius": "Outer radius of the smooth annulus (default the pitch radius).",
        "profile_shift": "Profile shift coefficient x.",
    },
    "ShaftSegment": {
        "length": "Axial length of the step.",
        "diameter": "Outer diameter of the step.",
    },
    "Bearing": {
        "body": "Body the bearing carries (a `[[bodies]]` name or a stage member name).",
        "k_radial": "Stiffness along local x and y.",
        "k_axial": "Stiffness along the axis (local z).",
        "k_tilt": "Stiffness about local x and y.",
        "k_torsion": "Stiffness about the axis (0: free to turn).",
        "frame": "Other side of the bearing (default the body's own `frame`, usually the housing).",
        "position": "Where it acts (default the body's position, or its `interface`'s master node).",
        "name": "Name in tables and messages (default `bearing[i]:<body>`).",
        "interface": "Interface of a component body where the bearing acts (e.g. `bearing_a`); required there.",
        "frame_interface": "Interface of the frame body where the bearing acts (e.g. a carrier's `pin_0`).",
    },
    "GearMesh": {
        "gear1": "First gear (a body or stage member name); the signs below refer to it.",
        "gear2": "Second gear.",
        "stiffness": "Mesh stiffness along the line of action.",
        "base_radius1": "Base radius of gear 1 (negative for an internal gear).",
        "base_radius2": "Base radius of gear 2 (negative for an internal gear, e.g. a ring).",
        "pressure_angle": "Transverse operating (working) pressure angle; from the teeth when both "
                          "gears have them.",
        "helix_angle": "Line-of-action helix (the base helix angle), positive when gear 1 is "
                       "left-hand; from teeth: minus gear 1's signed base helix angle.",
        "drive_sign": "+1 or -1: the sense of rotation of gear 1 about its axis that closes the mesh "
                      "with gear 2 held (picks the flank).",
        "name": "Name in tables and messages (default `mesh[i]:<gear1>-<gear2>`).",
        "center1": "Centre of gear 1 (default its body position, or its `gear_mesh` interface).",
        "center2": "Centre of gear 2 (same default).",
        "contact_point": "'pitch' (one shared point) or 'tangent' (each gear's base-circle tangent "
                         "point, to reproduce Kahraman's published table).",
        "interface1": "Interface of a component gear 1 (default `gear_mesh`).",
        "interface2": "Interface of a component gear 2 (default `gear_mesh`).",
        "place": "'gear1' or 'gear2': put that gear (with no `position`) at the working centre "
                 "distance from the other.",
        "centre_line_angle": "Direction of the line of centres for `place`, about the other gear's "
                             "axis from its local x.",
    },
    "Shaft": {
        "body1": "First body; the spring's axes are this body's axes.",
        "body2": "Second body (e.g. `<stage>.sun` for a quill shaft into a planetary stage).",
        "k_torsion": "Torsional stiffness about body1's axis (G J / L for a plain shaft).",
        "k_bending": "Bending stiffness about local x and y (0: none).",
        "k_axial": "Axial stiffness along body1's axis (0: none).",
        "k_shear": "Shear stiffness along local x and y (0: none).",
        "position": "Where the spring acts (default midway between the two attachment points).",
        "name": "Name in tables and messages (default `shaft[i]:<body1>-<body2>`).",
        "interface1": "Interface of a component body1 where the shaft attaches (e.g. `bore`).",
        "interface2": "Interface of a component body2.",
    },
    "Fixed": {
        "body": "Body whose DOFs are held (a body or stage member name).",
        "dofs": "Local DOF names held, among x, y, z, rx, ry, rz (default all six).",
    },
    "PlanetaryStage": {
        "name": "Stage name, without '.'; prefixes its members (`<name>.sun`, ...).",
        "sun": "The sun member.",
        "ring": "The ring member (internal gear).",
        "carrier": "The carrier member.",
        "planets": "The planets.",
        "k_mesh_sun": "Stiffness of every sun-planet mesh.",
        "k_mesh_ring": "Stiffness of every planet-ring mesh.",
        "pressure_angle_sun": "Transverse pressure angle of the sun-planet meshes.",
        "pressure_angle_ring": "Transverse pressure angle of the planet-ring meshes.",
        "helix_angle": "Without `normal_module`: the sun-planet meshes' helix as `[[meshes]]` "
                       "(planet-ring: the negative); with it: the sun teeth's reference helix "
                       "(> 0 right-hand).",
        "normal_module": "Normal module m_n of every gear of the stage: base radii, pressure angles "
                         "and carrier radius then come from the members' `teeth` and `profile_shift`.",
        "normal_pressure_angle": "Normal pressure angle alpha_n of the stage's gears (with `normal_module`).",
        "drive_sign": "+1 or -1: the sense about `axis` in which the sun closes its meshes.",
        "center": "Position of sun, ring and carrier (their centre of mass or component origin).",
        "axis": "Common axis of the stage; planet angles are measured from its local x.",
        "contact_point": "'pitch' or 'tangent', for every mesh of the stage (as `[[meshes]]`).",
    },
    "Member": {
        "mass": "Mass (not with a `component`).",
        "polar_inertia": "Inertia about the axis (not with a `component`).",
        "transverse_inertia": "Inertia normal to the axis (default polar/2).",
        "base_radius": "Base radius of sun or ring, positive for both (unused for the carrier).",
        "support": "'bearing' (to the housing), 'fixed' (six DOFs held) or 'floating' (no bearing).",
        "bearing": "Bearing to the housing, required with support = 'bearing' (named `<stage>.<member>.bearing`).",
        "fidelity": "torsional, rigid or flexible (flexible needs a `component`).",
        "component": "Carrier only: a `kind = \"carrier\"` table as under `[bodies.component]` "
                     "without planet_angles, pin_pitch_radius, n_planets (the stage sets them).",
        "flex": "Meshing and reduction options of a component carrier.",
        "bearing_interface": "Interface of a component carrier where its bearing acts.",
        "teeth": "Number of teeth of sun or ring (with the stage's `normal_module`).",
        "profile_shift": "Profile shift coefficient x of sun or ring (ISO 21771; the ring's as ISO gives it).",
    },
    "BearingSpec": {
        "k_radial": "Stiffness along local x and y.",
        "k_axial": "Stiffness along the axis.",
        "k_tilt": "Stiffness about local x and y.",
        "k_torsion": "Stiffness about the axis (0: free to turn).",
    },
    "Planets": {
        "count": "Number of planets (`<stage>.planet0` ... `planet<count-1>`).",
        "mass": "Mass of one planet.",
        "polar_inertia": "Polar inertia of one planet.",
        "base_radius": "Base radius of the planets.",
        "bearing": "Bearing of each planet to the carrier (named `<stage>.planet<i>.bearing`).",
        "transverse_inertia": "Inertia normal to the axis (default polar/2).",
        "angles": "Planet angles about the axis from the stage's local x (default equally spaced from 0).",
        "outer_radius": "Outer radius for the overlap check (default the operating pitch radius).",
        "fidelity": "torsional or rigid (planets have no component).",
        "teeth": "Number of teeth of each planet (with the stage's `normal_module`).",
        "profile_shift": "Profile shift coefficient x of the planets (ISO 21771).",
    },
    "LoadCase": {
        "input": "Body the torque enters (a body or stage member name).",
        "output": "Body held against rotation about its own axis (the reaction), in the housing frame.",
        "torque": "Torque about the input body's axis (sign: right-hand about that axis).",
        "input_interface": "Interface where the torque enters a component input body (required there).",
        "name": "Name of the load case.",
        "output_interface": "Interface of a component output body where it is held (required there).",
    },
}

#: class name -> {key -> description} of keys the schema accepts besides the fields
#: (:func:`assembly.schema.component_from_table`): ``kind`` of every component table, and the
#: carrier's equally spaced planets.
EXTRA_KEYS: dict[str, dict[str, str]] = {
    "CarrierParams": {
        "n_planets": "integer: instead of planet_angles, this many equally spaced planets.",
        "first_planet_angle": "number, rad (or `first_planet_angle_deg`): angle of the first of "
                              "`n_planets` (default 0).",
        "first_planet_angle_deg": "number, deg: `first_planet_angle` in degrees.",
    },
}

#: class name -> prose notes on the table (Markdown).
NOTES: dict[str, str] = {
    "Scene": (
        "Units are SI throughout: m, kg, s, N, rad, Pa; stiffness N/m and N m/rad; frequency Hz. "
        "Every angle may be given in degrees under its key plus `_deg` (`helix_angle_deg = 12.0`), "
        "never both. A bearing stiffness may be `inf`: that direction is then a constraint, not a "
        "spring. Unknown keys are refused, naming the allowed ones. Names of stage members "
        "(`<stage>.sun`, `.ring`, `.carrier`, `.planet<i>`) can be used wherever a body name is "
        "expected: `[[bearings]]`, `[[meshes]]`, `[[shafts]]`, `[[fixed]]`, `[load]`."),
    "Body": (
        "**Position.** A plain body's DOFs and inertia sit at its centre of mass, `position`; a gear's "
        "mesh centre defaults to it, so for a gear `position` is the centre of its mid-face. A body "
        "with a `component` places the component's local origin at `position`, local z along `axis`: "
        "pinion -- local z = 0 is the outer end of bearing seat A (the shaft runs along +z, the gear "
        "mid-face at `gear_center`); wheel -- the gear mid-face; carrier -- the mid-plane between the "
        "cheeks; cylinder -- the end face `end_a`. Its mass and inertia then come from the mesh, and "
        "bearings, meshes and shafts attach at its interface master nodes (`bearing_a`, "
        "`bearing_b`, `gear_mesh`, `bore`, `pin_<i>`, `output_bore`, `end_a`, `end_b`).\n\n"
        "**Defaults that depend on other fields.** `transverse_inertia` defaults to "
        "`polar_inertia`/2 (a thin disc). Give `mass` and `polar_inertia` (or `inertia_tensor`), "
        "or a `component`, not both."),
    "FlexOptions": (
        f"Either `n_modes` or `cutoff_hz`, not both. Without either the cutoff is {CUTOFF_FACTOR:g} x "
        f"the scene's `band_hz` (itself {DEFAULT_BAND_HZ:g} Hz when not given); a cutoff that would keep "
        f"more than {MAX_MODES} modes is refused. Also written inline: "
        "`flex = { mesh_size = 0.012 }`."),
    "Material": "Isotropic linear-elastic material; the defaults are structural steel.",
    "PinionParams": (
        "Local origin: the outer end of bearing seat A (local z = 0); the shaft steps run along +z, "
        "the first and last step are the bearing seats (interfaces `bearing_a`, `bearing_b` at their "
        "mid-length), the gear (interface `gear_mesh`) has its mid-face at `gear_center`."),
    "WheelParams": "Local origin: the gear mid-face; interfaces `bore` (at `hub_offset`) and `gear_mesh`.",
    "CarrierParams": (
        "Local origin: the mid-plane between the cheeks; interfaces `pin_<i>` (planet pins), "
        "`bearing_a`, `bearing_b`, `output_bore`. Give `planet_angles` or `n_planets` "
        "(+ `first_planet_angle`); inside a stage, neither (the stage places the pins)."),
    "CylinderParams": "Local origin: the end face `end_a`; the cylinder runs along +z to `end_b`.",
    "GearTeeth": (
        "ISO 21771 nomenclature, standard basic rack. **Helix hand:** `helix_angle` > 0 is a "
        "right-hand helix about local +z (the transverse profile turns positively as z grows). "
        "A `[[meshes]]` `helix_angle` is the line of action's, with the opposite sign convention: "
        "positive means gear 1 is left-hand. From teeth it is minus gear 1's base helix angle "
        "beta_b, tan(beta_b) = tan(beta) cos(alpha_t) (plus for an internal gear 1); an external "
        "pair has opposite hands, an internal pair the same hand."),
    "ShaftSegment": "Written as a two-number array `[length, diameter]` or as a table.",
    "Bearing": (
        "Diagonal spring diag(k_radial, k_radial, k_axial, k_tilt, k_tilt, k_torsion) on the motion of "
        "`body` relative to `frame`, at `position`, in the body's axes. `inf` holds that direction "
        "exactly (plain rigid bodies, at the body's position, to its own frame). A stage's own "
        "bearings are named `<body>.bearing` (`stage.sun.bearing`, `stage.planet0.bearing`)."),
    "GearMesh": (
        "Linear spring along the line of action of two parallel-axis gears.\n\n"
        "**Flank (`drive_sign`).** +1: turning gear 1 positively about its own axis, with gear 2 "
        "held, closes the mesh (loads this flank); -1: turning it negatively does. With a torque "
        "driving gear 1 positively, gear 2 of an external pair turns negatively.\n\n"
        "**Internal gear.** A ring is an internal gear: give its base radius **negative** here "
        "(`base_radius2 = -0.1391`); a `[[stages]]` ring takes it positive.\n\n"
        "**Geometry.** The transverse distance between the gear centres must equal "
        "|r1 + r2| / cos(`pressure_angle`) (base radii r, signed); the gears may sit at different "
        "axial positions.\n\n"
        "**Helix.** `helix_angle` > 0: gear 1 left-hand; from teeth, minus gear 1's signed base "
        "helix angle (see `[bodies.component.teeth]`).\n\n"
        "**From teeth.** When both gears carry teeth (`[bodies.teeth]` or their component's), "
        "leave out base radii, pressure angle and helix: they are derived (ISO 21771), with the "
        "working pressure angle from the profile shifts; typed values must agree. `place` puts "
        "one gear at the working centre distance (see docs/gears.md)."),
    "Shaft": (
        "A 6-DOF spring between two bodies: diag(k_shear, k_shear, k_axial, k_bending, k_bending, "
        "k_torsion) on their relative motion at `position`, in body1's axes. For a solid round "
        "shaft of length L, diameter d: k_torsion = G pi d^4 / (32 L), k_axial = E pi d^2 / (4 L). "
        "It joins two stages: body1 = the output gear of one stage, body2 = `<stage>.sun` of the "
        "next, whose sun has `support = \"floating\"` (no bearing: the shaft and the meshes carry "
        "it). A shaft also joins a component hub to a plain shaft body (`interface1 = \"bore\"`)."),
    "Fixed": "Holds DOFs of a body relative to its frame (a `support = \"fixed\"` member adds one).",
    "PlanetaryStage": (
        "One table expands into bodies `<name>.sun`, `<name>.ring`, `<name>.carrier` at `center`, "
        "and `<name>.planet0` ... `planet<count-1>` in the carrier's frame at the carrier radius "
        "(r_sun + r_planet) / cos(`pressure_angle_sun`); meshes `<name>.sun-planet<i>` (gear1 = sun) "
        "and `<name>.planet<i>-ring` (gear1 = planet, ring base radius negated); bearings "
        "`<body>.bearing`. Refer to these names from `[[bearings]]`, `[[shafts]]`, `[[fixed]]`, "
        "`[load]`.\n\n"
        "**Signs.** `drive_sign` is the sun-planet meshes' `drive_sign`: the sun turning in that "
        "sense about `axis` closes them; each planet-ring mesh takes `-drive_sign`, because the "
        "planet then turns the other way, so one sign loads every mesh on the consistent flank. "
        "`helix_angle` is the sun-planet meshes' (positive: the sun is left-hand; with "
        "`normal_module` it is the sun teeth's reference helix instead, and the meshes take minus "
        "its base helix angle); the planet-ring meshes take the negative (gear 1 = planet, of the "
        "other hand). The ring's `base_radius` "
        "is given **positive** here (the builder makes it negative).\n\n"
        "**Geometry.** The ring base radius must give the same carrier radius: "
        "(r_ring - r_planet) / cos(`pressure_angle_ring`) = (r_sun + r_planet) / "
        "cos(`pressure_angle_sun`)."),
    "Member": (
        "The same table for `sun`, `ring` and `carrier`. `support = \"floating\"` leaves the member "
        "held only by its meshes and by what you attach to it (a `[[shafts]]` quill shaft); "
        "`\"fixed\"` holds its six DOFs (a ring bolted to the housing)."),
    "BearingSpec": "Diagonal stiffnesses as in `[[bearings]]`; `inf` = rigid direction.",
    "Planets": "N identical planets, each on a bearing to the carrier at its pin.",
    "LoadCase": (
        "Static load case: `torque` about `input`'s axis, reacted by holding `output` against "
        "rotation about its own axis. Stage members by name (`input = \"stage.carrier\"`). "
        "`flexgear static` and `flexgear run` report mesh forces, bearing reactions, shaft loads "
        "and torque-balance and ratio checks for every case at every fidelity (docs/static.md)."),
}
