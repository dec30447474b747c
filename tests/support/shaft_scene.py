"""A coarse steel shaft (cylinder L = 0.2 m, D = 0.04 m, P2 mesh 0.02 m, 1530 FE DOFs) on two
bearings at its ends, as scene TOML: the smallest scene with a component body, meshed in
~0.1 s. ``shaft_scene("flexible")`` keeps 6 fixed-interface modes; ``"rigid"`` takes its mass
properties from the mesh."""
from __future__ import annotations

_TEMPLATE = """
name = "coarse steel shaft on two bearings ({fidelity})"
band_hz = 3000.0
[[bodies]]
name = "shaft"
fidelity = "{fidelity}"
flex = {{ mesh_size = 0.02, n_modes = 6 }}
component = {{ kind = "cylinder", length = 0.2, diameter = 0.04 }}
[[bearings]]
body = "shaft"
interface = "end_a"
k_radial = 1.0e8
k_axial = 1.0e8
k_tilt = 0.0
[[bearings]]
body = "shaft"
interface = "end_b"
k_radial = 1.0e8
k_axial = 1.0e8
k_tilt = 0.0
"""


def shaft_scene(fidelity: str) -> str:
    """The shaft scene's TOML text with the body at ``fidelity`` (rigid or flexible)."""
    return _TEMPLATE.format(fidelity=fidelity)
