"""Reference components with small committed meshes (``meshes/ref``) used by the tests.

``python -m fe_components.reference`` generates the committed meshes that are missing
and replaces unusable ones (needs gmsh); the tests load them without calling gmsh.  Every
load verifies a committed mesh's content hash (fe_components.meshing); a corrupt one
raises :class:`~fe_components.errors.MeshCacheError` instead of being rebuilt in place
(flexgear's scenes then fall back to a mesh generated in the cache, with a warning).
Lengths in m.
"""
from __future__ import annotations

import logging
import math
import sys
from pathlib import Path

from .meshing import REFERENCE_DIR, MeshOptions, ensure_mesh, mesh_path
from .params import CarrierParams, CylinderParams, GearTeeth, PinionParams, ShaftSegment, WheelParams

REF_DIR = REFERENCE_DIR

#: Free-free steel cylinder, L/D = 10 (validation: Timoshenko bending, torsion, axial).
CYLINDER = CylinderParams(length=0.5, diameter=0.05)
#: Thick annulus (validation: mass and inertia).
ANNULUS = CylinderParams(length=0.05, diameter=0.1, bore_diameter=0.06)

_SHAFT = (ShaftSegment(0.03, 0.03), ShaftSegment(0.05, 0.04), ShaftSegment(0.08, 0.05),
          ShaftSegment(0.05, 0.04), ShaftSegment(0.03, 0.03))
#: Pinion, smooth teeth (annulus at pitch radius), 20 teeth m_n = 4 mm.
PINION_SMOOTH = PinionParams(GearTeeth(20, 0.004, math.radians(20), 0.04), _SHAFT, gear_center=0.12)
#: Pinion, involute spur teeth.
PINION_INVOLUTE = PinionParams(GearTeeth(20, 0.004, math.radians(20), 0.04, fidelity="involute"),
                               _SHAFT, gear_center=0.12)
#: Wheel, smooth, web with 6 lightening holes.
WHEEL_SMOOTH = WheelParams(GearTeeth(60, 0.004, math.radians(20), 0.04), rim_inner_diameter=0.2,
                           web_thickness=0.012, hub_outer_diameter=0.08, hub_length=0.05,
                           bore_diameter=0.05, n_holes=6, hole_diameter=0.03)
#: Three-planet carrier.
CARRIER = CarrierParams(planet_angles=(0.0, 2 * math.pi / 3, 4 * math.pi / 3), pin_pitch_radius=0.1,
                        pin_bore_diameter=0.03, cheek_diameter=0.28, cheek_thickness=0.02,
                        cheek_spacing=0.06, post_diameter=0.035, seat_a_diameter=0.09, seat_a_length=0.04,
                        seat_b_diameter=0.1, seat_b_length=0.05, output_bore_diameter=0.06,
                        center_hole_diameter=0.03)

#: name -> (params, mesh options) of every committed reference mesh.
CASES = {
    "cylinder": (CYLINDER, MeshOptions(size=0.0125)),
    "annulus": (ANNULUS, MeshOptions(size=0.01)),
    "pinion_smooth": (PINION_SMOOTH, MeshOptions(size=0.012)),
    "pinion_involute": (PINION_INVOLUTE, MeshOptions(size=0.012)),
    "wheel_smooth": (WHEEL_SMOOTH, MeshOptions(size=0.015)),
    "carrier": (CARRIER, MeshOptions(size=0.02)),
}


def reference_mesh_path(name: str) -> Path:
    params, options = CASES[name]
    return mesh_path(params, options, REF_DIR)


def main(argv=None) -> int:
    logging.basicConfig(level=logging.INFO)
    for name, (params, options) in CASES.items():
        path = ensure_mesh(params, options, REF_DIR, heal=True)
        logging.getLogger(__name__).info("%s -> %s (%d kB)", name, path.name, path.stat().st_size // 1024)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
