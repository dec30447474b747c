"""An unbalance (assembly.dynamics.unbalance) on a rigid rotor on isotropic bearings, spun at a
constant speed: its steady response against the closed form.

Theory. The rotor's centre (x, y), mass M, bearing stiffness k and damping c per direction; the
unbalance m e at phase 0 on the rotation theta = Omega t: M x'' + c x' + k x = m e Omega^2 cos
Omega t (and sin for y), so x = Re{X e^{i Omega t}}, X = m e Omega^2 / (k - M Omega^2 + i c Omega):
the amplitude and phase of the textbook (e.g. Genta, Dynamics of Rotating Systems, 2005, ch. 3).
The time step is the trapezoidal rule, which maps s to s_d = (2/h) i tan(Omega h / 2) exactly
on a sampled harmonic; its steady response is X_d = m e Omega^2 / (k + M s_d^2 + c s_d), to
round-off, and X_d tends to X as (Omega h)^2 / 12.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.dynamics.observe_rows import state_rows
from assembly.dynamics.transient import integrate
from assembly.dynamics.unbalance import Unbalance

pytestmark = pytest.mark.usefixtures("step_path")

MR, K, C, J = 50.0, 2.0e7, 2.0e3, 1.0e9       # kg, N/m, N s/m, kg m^2 (a flywheel: the spin is imposed)
MU, E = 0.02, 0.1                              # kg, m
OMEGA = 0.8 * math.sqrt(K / MR)                # below the critical speed, 80 % of it


def test_unbalance_response_is_the_closed_form():
    wn = math.sqrt(K / MR)
    h = 2 * math.pi / OMEGA / 200
    t_end = 30 * 2 * MR / C                    # 30 decay times 2M/c of the free motion: e^-30 left
    M = np.diag([MR, MR, J])
    Kd, Cd = np.diag([K, K, 0.0]), np.diag([C, C, 0.0])
    ub = Unbalance(3, 0, 1, 2, MU, E, 0.0, h)
    run = integrate(M, Cd, Kd, lambda t: np.zeros(3), [0.0, 0.0, 0.0], [0.0, 0.0, OMEGA], h, t_end,
                    nonlinear=ub, observe=state_rows(3, q=True))
    t, x, y, th = run.time_s, run.y[:, 0], run.y[:, 1], run.y[:, 2]
    assert np.max(np.abs(th - OMEGA * t)) <= 1e-9 * OMEGA * t_end     # the spin: imposed
    sd = 2j / h * math.tan(OMEGA * h / 2)
    Xd = MU * E * OMEGA ** 2 / (K + MR * sd ** 2 + C * sd)
    X = MU * E * OMEGA ** 2 / (K - MR * OMEGA ** 2 + 1j * C * OMEGA)
    last = t >= t_end - 2 * math.pi / OMEGA * 5
    want_x = np.real(Xd * np.exp(1j * OMEGA * t[last]))
    want_y = np.real(-1j * Xd * np.exp(1j * OMEGA * t[last]))           # sin = Re(-i e^{i w t})
    # the steady part to Newton's tolerance (1e-10 of the forces) and what is left of the start
    # (e^-30 of the first swing)
    tol = 1e-9 * abs(Xd)
    assert np.max(np.abs(x[last] - want_x)) <= tol and np.max(np.abs(y[last] - want_y)) <= tol
    # and the continuous closed form within the rule's (Omega h)^2 / 12 (amplified near resonance
    # by the dynamic stiffness's sensitivity: M Omega^2 / |k - M Omega^2 + i c Omega|)
    rel = (OMEGA * h) ** 2 / 12 * (1 + MR * OMEGA ** 2 / abs(K - MR * OMEGA ** 2 + 1j * C * OMEGA)) * 2
    assert abs(Xd) == pytest.approx(abs(X), rel=rel)
    assert math.atan2(Xd.imag, Xd.real) == pytest.approx(math.atan2(X.imag, X.real), abs=rel)
    assert OMEGA < wn
