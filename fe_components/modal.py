"""Lowest free-free natural frequencies of a (K, M) pair (Hz), for checks and benchmarks.

Shift-invert Lanczos (``scipy.sparse.linalg.eigsh``) about a negative shift
sigma, so that K - sigma M is positive definite even for a free body; the
factorisation uses CHOLMOD when scikit-sparse is installed, else SuperLU.
"""
from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator, eigsh, splu

log = logging.getLogger(__name__)


def default_shift(K: sp.spmatrix, M: sp.spmatrix) -> float:
    """A negative shift [rad^2/s^2] well below the first elastic eigenvalue.

    The median diagonal ratio K_ii / M_ii scales like (c / h)^2 (c wave speed,
    h element size), far above the lowest modes; 1e-6 of it lies between the
    rigid-body (~0) and the first elastic eigenvalues for practical meshes.
    """
    d = K.diagonal() / np.where(M.diagonal() > 0, M.diagonal(), np.inf)
    return -1e-6 * float(np.median(d[np.isfinite(d) & (d > 0)]))


def _inverse(A: sp.spmatrix) -> LinearOperator:
    A = sp.csc_matrix(A)
    try:
        from sksparse.cholmod import cholesky

        f = cholesky(A)
        solve = f
    except ImportError:  # pragma: no cover - optional backend
        lu = splu(A)
        solve = lu.solve
    return LinearOperator(A.shape, matvec=lambda x: solve(np.asarray(x, dtype=float)), dtype=float)


def lowest_frequencies(K: sp.spmatrix, M: sp.spmatrix, n: int, sigma: float | None = None,
                       return_vectors: bool = False):
    """The ``n`` lowest natural frequencies [Hz] (signed: sign(lambda) sqrt|lambda| / 2 pi), ascending."""
    sigma = default_shift(K, M) if sigma is None else sigma
    op = _inverse(K - sigma * M)
    w, v = eigsh(sp.csr_matrix(K), k=n, M=sp.csr_matrix(M), sigma=sigma, which="LM", OPinv=op)
    order = np.argsort(w)
    w, v = w[order], v[:, order]
    f = np.sign(w) * np.sqrt(np.abs(w)) / (2 * np.pi)
    return (f, v) if return_vectors else f


def count_rigid_modes(freqs: np.ndarray, ratio: float = 1e-3) -> int:
    """Number of modes with |f| < ratio x (first frequency above that threshold)."""
    f = np.abs(np.asarray(freqs))
    elastic = f[f > ratio * f.max()]
    first = elastic.min() if len(elastic) else np.inf
    return int(np.sum(f < ratio * first))
