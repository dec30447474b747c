"""Parker's mesh-phasing rule: which mode classes of a planetary stage a mesh harmonic can excite.

For N equally spaced planets and a sun of Z_s teeth, the N sun-planet (and planet-ring)
mesh forces of mesh harmonic h are phase-shifted by h Z_s psi_n (psi_n = 2 pi n / N); their
net action on the central members (sun, ring, carrier) cancels except (Parker 2000,
"A physical explanation for the effectiveness of planet phasing to suppress planetary
gear vibration", J. Sound Vib. 236(4), 561-573):

* h Z_s / N an integer: a net torque only -> only **rotational** modes are excited;
* (h Z_s + 1) / N or (h Z_s - 1) / N an integer: a net force only -> only
  **translational** modes;
* otherwise no net force or torque on the central members -> only **planet** modes
  (central members at rest; Lin & Parker 1999).

For N = 2 the first two conditions can hold together (h Z_s odd: (h Z_s +- 1)/2 integer);
h Z_s even gives rotational, odd translational. The ring mesh gives the same classes:
equally spaced planets assemble only when (Z_s + Z_r)/N is an integer, so Z_r = -Z_s (mod N).
The rule assumes equally spaced planets whose meshes are phased by their angle alone
(in-phase indexing of the tooth positions); :func:`equally_spaced` tells whether a stage's
planets are.
"""
from __future__ import annotations

import math

#: Mode classes (:mod:`assembly.analysis.classify`) the rule speaks about.
RULE_CLASSES = ("rotational", "translational", "planet")
#: Angle tolerance (rad) under which planets count as equally spaced.
SPACING_TOL = 1e-9


def excited_class(harmonic: int, sun_teeth: int, n_planets: int) -> str:
    """The one mode class (``"rotational"``, ``"translational"`` or ``"planet"``) that mesh
    harmonic ``harmonic`` of a stage with ``n_planets`` equally spaced planets and a sun
    of ``sun_teeth`` teeth can excite (Parker 2000). ValueError on a harmonic, tooth count
    or planet count below 1."""
    for name, v in (("harmonic", harmonic), ("sun_teeth", sun_teeth), ("n_planets", n_planets)):
        if isinstance(v, bool) or not isinstance(v, int) or v < 1:
            raise ValueError(f"{name} = {v!r}: must be an integer >= 1")
    r = harmonic * sun_teeth % n_planets
    if r == 0:
        return "rotational"
    if r in (1, n_planets - 1):
        return "translational"
    return "planet"


def equally_spaced(angles) -> bool:
    """Whether planet angles (rad) are N equally spaced positions (any starting angle)."""
    n = len(angles)
    a0 = angles[0]
    for i, a in enumerate(angles):
        d = math.remainder(a - a0 - 2 * math.pi * i / n, 2 * math.pi)
        if abs(d) > SPACING_TOL:
            return False
    return True
