"""Implicit time integration of ``M q'' + C q' + K q = f(t)``: the generalized-alpha family.

One scheme (Chung & Hulbert 1993, J. Appl. Mech. 60, 371-375) holds the three the product
offers, by its four parameters:

* Newmark average acceleration (trapezoidal rule): ``alpha_m = alpha_f = 0``, ``beta = 1/4``,
  ``gamma = 1/2``: unconditionally stable, no numerical damping, energy of a linear undamped
  model conserved exactly; period elongation ``T_num / T = W / (2 atan(W / 2))``, ``W = omega dt``.
* HHT-alpha (Hilber, Hughes & Taylor 1977): ``alpha_m = 0``, ``alpha_f = alpha`` in
  [0, 1/3], ``gamma = 1/2 + alpha``, ``beta = (1 + alpha)^2 / 4``; spectral radius at
  ``omega dt -> inf`` ``(1 - alpha) / (1 + alpha)``.
* generalized-alpha with spectral radius ``rho_inf`` in [0, 1]: ``alpha_m = (2 rho - 1) /
  (rho + 1)``, ``alpha_f = rho / (rho + 1)``, ``gamma = 1/2 - alpha_m + alpha_f``, ``beta =
  (1 - alpha_m + alpha_f)^2 / 4``: high-frequency dissipation ``rho_inf``, second order.

Each step: Newmark's updates ``q+ = q + dt v + dt^2 ((1/2 - beta) a + beta a+)``, ``v+ = v
+ dt ((1 - gamma) a + gamma a+)`` and the balance at the intermediate instants ``M
a_{n+1-alpha_m} + C v_{n+1-alpha_f} + K q_{n+1-alpha_f} = f(t_{n+1-alpha_f})`` (``x_{n+1-a}
= (1 - a) x_{n+1} + a x_n``), solved for ``a+`` with the effective matrix ``(1 - alpha_m) M
+ (1 - alpha_f) (gamma dt C + beta dt^2 K)``, factorised once per run. Units: SI (s, and
the model's m, rad, N, N m).
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import SceneError
from .budget import check_memory

log = logging.getLogger(__name__)

#: Dense models up to this size keep the inverse of the effective matrix (one product a solve).
DENSE_INVERSE_MAX = 4000


@dataclass(frozen=True)
class Scheme:
    """Parameters of a generalized-alpha scheme (module notes); build with
    :func:`newmark`, :func:`hht` or :func:`generalized_alpha`."""

    name: str
    alpha_m: float
    alpha_f: float
    beta: float
    gamma: float


def newmark() -> Scheme:
    """Newmark average acceleration (trapezoidal rule): beta 1/4, gamma 1/2."""
    return Scheme("newmark", 0.0, 0.0, 0.25, 0.5)


def hht(alpha: float) -> Scheme:
    """HHT-alpha, ``alpha`` in [0, 1/3] (0: Newmark average acceleration)."""
    if not (0.0 <= alpha <= 1.0 / 3.0):
        raise SceneError("alpha", alpha, "HHT-alpha needs 0 <= alpha <= 1/3")
    return Scheme("hht", 0.0, alpha, (1 + alpha) ** 2 / 4, 0.5 + alpha)


def generalized_alpha(rho_inf: float) -> Scheme:
    """Chung & Hulbert's generalized-alpha with spectral radius ``rho_inf`` in [0, 1] at
    ``omega dt -> infinity`` (1: no numerical damping, the trapezoidal rule)."""
    if not (0.0 <= rho_inf <= 1.0):
        raise SceneError("rho_inf", rho_inf, "the spectral radius must lie in [0, 1]")
    am, af = (2 * rho_inf - 1) / (rho_inf + 1), rho_inf / (rho_inf + 1)
    return Scheme("generalized-alpha", am, af, (1 - am + af) ** 2 / 4, 0.5 - am + af)


@dataclass
class TimeHistory:
    """Response at ``time_s`` (n_t,): coordinates ``q``, velocities ``v``, accelerations
    ``a``, each (n_t, n_dof) in the model's units per s^0, s^-1, s^-2."""

    time_s: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    scheme: Scheme


def check_step(dt: float, t_end: float) -> int:
    """Number of steps of ``dt`` to ``t_end`` (s); SceneError naming the argument on dt <= 0,
    t_end <= 0 or non-finite values."""
    if not (math.isfinite(dt) and dt > 0):
        raise SceneError("dt", dt, "the time step must be a finite time > 0 s")
    if not (math.isfinite(t_end) and t_end > 0):
        raise SceneError("t_end", t_end, "the end time must be a finite time > 0 s")
    if not math.isfinite(t_end / dt):
        raise SceneError("t_end", t_end, f"t_end / dt = {t_end / dt} steps of dt = {dt:g} s: not a number of "
                                         "steps a run can take")
    return max(1, int(math.ceil(t_end / dt - 1e-9)))


class Solver:
    """``A^-1`` applied to vectors and blocks: a kept dense inverse, a dense LU, or for a large
    sparse matrix a sparse Cholesky factorisation (:func:`cms.linsolve.factor`: CHOLMOD when
    installed; the effective matrix of a model with symmetric M, C, K is positive definite),
    else a sparse LU."""

    def __init__(self, A):
        if sp.issparse(A) and A.shape[0] > DENSE_INVERSE_MAX:
            from cms.errors import InteriorMechanismError
            from cms.linsolve import factor
            try:
                f = factor(sp.csc_matrix(A))
                self._lu, self.kind = f, f"sparse Cholesky ({f.backend})" if f.backend == "cholmod" else "sparse LU"
            except InteriorMechanismError:
                self._lu, self.kind = spla.splu(sp.csc_matrix(A)), "sparse LU"
        else:
            A = A.toarray() if sp.issparse(A) else np.asarray(A, float)
            if A.shape[0] <= DENSE_INVERSE_MAX:
                self._inv, self.kind = sla.inv(A), "dense inverse"
            else:
                self._lu, self.kind = sla.lu_factor(A), "dense LU"

    @property
    def inverse(self) -> np.ndarray | None:
        """The kept dense inverse (kind "dense inverse"), else None."""
        return getattr(self, "_inv", None)

    def solve(self, b: np.ndarray) -> np.ndarray:
        if self.kind == "dense inverse":
            return self._inv @ b
        if self.kind.startswith("sparse"):
            return self._lu.solve(b)
        return sla.lu_solve(self._lu, b)


def integrate_linear(M, C, K, force: Callable[[float], np.ndarray], q0, v0, dt: float, t_end: float,
                     scheme: Scheme | None = None) -> TimeHistory:
    """Integrate ``M q'' + C q' + K q = force(t)`` from ``q0``, ``v0`` at t = 0 to ``t_end``
    with fixed step ``dt`` (s) by ``scheme`` (default :func:`newmark`). ``M``, ``C``, ``K``
    dense or sparse (``C`` may be None); the initial acceleration from ``M a0 = f(0) - C v0
    - K q0``. The effective matrix is factorised once; each step is one solve."""
    s = scheme or newmark()
    n_steps = check_step(dt, t_end)
    q = np.array(q0, float)
    v = np.array(v0, float)
    n = len(q)
    check_memory("t_end", t_end, 24.0 * (n_steps + 1) * (n + 1), f"the history of {n_steps:.3g} steps (dt = "
                 f"{dt:g} s) of {n} coordinates, velocities and accelerations", "shorten t_end or raise dt")
    C = sp.csr_matrix((n, n)) if C is None else C
    a = Solver(M).solve(np.asarray(force(0.0), float) - C @ v - K @ q)
    lu = Solver(effective_matrix(M, C, K, dt, s))
    t = np.arange(n_steps + 1) * dt
    Q, V, Acc = (np.empty((n_steps + 1, n)) for _ in range(3))
    Q[0], V[0], Acc[0] = q, v, a
    for i in range(n_steps):
        q, v, a = _step(M, C, K, np.asarray(force(t[i] + (1 - s.alpha_f) * dt), float), q, v, a, dt, s, lu.solve)
        if not np.all(np.isfinite(q)):
            raise FloatingPointError(f"integration diverged at t = {t[i + 1]:.6g} s (coordinate "
                                     f"{int(np.argmax(~np.isfinite(q)))})")
        Q[i + 1], V[i + 1], Acc[i + 1] = q, v, a
    log.info("%s: %d steps of %.3g s, %d DOFs", s.name, n_steps, dt, n)
    return TimeHistory(t, Q, V, Acc, s)


def effective_matrix(M, C, K, dt: float, s: Scheme):
    """The matrix that takes ``a+`` to the step's balance: ``(1 - alpha_m) M + (1 - alpha_f)
    (gamma dt C + beta dt^2 K)``."""
    return (1 - s.alpha_m) * M + (1 - s.alpha_f) * (s.gamma * dt * C + s.beta * dt * dt * K)


def _step(M, C, K, f, q, v, a, dt: float, s: Scheme, solve):
    """One step from ``(q, v, a)`` under the load ``f`` at ``t_{n+1-alpha_f}`` (module notes);
    ``solve`` applies the inverse of the effective matrix. Returns ``(q+, v+, a+)``."""
    am, af, b, g = s.alpha_m, s.alpha_f, s.beta, s.gamma
    qp = q + dt * v + dt * dt * (0.5 - b) * a                            # predictors (a+ = 0)
    vp = v + dt * (1 - g) * a
    a_new = solve(f - am * (M @ a) - C @ ((1 - af) * vp + af * v) - K @ ((1 - af) * qp + af * q))
    return qp + b * dt * dt * a_new, vp + g * dt * a_new, a_new


def amplification(omega: float, dt: float, scheme: Scheme, zeta: float = 0.0) -> np.ndarray:
    """The 3x3 matrix taking ``(q, dt v, dt^2 a)`` of a single mode (natural frequency
    ``omega`` rad/s, damping ratio ``zeta``) over one step: its eigenvalues give the
    scheme's spectral radius and numerical frequency (``angle / dt``)."""
    M, C, K = np.eye(1), np.array([[2 * zeta * omega]]), np.array([[omega ** 2]])
    A = effective_matrix(M, C, K, dt, scheme)
    out = np.empty((3, 3))
    for j, (q, v, a) in enumerate(np.eye(3) / np.array([1.0, dt, dt * dt])[None, :]):
        q1, v1, a1 = _step(M, C, K, np.zeros(1), np.array([q]), np.array([v]), np.array([a]), dt, scheme,
                           lambda rhs: np.linalg.solve(A, rhs))
        out[:, j] = [q1[0], dt * v1[0], dt * dt * a1[0]]
    return out
