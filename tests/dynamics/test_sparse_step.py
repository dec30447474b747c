"""The time step of a model above DENSE_INVERSE_MAX coordinates (a sparse factorisation, no
kept inverse: assembly.dynamics.transient.PythonSteps without a predictor's map): no product
acts on q, K q + C v coming from the step's balance (module notes of transient.py), so its
round-off does not grow with the rigid rotation a spinning drivetrain accumulates; and it is
the dense step's run on a model with nonlinear meshes. The sparse path is forced on small
models by lowering DENSE_INVERSE_MAX.
"""
from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

import assembly.dynamics.integrators as integrators
import assembly.dynamics.run_model as run_model
import assembly.dynamics.transient as transient
from assembly.dynamics.integrators import effective_matrix, generalized_alpha, newmark
from assembly.dynamics.simulate import simulate
from assembly.dynamics.step_kernel import NEWTON_RTOL
from assembly.dynamics.transient import integrate
from assembly.model.assemble import assemble
from assembly.scene.schema import load_scene, scene_from_dict
from tests.support.gear_pair_scene import gear_pair

EPS = np.finfo(float).eps
EPS_LD = np.finfo(np.longdouble).eps      # 2^-63 on x86 (80-bit), EPS where there is none
STEPS_PAIR = 500

#: a torsional chain of three inertias (kg m^2) on two shafts of the NREL 5 MW drivetrain's
#: torsional stiffness (DTTorSpr = 867 637 000 N m/rad, Jonkman et al. 2009, NREL/TP-500-38060,
#: table 5-1), the first twice as stiff
J = np.array([1.0, 0.5, 2.0])
K_SHAFT = 867.637e6
#: turning at the 5 MW generator's rated speed (1173.7 rpm = 122.91 rad/s, Jonkman 2009) for
#: 1 s at dt = 1e-4 s: 123 rad, the angle the time step carries in its coordinates
SPEED, DT, STEPS = 122.91, 1.0e-4, 10_000
#: a 50 Hz torque of 10 N m on the first inertia, its reaction on the last (no net torque:
#: the speed stays)
TORQUE, HZ = 10.0, 50.0


def _chain():
    B = np.array([[1.0, -1.0, 0.0], [0.0, 1.0, -1.0]])          # the shafts' twists, B q
    k = np.array([2.0 * K_SHAFT, K_SHAFT])
    K = B.T @ np.diag(k) @ B
    C = 1.0e-5 * K            # stiffness-proportional damping: ratio w 1e-5 / 2, 0.35 at the top mode
    return np.diag(J), C, K, B, k


def _force(t):
    return TORQUE * np.sin(2 * np.pi * HZ * t) * np.array([1.0, 0.0, -1.0])


def _reference(M, C, K, B, k, s, twists: bool, L=np.longdouble):
    """The linear step of transient.py (forces averaged, Newmark's updates), from the spinning
    start, in ``L`` arithmetic; ``twists``: K q + C v formed from the shafts' twists B q, B v,
    carried by the same Newmark updates (B q+ = B qp + beta dt^2 B a+: the same step in exact
    arithmetic, with no rotation in any product). Returns the accelerations (STEPS + 1, n) and
    the largest ``|f|``, ``|M a|``, ``|F|``, ``|K qp + C vp|`` and ``|v - v0|`` of the run
    (infinity norms)."""
    am, af, b, g, dt = s.alpha_m, s.alpha_f, s.beta, s.gamma, DT
    A0 = effective_matrix(M, C, K, dt, s)
    A0inv, Minv = np.linalg.inv(A0), np.linalg.inv(M)
    Ml, Cl, Kl, Al, Bl, kl, c = (X.astype(L) for X in (M, C, K, A0, B, k, 1.0e-5 * k))

    def solve(Ainv, A, r):             # a float solve, refined in L arithmetic
        z = (Ainv @ r.astype(float)).astype(L)
        for _ in range(3):
            z = z + (Ainv @ (r - A @ z).astype(float)).astype(L)
        return z

    def springs(d, w):                 # K q + C v = B' (k B q + c B v)
        return Bl.T @ (kl * d + c * w)

    q, v = np.zeros(3, L), np.full(3, SPEED, L)
    d, w = Bl @ q, Bl @ v
    F = springs(d, w) if twists else Kl @ q + Cl @ v
    a = solve(Minv, Ml, _force(0.0).astype(L) - F)
    Ma = Ml @ a
    out, sizes = [a], np.zeros(5)
    for i in range(STEPS):
        f_a = _force(i * dt + (1 - af) * dt).astype(L)
        qp, vp = q + dt * v + (dt * dt * (0.5 - b)) * a, v + (dt * (1 - g)) * a
        dp, wp = d + dt * w + (dt * dt * (0.5 - b)) * (Bl @ a), w + (dt * (1 - g)) * (Bl @ a)
        P = springs(dp, wp) if twists else Kl @ qp + Cl @ vp
        a_new = -solve(A0inv, Al, am * Ma + (1 - af) * P + af * F - f_a)
        q, v = qp + (b * dt * dt) * a_new, vp + (g * dt) * a_new
        d, w = dp + (b * dt * dt) * (Bl @ a_new), wp + (g * dt) * (Bl @ a_new)
        Ma_new = Ml @ a_new
        F = (f_a - am * Ma - (1 - am) * Ma_new - af * F) / (1 - af)
        a, Ma = a_new, Ma_new
        out.append(a)
        sizes = np.maximum(sizes, [float(np.abs(x).max()) for x in (f_a, Ma, F, P, v - SPEED)])
    return np.array(out).astype(float), sizes


@pytest.fixture
def sparse_path(monkeypatch):
    """Every model above 1 coordinate takes the sparse path (CHOLMOD or SuperLU)."""
    for module in (integrators, transient, run_model):
        monkeypatch.setattr(module, "DENSE_INVERSE_MAX", 1)


@pytest.mark.skipif(EPS_LD == EPS, reason="np.longdouble is double here: K v0 is formed to eps, and its round-off "
                                         "adds up as today's form's does")
@pytest.mark.parametrize("sparse", [True, False], ids=["sparse", "dense LU"])
@pytest.mark.parametrize("scheme", [newmark(), generalized_alpha(0.9)], ids=lambda s: s.name)
def test_sparse_step_keeps_its_accuracy_under_a_large_rotation(scheme, sparse, sparse_path):
    # the matrices sparse (one stacked product a step), or dense above the kept inverse's size
    # (a dense LU, three products a step): the same form
    M, C, K, B, k = _chain()
    as_run = sp.csr_matrix if sparse else np.asarray
    run = integrate(as_run(M), as_run(C), as_run(K), _force, np.zeros(3), np.full(3, SPEED),
                    DT, STEPS * DT, scheme, observe=lambda q, v, a, nu: a)
    assert run.info["solver"].startswith("sparse") if sparse else run.info["solver"] == "dense LU"
    ref, (f_max, Ma_max, F_max, P_max, dv_max) = _reference(M, C, K, B, k, scheme, twists=True)
    today, _ = _reference(M, C, K, B, k, scheme, twists=False, L=np.float64)   # K qp + C vp, as before
    a_max = np.abs(ref).max()
    err = np.abs(run.y - ref).max() / a_max
    err_today = np.abs(today - ref).max() / a_max
    # The bound. Round-off misplaces the step's balance by a force, and the form carries K q + C v
    # (module notes), so a step's error stays in the balance of every later step. In the modes of
    # the chain (M-normalised, Phi' M Phi = I) a force error F(t) from t = 0 moves mode i's
    # acceleration by at most its total variation over m_i = 1: a_i = int phi_i' F'(s) cos(w_i
    # (t - s)) ds (by parts, undamped; damping and the scheme's spectral radius <= 1 only lower
    # it), over 1 - alpha_m for the step's own share of a+. So |a error| <= G TV(F) / (1 - alpha_m),
    # G = || |Phi| |Phi'| || (infinity norms). TV(F):
    # * each of the N steps adds its own round-off once: the right-hand side sums 6 terms
    #   (alpha_m M a, P = K q + C v from the balance, dt K v0, K d + dt (1 - gamma) C a, alpha_f F,
    #   f) and the balance for F+ 4: 10 eps S, S = |f| + |M a| + |F| + |P| (the largest of the
    #   run); the products (3 terms a row, plus the sum they enter), 4 eps times ||K|| (dt |v -
    #   v0| + dt^2 (1/2 - beta) |a|) (K d), dt (1 - gamma) ||C|| |a| and 2 ||M|| |a| (M a, M a+);
    #   the solve (backward stable): eps ||A0|| |a|;
    # * K v0, formed once in extended precision (eps_ld) and added every step: a ramp, N dt 4
    #   eps_ld ||K|| |v0| at the end; the start's C v0: 3 eps ||C|| |v0|, once.
    # None of these holds the angle. Today's form forms K qp + C vp: its balance is off by about
    # eps ||K|| |q| a step, |q| the rotation (123 rad at the end), 2^11 times the K v0 term's
    # eps_ld ||K|| |v0| t: it must exceed the bound.
    norm = lambda X: np.abs(X).sum(axis=1).max()                        # noqa: E731 (infinity norm)
    _, Phi = sla.eigh(K, M)
    G = norm(np.abs(Phi) @ np.abs(Phi).T)
    A0 = effective_matrix(M, C, K, DT, scheme)
    am, b, g = scheme.alpha_m, scheme.beta, scheme.gamma
    S = f_max + Ma_max + F_max + P_max
    per_step = (10 * S + 4 * norm(K) * DT * (dv_max + DT * (0.5 - b) * a_max)
                + (4 * DT * (1 - g) * norm(C) + 8 * norm(M) + norm(A0)) * a_max)
    once = 4 * (EPS_LD / EPS) * norm(K) * STEPS * DT * SPEED + 3 * norm(C) * SPEED
    bound = G * EPS * (STEPS * per_step + once) / (1 - am) / a_max
    assert err <= bound < err_today


def _dense_and_sparse(model, steps: int, dt: float, monkeypatch, outputs=None):
    """(dense run, sparse run) of ``steps`` steps of ``model``: on its dense matrices (the kept
    inverse and the predictor's map; compiled when numba is installed), then on the same
    matrices made sparse (the step of the module notes, a sparse factorisation)."""
    import assembly.dynamics.simulate as sim_module
    real = sim_module.model_matrices

    def dense(model):
        monkeypatch.setattr(run_model, "DENSE_INVERSE_MAX", 4000)
        try:
            return real(model)
        finally:
            monkeypatch.setattr(run_model, "DENSE_INVERSE_MAX", 1)

    def sparse(model):
        M, K, C, G = dense(model)
        return sp.csr_matrix(M), sp.csr_matrix(K), sp.csr_matrix(C), G

    runs = []
    for matrices, limit in ((dense, 4000), (sparse, 1)):
        monkeypatch.setattr(sim_module, "model_matrices", matrices)
        for module in (integrators, transient):
            monkeypatch.setattr(module, "DENSE_INVERSE_MAX", limit)
        runs.append(simulate(model, steps * dt, dt, outputs))
    d, s = runs
    assert s.info["solver"].startswith("sparse") and d.info["solver"] == "dense inverse"
    return d, s


def _agree(d, s) -> None:
    # the two round differently (the dense step's x0 through the predictor's map and the kept
    # inverse, the sparse step's through the carried products and the factorisation), so each
    # step's Newton iterations stop at another point within their tolerance: the runs agree to
    # NEWTON_RTOL (1e-10 on xi, the forces along the meshes), as the Python and compiled steps
    # do without numba's Newton solve (test_compiled_step.py)
    assert s.info["mean_iterations"] == d.info["mean_iterations"]
    assert [m["contact_losses"] for m in s.meshes] == [m["contact_losses"] for m in d.meshes]
    for name, ref in d.outputs.items():
        assert np.all(np.isfinite(s.outputs[name]))
        err = np.max(np.abs(s.outputs[name] - ref))
        assert err <= NEWTON_RTOL * np.max(np.abs(ref)), name


SCHEMES = [{"simulation.scheme": "newmark"}, {"simulation.scheme": "generalized-alpha", "simulation.rho_inf": 0.9}]


@pytest.mark.parametrize("scheme", SCHEMES, ids=["newmark", "generalized-alpha"])
def test_sparse_step_is_the_dense_step_on_the_5mw_drivetrain(scheme, sparse_path, monkeypatch):
    # nrel5mw_transient: 126 DOFs, 13 meshes with stiffness driven by the gear angle and 0.4 mm
    # backlash (rank 26), at rated operation
    model = assemble(load_scene("nrel5mw_transient").with_values(scheme))
    d, s = _dense_and_sparse(model, 300, DT, monkeypatch)
    assert s.info["rank"] == 26 and s.info["dofs"] == 126
    _agree(d, s)


@pytest.mark.parametrize("scheme", SCHEMES, ids=["newmark", "generalized-alpha"])
def test_sparse_step_is_the_dense_step_through_contact_losses(scheme, sparse_path, monkeypatch):
    # a spur pair (tests/support/gear_pair_scene.py) with two stiffness harmonics (30 %, 10 %)
    # and 0.1 mm backlash, started at 50 rad/s out of equilibrium under 100 N m: it rattles
    # across the gap (contact losses), where the dead zone's kinks are
    d = gear_pair(0.01, 0.05, 0.05, 0.15, 1.0e7, backlash=1.0e-4, amplitudes=(0.3, 0.1), roles=("rotor", None),
                  simulation={"speed": 50.0, "static_start": False, "loads": [{"body": "g1", "value": 100.0}]})
    model = assemble(scene_from_dict(d).with_values(scheme))
    d, s = _dense_and_sparse(model, STEPS_PAIR, DT, monkeypatch, ["force:m", "speed:g2"])
    assert sum(m["contact_losses"] for m in d.meshes) > 0
    _agree(d, s)
