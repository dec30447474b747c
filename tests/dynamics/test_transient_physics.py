"""Time-domain runs (assembly.dynamics.transient / mesh_contact / simulate) against closed-form
physics: parametric resonance of a mesh, the dead-zone oscillator, energy, the linear
scheme, and an HSS brake stop. Every expected number comes from theory; every tolerance from
the discretisation (the trapezoidal rule = Newmark average acceleration, the default scheme).

Facts used throughout (Hughes, The Finite Element Method, 1987, ch. 9): the trapezoidal rule
integrates x'' + w^2 x = 0 as a rotation of (x, x'/w) by theta = 2 atan(W/2) per step, W =
w dt, so its period is too long by W / theta - 1 = W^2/12 + O(W^4) (relative), with no
amplitude error; it integrates a constant velocity, and a trapezoid-integrable force, exactly.

Torsional gear pair (tests/support/gear_pair_scene.py): delta = r1 theta1 + r2 theta2 along
the line of action, J1 theta1'' = -r1 F, J2 theta2'' = -r2 F with the mesh force F = k delta
+ c delta', so delta'' = r1 theta1'' + r2 theta2'' = -(r1^2/J1 + r2^2/J2) F, i.e.
m_e delta'' + c delta' + k delta = 0 with the effective mass m_e = 1 / (r1^2/J1 + r2^2/J2)
(exact: gear 1's share r1^2/J1 is kept, tiny as it is with J1 = 1e9 J2).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as sla
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicHermiteSpline
from scipy.optimize import brentq
from scipy.special import mathieu_a, mathieu_b

from assembly.dynamics.integrators import generalized_alpha, hht, integrate_linear, newmark
from assembly.dynamics.mesh_contact import Meshes
from assembly.dynamics.mesh_variation import factor
from assembly.dynamics.observe_rows import Rows, state_rows
from assembly.dynamics.simulate import simulate
from assembly.dynamics.transient import Nonlinear, integrate
from assembly.model.assemble import assemble
from assembly.model.damping import damping_matrix
from assembly.scene.schema import scene_from_dict
from tests.support.gear_pair_scene import gear_pair


def _pair(**kw):
    """Assembled torsional pair (gear_pair's arguments) and its dense M, K, C."""
    model = assemble(scene_from_dict(gear_pair(**kw)))
    return model, model.M.toarray(), model.K.toarray(), damping_matrix(model).toarray()


# every run here on both steps, the compiled and the Python one (tests/dynamics/conftest.py)
pytestmark = pytest.mark.usefixtures("step_path")


def _rows(*rows, v_of=()):
    """Rows recording ``r @ q`` then ``r @ v`` for each ``r`` of ``rows``, then the
    velocities ``v_of`` (coordinate indices)."""
    R = np.array(rows, float)
    n, z = R.shape[1], np.zeros_like(R)
    return Rows(np.vstack([R, z]), np.vstack([z, R]), np.zeros((0, n)), np.eye(n)[list(v_of)].reshape(-1, n))


def _zero(n):
    return lambda t: np.zeros(n)


# ---------------------------------------------------------------------------------------------
# 1. Parametric resonance of one mesh: Mathieu's equation and its Floquet exponents.
#
# Sources: McLachlan, Theory and Application of Mathieu Functions (1947); Nayfeh & Mook,
# Nonlinear Oscillations (1979), ch. 5 (Floquet theory, the principal region, damping).
#
# Gear 1 (J1 = 1e9 J2) turns at Omega, so phi = z1 Omega t and k = k0 (1 + eps cos(z1 Omega t)):
#   m_e delta'' + c delta' + k0 (1 + eps cos(z1 Omega t)) delta = 0.
# With tau = z1 Omega t / 2 (d/dt = (z1 Omega / 2) d/dtau), dividing by m_e (z1 Omega/2)^2:
#   y'' + 2 zeta' y' + a (1 + eps cos 2 tau) y = 0,  a = 4 w0^2 / (z1 Omega)^2, w0^2 = k0/m_e,
#   zeta' = c / (m_e z1 Omega),
# Mathieu's y'' + (a - 2 q cos 2 tau) y = 0 with q = -a eps / 2 (the sign of q only shifts tau
# by pi/2). The principal instability region (near a = 1, the mesh at twice the natural
# frequency) lies between b1(|q|) and a1(|q|) (scipy's mathieu_b(1, q), mathieu_a(1, q)).
# The monodromy matrix P (the map of (y, y') over one period pi) has det P = 1; the Floquet
# exponent is mu = ln(max |eig P|) / pi per unit tau, > 0 inside the region, 0 outside.
# Damping: y = e^{-zeta' tau} w turns the damped equation into w'' + (a - zeta'^2 - 2 q cos
# 2 tau) w = 0 (the same q), so the damped exponent is mu(a - zeta'^2, q) - zeta'.
# ---------------------------------------------------------------------------------------------
R1 = R2 = 0.05                 # m, base radii
K0 = 1.0e8                     # N/m, mean mesh stiffness
J2 = 1.0e-3                    # kg m^2
J1 = 1.0e9 * J2                # a flywheel: gear 1's speed is imposed
Z1 = 20                        # teeth counted (gear 1)
EPS = 0.3                      # k = k0 (1 + EPS cos phi)
M_E = 1.0 / (R1 ** 2 / J1 + R2 ** 2 / J2)
W0 = math.sqrt(K0 / M_E)       # rad/s: 15.8e3 (2.5 kHz)
STEPS = 200                    # steps per mesh period (period of cos 2 tau)
DELTA0 = 1.0e-8                # m, initial compression: the consistent term (~delta^2) stays negligible
FIT = 10                       # periods from which the run's one-period map is estimated


def _mathieu_monodromy(a: float, q: float, zeta: float = 0.0) -> np.ndarray:
    """P of y'' + 2 zeta y' + (a - 2 q cos 2 tau) y = 0 over tau in [0, pi] (solve_ivp)."""
    def rhs(t, y):
        return [y[1], -2 * zeta * y[1] - (a - 2 * q * math.cos(2 * t)) * y[0]]
    cols = [solve_ivp(rhs, (0.0, math.pi), e, method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]
            for e in np.eye(2)]
    return np.column_stack(cols)


def _floquet(a: float, q: float, zeta: float = 0.0) -> float:
    """Largest Floquet exponent (per unit tau) of the equation of _mathieu_monodromy."""
    return math.log(np.max(np.abs(np.linalg.eigvals(_mathieu_monodromy(a, q, zeta))))) / math.pi


def _trapezoidal_floquet(a: float, q: float, n: int, zeta: float = 0.0) -> float:
    """The same exponent of the trapezoidal rule's own one-period map (n steps of pi/n in tau):
    the exact discrete counterpart of what the run computes."""
    h = math.pi / n
    cols = []
    for x, v in np.eye(2):
        A = a - 2 * q
        acc = -2 * zeta * v - A * x
        for i in range(n):
            A = a - 2 * q * math.cos(2 * (i + 1) * h)
            # x+ = x + h v + h^2/4 (acc + acc+), v+ = v + h/2 (acc + acc+), acc+ = -2 zeta v+ - A x+
            xp, vp = x + h * v + h * h / 4 * acc, v + h / 2 * acc
            m = np.array([[1 + h * h / 4 * A, h * h / 4 * 2 * zeta], [h / 2 * A, 1 + h / 2 * 2 * zeta]])
            x, v = np.linalg.solve(m, [xp, vp])
            acc = -2 * zeta * v - A * x
        cols.append([x, v])
    P = np.array(cols).T
    return math.log(np.max(np.abs(np.linalg.eigvals(P)))) / math.pi


def _region() -> tuple[float, float]:
    """The a-interval of the principal region on the line q = a eps / 2 (|q|) of this pair."""
    lo = brentq(lambda a: a - mathieu_b(1, EPS * a / 2), 0.5, 1.0)
    hi = brentq(lambda a: a - mathieu_a(1, EPS * a / 2), 1.0, 1.5)
    return lo, hi


def _mathieu_run(a: float, zeta: float = 0.0, periods: int = 30):
    """Integrate the pair with gear 1 at the speed giving ``a`` (and the mesh damper giving
    ``zeta``): the states (y, dy/dtau) at every mesh period (rows), and W = w0 dt."""
    omega = 2 * W0 / (Z1 * math.sqrt(a))
    c = zeta * M_E * Z1 * omega
    model, M, K, C = _pair(J1=J1, J2=J2, r1=R1, r2=R2, k=K0, teeth=Z1, amplitudes=[EPS], damping=c)
    meshes = Meshes(model)
    g = meshes.U[:, 0]                                   # the line-of-action row: delta = g q
    assert np.allclose(g, [R1, R2]) and np.allclose(C, c * np.outer(g, g))
    period = 2 * math.pi / (Z1 * omega)
    dt = period / STEPS
    q0 = np.array([0.0, DELTA0 / R2])                    # delta = DELTA0, theta1 = 0 (phi = 0)
    v0 = np.array([omega, -R1 / R2 * omega])             # the rigid-body spin: delta' = 0
    run = integrate(M, C, K, _zero(2), q0, v0, dt, periods * period, nonlinear=meshes,
                    observe=_rows(g, v_of=[0]))
    s = run.y[::STEPS]                                   # t = n * period (dt = period / STEPS exactly)
    assert len(s) == periods + 1
    assert np.ptp(run.y[:, 2]) <= 1e-9 * omega          # gear 1's speed: imposed
    return np.column_stack([s[:, 0], s[:, 1] / (Z1 * omega / 2)]), W0 * dt


def _run_exponent(states: np.ndarray) -> float:
    """The exponent of the run's own one-period map P (x_{n+1} = P x_n, least squares over the
    first FIT periods, each pair scaled to unit x_n: linear, so exact for any mix of the two
    solutions). Round-off: delta = r1 theta1 + r2 theta2 is a difference of base-circle arcs of
    up to 0.16 m (10 mesh periods of gear 1) against delta ~ 1e-8 m, 1e-16 x 0.16 / 1e-8 ~ 2e-9
    relative per sample: the exponent is good to ~1e-8 while the amplitude stays near DELTA0
    (a decaying run sampled later loses digits as delta shrinks), so only the first periods
    are used."""
    states = states[:FIT + 1]
    scale = np.linalg.norm(states[:-1], axis=1)[:, None]
    X0, X1 = (states[:-1] / scale).T, (states[1:] / scale).T
    P = X1 @ np.linalg.pinv(X0)
    return math.log(np.max(np.abs(np.linalg.eigvals(P)))) / math.pi


def _tolerance(a: float, q: float, W: float, zeta: float = 0.0) -> float:
    """The trapezoidal rule's error on mu, from its period error W^2/12: the free oscillation
    runs slow by W^2/12, i.e. a (which is w0^2 in tau units) is seen W^2/6 low, moving mu by
    |d mu / d ln a| W^2/6; plus W^2/12 per unit tau for the pumped (time-varying) part, whose
    rate in tau is O(1). Measured errors are 0.1x to 0.7x of this (second order: 4x less at
    half the step)."""
    h = 1e-4
    dmu = (_floquet(a * (1 + h) - zeta ** 2, q, 0.0) - _floquet(a * (1 - h) - zeta ** 2, q, 0.0)) / (2 * h)
    return abs(dmu) * W ** 2 / 6 + W ** 2 / 12


def test_mathieu_region_is_scipys():
    # the region's ends: the run's equation at the ends has exponent 0 (a double multiplier -1)
    lo, hi = _region()
    assert 0.85 < lo < 1.0 < hi < 1.2
    for a in (lo, hi):
        P = _mathieu_monodromy(a, -EPS * a / 2)
        assert np.trace(P) == pytest.approx(-2.0, abs=1e-7)          # on the boundary: tr P = -2
        assert np.linalg.det(P) == pytest.approx(1.0, abs=1e-9)       # Liouville: det P = 1


@pytest.mark.parametrize("where", [0.2, 0.5, 0.8])
def test_mathieu_inside_principal_region_grows_at_the_floquet_rate(where):
    lo, hi = _region()
    a = lo + where * (hi - lo)
    q = -EPS * a / 2
    mu = _floquet(a, q)
    states, W = _mathieu_run(a)
    amp = np.linalg.norm(states, axis=1)
    # grows: e^{mu pi 30} >= e^{5.5} over the run (the start projects about half on the growing
    # solution), and at every period after the first few
    assert mu > 0.05 and amp[-1] / amp[0] >= math.exp(0.8 * mu * math.pi * 30)
    assert np.all(np.diff(amp[5:]) > 0)
    mu_run = _run_exponent(states)
    # the run is the trapezoidal rule on Mathieu's equation: its exponent equals the rule's
    # discrete one, to round-off (_run_exponent) and the Newton tolerance (1e-10 a step)
    assert mu_run == pytest.approx(_trapezoidal_floquet(a, q, STEPS), abs=2e-8)
    # and Mathieu's exact exponent within the rule's period error (STEPS = 200: W ~ 0.016)
    assert W < 2 * math.pi / STEPS
    assert abs(mu_run - mu) <= _tolerance(a, q, W)


@pytest.mark.parametrize("beyond", [-0.2, 0.2])
def test_mathieu_outside_principal_region_stays_bounded(beyond):
    # 20 % of the region's width outside either end: stable, |multipliers| = 1
    lo, hi = _region()
    a = lo + beyond * (hi - lo) if beyond < 0 else hi + beyond * (hi - lo)
    q = -EPS * a / 2
    P = _mathieu_monodromy(a, q)
    lam, V = np.linalg.eig(P)
    assert np.allclose(np.abs(lam), 1.0, atol=1e-9) and abs(np.trace(P)) < 2 - 1e-3
    states, W = _mathieu_run(a)
    # the rule's discrete monodromy also has det 1 (the per-step determinants (1 + h^2 A_n / 4) /
    # (1 + h^2 A_{n+1} / 4) telescope over a period) and a complex pair: spectral radius 1
    assert _run_exponent(states) == pytest.approx(0.0, abs=2e-8)
    # bounded: |P^n x0| <= cond(V) |x0| for every n (the eigenvectors of the exact P; the run's
    # differ by O(W^2), allowed for by 1 %)
    amp = np.linalg.norm(states, axis=1)
    assert np.max(amp) <= 1.01 * np.linalg.cond(V) * amp[0]


def test_mathieu_damping_threshold():
    lo, hi = _region()
    a = 0.5 * (lo + hi)
    q = -EPS * a / 2
    # the substitution y = e^{-zeta tau} w, checked on the exact monodromy at one zeta
    assert _floquet(a, q, 0.03) == pytest.approx(_floquet(a - 0.03 ** 2, q) - 0.03, abs=1e-9)
    threshold = brentq(lambda z: _floquet(a - z * z, q) - z, 1e-6, 0.5)
    assert 0.05 < threshold < 0.1                          # ~ |q| / 2 at the region's centre
    for f, grows in ((0.8, True), (1.2, False)):
        zeta = f * threshold
        net = _floquet(a - zeta ** 2, q) - zeta
        assert (net > 0) == grows and abs(net) > 0.01
        states, W = _mathieu_run(a, zeta, periods=40)
        amp = np.linalg.norm(states, axis=1)
        # e^{net pi 40} = 6.5 or 1/6.5 (times the start's projection, ~0.7, on that solution)
        assert (amp[-1] > 3 * amp[0]) if grows else (amp[-1] < amp[0] / 3)
        mu_run = _run_exponent(states)
        assert mu_run == pytest.approx(_trapezoidal_floquet(a, q, STEPS, zeta), abs=2e-8)
        assert abs(mu_run - net) <= _tolerance(a, q, W, zeta)


# ---------------------------------------------------------------------------------------------
# 2. Dead-zone oscillator (elementary piecewise-linear oscillator).
#
# Gear 1 held, gear 2 free: one DOF, delta = r2 theta2. In contact on either flank the motion
# is harmonic at w = sqrt(k r2^2 / J2); between the flanks (-b < delta < 0) it flies at
# constant speed. Released at rest from delta = A on the drive flank: it leaves the drive flank
# at speed w A after a quarter period, crosses the gap b at w A, spends half a period on the
# coast flank, leaves it at w A, crosses back and closes the period with another quarter:
#   T = 2 pi / w + 2 b / (w A),
# with two contact losses (flank leavings) per period.
# The rule runs the harmonic arcs slow by W^2/12 and the flight exactly, so the period is long
# by (W^2/12) (2 pi / w) / T < W^2/12 relative, up to the O(W^2) error of the steps that straddle
# a contact change (force continuous, its slope not): allowed by the W^2/12 bound.
# ---------------------------------------------------------------------------------------------
K_DZ, J_DZ, R_DZ, A_DZ = 1.0e8, 1.0e-3, 0.05, 1.0e-5


@pytest.mark.parametrize("b_over_a", [0.5, 2.0])
def test_dead_zone_period_and_contact_losses(b_over_a):
    b = b_over_a * A_DZ
    model, M, K, _ = _pair(J1=1.0, J2=J_DZ, r1=0.05, r2=R_DZ, k=K_DZ, backlash=b, fix_gear1=True)
    assert model.dof_names == ["g2.rz"]
    meshes = Meshes(model)
    g = meshes.U[:, 0]
    w = math.sqrt(K_DZ * R_DZ ** 2 / J_DZ)
    T = 2 * math.pi / w + 2 * b / (w * A_DZ)
    dt = 2 * math.pi / w / 200
    n_periods = 10
    run = integrate(M, None, K, _zero(1), [A_DZ / R_DZ], [0.0], dt, n_periods * T, nonlinear=meshes,
                    observe=_rows(g))
    d, dd, t = run.y[:, 0], run.y[:, 1], run.time_s
    # up-crossings of delta = A/2 (on the drive flank, mid-arc), located by the cubic Hermite
    # interpolant of (delta, delta') over the step: O(dt^4), far below the tolerance
    level = A_DZ / 2
    crossings = []
    for i in np.nonzero((d[:-1] < level) & (d[1:] >= level))[0]:
        s = CubicHermiteSpline([0.0, dt], [d[i] - level, d[i + 1] - level], [dd[i], dd[i + 1]])
        crossings.append(t[i] + brentq(s, 0.0, dt))
    periods = np.diff(crossings)
    assert len(periods) == n_periods - 1
    W = w * dt
    elongation = periods.mean() / T - 1
    assert 0.0 < elongation <= W ** 2 / 12
    assert np.max(np.abs(periods / T - 1)) <= W ** 2 / 12
    # amplitude: the drive flank is reached again at A (energy), to the same order
    assert np.max(d) == pytest.approx(A_DZ, rel=W ** 2 / 12)
    # t_end = 10 T: at delta = A again, far from any contact change: 2 losses per period
    assert meshes.losses.tolist() == [2 * n_periods]


# ---------------------------------------------------------------------------------------------
# 3. Energy.
#
# E = 1/2 v'Mv + 1/2 q'Kq + meshes.energy(U'q) (kinetic + the mesh potential 1/2 k(phi) e^2).
# With the energy-consistent term (Oh, Grosh & Barber 2005, J. Vib. Acoust. 127, 504) the mesh
# forces derive from that potential, so E is a constant of the motion; the trapezoidal rule
# keeps it to O(dt^2) on a nonlinear model (4x less at half the step). Without it, the
# stiffness variation does the work dE/dt = 1/2 k0 f'(phi) phi' delta^2 (the angle's
# generalized force left out): E changes by the integral of that power, a property of the
# model that does not shrink with dt. On a linear undamped model the rule conserves E exactly
# (test_integrators.py: (v+ + v)'M(v+ - v)/2 + (q+ + q)'K(q+ - q)/2 = 0).
# ---------------------------------------------------------------------------------------------
def _energy_run(consistent: bool, dt: float, amplitudes=(0.3, 0.1), omega=200.0, t_end=5e-3):
    # Peeters' pair (2955 Hz), 20 teeth: mesh 637 Hz at 200 rad/s; 10 um initial compression
    model, M, K, _ = _pair(J1=2.9e-3, J2=2.9e-3, r1=0.05, r2=0.05, k=2e8, teeth=20, amplitudes=amplitudes)
    meshes = Meshes(model, consistent)
    run = integrate(M, None, K, _zero(2), [0.0, 1e-5 / 0.05], [omega, -omega + 3.0], dt, t_end,
                    nonlinear=meshes, observe=state_rows(2, q=True, v=True))
    Q, V = run.y[:, :2], run.y[:, 2:]
    X, XD = Q @ meshes.U, V @ meshes.U
    E = (0.5 * np.einsum("ti,ij,tj->t", V, M, V) + 0.5 * np.einsum("ti,ij,tj->t", Q, K, Q)
         + np.array([meshes.energy(x) for x in X]))
    if meshes.m:
        _, df = factor(X[:, 1] - meshes.phase[0], np.broadcast_to(meshes.A[0], (len(X), meshes.A.shape[1])),
                       np.broadcast_to(meshes.P[0], (len(X), meshes.P.shape[1])))
        power = 0.5 * meshes.k0[0] * df * XD[:, 1] * X[:, 0] ** 2     # the missing power
    else:
        power = np.zeros(len(X))
    work = np.concatenate([[0.0], np.cumsum(0.5 * dt * (power[1:] + power[:-1]))])
    return E - E[0], work, E[0]


def test_energy_consistent_mesh_conserves_energy_to_second_order():
    drift = [np.max(np.abs(_energy_run(True, dt)[0])) for dt in (2e-6, 1e-6)]
    change = np.max(np.abs(_energy_run(False, 1e-6)[0]))
    assert drift[0] / drift[1] == pytest.approx(4.0, rel=0.1)           # O(dt^2)
    assert drift[0] <= 1e-3 * change                                      # and small beside the
    # inconsistent model's change (a strain energy 1/2 k0 1.4 (1e-5)^2 = 0.014 J)


def test_energy_inconsistent_mesh_changes_energy_by_the_missing_work():
    runs = {dt: _energy_run(False, dt) for dt in (2e-6, 1e-6)}
    change = {dt: np.max(np.abs(dE)) for dt, (dE, _, _) in runs.items()}
    # converges to a nonzero value (5.1e-3 J, a quarter of the 0.02 J of vibration), the same at
    # both steps
    assert change[2e-6] == pytest.approx(change[1e-6], rel=1e-3)
    assert change[1e-6] > 2e-3
    # it is the work of the stiffness variation: E - E0 = int 1/2 k0 f'(phi) phi' delta^2 dt to the
    # rule's O(dt^2) error (trapezoidal quadrature of the power on top of the integration)
    err = {dt: np.max(np.abs(dE - work)) for dt, (dE, work, _) in runs.items()}
    assert err[2e-6] / err[1e-6] == pytest.approx(4.0, rel=0.1)
    assert err[1e-6] <= 1e-3 * change[1e-6]


@pytest.mark.parametrize("omega", [0.0, 200.0])
def test_energy_linear_mesh_is_conserved_to_round_off(omega):
    dE, _, E0 = _energy_run(True, 2e-6, amplitudes=None, omega=omega)
    assert np.max(np.abs(dE)) <= 1e-12 * E0


# ---------------------------------------------------------------------------------------------
# 4. The linear model through integrate (the constant factorisation, rank-m corrections) against
# integrate_linear and exact modal superposition at the rule's numerical frequencies.
#
# A mode x'' + w^2 x = 0 is rotated by theta = 2 atan(w dt/2) per step in (x, x'/w) (Hughes
# 1987, ch. 9): x_n = x0 cos(n theta) + (x0'/w) sin(n theta); the rigid-body mode moves at its
# constant speed exactly, x_n = x0 + n dt x0'.
# ---------------------------------------------------------------------------------------------
def _chain():
    """rotor -- shaft -- wheel -- mesh -- pinion -- shaft -- generator, torsional: 4 DOFs, one
    rigid-body mode."""
    c = (0.4 + 0.1) / math.cos(math.radians(20.0))
    return assemble(scene_from_dict({
        "name": "chain", "fidelity": "torsional",
        "bodies": [{"name": "rotor", "mass": 1.0, "polar_inertia": 1.0e3, "position": [0, 0, -1.0], "role": "rotor"},
                   {"name": "wheel", "mass": 1.0, "polar_inertia": 5.0},
                   {"name": "pinion", "mass": 1.0, "polar_inertia": 0.1, "position": [c, 0, 0]},
                   {"name": "gen", "mass": 1.0, "polar_inertia": 2.0, "position": [c, 0, 1.0], "role": "generator"}],
        "meshes": [{"gear1": "wheel", "gear2": "pinion", "stiffness": 1e9, "base_radius1": 0.4, "base_radius2": 0.1,
                    "pressure_angle_deg": 20.0}],
        "shafts": [{"body1": "rotor", "body2": "wheel", "k_torsion": 1e7},
                   {"body1": "pinion", "body2": "gen", "k_torsion": 1e5}]}))


class _LinearSprings(Nonlinear):
    """nu = D x + E x' along the columns of U: a linear force passed through the nonlinear path."""

    def __init__(self, U, D, E):
        self.U, self.D, self.E = U, D, E

    def forces(self, t, x, xd):
        return self.D @ x + self.E @ xd, self.D, self.E


@pytest.mark.parametrize("scheme", [newmark(), hht(0.1), generalized_alpha(0.7)], ids=lambda s: s.name)
def test_integrate_equals_integrate_linear(scheme):
    model = _chain()
    M, K = model.M.toarray(), model.K.toarray()
    n = len(M)
    rng = np.random.default_rng(7)
    q0, v0 = 1e-4 * rng.normal(size=n), rng.normal(size=n)
    load = np.zeros(n)
    load[0] = 1e3

    def force(t):
        return load * math.sin(300.0 * t)

    dt, t_end = 2e-4, 0.2
    ref = integrate_linear(M, None, K, force, q0, v0, dt, t_end, scheme)
    run = integrate(M, None, K, force, q0, v0, dt, t_end, scheme, nonlinear=Meshes(model),
                    observe=state_rows(n, q=True, v=True))
    scale = np.max(np.abs(ref.q))
    assert np.max(np.abs(run.y[:, :n] - ref.q)) <= 1e-12 * scale
    # v+ = v + dt (a + a+)/2 carries the accelerations' round-off, which the stiffest mode (the
    # mesh, w = 1e4 rad/s, W = 2) scales up by w relative to q's: 1e-11 after 1000 steps
    assert np.max(np.abs(run.y[:, n:] - ref.v)) <= 1e-11 * np.max(np.abs(ref.v))
    # a linear spring and damper along two rows, given as "nonlinear" forces (the Woodbury path
    # of transient.integrate): the same as integrate_linear with K + U D U', C + U E U'
    U = np.column_stack([np.eye(n)[0] - np.eye(n)[1], np.eye(n)[3]])
    D, E = np.diag([3e6, 2e4]), np.array([[50.0, 0.0], [0.0, 5.0]])
    ref2 = integrate_linear(M, U @ E @ U.T, K + U @ D @ U.T, force, q0, v0, dt, t_end, scheme)
    run2 = integrate(M, None, K, force, q0, v0, dt, t_end, scheme, nonlinear=_LinearSprings(U, D, E))
    assert np.max(np.abs(run2.y - ref2.q)) <= 1e-11 * np.max(np.abs(ref2.q))   # Newton: 1e-10 on xi


def test_integrate_is_modal_superposition_at_the_numerical_frequencies():
    model = _chain()
    M, K = model.M.toarray(), model.K.toarray()
    n = len(M)
    lam, Phi = sla.eigh(K, M)                             # mass-normalised
    lam[0] = 0.0                                          # the rigid-body mode
    rng = np.random.default_rng(11)
    q0, v0 = 1e-4 * rng.normal(size=n), rng.normal(size=n)
    dt, t_end = 2e-4, 0.2
    run = integrate(M, None, K, _zero(n), q0, v0, dt, t_end, nonlinear=Meshes(model), observe=state_rows(n))
    x0, xd0 = Phi.T @ M @ q0, Phi.T @ M @ v0
    w = np.sqrt(lam)
    k = np.arange(len(run.time_s))[:, None]
    theta = 2 * np.arctan(w * dt / 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(w > 0, x0 * np.cos(k * theta) + xd0 / np.where(w > 0, w, 1) * np.sin(k * theta),
                     x0 + k * dt * xd0)
    exact = x @ Phi.T
    assert np.max(np.abs(run.y - exact)) <= 1e-10 * np.max(np.abs(exact))


# ---------------------------------------------------------------------------------------------
# 5. HSS brake stop (ElastoDyn's brake, HSSBrMode 1: Jonkman, Buhl, FAST User's Guide, and
# Jonkman et al. 2009, NREL/TP-500-38060).
#
# Rotor J_R and generator J_G on a torsional shaft k, spinning at Omega, the brake on the
# generator: T_b(t) = 0 before t_d, T t'/t_r over the ramp (t' = t - t_d), T after; it acts
# against the generator's speed w_G, proportionally to it below the stick speed. In the
# rigid-body mode phi = (1, 1) the shaft does no work, so the angular momentum p = phi'M v =
# J_R w_R + J_G w_G obeys dp/dt = -T_b(t) while w_G > stick speed:
#   p(t) = J Omega - I(t),  I(t) = T (t-t_d)^2 / (2 t_r) on the ramp, T (t - t_d - t_r/2) after,
# J = J_R + J_G; the momentum-weighted speed p/J reaches 0 at t_s = t_d + t_r/2 + J Omega / T.
# The rule's momentum update p+ - p = -dt (T_b + T_b+)/2 is the trapezoidal quadrature of T_b,
# exact for a piecewise-linear T_b with its corners on steps: p follows the closed form to
# round-off. The ramp lasts 4 elastic periods, so the shaft's vibration it leaves is O(W^2)
# small and w_G = p/J at constant deceleration T/J; w_G therefore enters the stick band when
# p/J = stick, J stick / T before t_s, and the first step inside is at most dt later:
#   |t_stop - t_s| <= J stick / T + dt.
# After the stop the brake is a damper T/stick: its torque always opposes w_G (it never drives
# the generator) and |w_G| stays below the stick speed. The shaft's twist J_R T/J, released at
# the stop, swings the rotor, and the generator follows it inside the band at w_G = shaft
# torque / (T/stick), of either sign: a flexible drivetrain under this brake law does creep
# backwards (|w_G| <= stick J_R / J); only a rigid one stops without reversing (last test).
# ---------------------------------------------------------------------------------------------
JR, JG, KS = 50.0, 5.0, 2.0e5          # kg m^2, kg m^2, N m/rad: 33.4 Hz free-free
TBRAKE, OMEGA = 500.0, 2.0             # N m, rad/s


def _brake_scene(stick: float, t_d: float, t_r: float):
    return scene_from_dict({
        "name": "two inertias and a brake", "fidelity": "torsional", "band_hz": 100.0,
        "bodies": [{"name": "rotor", "mass": 1.0, "polar_inertia": JR, "role": "rotor"},
                   {"name": "gen", "mass": 1.0, "polar_inertia": JG, "position": [0.0, 0.0, 1.0],
                    "role": "generator"}],
        "shafts": [{"body1": "rotor", "body2": "gen", "k_torsion": KS}],
        "simulation": {"speed": OMEGA, "brake": {"torque": TBRAKE, "deploy_time": t_d, "ramp_time": t_r,
                                                 "stick_speed": stick}}})


def _brake_integral(t, t_d, t_r):
    t = np.asarray(t, float)
    return TBRAKE * np.where(t < t_d, 0.0, np.where(t < t_d + t_r, (t - t_d) ** 2 / (2 * t_r),
                                                     t_r / 2 + (t - t_d - t_r)))


@pytest.mark.parametrize("stick", [
    1e-2,
    # the default stick speed: T dt / J (the speed lost per step) exceeds the band 2 stick, so
    # Newton's full steps jump across the band at the stop; the step halving finds the root
    1e-3])
def test_brake_stop(stick):
    J = JR + JG
    w_n = math.sqrt(KS * (1 / JR + 1 / JG))
    dt = 2 * math.pi / w_n / 100                          # 100 steps per elastic period
    t_d, t_r = 10 * dt, 400 * dt                          # corners on steps; ramp = 4 periods
    t_s = t_d + t_r / 2 + J * OMEGA / TBRAKE
    model = assemble(_brake_scene(stick, t_d, t_r))
    res = simulate(model, t_s + 0.1, dt, outputs=["speed:rotor", "speed:gen"])
    t, wr, wg = res.time_s, res.outputs["speed:rotor"], res.outputs["speed:gen"]
    # momentum in the rigid-body mode: phi = null space of K, scaled to the rotor's speed
    assert model.dof_names == ["rotor.rz", "gen.rz"]
    phi = sla.null_space(model.K.toarray())[:, 0]
    phi = phi / phi[0]
    assert np.allclose(phi, [1.0, 1.0])
    p = np.column_stack([wr, wg]) @ (model.M.toarray() @ phi)
    i = int(np.argmax(wg <= stick))                       # first step in the stick band
    assert i > 0
    before = slice(0, i)
    wbar = OMEGA - _brake_integral(t, t_d, t_r) / J
    assert np.max(np.abs(p[before] / J - wbar[before])) <= 1e-12 * OMEGA
    assert abs(t[i] - t_s) <= J * stick / TBRAKE + dt
    assert np.all(wg[before] > stick)                    # never reversed before
    # the brake torque from the momentum balance (nu_0 = 0: t_d > 0): nu+ = -2 (p+ - p)/dt - nu
    nu = np.zeros(len(t))
    for k in range(len(t) - 1):
        nu[k + 1] = -2 * (p[k + 1] - p[k]) / dt - nu[k]
    law = _brake_integral_rate(t, t_d, t_r) * np.clip(wg / stick, -1.0, 1.0)
    assert np.max(np.abs(nu - law)) <= 1e-6 * TBRAKE     # ElastoDyn's law at every step
    assert np.all(nu * wg >= -1e-6 * TBRAKE * stick)     # never drives the generator
    after = slice(i, None)
    assert np.max(np.abs(wg[after])) <= stick
    # the creep back (notes above): the rotor swings back through the released twist (the mode's
    # damping by the brake's T/stick is ~3 %), the generator follows at shaft torque / (T/stick),
    # at most the stop's J_R T/J over T/stick: |w_G| <= stick J_R/J (5 % for J_G's own inertia)
    assert -stick * JR / J * 1.05 <= np.min(wg[after]) < -0.5 * stick * JR / J


def _brake_integral_rate(t, t_d, t_r):
    """T_b(t): the brake torque magnitude (the derivative of _brake_integral)."""
    return TBRAKE * np.clip((np.asarray(t, float) - t_d) / t_r, 0.0, 1.0)


def test_brake_stops_a_rigid_drivetrain_without_reversing():
    # The generator carried rigidly by the rotor (its frame, all DOFs held): one DOF, J = J_R + J_G.
    # Full torque from t = 0: w = Omega - T t / J down to the band, then J w' = -(T/stick) w: an
    # exponential decay that never changes sign; the rule maps it by the factor
    # (1 - dt/(2 tau)) / (1 + dt/(2 tau)), tau = J stick / T, positive for dt < 2 tau. (For a
    # single DOF dt > 2 tau is also T dt / J > 2 stick: the Newton cycle of test_brake_stop's xfail.)
    stick = 1e-2
    J = JR + JG
    tau = J * stick / TBRAKE
    dt = 1.5 * tau
    scene = scene_from_dict({
        "name": "rigid drivetrain", "fidelity": "torsional", "band_hz": 10.0,
        "bodies": [{"name": "rotor", "mass": 1.0, "polar_inertia": JR, "role": "rotor"},
                   {"name": "gen", "mass": 1.0, "polar_inertia": JG, "position": [0.0, 0.0, 1.0],
                    "role": "generator", "frame": "rotor"}],
        "bearings": [{"body": "rotor", "k_radial": 1e8, "k_axial": 1e8, "k_tilt": 0.0}],
        "fixed": [{"body": "gen"}],
        "simulation": {"speed": OMEGA, "brake": {"torque": TBRAKE, "stick_speed": stick}}})
    t_s = J * OMEGA / TBRAKE
    res = simulate(scene, t_s + 40 * dt, dt, outputs=["speed:gen"])
    w = res.outputs["speed:gen"]
    i = int(np.argmax(w <= stick))
    assert np.allclose(w[:i], OMEGA - TBRAKE * res.time_s[:i] / J, rtol=0, atol=1e-12 * OMEGA)
    assert abs(res.time_s[i] - t_s) <= tau + dt
    tail = w[i + 1:]
    r = (1 - dt / (2 * tau)) / (1 + dt / (2 * tau))
    assert np.all(tail >= 0.0) and np.all(tail <= stick)
    big = tail[:-1] > 1e-12 * stick
    assert np.allclose(tail[1:][big] / tail[:-1][big], r, rtol=1e-6)


# ---------------------------------------------------------------------------------------------
# 4. The three steps agree: the compiled step (numba), the Python step on the same compiled
# laws, and the Python step with numba absent (the laws on numpy arrays, Newton's matrix summed
# in the compiled order, the same LAPACK solve) do the same arithmetic, so every physics run
# above gives the same numbers on each to round-off: 1e-12 of each output's largest value.
# ---------------------------------------------------------------------------------------------
AGREE = 1e-12


def _on_three_steps(run, monkeypatch) -> None:
    """``run()`` -> {name: array} on the three steps, each output within AGREE of the compiled one."""
    from assembly.dynamics import jit
    out = {}
    for name, enabled, compiled in (("compiled", True, True), ("python", False, True), ("no numba", False, False)):
        monkeypatch.setattr(jit, "ENABLED", enabled)
        monkeypatch.setattr(jit, "COMPILED", compiled)
        out[name] = run()
    ref = out["compiled"]
    for name in ("python", "no numba"):
        for key, y in out[name].items():
            y0 = np.asarray(ref[key], float)
            assert np.all(np.isfinite(y)), (name, key)
            assert np.max(np.abs(np.asarray(y, float) - y0)) <= AGREE * np.max(np.abs(y0)), (name, key)


def _dead_zone_rows(b_over_a: float) -> dict:
    b = b_over_a * A_DZ
    model, M, K, _ = _pair(J1=1.0, J2=J_DZ, r1=0.05, r2=R_DZ, k=K_DZ, backlash=b, fix_gear1=True)
    meshes = Meshes(model)
    w = math.sqrt(K_DZ * R_DZ ** 2 / J_DZ)
    run = integrate(M, None, K, _zero(1), [A_DZ / R_DZ], [0.0], 2 * math.pi / w / 200,
                    10 * (2 * math.pi / w + 2 * b / (w * A_DZ)), nonlinear=meshes, observe=_rows(meshes.U[:, 0]))
    return {"rows": run.y, "losses": meshes.losses.astype(float)}


def _brake_rows(stick: float) -> dict:
    w_n = math.sqrt(KS * (1 / JR + 1 / JG))
    dt = 2 * math.pi / w_n / 100
    t_d, t_r = 10 * dt, 400 * dt
    model = assemble(_brake_scene(stick, t_d, t_r))
    res = simulate(model, t_d + t_r / 2 + (JR + JG) * OMEGA / TBRAKE + 0.1, dt, outputs=["speed:rotor", "speed:gen"])
    return dict(res.outputs)


def test_the_three_steps_agree_on_every_physics_run(step_path, monkeypatch):
    if step_path != "compiled":
        pytest.skip("runs the three steps itself, once")
    lo, hi = _region()
    _on_three_steps(lambda: {"states": _mathieu_run(lo + 0.5 * (hi - lo))[0]}, monkeypatch)    # Mathieu, growing
    _on_three_steps(lambda: {"states": _mathieu_run(1.0, zeta=0.02)[0]}, monkeypatch)          # damped
    for b_over_a in (0.5, 2.0):                                                                 # dead zone
        _on_three_steps(lambda: _dead_zone_rows(b_over_a), monkeypatch)
    for consistent in (True, False):                                                            # energy
        _on_three_steps(lambda: dict(zip(("dE", "work"), _energy_run(consistent, 2e-6)[:2])), monkeypatch)
    for stick in (1e-2, 1e-3):                                                                  # brake stop
        _on_three_steps(lambda: _brake_rows(stick), monkeypatch)
