"""Modal solve of an assembled model: frequencies (Hz), mass-normalised shapes, checks.

``K phi = lambda M phi`` on the independent coordinates; frequencies ``f = sqrt(lambda)/2pi``.
Each solve reports its largest relative eigen-residual (norm-wise backward error
``|K phi - lambda M phi| / ((|K| + |lambda| |M|) |phi|)``, of the scaled problem it solved)
and groups repeated frequencies. The number of rigid-body modes comes from the model's
structure (:mod:`assembly.mechanics.nullity`); :mod:`assembly.analysis.resolution` checks that the solve
resolves them and every elastic mode to FREQ_RTOL, and names the offending scene field
otherwise. The same rules hold for the dense (all modes) and the sparse (lowest modes)
path; the sparse path estimates the highest eigenvalue by max K_ii / M_ii. A dense problem
of at most :data:`SMALL_DENSE` DOFs is solved with NumPy alone (Cholesky factor of the
mass, ``eigh`` of the symmetric standard form: :func:`numpy_eigh`), a larger one with
``scipy.linalg.eigh``: SciPy is imported only when a model needs it (0.2-0.3 s of a small
model's 0.5 s command).
"""
from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field

import numpy as np
from threadpoolctl import threadpool_limits

from .. import arguments
from ..errors import SceneError, SolverError
from ..mechanics.dense import dense, entries
from ..mechanics.nullity import rigid_body_count
from ..model.assemble import model_argument
from . import resolution

log = logging.getLogger(__name__)

#: Relative frequency tolerance under which modes count as one repeated frequency: the
#: documented accuracy of the solve (grouping is only meaningful above its errors).
REPEAT_RTOL = resolution.FREQ_RTOL


@dataclass(frozen=True, eq=False)
class ModalResult:
    """Modes of one model. ``shapes`` are columns on the independent DOFs (mass-normalised);
    ``abs_shapes`` the same modes on the absolute body DOFs (``z = T q``). ``eigenvalues``
    (rad^2/s^2) and ``frequencies_hz`` ascending, rigid-body modes (``n_rigid``, from the
    structure) first; ``groups`` the repeated frequencies; ``max_residual`` the largest
    relative eigen-residual; ``info``: ``frequency_rtol`` of the resolution check. ``memo``:
    results derived from these modes, computed once per result (``"inverted"``: the modes
    re-solved from the inverted pencil for the FRF, :func:`assembly.dynamics.frf.low_accurate`)."""

    model: object
    eigenvalues: np.ndarray
    frequencies_hz: np.ndarray
    shapes: np.ndarray
    abs_shapes: np.ndarray
    groups: list
    max_residual: float
    solve_time_s: float
    n_rigid: int
    info: dict = field(default_factory=dict)
    memo: dict = field(default_factory=dict, repr=False)

    def multiplicity(self) -> np.ndarray:
        m = np.zeros(len(self.frequencies_hz), int)
        for g in self.groups:
            m[g] = len(g)
        return m

    def body_motion(self, mode: int, body: str) -> np.ndarray:
        """Rigid(-equivalent) motion [ux, uy, uz, rx, ry, rz] of ``body`` at its centre of
        mass in mode ``mode`` (m, rad; global axes)."""
        bm = self.model.bodies[body]
        return bm.rigid_motion(self.abs_shapes[self.model.body_slice(body), mode])


def group_repeated(freqs: np.ndarray, rtol: float = REPEAT_RTOL, n_zero: int = 0) -> list:
    """Indices of (sorted) frequencies grouped where neighbours agree within ``rtol``; the
    first ``n_zero`` (rigid-body modes) form one group."""
    groups = [list(range(n_zero))] if n_zero else []
    cur = []
    for i in range(n_zero, len(freqs)):
        if cur and abs(freqs[i] - freqs[i - 1]) > rtol * max(abs(freqs[i]), abs(freqs[i - 1])):
            groups.append(cur)
            cur = []
        cur.append(i)
    if cur:
        groups.append(cur)
    return groups


def residuals(K, M, lam, Phi) -> np.ndarray:
    """Norm-wise relative backward error of each eigenpair (dense or sparse K, M)."""
    nK = np.linalg.norm(dense(K), 2) if K.shape[0] < DENSE_MAX else _norm1(K)
    nM = np.linalg.norm(dense(M), 2) if M.shape[0] < DENSE_MAX else _norm1(M)
    R = K @ Phi - (M @ Phi) * lam
    scale = (nK + np.abs(lam) * nM) * np.linalg.norm(Phi, axis=0)
    r = np.linalg.norm(R, axis=0)
    # a model without stiffness (K = 0: free rigid bodies only) has lam = 0 and R = 0 exactly
    return np.divide(r, scale, out=np.where(r > 0, np.inf, 0.0), where=scale > 0)


def _norm1(A) -> float:
    return float(abs(A).sum(axis=0).max())


#: Models up to this many DOFs are solved densely (all modes); larger ones by a sparse
#: shift-invert block solve of the lowest modes (cms.eigen, one sparse factorization).
DENSE_MAX = 3000
#: Dense problems up to this size are solved on one BLAS thread, with NumPy alone
#: (:func:`numpy_eigh`; the Cholesky reduction costs n^3 / 3 more than LAPACK's sygvd
#: at most, ~0.04 s at this size).
SMALL_DENSE = 500
#: Default number of modes of a sparse (large) solve.
SPARSE_DEFAULT_MODES = 30


def solve_modes(model, n_modes: int | None = None, check: bool = True) -> ModalResult:
    """All (or the lowest ``n_modes``, an integer >= 1; more than the model has gives all
    of them, n - 1 for a sparse model above DENSE_MAX DOFs) modes of ``model``.

    The number of rigid-body (0 Hz) modes comes from the model's structure
    (:func:`assembly.mechanics.nullity.rigid_body_count`), never from the size of the computed
    eigenvalues; :func:`assembly.analysis.resolution.check` then verifies that the solve resolves
    them and the lowest elastic mode (SceneError naming the field otherwise). ``check=False``
    records that error in ``info["resolution"]`` instead of raising (``frequency_rtol`` is
    then NaN): for a benchmark's unreduced reference, whose sparse solve is judged by its
    residuals and the dense round-off bound overestimates (it takes max K_ii / M_ii for the
    highest eigenvalue).
    """
    model_argument("model", model)
    arguments.flag("check", check)
    if n_modes is not None and (isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer))
                                or n_modes < 1):
        raise SceneError("n_modes", n_modes, "must be an integer >= 1 (or None: all modes)")
    t0 = time.perf_counter()
    K, M = model.K, model.M
    if not all(np.all(np.isfinite(entries(A))) for A in (K, M)):
        raise _overflow(model)
    n = K.shape[0]
    # one BLAS thread below SMALL_DENSE: waking OpenBLAS threads for a 100-DOF model cost
    # 0.1-0.2 s spikes (median 8 ms vs 2 ms measured, n = 118), and up to 1.5 s on a loaded
    # machine in the structural count's and the residuals' SVDs (NREL 5 MW rigid, 126 DOFs)
    with threadpool_limits(1 if n <= SMALL_DENSE else None):
        n_zero = rigid_body_count(model)
        if n <= DENSE_MAX:
            spec, Phi, top, res = _dense(model, n_modes)
        else:
            spec, Phi, top = _sparse(K, M, n_modes or SPARSE_DEFAULT_MODES)
            res = residuals(K, M, spec.lam, Phi)
    lam = spec.unscaled()
    if np.any(spec.lam < -spec.roundoff):
        log.warning("negative eigenvalues down to %.3e (stiffness not positive semi-definite?)", lam.min())
    info = {}
    try:
        info["frequency_rtol"] = resolution.check(model, spec, n_zero, top)
    except SceneError as exc:
        if check:
            raise
        info.update(frequency_rtol=float("nan"), resolution=str(exc))
    rtol = info["frequency_rtol"]
    f = spec.hz(spec.lam)
    dt = time.perf_counter() - t0
    out = ModalResult(model, lam, f, Phi, model.T @ Phi, group_repeated(f, n_zero=n_zero),
                      float(res.max(initial=0)), dt, n_zero, info)
    log.info("%d modes in %.3f s, max residual %.2e, %d rigid-body, lowest elastic frequency resolved to %.1e",
             len(f), dt, out.max_residual, n_zero, rtol)
    return out


def _dense(model, n_modes):
    """Dense generalized solve on symmetrically scaled matrices: unit mass diagonal (a rotor
    of 4e7 kg m^2 and a generator of 534 kg m^2 behind 97:1 then share one scale) and the
    largest K_ii / M_ii at 1, formed without overflow for any finite K, M. Returns the
    spectrum (scaled), mass-normalised shapes, the highest mode and the backward errors."""
    Kd = dense(model.K)
    Md = dense(model.M)
    d, kd = np.diag(Md), np.diag(Kd)
    if np.any(d <= 0):
        raise SolverError("M", "diagonal <= 0", "mass matrix is not positive definite")
    ld = np.log(d)
    with np.errstate(divide="ignore"):
        lrho = np.where(kd > 0, np.log(np.where(kd > 0, kd, 1.0)) - ld, -np.inf)
    # K is scaled by a power of 4 near 1 / max(K_ii / M_ii): exact in binary, so models
    # without extreme magnitudes get the very same eigenvalues as with unit mass scaling
    p4 = int(round(-float(lrho.max()) / math.log(4))) if np.isfinite(lrho.max()) else 0
    u = 1.0 / np.sqrt(d)                                     # unit mass diagonal
    v = np.where(kd > 0, np.ldexp(u, p4), 0.0)
    A = (v[:, None] * Kd) * v[None, :]
    B = (u[:, None] * Md) * u[None, :]
    n = len(d)
    subset = None if n_modes is None or n_modes >= n else (0, n_modes - 1)
    try:
        if n <= SMALL_DENSE:
            lam, Phi = numpy_eigh(A, B)
            lam_top, top = lam[-1], Phi[:, -1]
            if subset is not None:
                lam, Phi = lam[:n_modes], Phi[:, :n_modes]
        else:
            import scipy.linalg as sla
            lam, Phi = sla.eigh(A, B, subset_by_index=subset)
            lam_top, top = (lam[-1], Phi[:, -1]) if subset is None else \
                sla.eigh(A, B, subset_by_index=(n - 1, n - 1))
    except np.linalg.LinAlgError:
        # numerically singular mass: its near-null direction has an unbounded frequency
        w, V = np.linalg.eigh(B)
        raise resolution.culprit(model, u * V[:, 0], "top", f"the mass matrix is singular to working "
                                 f"precision (smallest scaled eigenvalue {w[0]:.1e})") from None
    res = residuals(A, B, lam, Phi)
    lam_max = float(np.max(lam_top))
    spec = resolution.Spectrum(lam, lam_max, resolution.mode_weights(lam, lam_max, Phi, _norm1(B)), p4)
    return spec, u[:, None] * Phi, u * np.ravel(top), res


def numpy_eigh(A: np.ndarray, B: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every eigenpair of the symmetric pencil ``A x = lam B x`` (``B`` positive definite),
    ascending, ``X' B X = I``, with NumPy alone: ``B = L L'`` (Cholesky), the standard
    symmetric problem ``C = L^-1 A L^-T`` (symmetrised) by ``numpy.linalg.eigh`` and
    ``X = L^-T Y``, the reduction LAPACK's sygvd makes (``scipy.linalg.eigh(A, B)``).
    LinAlgError if ``B`` is not positive definite."""
    L = np.linalg.cholesky(B)
    W = np.linalg.solve(L, A)                   # L^-1 A
    C = np.linalg.solve(L, W.T)                 # L^-1 (L^-1 A)' = L^-1 A L^-T (A symmetric)
    lam, Y = np.linalg.eigh(0.5 * (C + C.T))
    return lam, np.linalg.solve(L.T, Y)


def _sparse(K, M, k):
    """Lowest ``k`` modes by the sparse solve; the highest eigenvalue is estimated by the
    largest K_ii / M_ii (a lower bound: the Rayleigh quotient of that unit vector), whose
    unit vector stands in for the highest mode: the sparse checks are an estimate, lenient
    by the factor between that and the true highest eigenvalue."""
    lam, Phi = _sparse_lowest(K, M, k)
    d = M.diagonal()
    rho = K.diagonal() / d
    top = np.zeros(K.shape[0])
    top[int(np.argmax(rho))] = 1.0
    import scipy.sparse as sp
    u = sp.diags(1.0 / np.sqrt(d))
    X = np.sqrt(d)[:, None] * Phi            # the modes of the unit-diagonal problem
    weights = resolution.mode_weights(lam, float(rho.max()), X, _norm1(u @ M @ u))
    return resolution.Spectrum(lam, float(rho.max()), weights), Phi, top


def _overflow(model):
    """SceneError for a K or M that overflowed while assembling, naming the largest
    spring stiffness (or, if K is finite, the largest body mass field)."""
    K_bad = not np.all(np.isfinite(entries(model.K)))
    still = np.zeros(model.K.shape[0])
    cands = (resolution.spring_energies if K_bad else resolution.kinetic_energies)(model, still)
    c = max(cands, key=lambda c: c.magnitude, default=None)
    if c is None:
        return SolverError("K, M", "non-finite", "assembled matrices contain inf or NaN")
    what = "stiffness" if K_bad else "mass matrix"
    return SceneError(c.path, c.value, f"too large: the assembled {what} overflows double precision")


def _sparse_lowest(K, M, k):
    """Lowest ``k`` modes of a large sparse model by cms.eigen (ARPACK shift-invert on one
    sparse factorization, CHOLMOD when installed, residual-checked).

    The shift is negative (the model may have rigid-body modes) and small against the
    spectrum (:func:`cms.eigen.free_free_shift`), keeping ``K - sigma M`` positive definite.
    """
    from cms.eigen import free_free_shift, lowest_modes
    r = lowest_modes(K.tocsc(), M.tocsc(), min(k, K.shape[0] - 1), sigma=free_free_shift(K, M),
                     tol=1e-10, threads=1)
    return np.asarray(r.eigenvalues), np.asarray(r.vectors)


def mechanisms(result, top: int = 3) -> list:
    """Plain-language description of each rigid-body (0 Hz) mode: the independent DOFs that
    carry its kinetic energy, e.g. ``"pinion.z 50 %, wheel.z 50 %"`` -- which names the
    body and direction left unconstrained when there are more zero modes than expected."""
    out = []
    M = result.model.M
    for i in range(result.n_rigid):
        q = result.shapes[:, i]
        e = q * np.asarray(M @ q).ravel()
        e = np.abs(e) / max(np.abs(e).sum(), 1e-300)
        idx = np.argsort(-e)[:top]
        out.append(", ".join(f"{result.model.dof_names[j]} {100 * e[j]:.0f} %" for j in idx if e[j] > 0.01))
    return out


def modes_argument(name: str, value) -> ModalResult:
    """``value``, a :class:`ModalResult` (SceneError naming the argument ``name`` otherwise)."""
    return arguments.instance(name, value, ModalResult, "the modes of a model (solve_modes(model))")
