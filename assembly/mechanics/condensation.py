"""Static (Guyan) condensation of a stiffness matrix onto a few kept coordinates.

With the kept coordinates ``b`` given and every other one (``i``) free to settle, the
strain energy is least when ``K_ii q_i = -K_ib q_b``, which leaves the exact stiffness
seen at ``b``: ``K_cc = K_bb - K_bi K_ii^-1 K_ib`` (Guyan 1965, AIAA J. 3(2), p. 380).
No inertia is condensed: this is the static stiffness between the kept coordinates,
every spring between them in series and parallel as the structure joins them.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import MechanismError

#: Pivots of the LU factors of K_ii below this fraction of the largest are taken as zero:
#: an interior motion without stiffness (K_ii singular) once the kept coordinates are held.
PIVOT_RTOL = 1e-13


def condense(K, keep) -> np.ndarray:
    """``K_cc`` (len(keep) x len(keep), dense, units of ``K``) of the symmetric stiffness
    ``K`` (sparse or dense, n x n) condensed onto the coordinates ``keep`` (indices).

    ``K_ii`` is factorised once (sparse LU); a singular ``K_ii`` -- some motion of the
    other coordinates strains nothing while the kept ones are held -- raises
    :class:`MechanismError`."""
    return condense_along(K, K, keep)


def condense_along(K, A, keep) -> np.ndarray:
    """The symmetric matrix ``A`` (e.g. a damping, same size as ``K``) on the static
    condensation of ``K`` onto ``keep``: with ``q_i = -K_ii^-1 K_ib q_b`` (the interior
    settled as the stiffness says), ``A_cc = T' A T``, ``T = [I; -K_ii^-1 K_ib]``
    (``A = K`` gives :func:`condense`)."""
    K = sp.csc_matrix(K)
    A = sp.csc_matrix(A)
    keep = [int(k) for k in keep]
    inner = np.setdiff1d(np.arange(K.shape[0]), keep)
    A_bb = A[keep][:, keep].toarray()
    if inner.size == 0:
        return 0.5 * (A_bb + A_bb.T)
    K_ii = K[inner][:, inner].tocsc()
    K_ib = K[inner][:, keep].toarray()
    try:
        lu = spla.splu(K_ii)
    except RuntimeError as exc:  # "Factor is exactly singular"
        raise MechanismError(f"static condensation: K_ii is singular with the kept coordinates held ({exc})") from exc
    pivots = np.abs(lu.U.diagonal())
    small = pivots <= PIVOT_RTOL * pivots.max(initial=0.0)
    if np.any(small):
        raise MechanismError(f"static condensation: K_ii is singular ({int(small.sum())} pivot(s) below "
                             f"{PIVOT_RTOL:g} of the largest): some motion strains nothing with the kept "
                             "coordinates held")
    S = lu.solve(K_ib)                                   # q_i = -S q_b
    A_ib = A[inner][:, keep].toarray()
    A_cc = A_bb - A_ib.T @ S - S.T @ A_ib + S.T @ (A[inner][:, inner] @ S)
    return 0.5 * (A_cc + A_cc.T)
