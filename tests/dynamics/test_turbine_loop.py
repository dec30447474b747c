"""The controller in the loop (assembly.dynamics.turbine_loop): ROSCO's compiled NREL 5 MW
controller (its DISCON.IN) on the rotor and generator as one inertia with the rotor's
aerodynamics from ROSCO's performance table, in a steady wind above rated.

Checks:
- the controller is called at its sample times and nowhere else (count and times);
- the pitch actuator holds its closed form between samples;
- above rated the loop settles at DISCON.IN's reference generator speed (PC_RefSpd = VS_RefSpd
  = 122.90967 rad/s): the pitch PI's integral removes the steady error, so after 110 s of a
  steady 16 m/s the speed equals it to the float32 swap array's resolution (2^-24 relative: the
  speed the controller sees); the generator torque is VS_RtTq = 43 093.51876 N m there, the
  pitch positive, and the rotor's aerodynamic torque balances the generator's through the ratio
  (steady: J Omega' = 0).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.dynamics.discon import Discon
from assembly.dynamics.observe_rows import state_rows
from assembly.dynamics.rosco_data import NREL5MW_SURFACE, rosco_file
from assembly.dynamics.rotor_aero import RotorAero
from assembly.dynamics.rotor_surface import read_surface, rotor_loads
from assembly.dynamics.sampled import Sampled
from assembly.dynamics.transient import integrate
from assembly.dynamics.turbine_loop import ControllerLoop, PitchActuator

pytest.importorskip("rosco", reason="the rosco package (turbine extra) is not installed")
R, RHO, N = 63.0, 1.225, 97.0                    # m, kg/m^3, gear ratio (Jonkman et al. 2009)
J = 38759236.0 + 534.116 * N ** 2                # kg m^2 on the low-speed side
REF, VS_RTTQ = 122.90967, 43093.51876            # rad/s, N m: DISCON.IN


def test_pitch_actuator_between_samples():
    a = PitchActuator(0.1, 0.0)
    a.command(1.0, 0.2)
    for dt in (0.0, 0.05, 0.3):
        assert a.pitch(1.0 + dt) == pytest.approx(0.2 * (1 - math.exp(-dt / 0.1)), rel=1e-15, abs=0.0)
    a.command(1.3, 0.0)                          # from where it was
    assert a.pitch(1.3) == pytest.approx(0.2 * (1 - math.exp(-3.0)), rel=1e-15)


def test_rosco_holds_rated_speed_above_rated(tmp_path):
    s = read_surface(rosco_file(NREL5MW_SURFACE))
    wind = 16.0
    dt, period, t_end = 0.01, 0.01, 120.0
    ctrl = Discon(rosco_file("rosco/lib/libdiscon.so"), rosco_file("Examples/Test_Cases/NREL-5MW/DISCON.IN"),
                  workdir=tmp_path)
    act = PitchActuator(0.0, math.radians(10.0))
    loop = ControllerLoop(ctrl, [N], [1.0], period, lambda t: wind, act, efficiency=0.944, torque0=VS_RTTQ)
    aero = RotorAero(np.ones(1), s, R, RHO, lambda t: wind, act.pitch)
    try:
        run = integrate(np.array([[J]]), None, np.zeros((1, 1)), lambda t: np.zeros(1), [0.0], [REF / N], dt, t_end,
                        nonlinear=aero, observe=state_rows(1, q=False, v=True),
                        sampled=Sampled(loop.vector(), period, loop.law))
    finally:
        ctrl.close()
    n = round(t_end / period)
    assert ctrl.calls == n and np.allclose(loop.times, np.arange(n) * period, rtol=0, atol=1e-9)
    w_gen = N * run.y[:, 0]
    last = run.time_s >= t_end - 10.0
    F32 = 2.0 ** -24                              # the swap array's resolution: what the controller sees
    assert np.max(np.abs(w_gen[last] / REF - 1)) <= 4 * F32
    assert loop.torques[-1] == pytest.approx(VS_RTTQ, rel=2 * F32)
    beta = act.pitch(t_end)
    assert beta > 0.0
    # steady: the aerodynamic torque is the generator's through the ratio, to the acceleration
    # left over the last 10 s (J times the speed's spread over 10 s) and the torque's float32
    ld = rotor_loads(s, R, RHO, wind, run.y[-1, 0], beta)
    left = J * np.ptp(run.y[last, 0]) / 10.0
    assert abs(ld.torque - N * loop.torques[-1]) <= left + 2 * F32 * N * loop.torques[-1]


@pytest.mark.parametrize("wind", [6.0, 7.0, 8.0])
def test_region_2_settles_at_the_surfaces_operating_point(wind):
    # ServoDyn's simple law in region 2 (k = 0.0255764 N m/rpm^2, Jonkman et al. 2009) with the
    # pitch at 0: the steady rotor speed is where the rotor's torque from the surface equals the
    # generator's k (N Omega)^2 through the ratio -- found here by bisection on the surface
    # itself, independently of the time step; the loop must settle there
    from scipy.optimize import brentq

    from assembly.dynamics.variable_speed import RPM, SimpleVariableSpeed, TorqueLawController
    s = read_surface(rosco_file(NREL5MW_SURFACE))
    k = 0.0255764 / RPM ** 2
    law = SimpleVariableSpeed(rated_speed=1173.7 * RPM, rated_torque=43093.55, k=k, slip=0.10)

    def excess(w):
        return rotor_loads(s, R, RHO, wind, w, 0.0).torque - N * k * (N * w) ** 2
    w_star = brentq(excess, 4.0 * wind / R, 12.0 * wind / R, xtol=1e-14, rtol=1e-15)
    assert N * w_star < law.transition_speed                           # region 2 indeed
    ctrl = TorqueLawController(law)
    act = PitchActuator(0.0, 0.0)
    dt, t_end = 0.02, 400.0
    loop = ControllerLoop(ctrl, [N], [1.0], dt, lambda t: wind, act)
    aero = RotorAero(np.ones(1), s, R, RHO, lambda t: wind, act.pitch)
    run = integrate(np.array([[J]]), None, np.zeros((1, 1)), lambda t: np.zeros(1), [0.0], [0.9 * w_star], dt, t_end,
                    nonlinear=aero, observe=state_rows(1, q=False, v=True), sampled=Sampled(loop.vector(), dt, loop.law))
    # the speed's error decays as exp(-t / tau), tau = J / (N dT/dw - dQ/dw) at the point (the
    # torque held a sample adds a lag of dt/2 to it), so after t_end it is 0.1 exp(-t_end / tau)
    ld = rotor_loads(s, R, RHO, wind, w_star, 0.0)
    tau = J / (2 * N * k * N * N * w_star - ld.dq_domega)
    left = 0.1 * math.exp(-(t_end - dt) / (tau + dt))
    assert run.y[-1, 0] == pytest.approx(w_star, rel=left + 1e-9)
    assert ctrl.calls == round(t_end / dt)


@pytest.mark.parametrize("zeta", [0.3, 1.0, 2.0])
def test_second_order_pitch_actuator_is_its_ode_between_samples(zeta):
    # beta'' + 2 zeta w beta' + w^2 beta = w^2 beta_c, the demand held: integrated here by the
    # matrix exponential of its first-order form, which is exact (to round-off, ~1e-15 x the step)
    from scipy.linalg import expm

    from assembly.dynamics.turbine_loop import SecondOrderPitch
    w = 2 * math.pi * 1.6                        # rad/s (a typical pitch bandwidth)
    a = SecondOrderPitch(w, zeta, 0.05)
    A = np.array([[0.0, 1.0], [-w * w, -2 * zeta * w]])
    x = np.array([0.0, 0.0])                     # (beta - demand, beta'), at rest on 0.05
    demand, t0 = 0.05, 0.0
    for tj, new in ((0.0, 0.2), (0.3, 0.1), (0.35, 0.25)):
        x = expm(A * (tj - t0)) @ x
        x = np.array([x[0] + demand - new, x[1]])  # angle and rate continuous across a new demand
        a.command(tj, new)
        demand, t0 = new, tj
        for s in (0.0, 0.01, 0.04, 0.2):
            want = demand + (expm(A * s) @ x)[0]
            assert a.pitch(tj + s) == pytest.approx(want, abs=1e-12)
