"""The Craig-Bampton cutoff of a flexible body, as its scene sets it: the default factor on the
scene's band, the field that sets it, the modes a cutoff asks for, read without meshing.
"""
from __future__ import annotations

import logging
import math

log = logging.getLogger(__name__)

#: Default Craig-Bampton cutoff as a multiple of the scene's band of interest, with
#: residual vectors on (FlexOptions.residual_vectors). Convergence study against full FE
#: (docs/benchmarks.md), in-band coupled modes: HS stage 0.0002 % at 1.5x (plain CB:
#: 0.99 % at 1.5x and 2x, 0.19 % at 4x); planetary carrier < 1e-4 % (plain CB 0.17 %);
#: the two-gear test pair < 1e-4 % (plain CB 0.67 % up to 6x). 1.5x rather than 1x
#: keeps the modes just above the band within 0.02 % too.
CB_CUTOFF_FACTOR = 1.5


def weyl_mode_count(volume: float, material, f_hz: float) -> float:
    """Weyl's asymptotic number of elastic eigenfrequencies below ``f_hz`` of a body of
    ``volume`` (m^3): ``N(f) = (4 pi / 3) V f^3 (1/c_L^3 + 2/c_T^3)`` with the longitudinal
    and shear wave speeds ``c_L^2 = E (1 - nu) / (rho (1 + nu) (1 - 2 nu))``,
    ``c_T^2 = E / (2 rho (1 + nu))`` (H. Weyl, Rend. Circ. Mat. Palermo 39, 1915; one
    longitudinal and two shear wave branches). The leading term only: a body with mostly
    free surface has more modes (the surface term is positive), so it underestimates, and
    far below the asymptotic range (a few modes) it is no count at all -- it serves to refuse
    a cutoff that surely needs too many modes, without meshing."""
    E, nu, rho = material.E, material.nu, material.rho
    c_l = math.sqrt(E * (1 - nu) / (rho * (1 + nu) * (1 - 2 * nu)))
    c_t = math.sqrt(E / (2 * rho * (1 + nu)))
    return 4 * math.pi / 3 * volume * f_hz ** 3 * (c_l ** -3 + 2 * c_t ** -3)


def cutoff_for(body, options, band_hz: float) -> float | None:
    """Craig-Bampton cutoff (Hz): the option, else CB_CUTOFF_FACTOR x band (None with n_modes)."""
    if options.n_modes is not None:
        return None
    if options.cutoff_hz is None:
        return CB_CUTOFF_FACTOR * band_hz
    if options.cutoff_hz < band_hz:
        log.warning("%s: Craig-Bampton cutoff %.4g Hz lies below the scene's band %.4g Hz: coupled modes "
                    "in the band will be too stiff (the convergence study needs %g x band)",
                    body.name, options.cutoff_hz, band_hz, CB_CUTOFF_FACTOR)
    return options.cutoff_hz


def cutoff_source(path: str, options, band_hz: float) -> tuple[str, float]:
    """(scene path, value) of the field that sets the cutoff of the body at ``path``:
    its ``flex.cutoff_hz``, else the scene's ``band_hz``."""
    if options.cutoff_hz is not None:
        return f"{path}.flex.cutoff_hz", options.cutoff_hz
    return "band_hz", band_hz
