"""Damped modes: the quadratic eigenproblem ``(K + s C + s^2 M) x = 0`` of a damped model.

Solved in the modal coordinates of the undamped modes (``x = Phi y``, ``Phi' M Phi = I``,
``Phi' K Phi = diag(omega^2)``): ``(diag(omega^2) + s C_m + s^2 I) y = 0`` with ``C_m`` from
:func:`assembly.dynamics.damping.damping_in_modes`, through the first-order (state) form
``[[0, I], [-diag(omega^2), -C_m]] [y; s y] = s [y; s y]`` (``scipy.linalg.eig`` on the
2m state matrix). With every undamped mode in ``Phi`` (the dense solve, n <= DENSE_MAX)
this is the exact problem; with fewer, its modal truncation (``method`` says which).

Per mode: the eigenvalue ``s`` (1/s), the damped natural frequency ``Im(s) / 2 pi`` (Hz),
the undamped-equivalent ``|s| / 2 pi`` (Hz) and the damping ratio ``-Re(s) / |s|``. Each
undamped mode is paired one-to-one with a damped root by the mass-weighted MAC (in modal
coordinates ``|y_i|^2 / |y|^2``), the pairing of the largest total MAC.

Rigid-body modes that no damper strains (``C_m`` rows below :data:`RIGID_RTOL` of the
largest entry: round-off) are left out of the state form and stay at ``s = 0`` exactly.
Modal ratios alone (no element damper, no Rayleigh) need no eigen-solve:
``s = -zeta omega + i omega sqrt(1 - zeta^2)`` per mode.
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from .damping import damping_in_modes
from .modal_ratios import mode_ratios

log = logging.getLogger(__name__)

#: A rigid-body mode's row of the modal damping below this fraction of its largest entry
#: is round-off of the rigid shape through the dampers (relative ~1e-15 per entry), not a
#: damper acting on it: a damper that does act gives an entry of the order of the others.
RIGID_RTOL = 1e-9
#: Most modes in the state form (2 x this many states: ~2 s for scipy.linalg.eig).
MAX_STATE_MODES = 600


@dataclass(frozen=True)
class DampedModes:
    """Damped modes paired with the undamped modes of a :class:`assembly.analysis.modal.ModalResult`
    (entry i belongs to undamped mode i): ``s`` (complex, 1/s), ``damped_hz``
    (Im(s)/2pi, Hz), ``undamped_hz`` (|s|/2pi, Hz), ``ratios`` (-Re(s)/|s|), ``mac`` of the
    pairing (1 for modal ratios), ``method`` ("modal ratios", "state space" or "state
    space, truncated to m modes")."""

    s: np.ndarray
    damped_hz: np.ndarray
    undamped_hz: np.ndarray
    ratios: np.ndarray
    mac: np.ndarray
    method: str


def damped_modes(result) -> DampedModes:
    """The damped modes of ``result``'s model with its scene's damping (module notes)."""
    m = len(result.frequencies_hz)
    zeta = mode_ratios(result)
    omega = np.sqrt(np.maximum(result.eigenvalues, 0.0))
    omega[:result.n_rigid] = 0.0
    d = result.model.scene.damping
    elements = any(el.c is not None for el in result.model.elements)
    if not elements and not (d is not None and d.rayleigh):
        s = -zeta * omega + 1j * omega * np.sqrt(1.0 - zeta ** 2)
        return _modes(s, np.ones(m), "modal ratios")
    keep = min(m, MAX_STATE_MODES)
    C = damping_in_modes(result, zeta)[:keep, :keep]
    lam = omega[:keep] ** 2
    scale = np.abs(C).max(initial=0.0)
    r = result.n_rigid
    free = r if r and np.abs(C[:r]).max() <= RIGID_RTOL * scale else 0
    s_all, Y = state_form(np.diag(lam[free:]), C[free:, free:])
    s = np.zeros(m, complex)
    mac = np.ones(m)
    s[free:keep], mac[free:keep] = _pair(s_all, Y)
    s[keep:] = 1j * omega[keep:]          # beyond the state form: left undamped
    exact = keep == result.model.K.shape[0]
    method = "state space" if exact else f"state space, truncated to {keep} modes"
    if not exact:
        log.warning("damped modes: %s of %d (modal truncation)", method, result.model.K.shape[0])
    return _modes(s, mac, method)


def state_form(K: np.ndarray, C: np.ndarray):
    """Eigenvalues ``s`` (2m,) and coordinates ``Y`` (m x 2m) of the complex modes of
    ``(K + s C + s^2 I) y = 0`` (``K`` the diagonal of modal eigenvalues, or near it), from
    the first-order form in the scaled state ``u = [D y; y']`` (``D = sqrt(diag K)``, 1 for a
    rigid-body mode): entries of the size of omega, not omega^2, so high and low modes share
    one scale. Shared by the damped modes and the FRF (:mod:`assembly.dynamics.frf`)."""
    m = len(K)
    lam = np.diag(K)
    d = np.where(lam > 0, np.sqrt(np.maximum(lam, 0.0)), 1.0)
    A = np.block([[np.zeros((m, m)), np.diag(d)], [-K / d[None, :], -C]])
    import scipy.linalg as sla  # a damped scene only: an undamped one's modes import no SciPy
    s, V = sla.eig(A, check_finite=False)
    return s, V[:m] / d[:, None]


def _pair(s_all: np.ndarray, Y: np.ndarray):
    """One root per mode: among the roots of Im(s) >= 0 (a complex pair's upper member;
    both real roots of an overdamped mode), the one-to-one choice of largest total MAC
    ``|y_i|^2 / |y|^2``. Returns (s, MAC) per mode."""
    from scipy.optimize import linear_sum_assignment  # only for a damped scene: startup time
    cand = np.flatnonzero(s_all.imag >= -1e-12 * np.abs(s_all).max(initial=1.0))
    P = np.abs(Y[:, cand]) ** 2
    P = P / np.maximum(P.sum(axis=0), 1e-300)
    rows, cols = linear_sum_assignment(-P)
    order = np.argsort(rows)
    pick = cand[cols[order]]
    s = s_all[pick]
    return s.real + 1j * np.abs(s.imag), P[rows[order], cols[order]]


def _modes(s: np.ndarray, mac: np.ndarray, method: str) -> DampedModes:
    mag = np.abs(s)
    ratio = np.divide(-s.real, mag, out=np.zeros_like(mag), where=mag > 0)
    return DampedModes(s, s.imag / (2 * math.pi), mag / (2 * math.pi), ratio, mac, method)
