"""Modal solve of an assembled model: frequencies (Hz), mass-normalised shapes, checks.

``K phi = lambda M phi`` on the independent coordinates; frequencies ``f = sqrt(lambda)/2pi``.
Each solve reports its largest relative eigen-residual (norm-wise backward error
``|K phi - lambda M phi| / ((|K| + |lambda| |M|) |phi|)``) and groups repeated frequencies.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
from threadpoolctl import threadpool_limits

from .errors import SceneError, SolverError

log = logging.getLogger(__name__)

#: Relative frequency tolerance under which modes count as one repeated frequency.
REPEAT_RTOL = 1e-6
#: Modes with f below this fraction of the highest frequency are rigid-body (0 Hz) modes.
ZERO_RTOL = 1e-6


@dataclass
class ModalResult:
    """Modes of one model. ``shapes`` are columns on the independent DOFs (mass-normalised);
    ``abs_shapes`` the same modes on the absolute body DOFs (``z = T q``)."""

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


def group_repeated(freqs: np.ndarray, rtol: float = REPEAT_RTOL) -> list:
    """Indices of (sorted) frequencies grouped where neighbours agree within ``rtol``."""
    fmax = max(float(np.max(np.abs(freqs))), 1e-300) if len(freqs) else 1.0
    groups, cur = [], [0] if len(freqs) else []
    for i in range(1, len(freqs)):
        a, b = freqs[i - 1], freqs[i]
        zero = abs(a) < ZERO_RTOL * fmax and abs(b) < ZERO_RTOL * fmax
        if zero or abs(b - a) <= rtol * max(abs(a), abs(b)):
            cur.append(i)
        else:
            groups.append(cur)
            cur = [i]
    if cur:
        groups.append(cur)
    return groups


def residuals(K, M, lam, Phi) -> np.ndarray:
    """Norm-wise relative backward error of each eigenpair (dense or sparse K, M)."""
    nK = sla.norm(K.toarray() if hasattr(K, "toarray") else K, 2) if K.shape[0] < 3000 else _norm1(K)
    nM = sla.norm(M.toarray() if hasattr(M, "toarray") else M, 2) if M.shape[0] < 3000 else _norm1(M)
    R = K @ Phi - (M @ Phi) * lam
    return np.linalg.norm(R, axis=0) / ((nK + np.abs(lam) * nM) * np.linalg.norm(Phi, axis=0))


def _norm1(A) -> float:
    return float(abs(A).sum(axis=0).max())


#: Models up to this many DOFs are solved densely (all modes); larger ones by a sparse
#: shift-invert block solve of the lowest modes (cms.eigen, one sparse factorization).
DENSE_MAX = 3000
#: Dense problems up to this size are solved on one BLAS thread.
SMALL_DENSE = 500
#: Sparse solves: eigenvalues below this fraction of the median K_ii/M_ii are rigid-body.
SPARSE_ZERO_RTOL = 1e-10
#: Default number of modes of a sparse (large) solve.
SPARSE_DEFAULT_MODES = 30


def solve_modes(model, n_modes: int | None = None) -> ModalResult:
    """All (or the lowest ``n_modes``, an integer >= 1; more than the model has gives all
    of them, n - 1 for a sparse model above DENSE_MAX DOFs) modes of ``model``."""
    if n_modes is not None and (isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer))
                                or n_modes < 1):
        raise SceneError("n_modes", n_modes, "must be an integer >= 1 (or None: all modes)")
    t0 = time.perf_counter()
    K, M = model.K, model.M
    data = [getattr(A, "data", A) for A in (K, M)]
    if not all(np.all(np.isfinite(d)) for d in data):
        raise SolverError("K, M", "non-finite", "assembled matrices contain inf or NaN")
    n = K.shape[0]
    if n <= DENSE_MAX:
        Kd = K.toarray() if hasattr(K, "toarray") else K
        Md = M.toarray() if hasattr(M, "toarray") else M
        # Symmetric diagonal scaling (unit mass diagonal): a rotor of 4e7 kg m^2 and a
        # generator of 534 kg m^2 behind 97:1 then share one scale; eigenvectors are
        # scaled back, eigenvalues are unchanged.
        d = np.diag(Md)
        if np.any(d <= 0):
            raise SolverError("M", "diagonal <= 0", "mass matrix is not positive definite")
        sc = 1.0 / np.sqrt(d)
        try:
            subset = None if n_modes is None else (0, min(n_modes, n) - 1)
            # one BLAS thread below SMALL_DENSE: waking OpenBLAS threads for a 100-DOF
            # reduced model cost 0.1-0.2 s spikes (median 8 ms vs 2 ms measured, n = 118)
            with threadpool_limits(1 if n <= SMALL_DENSE else None):
                lam, Phi = sla.eigh(sc[:, None] * Kd * sc[None, :], sc[:, None] * Md * sc[None, :],
                                    subset_by_index=subset)
        except np.linalg.LinAlgError as exc:
            raise SolverError("M", "not positive definite", f"mass matrix is singular ({exc})") from exc
        Phi = sc[:, None] * Phi
        res = residuals(Kd, Md, lam, Phi)
    else:
        lam, Phi = _sparse_lowest(K, M, n_modes or SPARSE_DEFAULT_MODES)
        res = residuals(K, M, lam, Phi)
        # Rigid-body eigenvalues of an unreduced FE model carry an absolute error of about
        # eps * |K|/|M|; judge them against that scale (the median diagonal ratio), since
        # only the lowest modes are computed.
        scale = float(np.median(K.diagonal() / np.maximum(M.diagonal(), 1e-300)))
        zero_lam = SPARSE_ZERO_RTOL * scale
    fmax_guess = np.sqrt(max(lam.max(), 0.0)) / (2 * np.pi) if len(lam) else 0.0
    if np.any(lam < -1e-8 * max(abs(lam).max(), 1e-300)):
        log.warning("negative eigenvalues down to %.3e (stiffness not positive semi-definite?)", lam.min())
    f = np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi)
    if n <= DENSE_MAX:
        n_rigid = int(np.sum(f < ZERO_RTOL * max(fmax_guess, 1e-300)))
    else:
        n_rigid = int(np.sum(lam < zero_lam))
    dt = time.perf_counter() - t0
    out = ModalResult(model, lam, f, Phi, model.T @ Phi, group_repeated(f), float(res.max(initial=0)),
                      dt, n_rigid)
    log.info("%d modes in %.3f s, max residual %.2e, %d rigid-body", len(f), dt, out.max_residual, n_rigid)
    return out


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
