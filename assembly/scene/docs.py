"""What every scene key means: one short description per field of every scene table, and
prose notes per table (sign conventions, names, placement, defaults).

Data only, keyed by class name and field name, so that the reference generator
(``assembly/app/reference.py``) can walk the scene dataclasses and look each field up here;
``tests/app/test_reference.py`` fails when a field of the code has no description here or
a description names a field that no longer exists. Every claim below was checked against
the code it describes (the module named in brackets).
"""
from __future__ import annotations

from .cutoffs import CB_CUTOFF_FACTOR
from .tables import DEFAULT_BAND_HZ, HOUSING, MAX_MODES, MAX_NAME_LENGTH

#: The damper fields of a bearing table (:class:`Bearing`, :class:`BearingSpec`).
_BEARING_DAMPERS = {
    "c_radial": "Viscous damper along local x and y, beside `k_radial` (default none; or give `c_radial_x` and `c_radial_y`).",
    "c_axial": "Viscous damper along the axis (default 0).",
    "c_tilt": "Viscous damper about local x and y (default none; or give `c_tilt_x` and `c_tilt_y`).",
    "c_torsion": "Viscous damper about the axis (default 0).",
    "c_radial_x": "Damper along local x, with `c_radial_y` instead of `c_radial` (Nejad et al. 2016: c_y).",
    "c_radial_y": "Damper along local y, with `c_radial_x` instead of `c_radial` (Nejad et al. 2016: c_z).",
    "c_tilt_x": "Damper about local x, with `c_tilt_y` instead of `c_tilt` (Nejad et al. 2016: c_beta).",
    "c_tilt_y": "Damper about local y, with `c_tilt_x` instead of `c_tilt` (Nejad et al. 2016: c_gamma).",
}

#: The keys of a history read from a file, shared by `[[simulation.loads]]` and the generator.
_FILE_HISTORY = {
    "table": "CSV file (relative to the scene file) with a header row.",
    "openfast": "OpenFAST output, text (.out, FAST v7/v8 too) or binary (.outb); converted to SI by its units.",
    "column": "The column or channel to read (e.g. `RtAeroMxh`); a channel's unit must fit the quantity.",
    "time_column": "Time column of the CSV file (default `time`).",
    "scale": "Factor on a table's or file's values, after the conversion to SI (default 1).",
    "time_offset": "Shift of the file's time: run time = file time - time_offset (s, default 0).",
    "time_window": "[t0, t1]: the part of the file read (s, the file's time; default all).",
}

#: class name -> {field name -> one-line description}.
FIELDS: dict[str, dict[str, str]] = {
    "Scene": {
        "name": f"Name of the scene (titles, output file names; at most {MAX_NAME_LENGTH} characters).",
        "description": "Free text shown in the report.",
        "bodies": "Plain bodies, one `[[bodies]]` table each.",
        "bearings": "Bearings: 6x6 diagonal springs from a body to its frame or another body.",
        "meshes": "Parallel-axis gear meshes between two bodies.",
        "shafts": "Shafts between two bodies: 6-DOF springs typed by hand (quill shafts, shrink "
                  "fits, couplings), or Timoshenko beams by diameter with bearing stations.",
        "fixed": "DOFs held at zero relative to a body's frame.",
        "stages": "Planetary stages, each expanded into bodies, bearings and meshes.",
        "band_hz": f"Frequency band of interest; sets the Craig-Bampton cutoff of flexible bodies "
                   f"(default {DEFAULT_BAND_HZ:g} Hz).",
        "load": "One static load case (torque in, reaction out); or give `[[loads]]`.",
        "loads": "Several static load cases, names unique (not together with `[load]`).",
        "fidelity": "Default fidelity of every body, member and planets table that gives none "
                    "(default rigid).",
        "damping": "Scene-level damping: modal ratios or Rayleigh (`[damping]`); element dampers are "
                   "the `c_*` fields.",
        "simulation": "Settings of `flexgear simulate` (`[simulation]`, a `Simulation` table).",
        "turbine": "The turbine around the drivetrain in `flexgear simulate`: rotor aerodynamics, wind, "
                   "controller, gravity, nacelle motion, unbalance (`[turbine]`, a `Turbine` table).",
    },
    "Damping": {
        "modal_ratio": "Damping ratio zeta of every elastic mode, in [0, 1).",
        "class_ratios": "Ratio per mode class, e.g. `{ rotational = 0.05 }` (rotational, translational, "
                        "planet, out-of-plane, mixed, elastic); overrides `modal_ratio` for those modes.",
        "rayleigh_alpha": "Mass-proportional Rayleigh coefficient (>= 0): zeta = alpha/(2 omega) + "
                          "beta omega/2; rigid-body modes projected out.",
        "rayleigh_beta": "Stiffness-proportional Rayleigh coefficient (>= 0).",
    },
    "Body": {
        "name": f"Unique body name, not `{HOUSING}`; referred to by bearings, meshes, shafts, `[load]`.",
        "mass": "Mass of a plain body; left out with `polar_inertia` on a body with `teeth`: from its gear "
                "blank. With a `component` (optional, as `polar_inertia`, `transverse_inertia`, "
                "`inertia_tensor`): the value you expect; the mesh's is used, and both are reported (a "
                "warning and the body table of every report) when they differ.",
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
        "role": "`rotor` or `generator` (one body each): the ends of the drivetrain for `flexgear export "
                "elastodyn`; other text is free; the planetary-stage builder sets sun, ring, carrier, planet.",
        "component": "FE component table chosen by `kind`; its mesh gives mass and inertia (typed ones are "
                     "compared with it and reported, not used).",
        "flex": "Meshing and reduction options of a component body.",
        "teeth": "Gear teeth of a plain gear body (`[bodies.teeth]`, as a component's); a component "
                 "gear's own `teeth` serve instead (both given: must be equal).",
        "internal": "true: the teeth are internal (a ring gear; `n_teeth` stays positive).",
        "blank": "Gear blank dimensions (`[bodies.blank]`) of a body whose mass and inertia come from "
                 "its `teeth` (mass, polar_inertia and inertia_tensor left out).",
    },
    "GearBlank": {
        "bore_diameter": "Bore of an external gear's blank (0: solid to the centre).",
        "outer_diameter": "Outer diameter of a ring's rim (default d_f + 2 x 1.2 x 2.25 m_n; ISO 6336-3's "
                          "rim thickness for rim factor Y_B = 1).",
        "length": "Axial length of the blank (default the face width).",
    },
    "FlexOptions": {
        "mesh_size": "Element size (default from the component's thinnest wall).",
        "order": "Tetrahedron order: 2 = P2 (default), 1 = P1 (locks for nu near 0.5).",
        "n_modes": f"Fixed-interface modes kept (0 = Guyan); instead of `cutoff_hz`; at most {MAX_MODES}.",
        "cutoff_hz": f"Keep fixed-interface modes below this frequency (default {CB_CUTOFF_FACTOR:g} x `band_hz`).",
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
    "PartFile": {
        "file": "The part's file: CAD (.step/.stp/.brep) or volume mesh (.msh, .inp, .bdf, .vtu, ...); a "
                "relative path is relative to the scene file. The caches key on its content (SHA-256).",
        "interfaces": "The part's interfaces (`[[...component.interfaces]]`), in master order: where "
                      "bearings, meshes, planets and loads attach.",
        "units": "Length unit of the file's numbers: 'm', 'mm', 'cm', 'um', 'in', 'ft'. STEP: default the "
                 "unit the file declares; BREP: default 'mm'; a mesh file: required.",
        "volumes": "Several volumes in the file: 'refuse' (default) or 'fuse' them into one part (they must touch).",
        "order": "A mesh file's element order: left out, the file's own (linear tetrahedra warn: too stiff in "
                 "bending); 2 lifts a linear mesh to P2 (edge midpoints, straight edges); 1 keeps it linear "
                 "without the warning. A CAD part is meshed at `flex.order`.",
        "axis": "The part's rotation axis in the file's axes (default z); the part is read in the frame whose z "
                "it is (x, y as a body's local axes: docs/user_parts.md).",
        "origin": "The point of `axis` that becomes the part's local origin (m after the unit conversion, the "
                  "file's axes; default the file's origin).",
    },
    "InterfaceRule": {
        "name": "Interface name the scene refers to (`pin_0`, `bearing_b`, ...).",
        "select": "How its faces are found: 'group' (a named group of a mesh file), 'cylinder', 'plane' "
                  "or 'box'. A rule that selects no face, or a face another rule selects, is an error.",
        "group": "select = 'group': gmsh physical group, Abaqus node set or face element set.",
        "axis_point": "select = 'cylinder': a point of the axis (part axes, after the unit conversion).",
        "axis": "select = 'cylinder': axis direction (default +z).",
        "radius": "select = 'cylinder': faces on this radius about the axis.",
        "outer_radius": "select = 'cylinder': instead every face between `radius` and this radius that is "
                        "not normal to the axis (gear teeth, splines).",
        "span": "select = 'cylinder': [start, end] along the axis from `axis_point` the faces lie in.",
        "point": "select = 'plane': a point of the plane.",
        "normal": "select = 'plane': the plane's normal.",
        "box_min": "select = 'box' (or to restrict a cylinder or plane): faces inside box_min..box_max.",
        "box_max": "Upper corner of the box.",
        "coupling": "'rbe2' (rigid spider, default) or 'rbe3' (distributing: adds no stiffness).",
        "master": "Master node position; default the faces' area centroid (a cylinder's on its axis).",
        "tolerance": "How far a face may lie off the rule (default 1e-5 of the part's size).",
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
        "k_radial": "Stiffness along local x and y (or give `k_radial_x` and `k_radial_y`).",
        "k_axial": "Stiffness along the axis (local z); required.",
        "k_tilt": "Stiffness about local x and y (or give `k_tilt_x` and `k_tilt_y`).",
        "k_torsion": "Stiffness about the axis (0: free to turn).",
        "frame": "Other side of the bearing (default the body's own `frame`, usually the housing).",
        "position": "Where it acts (default the body's position, or its `interface`'s master node).",
        "name": "Name in tables and messages (default `bearing[i]:<body>`).",
        "interface": "Interface of a component body where the bearing acts (e.g. `bearing_a`); required there.",
        "frame_interface": "Interface of the frame body where the bearing acts (e.g. a carrier's `pin_0`).",
        "k_radial_x": "Stiffness along local x, with `k_radial_y` instead of `k_radial` (Nejad et al. 2016: K_y).",
        "k_radial_y": "Stiffness along local y, with `k_radial_x` instead of `k_radial` (Nejad et al. 2016: K_z).",
        "k_tilt_x": "Stiffness about local x, with `k_tilt_y` instead of `k_tilt` (Nejad et al. 2016: K_beta).",
        "k_tilt_y": "Stiffness about local y, with `k_tilt_x` instead of `k_tilt` (Nejad et al. 2016: K_gamma).",
        "radial_angle": "Turns the bearing's local x (and y) about the body's axis from the body's local x: "
                        "`k_radial_x` and `k_tilt_x` then act along / about that direction. Planet bearings of "
                        "a stage take their planet's angle: x radial, y tangential.",
        **_BEARING_DAMPERS,
    },
    "GearMesh": {
        "gear1": "First gear (a body or stage member name); the signs below refer to it.",
        "gear2": "Second gear.",
        "stiffness": "Mesh stiffness along the line of action; left out between gears with teeth: "
                     "ISO 6336-1 method B, c_gamma_alpha times the smaller face width.",
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
        "damping": "Viscous damper along the line of action, beside the mesh spring (default 0).",
        "backlash": "Time domain: normal backlash along the line of action (m); the teeth touch on the "
                    "driving flank at compression > 0, on the coast flank below -backlash, carry nothing "
                    "in between. Left out: a linear spring in both senses.",
        "variation": "Time domain: the stiffness as a function of the gear angle (a `MeshVariation` table).",
    },
    "MeshVariation": {
        "amplitudes": "a_h relative to the mean stiffness, harmonics h = 1, 2, ...: "
                      "k = k0 (1 + sum a_h cos(h phi + phi_h)).",
        "phases": "phi_h of each amplitude (rad, or `phases_deg`; default 0).",
        "step": "Instead of amplitudes: the relative stiffness step dk/k0 between double and single tooth "
                "contact; the rectangular wave's series 2 step sin(h pi (c-1)) / (h pi).",
        "contact_ratio": "Profile contact ratio c in (1, 2) of the `step` wave (default from the teeth).",
        "face_contact_ratio": "Overlap ratio eps_beta: harmonic h times sinc(h eps_beta) (default from the "
                              "teeth; 0 for spur gears).",
        "harmonics": "Harmonics of the `step` wave kept (default 8).",
        "phase": "Angle offset: phi = z (theta - theta_frame) - phase (rad, or `phase_deg`); planets add z psi_n.",
        "teeth": "Teeth the angle counts (default the counting gear's).",
        "counting_gear": "'gear1' (default) or 'gear2': the gear whose angle and teeth count.",
    },
    "Simulation": {
        "speed": "Starting speed of `reference` about its own axis (rad/s); every body starts at its "
                 "kinematic share.",
        "reference": "Body whose speed `speed` is (default the body of role 'rotor').",
        "loads": "Time-dependent loads (`[[simulation.loads]]`, `TimeLoad` tables).",
        "generator": "Generator torque law (a `Generator` table).",
        "brake": "Shaft brake (a `Brake` table).",
        "gearbox_efficiency": "ElastoDyn's GBoxEff in (0, 1]: friction torque (1/eta^s - 1) x the "
                              "generator-side torque on the generator (default 1: none).",
        "lss_shaft": "Shaft whose torque sign s sets the friction (default the shaft on the rotor).",
        "scheme": "'newmark' (average acceleration, default), 'hht' or 'generalized-alpha'.",
        "alpha": "HHT alpha in [0, 1/3] (default 0.05).",
        "rho_inf": "Generalized-alpha spectral radius at infinite frequency, [0, 1] (default 0.9).",
        "consistent": "Add the energy-consistent mesh term -1/2 dk/dtheta delta^2 (default true).",
        "static_start": "Start in static equilibrium under the loads at t = 0 (default true).",
        "points": "Named stress points (`[[simulation.points]]`, `StressPoint` tables): outputs `stress:NAME`.",
        "nacelle": "Prescribed housing accelerations (`[[simulation.nacelle]]`, `NacelleMotion` tables).",
        "unbalance": "Eccentric masses on turning bodies (`[[simulation.unbalance]]`, `UnbalanceMass` tables).",
        "drive": "A speed-controlled drive: a run-up or run-down (`[simulation.drive]`, a `SpeedDrive` table).",
        "life": "The loads-to-life tables of the run (`[simulation.life]`, a `LifeTables` table): DELs, load "
                "duration and revolution distributions, bearing L10, gear damage.",
    },
    "StressPoint": {
        "name": "Output name: `stress:NAME`.",
        "body": "The flexible body.",
        "point": "Global point (m); the stress is the von Mises stress at the nearest FE stress node.",
    },
    "Turbine": {
        "openfast": "An OpenFAST deck (.fst): radius, hub height, tilt, air density, controller library, "
                    "DISCON.IN and surface are read from it when not given here; 'rosco': the NREL 5 MW deck of the "
                    "installed rosco wheel.",
        "surface": "A ROSCO `Cp_Ct_Cq` file (relative to the scene file), or 'rosco': the NREL 5 MW "
                   "surface of the installed rosco wheel (default from the deck's DISCON.IN).",
        "radius": "Rotor (tip) radius (m).",
        "density": "Air density (kg/m^3, default 1.225).",
        "hub_height": "Hub height (m; the turbulence's reference height, default 90).",
        "tilt": "Shaft tilt (rad): gravity turned about x by it (default 0).",
        "rotor": "Body the aerodynamic torque and thrust act on (default the body of role 'rotor').",
        "generator": "Body the generator torque acts on (default the body of role 'generator').",
        "generator_ratio": "Generator speed per unit speed of that body (default 1; a two-mass model's "
                           "low-speed-side generator: the gear ratio, as ElastoDyn's GBRatio).",
        "pitch": "Collective blade pitch at t = 0 (rad).",
        "thrust": "Apply the thrust along the rotor's axis (default true).",
        "gravity": "Gravity (9.80665 m/s^2 along -y, turned by `tilt`) as a body load in `simulate` and "
                   "`static` (default false).",
        "wind": "The rotor-effective wind speed (a `Wind` table); without it, gravity and tilt only.",
        "controller": "The controller in the loop (a `Controller` table; default ROSCO's NREL 5 MW).",
    },
    "Wind": {
        "speed": "Constant wind speed, a ramp's start, or the turbulence's mean at hub height (m/s).",
        "end_speed": "A ramp's end speed (m/s, with `t_end`).",
        "t_start": "Ramp start (s, default 0).",
        "t_end": "Ramp end (s).",
        "steps": "[[t, V], ...]: V from t on (m/s; the first from t = 0).",
        "turbulence": "IEC 61400-1 turbulence class 'A', 'B' or 'C' about `speed` (pyconturb, the `wind` extra).",
        "seed": "Random seed of the turbulence (the same seed, the same wind).",
        "grid": "Points per side of the square grid over the rotor; those inside the disc are averaged "
                "(default 7).",
        "sample": "Time step of the generated turbulence (s, default 0.05); linear in between.",
        **{k: v.replace("(e.g. `RtAeroMxh`)", "(e.g. `RtVAvgxh`, in m/s)") for k, v in _FILE_HISTORY.items()},
    },
    "Controller": {
        "kind": "'rosco' (default: the rosco wheel's compiled controller), 'discon' (any DISCON "
                "library), 'simple' (ServoDyn's simple variable-speed law) or 'baseline' (the NREL 5 MW "
                "baseline torque law); the last two hold the pitch.",
        "library": "The DISCON library (.so/.dll; kind 'discon').",
        "input": "The library's input file (DISCON.IN; default for 'rosco': its NREL 5 MW file).",
        "period": "Sample time (s): a whole number of the run's steps (default the deck's DLL_DT, else 0.01).",
        "pitch_tau": "Time constant of the first-order pitch actuator (s; 0: none).",
        "pitch_omega": "Natural frequency of a second-order pitch actuator instead (rad/s).",
        "pitch_zeta": "Its damping ratio (default 0.7).",
        "efficiency": "Generator efficiency for the electrical power (default 0.944).",
        "rated_speed": "'simple': the generator's rated speed (rad/s; VS_RtGnSp).",
        "rated_torque": "'simple': the rated generator torque (N m; VS_RtTq).",
        "region2_k": "'simple': region 2's k in k omega^2 (N m s^2/rad^2; VS_Rgn2K).",
        "slip": "'simple': the rated slip as a fraction (VS_SlPc / 100).",
    },
    "NacelleMotion": {
        "dof": "'x', 'y', 'z' (m/s^2) or 'rx', 'ry', 'rz' (rad/s^2, about the global axes).",
        "amplitude": "Amplitude of the harmonic acceleration (m/s^2 or rad/s^2).",
        "frequency": "Its frequency (Hz; 0: a constant amplitude sin(phase)).",
        "phase": "Its phase (rad).",
        "origin": "The point the acceleration is given at (global, m; default the origin).",
        **_FILE_HISTORY,
    },
    "SpeedDrive": {
        "end_speed": "Speed at `t_end` (rad/s, the body's own axis); from the starting speed `speed`.",
        "t_end": "End of the ramp (s); the speed is held after it.",
        "t_start": "Start of the ramp (s, default 0).",
        "body": "The driven body (default the reference, the body of role 'rotor').",
        "bandwidth": "The servo's bandwidth (Hz, default 10): critically damped, on the drivetrain's inertia "
                     "referred to the body.",
    },
    "LifeTables": {
        "bearings": "Bearings rated from the run (`[[simulation.life.bearings]]`, `BearingRating` tables).",
        "gears": "Gears rated from the run (`[[simulation.life.gears]]`, `GearRating` tables).",
        "exponents": "Woehler exponents m of the damage-equivalent loads (default 3, 4, 10).",
        "cycles_ref": "Equivalent cycle count of the DELs (default the record's length in seconds: 1 Hz).",
        "bins": "Bins of the load duration and load revolution distributions (default 20).",
        "shaft": "The body whose revolutions the load revolution distributions count (default the reference).",
        "window": "[t0, t1] (s): the span of the record counted (default all of it; leave a start-up out).",
    },
    "BearingRating": {
        "bearing": "The bearing (its name in the expanded scene, as in `force:BEARING`).",
        "rating": "Basic dynamic load rating C (N), from the bearing's catalogue.",
        "exponent": "Life exponent p (default 10/3, roller bearings; 3 for ball bearings).",
        "radial_factor": "X of the dynamic equivalent load P = X F_r + Y F_a (default 1).",
        "axial_factor": "Y of the dynamic equivalent load P = X F_r + Y F_a (default 0: radial load only).",
    },
    "GearRating": {
        "mesh": "The mesh whose force loads the teeth (its name in the expanded scene, as in `force:MESH`).",
        "gear": "The gear rated: a body of the mesh (default its gear1).",
        "torque_ref": "Torque T_ref (N m) of the S-N curve N_f = cycles_ref (T_ref / T)^slope.",
        "cycles_ref": "Cycles N_ref the teeth bear at T_ref.",
        "slope": "S-N slope k (ISO 6336-6 tabulates it per material and failure mode).",
        "torque_limit": "Endurance limit (N m): no damage at or below it (default 0: none).",
    },
    "UnbalanceMass": {
        "body": "The rotating body that carries the mass.",
        "mass": "Eccentric mass (kg).",
        "radius": "Its distance from the body's axis (m).",
        "phase": "Its angle from the body's local x at t = 0 (rad).",
        "interface": "Interface master node of a flexible body the mass sits at.",
    },
    "TimeLoad": {
        "body": "Body loaded (a body or stage member name).",
        "kind": "'torque' (about the body's axis, N m, default), 'force' (N) or 'moment' (N m) along `direction`.",
        "direction": "Global direction of a force or moment (default (0, 0, 1)).",
        "interface": "Interface master node of a flexible body where the load acts.",
        "value": "Constant value, or a ramp's start value (N or N m).",
        "end_value": "A ramp's end value (with `t_end`).",
        "t_start": "Ramp start (s, default 0).",
        "t_end": "Ramp end (s); a step is a ramp of one time step.",
        **_FILE_HISTORY,
    },
    "Generator": {
        "body": "Body the generator acts on (default the body of role 'generator').",
        "law": "'constant' (default), 'pi' (rated torque with a PI speed controller) or 'table' (a "
               "recorded torque from `table` or `openfast`, e.g. OpenFAST's GenTq: positive brakes).",
        "torque": "Constant torque, or the PI's torque at rated speed (N m).",
        "rated_speed": "PI set point: the generator body's speed (rad/s).",
        "kp": "PI proportional gain (N m s/rad).",
        "ki": "PI integral gain (N m/rad).",
        "max_torque": "PI torque limit (N m, default 1.1 x torque).",
        **_FILE_HISTORY,
    },
    "Brake": {
        "torque": "Full brake torque (N m; ElastoDyn HSSBrTqF).",
        "deploy_time": "Time the brake starts to act (s).",
        "ramp_time": "Time to full torque (s; ElastoDyn HSSBrDT; 0: at once).",
        "body": "Body braked (default the body of role 'generator').",
        "stick_speed": "Below this speed (rad/s) the torque is proportional to speed, so it never "
                       "drives the shaft backwards (default 1e-3).",
    },
    "Shaft": {
        "body1": "First body; the spring's axes are this body's axes.",
        "body2": "Second body (e.g. `<stage>.sun` for a quill shaft into a planetary stage).",
        "position1": "Beam shaft: where it ends on body1 when that is not the body's position, e.g. "
                     "a gear's face (global, on a body without a component; a component names its "
                     "`interface1`). The shaft's length runs from here.",
        "position2": "Beam shaft: where it ends on body2, as `position1`.",
        "k_torsion": "Torsional stiffness about body1's axis (G J / L for a plain shaft); required "
                     "without `diameter`, left out with it.",
        "k_bending": "Bending stiffness about local x and y (0: none; not with `diameter`).",
        "k_axial": "Axial stiffness along body1's axis (0: none; not with `diameter`).",
        "k_shear": "Shear stiffness along local x and y (0: none; not with `diameter`).",
        "position": "Where the spring acts (default midway between the two attachment points; "
                    "not with `diameter`).",
        "name": "Name in tables and messages (default `shaft[i]:<body1>-<body2>`); required with "
                "`stations`, whose bodies it prefixes.",
        "interface1": "Interface of a component body1 where the shaft attaches (e.g. `bore`).",
        "interface2": "Interface of a component body2.",
        "diameter": "Outer diameter: the shaft is a Timoshenko beam from body1's attachment point "
                    "to body2's, its k_* derived.",
        "bore_diameter": "Bore of a beam shaft (0 = solid; less than `diameter`).",
        "material": "Material of a beam shaft (default steel).",
        "stations": "Points on a beam shaft (e.g. bearing seats), each a body `<name>.<station>`.",
        "stage": "Stage label of the station bodies (tables group bodies by it).",
        "c_torsion": "Spring shaft: viscous damper about body1's axis (default 0; not with `diameter`).",
        "c_bending": "Spring shaft: damper about local x and y (default 0; not with `diameter`).",
        "c_axial": "Spring shaft: damper along body1's axis (default 0; not with `diameter`).",
        "c_shear": "Spring shaft: damper along local x and y (default 0; not with `diameter`).",
        "beta": "Beam shaft: stiffness-proportional damping, each element's C_e = beta K_e (default 0; "
                "only with `diameter`).",
    },
    "Station": {
        "name": "Station name (no `.`, unique on its shaft); its body is `<shaft name>.<name>`.",
        "at": "Distance from body1's attachment point along the shaft, strictly between 0 and the "
              "shaft's length.",
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
        "k_mesh_sun": "Stiffness of every sun-planet mesh; left out with `normal_module`: ISO 6336-1 "
                      "method B, c_gamma_alpha times `face_width`.",
        "k_mesh_ring": "Stiffness of every planet-ring mesh; left out with `normal_module`: ISO 6336-1 "
                       "method B, c_gamma_alpha times `face_width`.",
        "pressure_angle_sun": "Transverse pressure angle of the sun-planet meshes.",
        "pressure_angle_ring": "Transverse pressure angle of the planet-ring meshes.",
        "helix_angle": "Without `normal_module`: the sun-planet meshes' helix as `[[meshes]]` "
                       "(planet-ring: the negative); with it: the sun teeth's reference helix "
                       "(> 0 right-hand).",
        "normal_module": "Normal module m_n of every gear of the stage: base radii, pressure angles "
                         "and carrier radius then come from the members' `teeth` and `profile_shift`.",
        "normal_pressure_angle": "Normal pressure angle alpha_n of the stage's gears (with `normal_module`).",
        "face_width": "Face width b of the stage's gears (with `normal_module`): the length of the gear "
                      "blanks that give sun, planets and ring the mass and inertia they leave out, and "
                      "the b of the ISO 6336-1 mesh stiffness when `k_mesh_sun` or `k_mesh_ring` is left out.",
        "drive_sign": "+1 or -1: the sense about `axis` in which the sun closes its meshes.",
        "center": "Position of sun, ring and carrier (their centre of mass or component origin); "
                  "default the origin. Not with `coaxial_with`.",
        "axis": "Common axis of the stage; planet angles are measured from its local x. With "
                "`coaxial_with`: parallel to that body's axis (either sense, 1e-6 rad), and then "
                "exactly the body's.",
        "coaxial_with": "Name of a body (of `[[bodies]]`, or the sun, ring or carrier of a stage "
                        "written before) whose axis the stage sits on exactly, no typed centre needed: "
                        "the centre is that body's `position` moved `axial_offset` along its axis. Use "
                        "it for a stage joined to a body by a shaft: a typed `center` a hair off the "
                        "body's axis is a lever arm on the shaft that the torsional model cannot turn.",
        "axial_offset": "With `coaxial_with`: the stage centre's distance from the body's position "
                        "along the body's axis (default 0).",
        "contact_point": "'pitch' or 'tangent', for every mesh of the stage (as `[[meshes]]`).",
        "c_mesh_sun": "Viscous damper along the line of action of every sun-planet mesh (default 0).",
        "c_mesh_ring": "Viscous damper along the line of action of every planet-ring mesh (default 0).",
        "backlash": "Time domain: normal backlash (m) of every mesh of the stage.",
        "variation_sun": "Time domain: stiffness variation of the sun-planet meshes (counted on the sun's "
                         "teeth relative to the carrier; planets phased by angle).",
        "variation_ring": "Time domain: stiffness variation of the planet-ring meshes (counted on the ring's teeth).",
    },
    "Member": {
        "mass": "Mass; sun and ring with `teeth` may leave it out with `polar_inertia` (from the gear "
                "blank and the stage's `face_width`). A carrier with a `component` may give it as the value "
                "you expect: the mesh's is used, both are reported.",
        "polar_inertia": "Inertia about the axis (with a `component`: the value you expect, as `mass`).",
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
        "blank": "Gear blank of sun or ring (`bore_diameter`, `outer_diameter` of the ring, `length`) when "
                 "their mass and polar_inertia are left out.",
    },
    "BearingSpec": {
        "k_radial": "Stiffness along local x and y (or give `k_radial_x` and `k_radial_y`).",
        "k_axial": "Stiffness along the axis; required.",
        "k_tilt": "Stiffness about local x and y (or give `k_tilt_x` and `k_tilt_y`).",
        "k_torsion": "Stiffness about the axis (0: free to turn).",
        "k_radial_x": "Stiffness along local x, with `k_radial_y` instead of `k_radial` (Nejad et al. 2016: K_y).",
        "k_radial_y": "Stiffness along local y, with `k_radial_x` instead of `k_radial` (Nejad et al. 2016: K_z).",
        "k_tilt_x": "Stiffness about local x, with `k_tilt_y` instead of `k_tilt` (Nejad et al. 2016: K_beta).",
        "k_tilt_y": "Stiffness about local y, with `k_tilt_x` instead of `k_tilt` (Nejad et al. 2016: K_gamma).",
        **_BEARING_DAMPERS,
    },
    "Planets": {
        "count": "Number of planets (`<stage>.planet0` ... `planet<count-1>`). On a stage with teeth, "
                 "equally spaced planets need (sun teeth + ring teeth) / count an integer (assembly condition).",
        "mass": "Mass of one planet; with `teeth` it may be left out with `polar_inertia` (from the gear "
                "blank and the stage's `face_width`).",
        "polar_inertia": "Polar inertia of one planet.",
        "base_radius": "Base radius of the planets.",
        "bearing": "Bearing of each planet to the carrier (named `<stage>.planet<i>.bearing`).",
        "transverse_inertia": "Inertia normal to the axis (default polar/2).",
        "angles": "Planet angles about the axis from the stage's local x (default equally spaced from 0). On a "
                  "stage with teeth, (sun teeth + ring teeth) (angle - first angle) / 2 pi must be an integer "
                  "(to 0.01/pi of a pitch).",
        "outer_radius": "Outer radius for the overlap check (default the operating pitch radius).",
        "fidelity": "torsional or rigid (planets have no component).",
        "teeth": "Number of teeth of each planet (with the stage's `normal_module`).",
        "profile_shift": "Profile shift coefficient x of the planets (ISO 21771).",
        "blank": "Gear blank of each planet (`bore_diameter`, `length`) when mass and polar_inertia are "
                 "left out.",
    },
    "LoadCase": {
        "input": "Body the torque enters (a body or stage member name); with `output` and `torque`, or none.",
        "output": "Body held against rotation about its own axis (the reaction), in the housing frame.",
        "torque": "Torque about the input body's axis (sign: right-hand about that axis).",
        "input_interface": "Interface where the torque enters a component input body (required there).",
        "name": "Name of the load case.",
        "output_interface": "Interface of a component output body where it is held (required there).",
        "forces": "Point loads of this case, `[[loads.forces]]` tables (force and moment at a point or interface).",
        "supports": "DOFs held relative to the housing for this case only, `[[loads.supports]]` tables.",
    },
    "PointLoad": {
        "body": "Body the load acts on (a body or stage member name).",
        "force": "Force vector (in `axes`).",
        "moment": "Moment vector (in `axes`); force and moment not both zero.",
        "point": "Where a plain body is loaded (global; default its position); not on a component body.",
        "interface": "Interface master node where a component body is loaded (required there).",
        "axes": "`global` or `body` (the body's local axes, z = its axis) for `force` and `moment`.",
    },
    "Support": {
        "body": "Body held (a body or stage member name).",
        "interface": "Interface master node of a component body where it is held (required there).",
        "dofs": "Held DOFs, local axes at the support point: subset of x, y, z, rx, ry, rz (default all six).",
    },
}

#: class name -> {key -> description} of keys the schema accepts besides the fields
#: (:func:`assembly.scene.schema.component_from_table`): ``kind`` of every component table, and the
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
    "Damping": (
        "Damping shows as \"damping ratio\" and \"damped frequency\" columns of the mode table "
        "(`flexgear modes`, the report). Element dampers (`c_*` of bearings, shafts, stages; a mesh's "
        "`damping`; a beam shaft's `beta`) and Rayleigh damping solve the quadratic eigenproblem "
        "(K + s C + s^2 M) x = 0; modal ratios give each elastic mode its zeta directly; given together, "
        "they add in the undamped modes' coordinates. Rigid-body (0 Hz) modes stay undamped: "
        "Rayleigh's alpha M acts with them projected out [assembly.dynamics]."),
    "Scene": (
        "Units are SI throughout: m, kg, s, N, rad, Pa; stiffness N/m and N m/rad; frequency Hz. "
        "Every angle may be given in degrees under its key plus `_deg` (`helix_angle_deg = 12.0`), "
        "never both. A bearing stiffness may be `inf`: that direction is then a constraint, not a "
        "spring. Unknown keys are refused, naming the allowed ones. Names of stage members "
        "(`<stage>.sun`, `.ring`, `.carrier`, `.planet<i>`) can be used wherever a body name is "
        "expected: `[[bearings]]`, `[[meshes]]`, `[[shafts]]`, `[[fixed]]`, `[load]`. "
        "**Variants.** A file whose top level holds `extends = \"<scene file>\"` (relative to its "
        "folder, or a shipped scene) describes that scene with the fields under `[set]` changed, "
        "each key a path such as `\"stages.stage1.carrier.fidelity\"` or `\"bearings[2].k_radial\"`; "
        "besides `[set]` it may give only `name` and `description` [assembly.scene.variant]."),
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
        f"Either `n_modes` or `cutoff_hz`, not both. Without either the cutoff is {CB_CUTOFF_FACTOR:g} x "
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
    "PartFile": (
        "The user's own part (`kind = \"file\"`): a STEP/BREP file meshed by gmsh, or a tetrahedral "
        "volume mesh (gmsh, Abaqus, Salome/Code_Aster MED, Nastran, VTK), converted to metres on reading. "
        "Local origin and axes: the file's, or those `axis` and `origin` give; the rotation axis is the "
        "local z. Interface rules are in the file's axes. Refused with one line naming the file: an open "
        "shell, several volumes (unless `volumes = 'fuse'`), loose faces, inverted or degenerate "
        "elements, other volume cells than tetrahedra, a size outside 1 mm to 100 m (wrong units), a "
        "master the part does not reach. Other cells of a mesh file are dropped and reported. A stage "
        "carrier's `pin_<n>` must be at planet n. Check a part alone: `flexgear part`. See "
        "docs/user_parts.md."),
    "InterfaceRule": (
        "A face belongs to a rule when every sample of it does (within `tolerance`); each interface "
        "is coupled (RBE2 or RBE3) to a 6-DOF master node."),
    "GearTeeth": (
        "ISO 21771 nomenclature, standard basic rack. **Helix hand:** `helix_angle` > 0 is a "
        "right-hand helix about local +z (the transverse profile turns positively as z grows). "
        "A `[[meshes]]` `helix_angle` is the line of action's, with the opposite sign convention: "
        "positive means gear 1 is left-hand. From teeth it is minus gear 1's base helix angle "
        "beta_b, tan(beta_b) = tan(beta) cos(alpha_t) (plus for an internal gear 1); an external "
        "pair has opposite hands, an internal pair the same hand."),
    "GearBlank": (
        "A gear given by its teeth only gets mass and inertia from a steel blank "
        "(`fe_components/gear_blank.py`): coaxial annuli of length `length` (default the face width) -- "
        "solid from the bore to the root diameter d_f, the tooth zone from d_f to the tip diameter d_a "
        "counted as half metal (ISO 21771 / ISO 53: d_a = d + 2 m_n (1 + x + k), d_f = d - 2 m_n (1.25 - x), "
        "k <= 0 the tip alteration of the gear's external pair, k m_n = a_w - a - (x1 + x2) m_n; none on a ring); "
        "a ring's tooth zone lies inside d_f and its rim runs from d_f to `outer_diameter`."),
    "ShaftSegment": "Written as a two-number array `[length, diameter]` or as a table.",
    "Bearing": (
        "Diagonal spring diag(k_radial, k_radial, k_axial, k_tilt, k_tilt, k_torsion) on the motion of "
        "`body` relative to `frame`, at `position`, in the body's axes; `k_radial_x`/`k_radial_y` and "
        "`k_tilt_x`/`k_tilt_y` give the two radial or tilt directions different stiffnesses (both of "
        "a pair instead of `k_radial` or `k_tilt`). `inf` holds that direction "
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
        "it). A shaft also joins a component hub to a plain shaft body (`interface1 = \"bore\"`).\n\n"
        "**Beam shafts.** Give `diameter` (and optionally `bore_diameter`, `material`) instead of "
        "the k_* fields: the shaft runs from body1's attachment point (its position, or "
        "`interface1`'s master) to body2's, its length L is their distance and its axis their "
        "direction, which must be body1's axis. `stations` split it: each `[[shafts.stations]]` "
        "(`name`, `at` in m from body1's end, strictly inside (0, L), any order) becomes a rigid "
        "body `<shaft name>.<station name>` on the axis (the scene's default fidelity, never "
        "flexible; `stage` = the shaft's `stage`), which bearings, meshes and loads name like any "
        "body, e.g. `body = \"main_shaft.inp_a\"`. Between consecutive nodes (body1's end, the "
        "stations by `at`, body2's end) act two-node Timoshenko elements (shear coefficient of "
        "Cowper 1966); their mass is lumped, half of each element at each of its nodes (mass, "
        "polar and section rotary inertia): a station body holds the halves of its two elements, "
        "the halves at the end bodies stay with the shaft's first and last elements."),
    "Station": ("Written as a table or as an array `[name, at]`; e.g. the NREL 5 MW main shaft "
                "(Nejad et al. 2016): `stations = [[\"inp_a\", 0.333], [\"inp_b\", 1.166]]`."),
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
        "rotation about its own axis, and/or point loads (`[[loads.forces]]`) with supports "
        "(`[[loads.supports]]`) for this case only. Stage members by name (`input = \"stage.carrier\"`). "
        "`flexgear static` and `flexgear run` report mesh forces, bearing and support reactions, "
        "shaft loads, the equilibrium check and, for a torque case, torque-balance and ratio "
        "checks for every case at every fidelity (docs/static.md). A case that leaves the "
        "assembly free to move, or holds one direction twice, is refused naming the case."),
    "PointLoad": (
        "A plain body is loaded at `point` (default its position; a force away from it acts "
        "through the rigid lever arm), a component body at the master node of `interface`, at "
        "every fidelity; never both."),
    "Support": (
        "Holds the motion of the body at the support point relative to the housing: a plain "
        "body's position, a component body's interface master node. Directions a constraint "
        "already holds (fixed DOF, rigid bearing direction, torsional fidelity) report their "
        "reaction under the held directions."),
}
