"""The aerodynamic torque in the time step (assembly.dynamics.rotor_aero): the rotor and
generator as one inertia against a constant generator torque, perturbed from its operating
point, decays at the rate the surface's slope gives -- the aerodynamic damping, not added by hand.

Theory. J Omega' = Q(Omega) - T_g. Inside one cell of the bilinear surface, at fixed wind and
pitch, Q is linear in Omega: Q = Q* + Q' (Omega - Omega*), Q' = dQ/dOmega (constant there), and
with T_g = Q* the error e = Omega - Omega* obeys J e' = Q' e, sigma = Q' / J < 0. The trapezoidal
rule (Newmark's average acceleration: v+ = v + h (a + a+) / 2) maps it exactly:
    e_{n+1} = e_n (1 + h sigma / 2) / (1 - h sigma / 2),
so the run equals that geometric decay to Newton's tolerance (1e-10 of the forces a step).
J: the NREL 5 MW rotor 38 759 236 kg m^2 plus the generator's 534.116 kg m^2 x 97^2 on the
low-speed side (Jonkman et al. 2009); R = 63 m, rho = 1.225 kg/m^3.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.dynamics.observe_rows import state_rows
from assembly.dynamics.rosco_data import NREL5MW_SURFACE, rosco_file
from assembly.dynamics.rotor_aero import RotorAero
from assembly.dynamics.rotor_surface import read_surface, rotor_loads
from assembly.dynamics.transient import integrate

pytest.importorskip("rosco", reason="the rosco package (turbine extra) is not installed")
R, RHO, V = 63.0, 1.225, 8.0
J = 38759236.0 + 534.116 * 97.0 ** 2


def test_aerodynamic_damping_is_the_surfaces_slope():
    s = read_surface(rosco_file(NREL5MW_SURFACE))
    w_star = 7.2 * V / R                                 # lambda = 7.2, inside the cell 7.0 .. 7.5
    ld = rotor_loads(s, R, RHO, V, w_star, 0.0)
    sigma = ld.dq_domega / J
    assert sigma < 0.0                                   # the rotor damps here (above Cq's peak)
    e0 = 0.04 * V / R                                    # lambda 7.24: the same cell throughout
    aero = RotorAero(np.ones(1), s, R, RHO, lambda t: V, lambda t: 0.0)
    h, n = 0.01, 1000
    run = integrate(np.array([[J]]), None, np.zeros((1, 1)), lambda t: np.array([-ld.torque]), [0.0],
                    [w_star + e0], h, n * h, nonlinear=aero, observe=state_rows(1, q=False, v=True))
    e = run.y[:, 0] - w_star
    g = (1 + h * sigma / 2) / (1 - h * sigma / 2)
    want = e0 * g ** np.arange(n + 1)
    # per step the balance closes to Newton's tolerance on the forces, 1e-10 of Q, i.e. an error
    # in e of 1e-10 Q h / J a step, summed over the steps at most
    tol = n * 1e-10 * ld.torque * h / J
    assert np.max(np.abs(e - want)) <= tol + 1e-12 * e0
    # and the continuous decay exp(sigma t): the rule's factor g is exp(h sigma) to
    # (h sigma)^3 / 12 a step, n of them, plus the Newton tolerance above
    end = e0 * g ** n
    assert e[-1] / e0 == pytest.approx(math.exp(sigma * n * h), rel=1.01 * n * abs(h * sigma) ** 3 / 12 + tol / end)


def test_thrust_on_the_axial_row_settles_on_its_spring():
    # the rotor's rotation and its axial translation on a spring k: at the operating point
    # (generator torque = Q*) the axial spring carries the thrust from the surface, x = T / k
    s = read_surface(rosco_file(NREL5MW_SURFACE))
    w_star = 7.2 * V / R
    ld = rotor_loads(s, R, RHO, V, w_star, 0.0)
    k, m = 5.0e8, 1.1e5                                  # N/m, kg: the rotor's axial mount and mass
    aero = RotorAero([1.0, 0.0], s, R, RHO, lambda t: V, lambda t: 0.0, axial=[0.0, 1.0])
    c = 2 * 0.2 * math.sqrt(k * m)                        # 20 % damping: the axial swing dies out
    h, n = 0.01, 3000
    run = integrate(np.diag([J, m]), np.diag([0.0, c]), np.diag([0.0, k]),
                    lambda t: np.array([-ld.torque, 0.0]), [0.0, 0.0], [w_star, 0.0], h, n * h, nonlinear=aero,
                    observe=state_rows(2, q=True, v=True))
    # steady: Omega stays at Omega* (torques balance from the start) and x = T / k, to the
    # Newton tolerance (1e-10 of the forces)
    assert run.y[-1, 2] == pytest.approx(w_star, rel=1e-9)
    assert run.y[-1, 1] == pytest.approx(ld.thrust / k, rel=1e-9)
