"""The Newton iterations of a time step (:func:`assembly.dynamics.transient.integrate`) and of
the static start (:func:`assembly.dynamics.run_start.static_start`) stop at the round-off of
the forces they sum (an absolute floor), and only there.

A damped mesh with backlash and constant stiffness resting in contact has its correction
force nu = k e + c delta' - k0 delta - c delta' at round-off (eps x the mesh force), so the
relative tests on xi and U' a+ (both at round-off too) never passed: such a run was refused
as "did not converge (residual 1.4e-14)". A step equation with no root is still refused."""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.dynamics.run_start import static_start
from assembly.dynamics.simulate import simulate
from assembly.dynamics.transient import Diverged, Nonlinear, integrate
from assembly.errors import SceneError
from assembly.scene.schema import scene_from_dict
from tests.support.fuzz import examples
from tests.support.gear_pair_scene import gear_pair

# A torsional spur pair (round numbers): gear 1 driven by a torque T, gear 2 free.
J1, J2 = 0.01, 0.05                 # kg m^2
R1, R2 = 0.05, 0.15                 # m, base radii
K, C = 1.0e7, 200.0                 # N/m mesh stiffness, N s/m mesh damper (the damping = 200)
BACKLASH = 1.0e-4                   # m (the backlash)
T = 10.0                            # N m on gear 1
# Along the line of action delta = r1 th1 + r2 th2 (tests/support/gear_pair_scene.py):
# J1 th1'' = T - r1 F, J2 th2'' = -r2 F give m_e delta'' + F = m_e r1 T / J1 with
# 1/m_e = r1^2/J1 + r2^2/J2 and F = k delta + c delta' (in contact).
M_E = 1.0 / (R1 ** 2 / J1 + R2 ** 2 / J2)
P = M_E * R1 * T / J1               # N, the steady mesh force = J2 r1 T / (J2 r1^2 + J1 r2^2)
OMEGA = math.sqrt(K / M_E)          # rad/s (421 Hz)
ZETA = C / (2.0 * math.sqrt(K * M_E))   # 0.026


# every run here on both steps, the compiled and the Python one (tests/dynamics/conftest.py)
pytestmark = pytest.mark.usefixtures("step_path")


def pair(backlash, simulation: dict, damping: float = C):
    return scene_from_dict(gear_pair(J1, J2, R1, R2, K, backlash=backlash, damping=damping, roles=("rotor", None),
                                     simulation=simulation))


def test_damped_backlash_mesh_accelerating_in_contact_runs_at_the_rigid_body_closed_form():
    # the case: started at its static equilibrium under inertia relief, the pair turns
    # as one body, alpha1 = T / (J1 + J2 (r1/r2)^2), the mesh carrying P from the first step
    # (exact for any step: a linear-in-time speed is integrated exactly); on main the run
    # stopped at t = 7.6 ms, "did not converge (residual 1.41e-14)"
    s = pair(BACKLASH, {"speed": 0.0, "loads": [{"body": "g1", "value": T}]})
    r = simulate(s, 0.01, 1e-5, ["force:m", "speed:g1"])
    alpha = T / (J1 + J2 * (R1 / R2) ** 2)
    np.testing.assert_allclose(r.outputs["force:m"], P, rtol=1e-9)
    np.testing.assert_allclose(r.outputs["speed:g1"], alpha * r.time_s, rtol=1e-9, atol=1e-12 * alpha)
    assert r.meshes[0]["contact_losses"] == 0


@pytest.mark.parametrize("dt", [1e-5, 2e-5])
def test_damped_backlash_mesh_step_response_is_the_closed_form_within_the_schemes_error(dt):
    # gear 1 held, gear 2 from rest with the teeth touching (delta = r2 th2 = 0, no static
    # start), a torque step T on gear 2: a single oscillator m delta'' + c delta' + k delta = T/r2,
    # m = J2 / r2^2, that stays in contact (an underdamped step response from rest never goes
    # below 0), so with P = T / r2:
    #   delta(t) = P/k [1 - e^{-zeta w t} (cos wd t + zeta / sqrt(1 - zeta^2) sin wd t)],
    #   F = k delta + c delta', delta' = P/k w / sqrt(1 - zeta^2) e^{-zeta w t} sin wd t.
    # The trapezoidal rule is the exact solution with each pole s moved by s^3 dt^2 / 12
    # (|s| = w; period elongation W^2/12, W = w dt; assembly/dynamics/integrators.py): to first
    # order a drift |ds| t plus a change |ds| / w of the coefficients fitted to the start, of the
    # oscillation of amplitude P e^{-zeta w t} / sqrt(1 - zeta^2); the next terms are O(W^2) of
    # that, and round-off adds ~1e-12 P. zeta = 0.21: the vibration decays to 1e-7 by 40 ms, where
    # on main the run stopped (29.6 ms, 32.5 ms: "did not converge (residual 1.1e-14)").
    c, J2_, T2 = 2000.0, 0.05, 10.0
    m, P = J2_ / R2 ** 2, T2 / R2
    omega, zeta = math.sqrt(K / m), c / (2.0 * math.sqrt(K * m))
    sim = {"static_start": False, "loads": [{"body": "g2", "value": T2}]}

    def run(backlash):
        d = gear_pair(J1, J2_, R1, R2, K, backlash=backlash, damping=c, fix_gear1=True, simulation=sim)
        return simulate(scene_from_dict(d), 0.04, dt, ["force:m"])
    r = run(BACKLASH)
    t = r.time_s
    decay = np.exp(-zeta * omega * t)
    root = math.sqrt(1.0 - zeta ** 2)
    wd = omega * root
    delta = P / K * (1.0 - decay * (np.cos(wd * t) + zeta / root * np.sin(wd * t)))
    ddot = P / K * omega / root * decay * np.sin(wd * t)
    W = omega * dt
    bound = P * decay / root * (omega * t + 1.0) * W ** 2 / 12.0 * (1.0 + W ** 2) + 1e-12 * P
    assert np.all(np.abs(r.outputs["force:m"] - (K * delta + c * ddot)) <= bound)
    assert r.meshes[0]["contact_losses"] == 0
    # the same run without backlash is linear (no nonlinear columns at all): the two agree to
    # the Newton tolerance (1e-10 on xi, the force along the line of action)
    np.testing.assert_allclose(r.outputs["force:m"], run(None).outputs["force:m"], rtol=0, atol=1e-9 * P)


def test_a_step_far_too_large_for_a_varying_contact_is_still_refused():
    # 90 % stiffness variation with backlash, 20 teeth at 50 rad/s (159 Hz mesh frequency),
    # dt = 10 ms: 0.6 steps per mesh period; the step equation has no root Newton can reach,
    # and its residual (hundreds of N) is far above the round-off floor (~1e-12 N)
    d = gear_pair(J1, J2, R1, R2, K, backlash=BACKLASH, amplitudes=(0.9,), roles=("rotor", None),
                  simulation={"speed": 50.0, "static_start": False, "loads": [{"body": "g1", "value": 100.0}]})
    with pytest.raises(Diverged) as e:
        simulate(scene_from_dict(d), 0.05, 1e-2, ["force:m"])
    msg = str(e.value)
    assert "did not converge" in msg and float(msg.split("residual ")[1].split(")")[0]) > 1.0, msg


class _Relay(Nonlinear):
    """nu = F sign(x) (x >= 0: +F) on one coordinate: a force with a jump and no slope."""

    def __init__(self, F: float):
        self.U, self.F = np.ones((1, 1)), F

    def forces(self, t, x, xd):
        return np.where(x >= 0.0, self.F, -self.F), np.zeros(1), np.zeros(1)


def test_a_step_equation_without_root_is_refused():
    # a unit mass at x = 0, at rest, under the relay: Newmark's step equation xi + F sign(x(xi))
    # = 0 with x = dt^2/4 xi has no root (xi = -F needs x >= 0, xi = +F needs x < 0)
    with pytest.raises(Diverged) as e:
        integrate(np.eye(1), None, np.zeros((1, 1)), lambda t: np.zeros(1), [0.0], [0.0], 1e-3, 0.01,
                  nonlinear=_Relay(1e3))
    assert "did not converge" in str(e.value)
    # and the static start: K z + F sign(z) = 0.5 F (K = 1) has no root either
    with pytest.raises(SceneError) as e:
        static_start(np.eye(1), np.eye(1), np.ones((1, 1)), _Relay(1.0), np.array([0.5]), None, np.zeros(1))
    assert str(e.value).startswith("simulation.static_start")


class _PreloadedSpring(Nonlinear):
    """A linear spring k x evaluated as (F + k x) - F - k x + k x: a correction force that is
    exactly the spring but summed from terms of size F (as a mesh's nu is from its contact
    force and the linear model's k0 delta), so it carries eps F of round-off."""

    def __init__(self, k: float, F: float):
        self.U, self.k, self.F = np.ones((1, 1)), k, F

    def forces(self, t, x, xd):
        return ((self.F + self.k * x) - self.F - self.k * x) + self.k * x, np.full(1, self.k), np.zeros(1)

    def force_scale(self, nu):
        return np.abs(nu) + 2.0 * self.F


def test_static_start_stops_at_the_round_off_of_its_forces():
    # K = 1 N/m plus the spring k = 1 N/m, load 1e-3 N: z = 5e-4 m. The correction carries
    # ~eps x 1e6 N = 2e-10 N of round-off, above the relative test's 1e-12 x 1e-3 N, and it
    # moves z by ~1e-10 m a step (above 1e-8 |z|): before the floor, 60 iterations and a refusal
    z = static_start(np.eye(1), np.eye(1), np.ones((1, 1)), _PreloadedSpring(1.0, 1e6), np.array([1e-3]), None,
                     np.zeros(1))
    assert abs(z[0] - 5e-4) <= 1e-9          # N round-off / (2 N/m), 4 eps x 1e6 / 2


def _cases(n: int, seed: int = 26):
    """Seeded draws of the class: backlash (m), contact damper (N s/m), torque (N m), speed
    (rad/s), static start or not, step (s)."""
    rng = np.random.default_rng(seed)
    return [(float(10 ** rng.uniform(-7, -3)), float(rng.choice([0.0, 20.0, 200.0, 2000.0, 4000.0])),
             round(float(rng.uniform(-50, 50)), 3), round(float(rng.uniform(0, 50)), 3), bool(rng.integers(2)),
             float(rng.choice([2e-5, 5e-5]))) for _ in range(n)]


@pytest.mark.parametrize("backlash, damping, torque, speed, start, dt", _cases(examples(20)))
def test_damped_backlash_meshes_of_constant_stiffness_run_to_the_end(backlash, damping, torque, speed, start, dt):
    # the class: constant stiffness, a dead zone and a contact damper, any load and start. The
    # chain's rigid-body speed gains the torque's impulse, T t / (J1 + J2 (r1/r2)^2), whatever
    # the mesh does: its generalized momentum J1 w1 - J2 (r1/r2) w2 (the rigid-body mode's) is
    # untouched by the mesh force, which does no work along that mode.
    s = pair(backlash, {"speed": speed, "static_start": start, "loads": [{"body": "g1", "value": torque}]},
             damping)
    try:
        r = simulate(s, 0.03, dt, ["force:m", "speed:g1", "speed:g2"])
    except Diverged as exc:
        # the contact damper's force c delta' jumps at an impact, so a step may have no root (1 in
        # 200 draws, c = 4000 N s/m): then the residual is that jump, newtons, never the round-off
        # (~1e-12 N: 4 eps x forces of at most k backlash + T / r1 ~ 1e3 N) refused before
        residual = float(str(exc).split("residual ")[1].split(")")[0])
        assert damping > 0 and residual > 1e-6, str(exc)
        return
    assert r.complete and all(np.all(np.isfinite(v)) for v in r.outputs.values())
    J = J1 + J2 * (R1 / R2) ** 2
    mean = (J1 * r.outputs["speed:g1"] - J2 * (R1 / R2) * r.outputs["speed:g2"]) / J      # rotor speed units
    np.testing.assert_allclose(mean, speed + torque / J * r.time_s, rtol=0,
                               atol=1e-9 * (abs(speed) + abs(torque) / J * 0.03) + 1e-12)
