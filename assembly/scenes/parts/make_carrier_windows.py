"""Build ``carrier_windows.step``: a one-piece planet carrier with windows.

The part is the planet carrier of the planetary stage of
``assembly/scenes/planetary_flexible_carrier.toml`` (three planets at 0, 120 and
240 deg, pin pitch radius 97.77438348018569 mm, the stage's carrier radius), made
the way a cast or forged carrier is: two cheeks joined by a cylindrical drum wall
with three windows through which the planets mesh with the ring; the drum left
between the windows forms three webs.  A parametric "two cheeks joined by round
posts" carrier (``fe_components.params.CarrierParams``) cannot represent it.

Units: the model is built in MILLIMETRES and the STEP file declares mm
(``SI_UNIT(.MILLI.,.METRE.)``); flexgear reads it in mm and converts to metres
(:mod:`fe_components.part.cad`).  Rotation axis +z, carrier mid-plane z = 0.

Geometry (mm):

* cheek A: disc of diameter 270, z in [-40, -25]; cheek B: z in [25, 40];
* drum wall between the cheeks: outer radius 135, inner radius 115, z in [-25, 25];
* three windows through the drum, centred on the planet angles 0, 120, 240 deg
  (from +x about +z): each is the drum cut by a slab of width 130 mm
  (|tangential coordinate| <= 65) on the planet's side, z in [-25, 25], so a planet
  of tip radius up to ~60 mm on the pin circle passes out to the ring; sharp edges
  (no fillets: 3, 5 and 8 mm OCC fillets on the webs' edges along z built, but their
  thin blend faces gave folded second-order tetrahedra at mesh sizes 5-8 mm);
* pin bores: diameter 30 through both cheeks at radius 97.77438348018569,
  angles 0, 120, 240 deg;
* centre hole: diameter 40 through both cheeks and hub A (the sun passes);
* hub A (-z): bearing seat A, diameter 80, z in [-70, -40];
* hub B (+z): bearing seat B, diameter 90, z in [40, 80], with the output bore of
  diameter 50 through it (z in [40, 80]).

Interface surfaces, in METRES (for the scene's selectors), r = 0.09777438348018569:

* ``pin_i`` (i = 0, 1, 2; a = 0, 2 pi/3, 4 pi/3): cylinders of radius 0.015 about the
  axes through (r cos a, r sin a), z span [-0.04, 0.04] (the bore faces in the
  cheeks, z in [-0.04, -0.025] and [0.025, 0.04]);
* ``bearing_a`` seat: cylinder radius 0.04 about z, z in [-0.07, -0.04];
* ``bearing_b`` seat: cylinder radius 0.045 about z, z in [0.04, 0.08];
* ``output_bore``: cylinder radius 0.025 about z, z in [0.04, 0.08].

The file is byte-deterministic: the STEP header's FILE_NAME record, where gmsh /
OpenCASCADE write the file path and the time of writing, is rewritten to the fixed
name 'carrier_windows.step' and the fixed time stamp '2026-11-24T00:00:00'.

Run: ``python assembly/scenes/parts/make_carrier_windows.py`` (writes the STEP file
next to this script; ``--out PATH`` writes elsewhere).
"""
from __future__ import annotations

import argparse
import math
import os
import re
import tempfile
from pathlib import Path

from fe_components.gmsh_session import gmsh_model

# ---------------------------------------------------------------- dimensions (mm)
PIN_RADIUS = 97.77438348018569          # stage carrier radius (pin pitch radius)
PLANET_ANGLES_DEG = (0.0, 120.0, 240.0)
PIN_BORE_D = 30.0
CHEEK_D = 270.0
CHEEK_T = 15.0
CHEEK_SPACING = 50.0
DRUM_R_IN = 115.0
WINDOW_HALF_WIDTH = 65.0                # planet tip radius ~60 mm + 5 mm clearance
CENTER_HOLE_D = 40.0
SEAT_A_D, SEAT_A_L = 80.0, 30.0
SEAT_B_D, SEAT_B_L = 90.0, 40.0
OUTPUT_BORE_D = 50.0

STEP_NAME = "carrier_windows.step"
TIMESTAMP = "2026-11-24T00:00:00"


def _cyl(occ, x, y, z0, z1, r):
    return (3, occ.addCylinder(x, y, z0, 0.0, 0.0, z1 - z0, r))


def build(gmsh) -> tuple[int, int]:
    """Create the carrier in the current gmsh model's OCC kernel (mm); return its single
    volume dimTag."""
    occ = gmsh.model.occ
    s, t = CHEEK_SPACING, CHEEK_T
    R = CHEEK_D / 2
    zc = s / 2 + t                      # outer cheek faces at z = +-zc
    # the envelope: cheeks + drum, one cylinder; then the cavity between the cheeks
    body = _cyl(occ, 0, 0, -zc, zc, R)
    cavity = [_cyl(occ, 0, 0, -s / 2, s / 2, DRUM_R_IN)]
    for a_deg in PLANET_ANGLES_DEG:     # windows: slabs from the axis side out past the rim
        box = occ.addBox(0.0, -WINDOW_HALF_WIDTH, -s / 2, R + 20.0, 2 * WINDOW_HALF_WIDTH, s)
        occ.rotate([(3, box)], 0, 0, 0, 0, 0, 1, math.radians(a_deg))
        cavity.append((3, box))
    out, _ = occ.cut([body], cavity)
    assert len(out) == 1, out
    body = out[0]
    hub_a = _cyl(occ, 0, 0, -zc - SEAT_A_L, -zc, SEAT_A_D / 2)
    hub_b = _cyl(occ, 0, 0, zc, zc + SEAT_B_L, SEAT_B_D / 2)
    out, _ = occ.fuse([body], [hub_a, hub_b])
    assert len(out) == 1, out
    body = out[0]
    L = zc + max(SEAT_A_L, SEAT_B_L) + 10.0
    tools = []
    for a_deg in PLANET_ANGLES_DEG:
        a = math.radians(a_deg)
        tools.append(_cyl(occ, PIN_RADIUS * math.cos(a), PIN_RADIUS * math.sin(a), -L, L, PIN_BORE_D / 2))
    tools.append(_cyl(occ, 0, 0, -L, L, CENTER_HOLE_D / 2))
    tools.append(_cyl(occ, 0, 0, zc, L, OUTPUT_BORE_D / 2))
    out, _ = occ.cut([body], tools)
    assert len(out) == 1, out
    occ.removeAllDuplicates()
    occ.synchronize()
    vols = gmsh.model.getEntities(3)
    if len(vols) != 1:
        raise RuntimeError(f"expected one volume, got {vols}")
    return vols[0]


def _fix_header(path: Path) -> None:
    """Rewrite the STEP header's FILE_NAME (file name and time stamp) to fixed values."""
    text = path.read_text()
    pat = re.compile(r"FILE_NAME\('(?:[^']|'')*','[^']*'")
    new, n = pat.subn(f"FILE_NAME('{STEP_NAME}','{TIMESTAMP}'", text, count=1)
    if n != 1:
        raise RuntimeError("STEP header FILE_NAME not found")
    path.write_text(new)


def main(argv=None) -> Path:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path(__file__).resolve().parent / STEP_NAME)
    args = ap.parse_args(argv)
    out = args.out.resolve()
    with gmsh_model("carrier_windows") as gmsh:
        build(gmsh)
        fd, tmp = tempfile.mkstemp(suffix=".step", dir=out.parent)
        os.close(fd)
        tmp = Path(tmp)
        try:
            gmsh.write(str(tmp))
            _fix_header(tmp)
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)   # mkstemp makes the file 0600
            os.replace(tmp, out)
        finally:
            if tmp.exists():
                tmp.unlink()
    print(f"wrote {out} ({out.stat().st_size} bytes)")
    return out


if __name__ == "__main__":
    main()
