"""Mesh stiffness as a Fourier series in the gear angle, and backlash as a dead zone.

Per mesh, ``k(phi) = k0 f(phi)`` with ``f(phi) = 1 + sum_h a_h cos(h phi + phi_h)`` and
``phi = z (theta - theta_frame) - phase`` (module :mod:`assembly.scene.time_domain`). The
rectangular wave of alternating single and double tooth contact, contact ratio c in
(1, 2), step dk and double contact centred on phi = 0, has the cosine series
``a_h = 2 (dk/k0) sin(h pi (c - 1)) / (h pi)`` (a pulse of width 2 pi (c - 1) per mesh
period); a helical contact line sweeping eps_beta mesh periods across the face averages it
over that window, multiplying harmonic h by ``sinc(h eps_beta) = sin(h pi eps_beta) /
(h pi eps_beta)``.

Backlash b >= 0 (normal, along the line of action) makes the contact a dead zone in the
compression delta: the driving flank carries ``delta`` for delta > 0, the coast flank
``delta + b`` for delta < -b, nothing in between: ``e(delta) = max(delta, 0) + min(delta +
b, 0)``, slope ``s = 1`` in contact and 0 in the gap. The mesh potential is ``V = 1/2
k(phi) e^2`` and its generalized forces are ``k e`` along the line of action and ``1/2
k0 f'(phi) e^2`` on the angle -- the term that keeps the equations energy-consistent
(Oh, Grosh & Barber 2005, J. Vib. Acoust. 127, doi 10.1115/1.1891815).
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import SceneError
from .mesh_laws import flank, series_at

#: Points per period of the highest harmonic at which the series is checked for k < 0.
CHECK_POINTS = 64


def rectangular_wave(step: float, contact_ratio: float, harmonics: int, overlap: float = 0.0) -> np.ndarray:
    """Relative amplitudes a_1..a_H of the rectangular wave (module notes): ``2 step
    sin(h pi (c - 1)) / (h pi)`` times ``sinc(h overlap)``."""
    h = np.arange(1, harmonics + 1, dtype=float)
    return 2.0 * step * np.sin(h * math.pi * (contact_ratio - 1.0)) / (h * math.pi) * np.sinc(h * overlap)


def series(v) -> tuple[np.ndarray, np.ndarray]:
    """(amplitudes, phases) of a filled :class:`assembly.scene.time_domain.MeshVariation`."""
    if v.amplitudes is not None:
        a = np.asarray(v.amplitudes, float)
        return a, np.zeros_like(a) if v.phases is None else np.asarray(v.phases, float)
    a = rectangular_wave(v.step, v.contact_ratio, v.harmonics, v.face_contact_ratio or 0.0)
    return a, np.zeros_like(a)


class Series:
    """The series of meshes with amplitudes and phases ``A``, ``P`` (m, H), its harmonic
    numbers prepared once (a time step evaluates it several times)."""

    def __init__(self, A: np.ndarray, P: np.ndarray):
        self.A, self.P = A, P
        self.h = np.arange(1, A.shape[-1] + 1, dtype=float)

    def __call__(self, phi, second: bool = False):
        """``f(phi)``, ``f'(phi)`` (and ``f''(phi)`` if ``second``) at the meshes' angles
        (:func:`assembly.dynamics.mesh_laws.fourier`)."""
        out = series_at(phi, np.broadcast_to(self.A, np.shape(phi) + self.A.shape[-1:]),
                        np.broadcast_to(self.P, np.shape(phi) + self.P.shape[-1:]))
        return out if second else out[:2]


def factor(phi, A: np.ndarray, P: np.ndarray, second: bool = False):
    """``f(phi)``, ``f'(phi)`` (and ``f''(phi)`` if ``second``) for meshes' angles ``phi``
    (m,), amplitudes and phases (m, H) each (:class:`Series`)."""
    return Series(A, P)(phi, second)


def lowest_factor(a: np.ndarray, p: np.ndarray) -> tuple[float, float]:
    """(min f, angle where) of one mesh's series, sampled at CHECK_POINTS per period of its
    highest harmonic over one mesh period."""
    if len(a) == 0:
        return 1.0, 0.0
    phi = np.linspace(0.0, 2 * math.pi, CHECK_POINTS * len(a), endpoint=False)
    f, _ = factor(phi, np.broadcast_to(a, (len(phi), len(a))), np.broadcast_to(p, (len(phi), len(a))))
    i = int(np.argmin(f))
    return float(f[i]), float(phi[i])


def check_positive(a: np.ndarray, p: np.ndarray, path: str) -> None:
    """SceneError at ``path`` when the series makes the stiffness negative or zero somewhere
    (teeth out of contact are the backlash's business, not a stiffness of zero)."""
    f, phi = lowest_factor(a, p)
    if f <= 0.0:
        raise SceneError(path, [round(float(x), 6) for x in a],
                         f"the stiffness 1 + sum a_h cos(h phi + phi_h) falls to {f:.4g} k0 at phi = "
                         f"{phi:.4g} rad: a mesh stiffness must stay positive")


class DeadZone:
    """The backlash of meshes (m; NaN: no dead zone), prepared once: calling it with the
    compressions ``delta`` gives :func:`dead_zone`'s (e, s)."""

    def __init__(self, backlash: np.ndarray):
        self.linear = np.isnan(backlash)
        self.gap = np.where(self.linear, 0.0, backlash)

    def __call__(self, delta: np.ndarray):
        return flank(delta, self.linear.astype(float), self.gap)


def dead_zone(delta: np.ndarray, backlash: np.ndarray):
    """(e, s): the flank compression ``e`` and contact slope ``s`` (1 in contact, 0 in the
    gap) of compressions ``delta`` (m); ``backlash`` NaN: no dead zone (e = delta)."""
    return DeadZone(backlash)(delta)
