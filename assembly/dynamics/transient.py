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
  the residual is halved (the kinks of backlash and of the brake's stick band).

So a step costs one solve with the constant factorisation, two products with the model's
matrices and O(n m) work. ``F+`` follows from the balance itself. Units: the model's (SI).
"""
from __future__ import annotations

import logging
import math
import time as _time
from dataclasses import dataclass, field
from typing import Callable, Optional

import numpy as np
import scipy.sparse as sp

from .budget import check_memory
from .history import STEP_BYTES, MemoryHistory, chunk_steps
from .integrators import DENSE_INVERSE_MAX, Scheme, Solver, check_step, effective_matrix, newmark

log = logging.getLogger(__name__)

#: Newton iterations (and halved steps) of one step before it is declared not converging.
MAX_ITERATIONS = 60
#: Relative tolerance of a step's Newton iterations (on xi, the forces along U).
NEWTON_RTOL = 1e-10


def check_history(dt: float, t_end: float, rows: int, n_dofs: int = 0, n_forces: int = 0,
                  streaming: bool = False) -> int:
    """The number of steps of ``dt`` to ``t_end`` (:func:`check_step`), once the run is known to
    fit the memory budget (:func:`assembly.dynamics.budget.check_memory`; SceneError at
    ``t_end`` otherwise): its history, ``rows`` recorded values a step (8 bytes each) plus
    :data:`STEP_BYTES`, and its state, ``8 n_dofs (n_forces + 12)`` bytes (``W`` and the
    step's vectors of a model of ``n_dofs`` coordinates with ``n_forces`` nonlinear forces).
    ``streaming``: the history goes elsewhere (a file, statistics) as the run goes, and only the
    integrator's row buffer (:func:`assembly.dynamics.history.chunk_steps` steps) is counted."""
    n_steps = check_step(dt, t_end)
    kept = min(n_steps + 1, chunk_steps(rows)) if streaming else n_steps + 1
    what = (f"the buffer of {kept} steps" if streaming else f"the history of {n_steps:.3g} steps (dt = {dt:g} s)")
    check_memory("t_end", t_end, kept * (8.0 * rows + STEP_BYTES) + 8.0 * n_dofs * (n_forces + 12),
                 f"{what} of {rows} recorded values and the time",
                 "shorten t_end, raise dt or record fewer outputs")
    return n_steps
#: Absolute floor of a step's residual, in units of eps x the size of the forces it is summed
#: from (:meth:`Nonlinear.force_scale`, plus xi): a column of a mesh's nu sums four rounded
#: terms (k e + c s delta' - k0 delta - c delta'), so it is known to about 4 eps x their size;
#: a residual below that is round-off, and no Newton step can lower it further.
ROUNDOFF = 4
EPS = float(np.finfo(float).eps)


class Nonlinear:
    """Forces along the columns of ``U`` (n x m): :meth:`forces` gives ``nu`` (m,) and its
    tangents ``d nu / d x`` and ``d nu / d x'`` (m x m, or (m,) for a diagonal one) at ``x =
    U' q``, ``x' = U' q'`` and time t; :meth:`commit` is told each accepted step (state,
    event counts)."""

    U: np.ndarray

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


def _matrix(A, n: int):
    if A is None:
        return sp.csr_matrix((n, n))
    if sp.issparse(A):
        return A.tocsr() if n > DENSE_INVERSE_MAX else A.toarray()
    return np.asarray(A, float)


def integrate(M, C, K, force: Callable[[float], np.ndarray], q0, v0, dt: float, t_end: float,
              scheme: Optional[Scheme] = None, nonlinear: Optional[Nonlinear] = None,
              observe: Optional[Callable] = None, progress: Optional[Callable] = None,
              dof_names: Optional[list] = None, history=None) -> Transient:
    """Integrate the model of the module notes from ``q0``, ``v0`` at t = 0 to ``t_end`` (s)
    with fixed step ``dt`` (s). ``force(t)``: the external load vector (n,).
    ``observe(q, v, a, nu)`` -> 1-D array recorded at every step (default ``q``);
    ``progress(step, n_steps, t)`` is called about 200 times a run. :class:`Diverged` (with
    the partial result) when a state is not finite or a step's Newton iterations do not
    converge; its message names the time and the coordinate (``dof_names``).

    ``history``: where the recorded rows go (:mod:`assembly.dynamics.history`: ``append`` of
    blocks of consecutive steps from a buffer of
    :func:`~assembly.dynamics.history.chunk_steps` steps, then ``close``, also when the run
    stops); default a :class:`~assembly.dynamics.history.MemoryHistory` whose arrays the
    result holds. With another history the result's ``time_s``, ``y`` and ``iterations`` are
    None and ``history`` is it; memory is then flat in ``t_end``."""
    s = scheme or newmark()
    q, v = np.array(q0, float), np.array(v0, float)
    n = len(q)
    nl = nonlinear or Stack([], n)
    U = np.asarray(nl.U, float)
    n_steps = check_history(dt, t_end, 0, n, U.shape[1])       # before any factorisation
    M, C, K = (_matrix(X, n) for X in (M, C, K))
    observe = observe or (lambda q, v, a, nu: q)
    am, af, b, g = s.alpha_m, s.alpha_f, s.beta, s.gamma
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
    check_history(dt, t_end, len(first), n, U.shape[1], streaming=history is not None)
    # the rows of the steps not yet handed to the history: steps start .. start + filled - 1 (in
    # memory, the history's own arrays, handed over once at the end: the rows are held once)
    if history is None:
        hist = MemoryHistory(n_steps + 1)
        Y, its = hist.buffers(len(first))
    else:
        hist = history
        Y = np.empty((min(n_steps + 1, chunk_steps(len(first))), len(first)))
        its = np.zeros(len(Y), dtype=np.int32)
    Y[0] = first
    filled, start, its_sum = 1, 0, 0
    report = max(1, n_steps // 200)

    def flush():
        nonlocal filled, start
        if filled:      # the times as np.arange(n_steps + 1) * dt gives them, step by step
            hist.append(np.arange(start, start + filled, dtype=float) * dt, Y[:filled], its[:filled])
            start, filled = start + filled, 0

    def result(info: dict, complete: bool) -> Transient:
        flush()
        hist.close(complete, info)
        if isinstance(hist, MemoryHistory):
            return Transient(hist.time_s, hist.y, hist.iterations, s, info, complete, hist)
        return Transient(None, None, None, s, info, complete, hist)

    def stop(i: int, why: str):
        raise Diverged(why, result({"stopped": why, "steps": i}, False))

    Ma = M @ a
    xi = xi_prev = dxi = np.zeros(U.shape[1])
    eye, ck, cc = np.eye(U.shape[1]), (1 - af) * b * dt * dt, (1 - af) * g * dt
    UT = np.ascontiguousarray(U.T)
    for i in range(n_steps):
        t_i1 = (i + 1) * dt                               # bit for bit np.arange(n_steps + 1) * dt
        t_a = i * dt + (1 - af) * dt
        f_a = np.asarray(force(t_a), float)
        qp = q + dt * v + (dt * dt * (0.5 - b)) * a
        vp = v + (dt * (1 - g)) * a
        x0 = lu.solve(am * Ma + (1 - af) * (K @ qp + C @ vp) + af * F - f_a)
        y0, xp, xdp = UT @ x0, UT @ qp, UT @ vp
        best = np.inf
        for it in range(1, MAX_ITERATIONS + 1):
            ua = S @ xi - y0                              # U' a+
            x, xd = xp + (b * dt * dt) * ua, xdp + (g * dt) * ua
            nu, dk, dc = nl.forces(t_i1, x, xd)
            r = xi + (1 - af) * nu
            if not len(r):
                break
            res = _norm(r)
            # converged at round-off: nu is a difference of forces (a mesh's contact force less the
            # linear model's k0 delta + c delta'), known only to eps x their size, so no iteration
            # lowers the residual below that floor; a damped mesh resting in contact has xi and
            # U' a+ themselves at round-off, where the relative tests below can never pass
            if res <= ROUNDOFF * EPS * (_norm(xi) + (1 - af) * _norm(nl.force_scale(nu))):
                break
            if res >= best and res > 1e-13 * (_norm(xi) + (1 - af) * _norm(nu)):
                # the full step did not lower the residual (a kink of a piecewise law, e.g. the
                # brake saturating on both sides of its stick band): halve it, from the last point
                dxi = 0.5 * dxi
                xi = xi + dxi
                continue
            best = res
            J = eye + _weighted(dk, dc, ck, cc) @ S
            dxi = np.linalg.solve(J, r)
            xi = xi - dxi
            # converged: xi (forces along U) or what it changes, U' a+, settled to NEWTON_RTOL
            # (x, nu: the last iterate's, that close)
            step = _norm(dxi)
            if step <= NEWTON_RTOL * _norm(xi) or step == 0.0 or _norm(S @ dxi) <= NEWTON_RTOL * _norm(ua):
                break
        else:
            stop(i, f"step to t = {t_i1:.6g} s: Newton's iterations did not converge in {MAX_ITERATIONS} "
                    f"(residual {np.linalg.norm(r):.3g}); try a smaller dt")
        xi, xi_prev = 2 * xi - xi_prev, xi               # next guess: linear extrapolation
        a_new = W @ xi_prev - x0
        q = qp + (b * dt * dt) * a_new
        v = vp + (g * dt) * a_new
        if not np.all(np.isfinite(q)):
            bad = int(np.argmax(~np.isfinite(q)))
            name = dof_names[bad] if dof_names is not None else f"coordinate {bad}"
            stop(i, f"the run diverged at t = {t_i1:.6g} s ({name} is not finite)")
        Ma_new = M @ a_new
        F = (f_a - am * Ma - (1 - am) * Ma_new - af * F) / (1 - af)
        a, Ma = a_new, Ma_new
        nl.commit(t_i1, x, xd)
        if filled == len(Y):
            flush()
        Y[filled] = observe(q, v, a, nu)
        its[filled] = it
        filled += 1
        its_sum += it
        if progress is not None and ((i + 1) % report == 0 or i + 1 == n_steps):
            progress(i + 1, n_steps, t_i1)
    wall = _time.perf_counter() - t0
    info = {"steps": n_steps, "dofs": n, "rank": U.shape[1], "solver": lu.kind, "factor_s": t_factor,
            "wall_s": wall, "steps_per_s": n_steps / max(wall - t_factor, 1e-12),
            "mean_iterations": its_sum / n_steps if n_steps else 0.0}
    log.info("%s: %d steps of %.3g s, %d DOFs, rank %d, %.0f steps/s, %.2f iterations/step", s.name, n_steps,
             dt, n, U.shape[1], info["steps_per_s"], info["mean_iterations"])
    return result(info, True)
