"""A small rigid geared chain for Campbell tests, as scene TOML: a helical pair (pinion 21
teeth, role "rotor", wheel 83 teeth; the gear data of ``two_stage_quill.toml``, masses from
the gear blanks) driving, through a quill shaft, the sun (20 teeth) of a planetary stage with
four planets (30 teeth) in a fixed ring (80 teeth), carrier output. ``planet_angles_deg``
places the planets (default equally spaced); any multiple of 360/(20 + 80) = 3.6 deg meets
the assembly condition."""
from __future__ import annotations

_TEMPLATE = """
name = "pair and planetary (Campbell test)"
fidelity = "rigid"
[[bodies]]
name = "pinion"
role = "rotor"
teeth = {{ n_teeth = 21, normal_module = 0.005, pressure_angle_deg = 20.0, helix_angle_deg = 12.0, face_width = 0.06, profile_shift = 0.30 }}
[[bodies]]
name = "wheel"
teeth = {{ n_teeth = 83, normal_module = 0.005, pressure_angle_deg = 20.0, helix_angle_deg = -12.0, face_width = 0.06, profile_shift = 0.10 }}
[[bearings]]
body = "pinion"
k_radial = 1.0e9
k_axial = 5.0e8
k_tilt = 1.0e6
[[bearings]]
body = "wheel"
k_radial = 2.0e9
k_axial = 5.0e8
k_tilt = 5.0e6
[[meshes]]
name = "pinion-wheel"
gear1 = "pinion"
gear2 = "wheel"
stiffness = 8.4e8
place = "gear2"
[[shafts]]
name = "quill"
body1 = "wheel"
body2 = "planetary.sun"
k_torsion = 1.239e5
k_bending = 1.611e5
k_axial = 1.031e9
k_shear = 1.208e7
[[stages]]
name = "planetary"
center = [0.2677581560127026, 0.0, 0.4]
normal_module = 0.006
normal_pressure_angle_deg = 20.0
k_mesh_sun = 1.12e9
k_mesh_ring = 1.12e9
drive_sign = -1
[stages.sun]
teeth = 20
profile_shift = 0.2
mass = 7.103
polar_inertia = 1.278e-2
support = "floating"
[stages.ring]
teeth = 80
profile_shift = -0.4
mass = 41.04
polar_inertia = 2.790
support = "fixed"
[stages.carrier]
mass = 59.19
polar_inertia = 1.184
support = "bearing"
bearing = {{ k_radial = 2.0e9, k_axial = 1.0e9, k_tilt = 1.0e7, k_torsion = 0.0 }}
[stages.planets]
count = 4
teeth = 30
profile_shift = 0.1
mass = 15.98
polar_inertia = 6.472e-2
bearing = {{ k_radial = 1.0e9, k_axial = 2.0e8, k_tilt = 2.0e6, k_torsion = 0.0 }}
{angles}
"""


def campbell_scene(planet_angles_deg=None) -> str:
    """The scene's TOML text (planets equally spaced unless ``planet_angles_deg`` is given)."""
    angles = "" if planet_angles_deg is None else f"angles_deg = {list(planet_angles_deg)}"
    return _TEMPLATE.format(angles=angles)
