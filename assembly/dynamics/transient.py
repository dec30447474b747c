"""Implicit integration of ``M q'' + C q' + K q + U nu(U' q, U' q', t) = f(t)``: a linear
model plus nonlinear forces that act along a few fixed directions (the columns of ``U``).

Gear meshes (stiffness varying with the gear angle, backlash), the generator torque law and
the brake are such forces: each acts along one row of the model (a mesh's line of action, a
shaft's rotation), so the Jacobian of a step differs from the constant effective matrix
``A0`` of :mod:`assembly.dynamics.integrators` by a matrix ``U D U'`` of rank m = U's
columns. The step is solved without refactorising:

* the step's balance (generalized-alpha, forces averaged: ``(1 - alpha_m) M a+ + alpha_m M
  a + (1 - alpha_f) F+ + alpha_f F = f(t_{n+1-alpha_f})``, ``F = K q + C v + U nu``) with
  ``q+``, ``v+`` Newmark's updates of ``a+``, reads ``A0 a+ + b0 + (1 - alpha_f) U nu+ = 0``
  (``b0`` known from the last step);
* with ``x0 = A0^-1 b0`` (one solve with the constant factorisation) and ``W = A0^-1 U``
  (m solves, once per run), ``a+ = -x0 + W xi`` where ``xi`` solves the m-dimensional
  ``xi + (1 - alpha_f) nu(x(xi), x'(xi)) = 0``, ``x = U' q+ = U' qp + beta dt^2 U' a+``;
* Newton's iterations on ``xi`` use the tangents of ``nu`` and ``S = U' W``: the Woodbury
  form of the full Newton step, O(m^3) each, no solve with A0; a step that does not lower
  the residual is halved (the kinks of backlash and of the brake's stick band). Newton's
  matrix is factored once an iteration and kept: a later iterate of the same time step first
  tries a chord step on those factors (O(m^2)), which ends the step if it already meets the
  convergence tests (the step is then within NEWTON_RTOL of the full Newton step's answer);
  otherwise the matrix is formed and factored again. Converged Newton iterations take one
  factorisation, the second iterate's step only confirming convergence.

So a step costs one solve with the constant factorisation, products with the model's
matrices and O(n m) work. ``F+`` follows from the balance itself. Units: the model's (SI).

``b0`` holds ``K qp + C vp`` (``qp = q + dt v + dt^2 (1/2 - beta) a``, ``vp = v + dt (1 -
gamma) a``, Newmark's predictors). A spinning drivetrain carries its rigid rotation in q, which
K and C annihilate: formed as products, ``K qp`` is off by eps ``|K| |q|``, which grows with
the angle (about 1e3 rad after 10 s at a generator's speed); recovering ``a+`` from ``q+ - qp``
(a displacement form) cancels the same digits. A model without the predictor's map
(:func:`assembly.dynamics.stretches.predictor_map`: a sparse model, or a dense one above
PREDICTOR_MAX coordinates) forms it with no product on q:

* the ``F+`` the balance gives is ``K q+ + C v+ + U nu+`` with ``(1 - alpha_f) U nu+ = -U xi``
  exactly (``A0 a+ + b0 = U xi`` for ``a+ = -x0 + W xi``; this ``nu+`` is the last iterate's
  forces to Newton's tolerance, ``r = xi + (1 - alpha_f) nu``), so ``P = K q + C v = F + U xi /
  (1 - alpha_f)`` at the last step, from that step's ``F`` and ``xi``;
* ``K qp + C vp = P + dt K v0 + K d + dt (1 - gamma) C a`` with ``d = dt (v - v0) + dt^2 (1/2 -
  beta) a``: ``v0`` the run's starting velocity (its rigid speed), so ``d`` holds no rotation;
* ``K d + dt (1 - gamma) C a+`` and ``M a+`` (for ``F+``) are one product with ``[[K, dt (1 -
  gamma) C], [0, M]]`` on ``[d; a+]`` (a dense model: three products, no stacked copy);
* ``q`` and ``v`` are sums of their steps' increments, compensated (Kahan): the forces no
  longer follow from q, so q's own round-off would otherwise drift from them.

``P`` is carried this way (through the balance), so the round-off of every step's ``K qp + C
vp`` stays in it: that of ``K d`` (eps ``|K| dt |v - v0|``, no rotation), and that of ``K v0``,
the same every step, which adds up to ``t`` times it. ``K v0`` is therefore formed once in
extended precision (:func:`extended_product`): ``eps_ld |K| |v0| t``, ``2^-11`` of the product
form's eps ``|K| |q|`` where np.longdouble has 64 bits (x86), the same where it has none
(tests/dynamics/test_sparse_step.py).
"""
from __future__ import annotations

import logging
import math
import time as _time
from dataclasses import dataclass, field
from typing import Callable, Optional

import numpy as np
import scipy.sparse as sp

from ..errors import SceneError
from . import jit
from .budget import check_memory
from .history import STEP_BYTES, Gathered, MemoryHistory
from .integrators import DENSE_INVERSE_MAX, Scheme, Solver, check_step, effective_matrix, newmark
from .jit import pick
from .sampled import HeldForce, sample_steps
from .step_kernel import (
    DONE,
    EPS,
    MAX_ITERATIONS,
    NOT_CONVERGED,
    NOT_FINITE,
    ROUNDOFF,
    lu_factor,
    lu_factor_rows,
    lu_solve,
    lu_solve_rows,
    newton_matrix,
    newton_matrix_rows,
    predictor,
    settled,
)
from .stretches import (
    PREDICTOR_MAX,
    STRETCH_MAX,
    STRETCH_MIN,
    CompiledSteps,
    compiled_parts,
    load_block,
    plan,
    predictor_map,
)

log = logging.getLogger(__name__)



def check_history(dt: float, t_end: float, rows: int, n_dofs: int = 0, n_forces: int = 0,
                  streaming: bool = False) -> int:
    """The number of steps of ``dt`` to ``t_end`` (:func:`check_step`), once the run is known to
    fit the memory budget (:func:`assembly.dynamics.budget.check_memory`; SceneError at
    ``t_end`` otherwise): its history, ``rows`` recorded values a step (8 bytes each) plus
    :data:`~assembly.dynamics.history.STEP_BYTES`, and its state, ``8 n_dofs (n_forces + 12)``
    bytes (``W`` and the step's vectors of a model of ``n_dofs`` coordinates with ``n_forces``
    nonlinear forces), plus up to ``24 n_dofs^2`` for the predictor's map of a dense model
    (:func:`assembly.dynamics.stretches.predictor_map`, up to PREDICTOR_MAX coordinates).
    ``streaming``: the history goes elsewhere (a file, statistics) as the run goes, and only the
    integrator's row buffer (the longest stretch, :func:`assembly.dynamics.stretches.plan`) is
    counted."""
    n_steps = check_step(dt, t_end)
    kept = min(n_steps + 1, STRETCH_MAX + 1) if streaming else n_steps + 1
    what = f"the buffer of {kept} steps" if streaming else f"the history of {n_steps:.3g} steps (dt = {dt:g} s)"
    state = 8.0 * n_dofs * (n_forces + 12) + (24.0 * n_dofs * n_dofs if n_dofs <= PREDICTOR_MAX else 0.0)
    check_memory("t_end", t_end, kept * (8.0 * rows + STEP_BYTES) + state,
                 f"{what} of {rows} recorded values and the time",
                 "shorten t_end, raise dt or record fewer outputs")
    return n_steps

class Nonlinear:
    """Forces along the columns of ``U`` (n x m): :meth:`forces` gives ``nu`` (m,) and its
    tangents ``d nu / d x`` and ``d nu / d x'`` (m x m, or (m,) for a diagonal one) at ``x =
    U' q``, ``x' = U' q'`` and time t; :meth:`commit` is told each accepted step (state,
    event counts)."""

    U: np.ndarray
    #: the laws the compiled step knows these forces by (None: Python's step only)
    compiled = None

    def forces(self, t: float, x: np.ndarray, xd: np.ndarray):
        raise NotImplementedError

    def commit(self, t: float, x: np.ndarray, xd: np.ndarray) -> None:
        pass

    def force_scale(self, nu: np.ndarray) -> np.ndarray:
        """(m,) the size of the terms the last :meth:`forces` summed into ``nu`` (same units):
        ``nu`` is known to about eps times it. Default ``|nu|`` (a force computed directly)."""
        return np.abs(nu)


class Stack(Nonlinear):
    """Several :class:`Nonlinear` parts as one (their columns side by side)."""

    def __init__(self, parts: list, n: int):
        self.parts = [p for p in parts if p is not None and p.U.shape[1]]
        if len(self.parts) == 1:                   # one part: its own methods, no splitting
            self.forces, self.commit, self.force_scale = (self.parts[0].forces, self.parts[0].commit,
                                                          self.parts[0].force_scale)
        self.U = np.hstack([p.U for p in self.parts]) if self.parts else np.zeros((n, 0))
        self._cuts = np.cumsum([0] + [p.U.shape[1] for p in self.parts])

    def _split(self, x):
        return [x[a:b] for a, b in zip(self._cuts[:-1], self._cuts[1:])]

    def forces(self, t, x, xd):
        if not self.parts:
            z = np.zeros(0)
            return z, z, z
        out = [p.forces(t, a, b) for p, a, b in zip(self.parts, self._split(x), self._split(xd))]
        if len(out) == 1:
            return out[0]
        m = self.U.shape[1]
        Kt, Ct = np.zeros((m, m)), np.zeros((m, m))
        for (a, b), (_, k, c) in zip(zip(self._cuts[:-1], self._cuts[1:]), out):
            for T, blk in ((Kt, k), (Ct, c)):
                if blk.ndim == 1:
                    np.fill_diagonal(T[a:b, a:b], blk)
                else:
                    T[a:b, a:b] = blk
        return np.concatenate([o[0] for o in out]), Kt, Ct

    def commit(self, t, x, xd):
        for p, a, b in zip(self.parts, self._split(x), self._split(xd)):
            p.commit(t, a, b)

    def force_scale(self, nu):
        return np.concatenate([p.force_scale(a) for p, a in zip(self.parts, self._split(nu))] or [np.zeros(0)])


def tangent(T: np.ndarray) -> np.ndarray:
    """A tangent as a matrix (a 1-D one is its diagonal)."""
    return np.diag(T) if T.ndim == 1 else T


def _norm(v: np.ndarray) -> float:
    """Euclidean norm of a short vector (cheaper than np.linalg.norm's checks)."""
    return math.sqrt(v @ v)


def _weighted(dk: np.ndarray, dc: np.ndarray, ck: float, cc: float) -> np.ndarray:
    """``ck dk + cc dc`` as a matrix, either tangent given as a matrix or its diagonal."""
    if dk.ndim == 2:
        out = ck * dk
        if dc.ndim == 2:
            return out + cc * dc
        out[np.diag_indices_from(out)] += cc * dc
        return out
    return tangent(ck * dk) + cc * tangent(dc) if dc.ndim == 2 else np.diag(ck * dk + cc * dc)


@dataclass
class Transient:
    """A run: ``time_s`` (n_t,), the observed rows ``y`` (n_t, n_obs), Newton iterations
    per step ``iterations`` and run statistics ``info`` (solve times, steps per second).
    ``complete``: False for the partial result of a run that stopped (``info['stopped']``;
    ``info['steps']``: the steps done). ``history``: where the rows went (:func:`integrate`;
    ``time_s``, ``y`` and ``iterations`` None when it is not in memory)."""

    time_s: Optional[np.ndarray]
    y: Optional[np.ndarray]
    iterations: Optional[np.ndarray]
    scheme: Scheme
    info: dict = field(default_factory=dict)
    complete: bool = True
    history: object = None


class Diverged(FloatingPointError):
    """A run stopped: not finite, or Newton did not converge. ``partial`` holds what was
    computed (a :class:`Transient` with ``complete = False``)."""

    def __init__(self, message: str, partial: Transient):
        super().__init__(message)
        self.partial = partial


def extended_product(A, x: np.ndarray, rows: int = 512) -> np.ndarray:
    """``A x`` formed in extended precision (np.longdouble: 64-bit mantissa on x86, eps 1.1e-19;
    plain double where the platform has none), ``rows`` rows of ``A`` at a time, rounded once."""
    xl, out = x.astype(np.longdouble), np.empty(A.shape[0])
    for i in range(0, A.shape[0], rows):
        out[i:i + rows] = np.asarray(A[i:i + rows].astype(np.longdouble) @ xl).ravel()
    return out


def _matrix(A, n: int):
    if A is None:
        return sp.csr_matrix((n, n)) if n > DENSE_INVERSE_MAX else np.zeros((n, n))
    if sp.issparse(A):
        return A.tocsr() if n > DENSE_INVERSE_MAX else A.toarray()
    return np.asarray(A, float)


class PythonSteps:
    """Runs steps in Python, one at a time (module notes): the reference of the compiled step
    (:mod:`assembly.dynamics.step_kernel`), and the step of every other run (a sparse model,
    forces or rows the compiled step does not know, or numba absent). The state ``(q, v, a,
    Ma, F, xi, xi_prev)``; a dense model's predictor map ``Z`` and ``AinvL`` (the inverse times
    the load vectors): its ``x0`` as the compiled step forms it
    (:func:`assembly.dynamics.step_kernel.predictor`), else from ``K q + C v`` taken from the
    balance and one product a step (module notes; kept across the calls of :meth:`run`)."""

    def __init__(self, M, C, K, lu, W, S, U, scheme, dt, nl, observe, force, state, Z=None, AinvL=None):
        self.M, self.C, self.K, self.lu, self.W, self.S, self.Z, self.AinvL = M, C, K, lu, W, S, Z, AinvL
        self.UT = np.ascontiguousarray(U.T)
        self.s, self.dt, self.nl, self.observe, self.force = scheme, dt, nl, observe, force
        self.q, self.v, self.a, self.Ma, self.F, self.xi, self.xi_prev = state
        self.dxi = np.zeros(U.shape[1])
        if Z is None:
            # the products of the module notes: one with [[K, dt (1 - gamma) C], [0, M]] when
            # sparse, three of a dense model (a stacked dense copy: 4 n^2 more numbers); K q + C v
            # and K v0 formed once, at the start; q's and v's compensations
            e = dt * (1 - scheme.gamma)
            self.KM = sp.bmat([[K, e * C], [None, M]], format="csr") if sp.issparse(K) else None
            self.v0, self.Kv0 = self.v.copy(), extended_product(K, self.v)
            self.P, (self.Kd, _) = K @ self.q + C @ self.v, self._products((dt * dt * (0.5 - scheme.beta)) * self.a,
                                                                            self.a)
            self.cq, self.cv = np.zeros(len(self.q)), np.zeros(len(self.q))

    def _products(self, d: np.ndarray, a: np.ndarray):
        """``(K d + dt (1 - gamma) C a, M a)``: one product of a sparse model."""
        if self.KM is None:
            return self.K @ d + (self.dt * (1 - self.s.gamma)) * (self.C @ a), self.M @ a
        return np.split(self.KM @ np.concatenate([d, a]), 2)

    def now(self):
        """(q, v) of the last step."""
        return self.q, self.v

    def run(self, t: np.ndarray, Y: np.ndarray, its: np.ndarray):
        """The ``len(t) - 1`` steps from ``t[0]`` (rows into ``Y``, counts into ``its``):
        (steps done, why it stopped or DONE, the residual or the coordinate)."""
        M, lu, W, S, UT, nl = self.M, self.lu, self.W, self.S, self.UT, self.nl
        am, af, b, g, dt = self.s.alpha_m, self.s.alpha_f, self.s.beta, self.s.gamma, self.dt
        q, v, a, Ma, F, xi, xi_prev, dxi = self.q, self.v, self.a, self.Ma, self.F, self.xi, self.xi_prev, self.dxi
        Z, predict = self.Z, pick(predictor)
        if Z is None:
            Kd, P, U, cq, cv, v0, Kv0 = self.Kd, self.P, self.UT.T, self.cq, self.cv, self.v0, self.Kv0
        ck, cc = (1 - af) * b * dt * dt, (1 - af) * g * dt
        factor, back, jacobian = ((lu_factor, lu_solve, newton_matrix) if jit.COMPILED
                                  else (lu_factor_rows, lu_solve_rows, newton_matrix_rows))
        converged = pick(settled)
        for k in range(len(t) - 1):
            t_a = t[k] + (1 - af) * dt
            qp = q + dt * v + (dt * dt * (0.5 - b)) * a
            vp = v + (dt * (1 - g)) * a
            if Z is None:
                f_a = np.asarray(self.force(t_a), float)
                x0 = lu.solve(am * Ma + (1 - af) * (P + dt * Kv0 + Kd) + af * F - f_a)     # K qp + C vp
            else:                                             # the compiled step's arithmetic
                LV, LH, direct = load_block(self.force, np.array([t_a]))
                h = LH[0]
                x0 = predict(Z, qp, vp, a, self.AinvL, h)
                if af != 0.0:
                    f_a = h.copy() if direct else (LV @ h if len(h) else np.zeros(len(q)))
                    x0 = x0 + af * lu.solve(F)
            y0, xp, xdp = UT @ x0, UT @ qp, UT @ vp
            best = np.inf
            factors = None                                    # Newton's matrix of this step, factored
            for it in range(1, MAX_ITERATIONS + 1):
                ua = S @ xi - y0                              # U' a+
                x, xd = xp + (b * dt * dt) * ua, xdp + (g * dt) * ua
                nu, dk, dc = nl.forces(t[k + 1], x, xd)
                r = xi + (1 - af) * nu
                if not len(r):
                    break
                res = _norm(r)
                # converged at round-off: nu is a difference of forces (a mesh's contact force less
                # the linear model's k0 delta + c delta'), known only to eps x their size, so no
                # iteration lowers the residual below that floor; a damped mesh resting in contact
                # has xi and U' a+ themselves at round-off, where the relative tests below can
                # never pass
                if res <= ROUNDOFF * EPS * (_norm(xi) + (1 - af) * _norm(nl.force_scale(nu))):
                    break
                if res >= best and res > 1e-13 * (_norm(xi) + (1 - af) * _norm(nu)):
                    # the full step did not lower the residual (a kink of a piecewise law, e.g.
                    # the brake saturating on both sides of its stick band): halve it, from the
                    # last point
                    dxi = 0.5 * dxi
                    xi = xi + dxi
                    continue
                best = res
                if factors is not None:                       # a chord step on this step's last factors
                    dxi = back(*factors, r)
                    if converged(dxi, xi - dxi, S, ua):
                        xi = xi - dxi
                        break
                factors = factor(jacobian(_weighted(dk, dc, ck, cc), S))
                dxi = back(*factors, r)
                xi = xi - dxi
                # converged: xi (forces along U) or what it changes, U' a+, settled to
                # NEWTON_RTOL (x, nu: the last iterate's, that close)
                if converged(dxi, xi, S, ua):
                    break
            else:
                return k, NOT_CONVERGED, float(np.linalg.norm(r))
            its[k] = it
            xi, xi_prev = 2 * xi - xi_prev, xi               # next guess: linear extrapolation
            a_new = W @ xi_prev - x0
            if Z is None:                                     # compensated sums (module notes)
                dq = (dt * v + (dt * dt * (0.5 - b)) * a + (b * dt * dt) * a_new) - cq
                dv = (dt * (1 - g)) * a + (g * dt) * a_new - cv
                q_new, v_new = q + dq, v + dv
                cq, cv = (q_new - q) - dq, (v_new - v) - dv
                q, v = q_new, v_new
            else:
                q = qp + (b * dt * dt) * a_new
                v = vp + (g * dt) * a_new
            if not np.all(np.isfinite(q)):
                return k, NOT_FINITE, float(np.argmax(~np.isfinite(q)))
            if Z is None:
                Kd, Ma_new = self._products(dt * (v - v0) + (dt * dt * (0.5 - b)) * a_new, a_new)
                F = (f_a - am * Ma - (1 - am) * Ma_new - af * F) / (1 - af)
                P = F + U @ (xi_prev / (1 - af))             # K q+ + C v+ = F+ - U nu+ (module notes)
                Ma = Ma_new
                self.Kd, self.P, self.cq, self.cv = Kd, P, cq, cv
            elif af != 0.0:
                Ma_new = M @ a_new
                F = (f_a - am * Ma - (1 - am) * Ma_new - af * F) / (1 - af)
                Ma = Ma_new
            a = a_new
            nl.commit(t[k + 1], x, xd)
            Y[k] = self.observe(q, v, a, nu)
            self.q, self.v, self.a, self.Ma, self.F, self.xi, self.xi_prev, self.dxi = q, v, a, Ma, F, xi, xi_prev, dxi
        return len(t) - 1, DONE, 0.0


def integrate(M, C, K, force: Callable[[float], np.ndarray], q0, v0, dt: float, t_end: float,
              scheme: Optional[Scheme] = None, nonlinear: Optional[Nonlinear] = None,
              observe: Optional[Callable] = None, progress: Optional[Callable] = None,
              dof_names: Optional[list] = None, history=None, sampled=None) -> Transient:
    """Integrate the model of the module notes from ``q0``, ``v0`` at t = 0 to ``t_end`` (s)
    with fixed step ``dt`` (s). ``force(t)``: the external load vector (n,) (a force with
    load ``vectors`` and ``histories``, :class:`assembly.dynamics.run_loads.RunLoads`, is
    evaluated a stretch at a time). ``observe(q, v, a, nu)`` -> 1-D array recorded at every
    step (default ``q``; rows with ``held``, :class:`assembly.dynamics.observe_rows.Rows`: it
    fills each block of rows made, the first row's too); ``progress(step, n_steps, t)`` is
    called about 200 times a run.
    ``history``: where the rows go (:mod:`assembly.dynamics.history`: ``append`` a block,
    ``close``; default :class:`~assembly.dynamics.history.MemoryHistory`). ``sampled``: loads
    a law sets from the state at its own sample times and holds in between
    (:class:`assembly.dynamics.sampled.Sampled`; its period a whole number of steps), called
    between stretches.

    The steps run in stretches (:mod:`assembly.dynamics.stretches`): compiled
    (:mod:`assembly.dynamics.step_kernel`) when numba is installed and switched on
    (:data:`assembly.dynamics.jit.ENABLED`), the model dense (the kept inverse), the nonlinear
    forces the meshes, shaft torques and the rotor's aerodynamics and ``observe`` rows
    (:class:`assembly.dynamics.observe_rows.Rows`); else by :class:`PythonSteps`, the same
    numbers to round-off. :class:`Diverged` (with the partial result) when a state is not
    finite or a step's Newton iterations do not converge; its message names the time and the
    coordinate (``dof_names``)."""
    s = scheme or newmark()
    q, v = np.array(q0, float), np.array(v0, float)
    n = len(q)
    nl = nonlinear or Stack([], n)
    U = np.asarray(nl.U, float)
    n_steps = check_history(dt, t_end, 0, n, U.shape[1])       # before any factorisation
    M, C, K = (_matrix(X, n) for X in (M, C, K))
    observe = observe or (lambda q, v, a, nu: q)
    every = 0
    if sampled is not None:                                        # the law's first sample, at t = 0
        every = sample_steps(sampled.period, dt)
        force = HeldForce(force, sampled, n)
        if not force.sample(0.0, q, v):
            raise SceneError("sampled.law", force.u.tolist(), "is not finite at t = 0 s")
    t0 = _time.perf_counter()
    lu = Solver(effective_matrix(M, C, K, dt, s))
    W = lu.solve(U) if U.shape[1] else np.zeros((n, 0))
    S = U.T @ W
    x, xd = U.T @ q, U.T @ v
    nu, _, _ = nl.forces(0.0, x, xd)
    nl.commit(0.0, x, xd)
    F = K @ q + C @ v + U @ nu
    a = Solver(M).solve(np.asarray(force(0.0), float) - F)      # the starting acceleration
    t_factor = _time.perf_counter() - t0                           # both factorisations
    first = observe(q, v, a, nu)
    held = getattr(observe, "held", None)                          # values held over a stretch
    if held is not None:
        first = np.asarray(first, float)
        held(first[None, :])
    check_history(dt, t_end, len(first), n, U.shape[1], streaming=history is not None)
    history = history if history is not None else MemoryHistory(n_steps + 1)
    history.append(np.zeros(1), np.asarray(first, float)[None, :], np.zeros(1, np.int32))
    report = max(1, n_steps // 200)
    state = (q, v, a, M @ a, F, np.zeros(U.shape[1]), np.zeros(U.shape[1]))
    Z = AinvL = None
    if lu.kind == "dense inverse" and n <= PREDICTOR_MAX:
        Z = predictor_map(lu.inverse, M, C, K, dt, s)
        LV, _, direct = load_block(force, np.zeros(1))
        AinvL = lu.inverse if direct else lu.inverse @ LV
        t_factor = _time.perf_counter() - t0                       # and the predictor's map
    parts = compiled_parts(nl, observe, Z)
    steps = (CompiledSteps(parts, M, lu.inverse, Z, AinvL, W, S, U, s, dt, observe, force, state)
             if parts is not None else PythonSteps(M, C, K, lu, W, S, U, s, dt, nl, observe, force, state, Z, AinvL))
    stretches = plan(n_steps, report, every, parts is not None)
    # a history in memory lends its own rows for the steps to be written into (held once); any
    # other gets them in blocks of the longest stretch, or, where sample times cut the stretches
    # below STRETCH_MIN steps (a controller sampled every step: a file write and flush a step),
    # gathered into blocks of up to STRETCH_MAX steps, a compiled stretch's
    gathered = None
    if isinstance(history, MemoryHistory) and history.capacity:
        sink = history
    else:
        longest = max(c for _, c in stretches)
        size = longest if longest >= STRETCH_MIN else min(n_steps, STRETCH_MAX)
        sink = gathered = Gathered(history, size, len(first))
    its_sum = 0
    try:
        for i0, count in stretches:
            t = np.arange(i0, i0 + count + 1, dtype=float)
            t *= dt                                                # the steps' times, i dt
            if every and i0 and i0 % every == 0 and not force.sample(t[0], *steps.now()):
                _stop(sink, history, s, f"the sampled load at t = {t[0]:.6g} s is not finite "
                                        f"({force.u.tolist()})", parts is not None, i0)
            _, Y, its = sink.reserve(count)
            done, why, value = steps.run(t, Y, its)
            if done and held is not None:
                held(Y[:done])
            if done:
                sink.append(t[1:done + 1], Y[:done], its[:done])
                its_sum += int(its[:done].sum())
            if progress is not None:
                for j in range(i0 + 1, i0 + done + 1):
                    if j % report == 0 or j == n_steps:
                        progress(j, n_steps, t[j - i0])
            if why == NOT_CONVERGED:
                _stop(sink, history, s, f"step to t = {t[done + 1]:.6g} s: Newton's iterations did not converge in "
                                        f"{MAX_ITERATIONS} (residual {value:.3g}); try a smaller dt",
                      parts is not None, i0 + done)
            if why != DONE:
                bad = int(value)
                name = dof_names[bad] if dof_names is not None else f"coordinate {bad}"
                _stop(sink, history, s, f"the run diverged at t = {t[done + 1]:.6g} s ({name} is not finite)",
                      parts is not None, i0 + done)
    except BaseException:
        if gathered is not None:          # the steps done so far to the history (a refusal, an interrupt)
            gathered.flush()
        raise
    wall = _time.perf_counter() - t0
    info = {"steps": n_steps, "dofs": n, "rank": U.shape[1], "solver": lu.kind, "factor_s": t_factor,
            "wall_s": wall, "steps_per_s": n_steps / max(wall - t_factor, 1e-12),
            "compiled": parts is not None, "mean_iterations": its_sum / n_steps if n_steps else 0.0}
    sink.close(True, info)
    log.info("%s: %d steps of %.3g s, %d DOFs, rank %d, %.0f steps/s, %.2f iterations/step%s", s.name, n_steps,
             dt, n, U.shape[1], info["steps_per_s"], info["mean_iterations"], " (compiled)" if parts else "")
    return _result(history, s, info, True)


def _result(history, scheme: Scheme, info: dict, complete: bool) -> Transient:
    """The run's :class:`Transient`: the arrays of a history in memory, else None (the rows
    went where ``history`` put them)."""
    if isinstance(history, MemoryHistory):
        return Transient(history.time_s, history.y, history.iterations, scheme, info, complete, history)
    return Transient(None, None, None, scheme, info, complete, history)


def _stop(sink, history, scheme: Scheme, why: str, compiled: bool, steps: int):
    """Close the history as incomplete (``steps`` done; through ``sink``, the history or what
    gathers its blocks) and raise :class:`Diverged` with what it holds."""
    info = {"stopped": why, "steps": steps, "compiled": compiled}
    sink.close(False, info)
    raise Diverged(why, _result(history, scheme, info, False))
