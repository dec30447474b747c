"""Where the planets of a planetary stage may sit on the carrier: neighbours must not
overlap, and planets with teeth must mesh with sun and ring at once (assembly condition).

Assembly condition (Lynwander, *Gear Drive Systems: Design and Application*, Marcel Dekker
1983, planetary gear trains): with the ring held, turning the carrier by psi turns the sun
by psi (z_s + z_r) / z_s, so a planet placed psi (rad) from the first one finds sun and ring
teeth in the same relative position only if ``(z_s + z_r) psi / (2 pi)`` is an integer
(ring teeth counted positive); for ``N`` equally spaced planets (psi = 2 pi / N) that is
``(z_s + z_r) / N`` an integer. Profile shifts and helix do not enter: the condition counts
tooth pitches on the pitch circles. Angles are measured from the first planet (the carrier
may be turned as a whole).
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import SceneError
from .gears import RING_CENTRE_TOLERANCE
from .schema import as_written
from .tables import PlanetaryStage

#: Largest part of a circular pitch by which a planet's given angle may miss the assembly
#: condition: a residual of eps pitches displaces the tooth pattern the planet must meet by
#: eps p_t = eps pi m_n / cos(beta) along the pitch circle; held to the same 0.01 m_n as the
#: ring centre distance (:data:`assembly.scene.gears.RING_CENTRE_TOLERANCE`, within the
#: backlash) for a spur stage, eps <= 0.01 / pi = 3.2e-3 pitches (0.015 deg of carrier angle
#: for z_s + z_r = 75, whose pitch is 4.8 deg); a helical stage's transverse pitch is longer by
#: 1 / cos(beta) (1.5 % at 10 deg). Round-off of angles written in degrees (1e-12) lies far below.
ASSEMBLY_TOLERANCE = RING_CENTRE_TOLERANCE / math.pi


def outer_radius(st: PlanetaryStage) -> float:
    """The planets' outer radius (m) for the overlap check: ``planets.outer_radius`` or the
    pitch radius (base radius / cos of the sun mesh's pressure angle)."""
    pl = st.planets
    return pl.outer_radius if pl.outer_radius is not None else pl.base_radius / math.cos(st.pressure_angle_sun)


def fits_around(st: PlanetaryStage, count: int) -> bool:
    """``count`` equally spaced planets clear one another on the carrier circle."""
    return count < 2 or math.sin(math.pi / count) * st.carrier_radius() > outer_radius(st)


def planets_field(st: PlanetaryStage, path: str) -> tuple:
    """(scene path, value as written) of what places the planets of stage ``st`` (scene path
    ``path``): ``planets.angles`` (or ``angles_deg``, a list) when given, else ``planets.count``."""
    pl = st.planets
    if pl.angles is None:
        return f"{path}.planets.count", pl.count
    p, v = as_written(pl, "angles", f"{path}.planets.angles")
    return p, list(v)


def check_planet_spacing(st: PlanetaryStage, path: str) -> None:
    """One angle per planet, and neighbouring planets must not overlap."""
    pl = st.planets
    if pl.angles is not None and len(pl.angles) != pl.count:
        raise SceneError(*planets_field(st, path), f"must list exactly planets.count = {pl.count} angles")
    if pl.count < 2:
        return
    psi = np.sort(np.mod(np.asarray(st.planet_angles()), 2 * math.pi))
    gaps = np.diff(np.concatenate([psi, psi[:1] + 2 * math.pi]))
    r_out = outer_radius(st)
    chord = 2 * st.carrier_radius() * np.sin(gaps.min() / 2)
    if chord <= 2 * r_out:
        raise SceneError(*planets_field(st, path),
                         f"planets overlap: closest centres {chord:.4g} m apart, "
                         f"planet outer diameter {2 * r_out:.4g} m")


def fitting_counts(z_sum: int, count: int, fits=lambda n: True) -> list:
    """The planet counts nearest ``count`` (the next one below and the next above, as far as
    they exist) that divide ``z_sum`` = z_s + z_r and ``fits(n)``."""
    ok = [n for n in range(2, z_sum + 1) if z_sum % n == 0 and fits(n)]
    below = [n for n in ok if n < count]
    above = [n for n in ok if n > count]
    return below[-1:] + above[:1]


def assembly_residual(z_sum: int, psi: float) -> float:
    """Signed distance (in circular pitches) of ``z_sum psi / (2 pi)`` from the nearest
    integer; ``psi`` in rad from the first planet."""
    t = z_sum * psi / (2 * math.pi)
    return t - round(t)


def check_planet_assembly(st: PlanetaryStage, path: str) -> None:
    """The assembly condition of a stage with teeth (``normal_module``); a stage of typed
    base radii has no tooth counts to check."""
    if st.normal_module is None or st.planets.count < 2:
        return
    z_sum = st.sun.teeth + st.ring.teeth
    pl = st.planets
    if pl.angles is None:
        if z_sum % pl.count:
            near = fitting_counts(z_sum, pl.count, lambda n: fits_around(st, n))
            hint = (f"counts that fit and clear one another: {' or '.join(map(str, near))}" if near
                    else "no other count fits; change the sun or ring teeth")
            raise SceneError(f"{path}.planets.count", pl.count,
                             f"equally spaced planets cannot mesh with sun and ring: (z_sun + z_ring) / count = "
                             f"({st.sun.teeth} + {st.ring.teeth}) / {pl.count} = {z_sum / pl.count:.6g} is not "
                             f"an integer (assembly condition, Lynwander 1983); {hint}")
        return
    pitch = 2 * math.pi / z_sum
    for j, psi in enumerate(pl.angles[1:], start=1):
        eps = assembly_residual(z_sum, psi - pl.angles[0])
        if abs(eps) > ASSEMBLY_TOLERANCE:
            best = pl.angles[0] + round((psi - pl.angles[0]) / pitch) * pitch
            p, v = as_written(pl, "angles", f"{path}.planets.angles", (psi,))
            _, near = as_written(pl, "angles", "", (best,))
            unit = "deg" if p.endswith("_deg") else "rad"
            spacing = math.degrees(pitch) if unit == "deg" else pitch
            raise SceneError(f"{p}[{j}]", v[0],
                             f"the planet cannot mesh with sun and ring: (z_sun + z_ring) (angle - angles[0]) / "
                             f"(2 pi) = {z_sum * (psi - pl.angles[0]) / (2 * math.pi):.6g} misses an integer by "
                             f"{abs(eps):.3g} pitches, more than {ASSEMBLY_TOLERANCE:.2g} (assembly condition, "
                             f"Lynwander 1983); nearest angle that fits: {near[0]:.12g} {unit} (steps of "
                             f"{spacing:.6g} {unit} from angles[0])")
