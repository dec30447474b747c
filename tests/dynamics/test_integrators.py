"""Generalized-alpha integrators (assembly.dynamics.integrators) against their theory.

* Trapezoidal rule (Newmark beta 1/4, gamma 1/2) on q'' + w^2 q = 0: one step maps q0 (v0 = 0)
  to q0 (1 - W^2/4) / (1 + W^2/4) = q0 cos(theta), tan(theta/2) = W/2, W = w dt, and by
  symmetry q_n = q0 cos(n theta) exactly; the amplification eigenvalues lie on the unit circle
  at angle theta = 2 atan(W/2), so T_num / T = W / theta = W / (2 atan(W/2)) (Hughes, The
  Finite Element Method, ch. 9). A decoupled (modal) system follows it mode by mode.
* Its energy (1/2 v'Mv + 1/2 q'Kq) is conserved exactly on a linear undamped model: with
  q+ - q = dt (v + v+)/2 and M (v+ - v) = -dt K (q + q+)/2, the change in energy is
  (v+ + v)' M (v+ - v)/2 + (q+ + q)' K (q+ - q)/2 = 0.
* Spectral radius at W -> infinity: HHT (1 - alpha)/(1 + alpha) (Hilber et al. 1977),
  generalized-alpha rho_inf (Chung & Hulbert 1993).
* Second order: the error at a fixed time falls as dt^2 (Chung & Hulbert 1993).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as sla

from assembly import SceneError
from assembly.dynamics.integrators import amplification, generalized_alpha, hht, integrate_linear, newmark


@pytest.mark.parametrize("W", [0.01, 0.1, 0.5, 1.0, 2.0, 5.0])
def test_trapezoidal_period_elongation(W):
    lam = np.linalg.eigvals(amplification(1.0, W, newmark()))
    lam = lam[np.abs(lam) > 1e-8]                                       # the third eigenvalue is 0
    theta = np.max(np.abs(np.angle(lam)))
    assert len(lam) == 2 and np.allclose(np.abs(lam), 1.0, atol=1e-13)  # no numerical damping
    # the eigen-angle of a 3x3 amplification matrix carries round-off ~eps / W relative (its
    # eigenvalue pair closes on 1 as W -> 0)
    assert W / theta == pytest.approx(W / (2 * math.atan(W / 2)), rel=max(1e-12, 1e-13 / W))


@pytest.mark.parametrize("scheme,rho", [(hht(0.1), 0.9 / 1.1), (hht(1 / 3), 0.5), (generalized_alpha(0.8), 0.8),
                                        (generalized_alpha(0.0), 0.0), (generalized_alpha(1.0), 1.0)])
def test_spectral_radius_at_infinity(scheme, rho):
    # the limit is approached as W^-1/2 where the schemes put a double root (HHT at alpha = 1/3,
    # generalized-alpha by design): W = 1e12 is within ~1e-6 of it
    r = np.max(np.abs(np.linalg.eigvals(amplification(1.0, 1e12, scheme))))
    assert r == pytest.approx(rho, abs=1e-5)


def _chain(n=4, k=1.0e4):
    """n unit masses in a chain, the first grounded: K tridiagonal, M = I."""
    K = 2 * k * np.eye(n) - k * (np.eye(n, k=1) + np.eye(n, k=-1))
    K[-1, -1] = k
    return np.eye(n), K


def test_undamped_chain_is_modal_superposition_at_the_numerical_frequencies():
    M, K = _chain()
    lam, Phi = sla.eigh(K, M)
    q0 = Phi @ np.array([1.0, -0.5, 0.25, 0.1])
    dt = 2e-3
    h = integrate_linear(M, None, K, lambda t: np.zeros(4), q0, np.zeros(4), dt, 0.5)
    theta = 2 * np.arctan(np.sqrt(lam) * dt / 2)
    n = np.arange(len(h.time_s))[:, None]
    exact = (np.cos(n * theta[None, :]) * (Phi.T @ M @ q0)[None, :]) @ Phi.T
    assert np.max(np.abs(h.q - exact)) <= 1e-10 * np.max(np.abs(q0))


def test_trapezoidal_rule_conserves_energy():
    M, K = _chain()
    rng = np.random.default_rng(3)
    h = integrate_linear(M, None, K, lambda t: np.zeros(4), rng.normal(size=4), rng.normal(size=4), 1e-2, 2.0)
    E = 0.5 * np.einsum("ti,ij,tj->t", h.v, M, h.v) + 0.5 * np.einsum("ti,ij,tj->t", h.q, K, h.q)
    assert np.max(np.abs(E / E[0] - 1)) <= 1e-12
    # the dissipative schemes lose energy (the high mode, W = 1.9 here, most)
    g = integrate_linear(M, None, K, lambda t: np.zeros(4), h.q[0], h.v[0], 1e-2, 2.0, generalized_alpha(0.5))
    Eg = 0.5 * np.einsum("ti,ij,tj->t", g.v, M, g.v) + 0.5 * np.einsum("ti,ij,tj->t", g.q, K, g.q)
    assert Eg[-1] < 0.99 * Eg[0]


@pytest.mark.parametrize("scheme", [newmark(), hht(0.1), generalized_alpha(0.6)], ids=lambda s: s.name)
def test_second_order_convergence(scheme):
    # damped oscillator under F cos(Omega t) from rest: exact solution by the closed form below
    w, z, Om, F = 10.0, 0.05, 7.0, 1.0
    M, C, K = np.eye(1), np.array([[2 * z * w]]), np.array([[w * w]])
    H = F / (w * w - Om * Om + 2j * z * w * Om)                          # steady-state amplitude
    wd = w * math.sqrt(1 - z * z)
    # q = Re(H e^{i Om t}) + e^{-z w t} (A cos wd t + B sin wd t); q(0) = 0: A = -Re H;
    # q'(0) = -Om Im H - z w A + wd B = 0
    A = -H.real
    B = (Om * H.imag + z * w * A) / wd

    def exact(t):
        return (H * np.exp(1j * Om * t)).real + np.exp(-z * w * t) * (A * np.cos(wd * t) + B * np.sin(wd * t))

    T = 2.0
    errs = []
    dts = [T / 400, T / 800, T / 1600, T / 3200]
    for dt in dts:
        h = integrate_linear(M, C, K, lambda t: np.array([F * math.cos(Om * t)]), [0.0], [0.0], dt, T, scheme)
        errs.append(abs(h.q[-1, 0] - exact(h.time_s[-1])))
    assert abs(exact(0.0)) < 1e-15 and abs((exact(1e-7) - exact(-1e-7)) / 2e-7) < 1e-6   # from rest
    slope = np.polyfit(np.log(dts), np.log(errs), 1)[0]
    assert slope == pytest.approx(2.0, abs=0.1)


@pytest.mark.parametrize("dt,t_end,named", [(0.0, 1.0, "dt"), (-1e-3, 1.0, "dt"), (math.nan, 1.0, "dt"),
                                            (1e-3, 0.0, "t_end"), (1e-3, -2.0, "t_end"), (1e-3, math.inf, "t_end")])
def test_bad_step_or_end_names_it(dt, t_end, named):
    M, K = _chain()
    with pytest.raises(SceneError) as err:
        integrate_linear(M, None, K, lambda t: np.zeros(4), np.zeros(4), np.zeros(4), dt, t_end)
    assert err.value.path == named


@pytest.mark.parametrize("make,bad", [(hht, -0.1), (hht, 0.5), (generalized_alpha, 1.5), (generalized_alpha, -0.2)])
def test_bad_scheme_parameter_names_it(make, bad):
    with pytest.raises(SceneError) as err:
        make(bad)
    assert err.value.path in ("alpha", "rho_inf")
