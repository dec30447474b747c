"""The steps of :func:`assembly.dynamics.transient.integrate` on a dense reduced model, as one
function on arrays that numba compiles (:mod:`assembly.dynamics.jit`): a stretch of steps
between two visits of Python, whose loads, generator torque table and brake torque Python
evaluated before, and the wind speed and pitch the rotor's aerodynamics read (module notes of
:mod:`assembly.dynamics.transient` derive the step; this is the same step: predictor, the
constant inverse ``A0^-1``, Newton on the m-rank Woodbury system with its convergence, round-off
floor and step-halving tests, the corrector, the meshes', shaft torques' and rotor's laws of
:mod:`assembly.dynamics.mesh_laws`, :mod:`assembly.dynamics.torque_laws` and
:mod:`assembly.dynamics.rotor_laws`, the contact-loss counts, and the recorded rows).

The columns of ``U`` are the meshes' (2 a mesh), then the shaft torques' from ``t0``, then the
rotor's from ``r0`` (its rotation, and its axial translation when it has thrust). The state (q,
v, a, M a, the averaged force F, Newton's xi and its last value, the meshes' contact flags, loss
counts and last contact forces, the torques' and the rotor's state arrays) is updated in place,
so a stretch continues where the last one stopped.
"""
from __future__ import annotations

import math

import numpy as np

from .jit import njit
from .mesh_laws import mesh_commit, mesh_forces
from .rotor_laws import INSIDE, N_OUT, rotor_commit, rotor_forces
from .torque_laws import shaft_commit, shaft_forces

#: Newton iterations (and halved steps) of one step before it is declared not converging.
MAX_ITERATIONS = 60
#: Relative tolerance of a step's Newton iterations (on xi, the forces along U).
NEWTON_RTOL = 1e-10
#: Absolute floor of a step's residual, in units of eps x the size of the forces it is summed
#: from (``force_scale`` of :class:`assembly.dynamics.transient.Nonlinear`, plus xi): a column
#: of a mesh's nu sums four rounded terms (k e + c s delta' - k0 delta - c delta'), so it is
#: known to about 4 eps x their size; a residual below that is round-off, and no Newton step
#: can lower it further.
ROUNDOFF = 4
EPS = float(np.finfo(float).eps)
#: What a stretch ends with: every step done, Newton did not converge, a state not finite, the
#: rotor's state outside its aerodynamic surface (:meth:`assembly.dynamics.rotor_aero.RotorAero.refuse`).
DONE, NOT_CONVERGED, NOT_FINITE, OFF_SURFACE = 0, 1, 2, 3


@njit
def norm(v):
    """Euclidean norm of a short vector."""
    return math.sqrt(np.dot(v, v))


@njit
def settled(dxi, xi, S, ua):
    """A Newton step ``dxi`` that ends a time step: it, or what it changes of ``U' a+``
    (``S dxi``), is within NEWTON_RTOL of ``xi`` (the iterate after it) or of ``ua``, or it is 0."""
    step = norm(dxi)
    return step <= NEWTON_RTOL * norm(xi) or step == 0.0 or norm(S @ dxi) <= NEWTON_RTOL * norm(ua)


@njit
def newton_matrix(T, S):
    """``I + T S``, the zero entries of ``T`` (most: a mesh couples its own two columns)
    skipped, each sum in column order (:func:`newton_matrix_rows` rounds the same)."""
    mm = S.shape[0]
    J = np.eye(mm)
    for i in range(mm):
        for j in range(mm):
            t = T[i, j]
            if t != 0.0:
                for r in range(mm):
                    J[i, r] += t * S[j, r]
    return J


def newton_matrix_rows(T, S):
    """:func:`newton_matrix` on numpy arrays, numba absent: the same sums in the same order
    (row by row, the k-th nonzero of every row at once), so the same bits."""
    nz = T != 0.0
    J = np.eye(S.shape[0])
    order = np.argsort(~nz, axis=1, kind="stable")     # each row's nonzero columns first, ascending
    counts = nz.sum(axis=1)
    for k in range(int(counts.max(initial=0))):
        rows = np.flatnonzero(counts > k)
        cols = order[rows, k]
        J[rows] += T[rows, cols][:, None] * S[cols]
    return J


@njit
def lu_factor(J):
    """(LU, piv): ``J``'s LU factors by Gaussian elimination with partial pivoting (LAPACK's
    getrf order: L's multipliers below the diagonal, unit diagonal; ``piv[c]`` the row swapped
    with row c), each entry updated as ``a - f b`` (:func:`lu_factor_rows` rounds the same).
    Newton's matrix of the step: kept for a chord step (module notes of
    :mod:`assembly.dynamics.transient`)."""
    A = J.copy()
    mm = A.shape[0]
    piv = np.empty(mm, np.int64)
    for c in range(mm):
        p = c
        big = abs(A[c, c])
        for i in range(c + 1, mm):
            if abs(A[i, c]) > big:
                p, big = i, abs(A[i, c])
        if not big > 0.0:
            raise np.linalg.LinAlgError("singular Newton matrix")
        piv[c] = p
        if p != c:
            for j in range(mm):
                A[c, j], A[p, j] = A[p, j], A[c, j]
        inv = 1.0 / A[c, c]
        for i in range(c + 1, mm):
            f = A[i, c] * inv
            A[i, c] = f
            for j in range(c + 1, mm):
                A[i, j] = A[i, j] - f * A[c, j]
    return A, piv


@njit
def lu_solve(A, piv, r):
    """``J^-1 r`` from :func:`lu_factor`'s factors: the swaps, then L and U column by column
    (:func:`lu_solve_rows` rounds the same)."""
    mm = A.shape[0]
    x = r.copy()
    for c in range(mm):
        p = piv[c]
        if p != c:
            x[c], x[p] = x[p], x[c]
    for c in range(mm):
        for i in range(c + 1, mm):
            x[i] = x[i] - A[i, c] * x[c]
    for j in range(mm - 1, -1, -1):
        x[j] = x[j] / A[j, j]
        for i in range(j):
            x[i] = x[i] - A[i, j] * x[j]
    return x


def lu_factor_rows(J):
    """:func:`lu_factor` on numpy arrays, numba absent: the same operations a column at a time
    (the first largest pivot, ``a - f b`` entry by entry), so the same bits."""
    A = np.array(J, float)
    mm = A.shape[0]
    piv = np.empty(mm, np.int64)
    for c in range(mm):
        col = np.abs(A[c:, c])
        p = c + int(np.argmax(col))
        if not col[p - c] > 0.0:
            raise np.linalg.LinAlgError("singular Newton matrix")
        piv[c] = p
        if p != c:
            A[[c, p]] = A[[p, c]]
        f = A[c + 1:, c] * (1.0 / A[c, c])
        A[c + 1:, c] = f
        A[c + 1:, c + 1:] = A[c + 1:, c + 1:] - f[:, None] * A[c, c + 1:][None, :]
    return A, piv


def lu_solve_rows(A, piv, r):
    """:func:`lu_solve` on numpy arrays, numba absent: the same bits."""
    x = np.array(r, float)
    mm = A.shape[0]
    for c in range(mm):
        p = piv[c]
        if p != c:
            x[c], x[p] = x[p], x[c]
    for c in range(mm):
        x[c + 1:] = x[c + 1:] - A[c + 1:, c] * x[c]
    for j in range(mm - 1, -1, -1):
        x[j] = x[j] / A[j, j]
        x[:j] = x[:j] - A[:j, j] * x[j]
    return x


@njit
def csr_into(indptr, indices, data, x, out, first, add):
    """Rows of a CSR matrix times ``x`` into ``out[first:]`` (added when ``add``), each row summed
    in its column order from 0 (SciPy's CSR product sums the same way)."""
    for i in range(indptr.shape[0] - 1):
        s = csr_row(indptr, indices, data, i, x)
        if add:
            out[first + i] += s
        else:
            out[first + i] = s


@njit
def csr_row(indptr, indices, data, i, x):
    """Row ``i`` of a CSR matrix times ``x`` (:func:`csr_into`'s sum)."""
    s = 0.0
    for p in range(indptr[i], indptr[i + 1]):
        s += data[p] * x[indices[p]]
    return s


@njit
def predictor(Z, qp, vp, a, AinvL, h):
    """``x0`` of a step but its ``alpha_f F`` term: ``Z [qp; vp] - A0^-1 L h`` (``Z [qp; vp;
    a]`` when alpha_m != 0), ``Z`` the predictor's map
    (:func:`assembly.dynamics.stretches.predictor_map`), ``qp``, ``vp`` the step's predictors,
    ``L h`` the load at the step (``AinvL = A0^-1 L``). The Python step of a dense model calls
    this too."""
    n = qp.shape[0]
    sv = np.empty(Z.shape[1])
    sv[:n] = qp
    sv[n:2 * n] = vp
    if Z.shape[1] > 2 * n:
        sv[2 * n:] = a
    x0 = Z @ sv
    if h.shape[0]:
        x0 -= AinvL @ h
    return x0


@njit
def run_stretch(count, t, scheme, Ainv, M, Z, W, S, UT, LV, AinvL, LH, direct,
                mk0, mc, mA, mcP, msP, mphase, mlin, mgap, con, p, ps, table, brake, has_torques, t0,
                rp, rtsr, rpitch, rcq, rct, rs, wind, beta, has_rotor, r0,
                kp, ki, kd, cp, ci, cd, sp_, si, sd, ap, ai, ad, vp_, vi, vd, swap_i, swap_j, pick_i, pick_j,
                q, v, a, Ma, F, xi, xi_prev, contact, losses, last_force, Y, its):
    """``count`` steps from ``t[0]`` (``t``: the count + 1 step times); ``scheme``: (alpha_m,
    alpha_f, beta, gamma, dt); ``Z`` the predictor's map (:func:`predictor`). Loads at ``t[k] +
    (1 - alpha_f) dt``: ``LV @ LH[k]`` (or ``LH[k]`` itself if ``direct``), ``AinvL = A0^-1 LV``
    (or ``A0^-1``); ``M a`` and the averaged force ``F`` are kept only when alpha_f != 0;
    ``table``, ``brake`` (count,): the generator's recorded torque and the brake torque at
    ``t[k + 1]``, the torques' columns from ``t0``; ``rp``, the surface's ``rtsr``, ``rpitch``,
    ``rcq``, ``rct`` and the state ``rs``: the rotor's (:mod:`assembly.dynamics.rotor_laws`), its
    columns from ``r0``, ``wind``, ``beta`` (count,) the wind speed and pitch at ``t[k + 1]``.
    Rows into ``Y[k]`` (``pick_i[s]``: the rotor's state ``rs[pick_j[s]]``) and Newton counts
    into ``its[k]``. Returns (steps done, :data:`DONE` / :data:`NOT_CONVERGED` /
    :data:`NOT_FINITE` / :data:`OFF_SURFACE`, the residual, the coordinate that is not finite or
    the rotor row's speed the surface does not cover)."""
    am, af, b, g, dt = scheme[0], scheme[1], scheme[2], scheme[3], scheme[4]
    mm = UT.shape[0]
    m = mk0.shape[0]
    nu, dc, scale = np.zeros(mm), np.zeros(mm), np.zeros(mm)
    Kt = np.zeros((mm, mm))
    Tw = np.zeros((mm, mm))
    force, slope = np.zeros(m), np.ones(m)
    dxi = np.zeros(mm)
    LU, piv = np.eye(mm), np.arange(mm)
    x, xd = np.zeros(mm), np.zeros(mm)
    ck, cc = (1 - af) * b * dt * dt, (1 - af) * g * dt
    n_k, n_a = kp.shape[0] - 1, ap.shape[0] - 1
    f_a = np.zeros(q.shape[0])
    rout = np.zeros(N_OUT)
    cross = 0.0
    axial = has_rotor and mm - r0 > 1
    for k in range(count):
        h = LH[k]
        qp = q + dt * v + (dt * dt * (0.5 - b)) * a
        vp = v + (dt * (1 - g)) * a
        x0 = predictor(Z, qp, vp, a, AinvL, h)
        if af != 0.0:
            if direct:
                f_a[:] = h
            elif h.shape[0]:
                f_a[:] = LV @ h
            x0 += af * (Ainv @ F)
        y0, xp, xdp = UT @ x0, UT @ qp, UT @ vp
        best = np.inf
        converged = False
        have_lu = False
        res = 0.0
        it = 0
        for it in range(1, MAX_ITERATIONS + 1):
            ua = S @ xi - y0                              # U' a+
            x = xp + (b * dt * dt) * ua
            xd = xdp + (g * dt) * ua
            if m:
                mesh_forces(x, xd, mk0, mc, mA, mcP, msP, mphase, mlin, mgap, con, 0.0, nu, Kt, dc, scale,
                            force, slope)
            if has_torques:
                shaft_forces(p, ps, table[k], brake[k], xd[t0:r0], nu[t0:r0], dc[t0:r0])
                scale[t0:r0] = np.abs(nu[t0:r0])
            if has_rotor:
                status, cross = rotor_forces(rp, rtsr, rpitch, rcq, rct, wind[k], beta[k], xd[r0:], nu[r0:],
                                             dc[r0:], rout)
                if status != INSIDE:
                    return k, OFF_SURFACE, xd[r0]
                scale[r0:] = np.abs(nu[r0:])
            r = xi + (1 - af) * nu
            if mm == 0:
                converged = True
                break
            res = norm(r)
            if res <= ROUNDOFF * EPS * (norm(xi) + (1 - af) * norm(scale)):
                converged = True
                break
            if res >= best and res > 1e-13 * (norm(xi) + (1 - af) * norm(nu)):
                dxi = 0.5 * dxi                           # the full step did not lower the residual
                xi += dxi                                 # (in place: xi is the caller's state)
                continue
            best = res
            if have_lu:                                   # a chord step on this step's last factors
                dxi = lu_solve(LU, piv, r)
                trial = xi - dxi
                if settled(dxi, trial, S, ua):
                    xi[:] = trial
                    converged = True
                    break
            for i in range(mm):
                for j in range(mm):
                    Tw[i, j] = ck * Kt[i, j]
                Tw[i, i] += cc * dc[i]
            if axial:                                     # the thrust's tangent in the rotor's speed
                Tw[r0 + 1, r0] += cc * cross
            LU, piv = lu_factor(newton_matrix(Tw, S))
            have_lu = True
            dxi = lu_solve(LU, piv, r)
            xi -= dxi
            if settled(dxi, xi, S, ua):
                converged = True
                break
        if not converged:
            return k, NOT_CONVERGED, norm(r)
        its[k] = it
        xi_next = 2 * xi - xi_prev                        # next guess: linear extrapolation
        xi_prev[:] = xi
        xi[:] = xi_next
        a_new = W @ xi_prev - x0
        q[:] = qp + (b * dt * dt) * a_new
        v[:] = vp + (g * dt) * a_new
        for i in range(q.shape[0]):
            if not np.isfinite(q[i]):
                return k, NOT_FINITE, float(i)
        if af != 0.0:
            Ma_new = M @ a_new
            F[:] = (f_a - am * Ma - (1 - am) * Ma_new - af * F) / (1 - af)
            Ma[:] = Ma_new
        a[:] = a_new
        if m:
            mesh_commit(contact, losses, slope)
            last_force[:] = force
        if has_torques:
            shaft_commit(p, ps, table[k], brake[k], x[t0:r0], xd[t0:r0])
        if has_rotor:
            rotor_commit(rp, rtsr, rpitch, rcq, rct, wind[k], beta[k], xd[r0:], rs, rout)
        row = Y[k]
        csr_into(kp, ki, kd, q, row, 0, False)           # Ok q + Oc v (observe_rows: CSR rows)
        csr_into(cp, ci, cd, v, row, 0, True)
        for s in range(swap_i.shape[0]):
            row[swap_i[s]] = last_force[swap_j[s]] + csr_row(sp_, si, sd, swap_i[s], v)
        csr_into(ap, ai, ad, a, row, n_k, False)         # Oa a
        csr_into(vp_, vi, vd, v, row, n_k + n_a, False)  # Sv v
        for s in range(pick_i.shape[0]):
            row[pick_i[s]] = rs[pick_j[s]]
    return count, DONE, 0.0
