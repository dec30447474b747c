"""Viscous damping matrices of an assembled model, on its independent coordinates ``q``.

Element dampers sit beside the springs, on the same strain rows ``B`` (:class:`assembly.
elements.Element` ``c``): ``C_abs = sum L' B' diag(c) B L`` is assembled exactly as
``K_abs`` is, and ``C = T' C_abs T`` (N s/m, N m s/rad entries on q).

Rayleigh damping ``alpha M + beta K`` (alpha in 1/s, beta in s) gives a mode of angular
frequency omega (rad/s) the ratio ``zeta = alpha / (2 omega) + beta omega / 2``. Its
``alpha M`` part would also act on a rigid-body mode (a free rotor-generator spin would be
braked at the rate alpha, as by a damper to ground that no bearing holds). Rayleigh's
alpha is a device to fit the elastic modes' ratios, not a drag on the housing, so it is
applied with the rigid-body modes ``Phi_r`` (mass-normalised) projected out:
``alpha (M - M Phi_r Phi_r' M)``. Every elastic mode, M-orthogonal to ``Phi_r``, sees
``alpha`` exactly as before, and every rigid-body mode sees nothing: it stays at s = 0.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..model import on_q


def damping_matrix(model) -> sp.csr_matrix:
    """Sparse symmetric damping of every element damper of ``model`` on q (zero when the
    scene has no ``c_*`` field set)."""
    C_abs = sp.csr_matrix((model.n_abs, model.n_abs))
    for el in model.elements:
        if el.c is not None:
            C_abs = C_abs + model.element_damping_abs(el)
    return on_q(model.T, C_abs.tocsr())


def damping_in_modes(result, ratios: np.ndarray) -> np.ndarray:
    """Dense damping (1/s) on the modal coordinates of ``result`` (mass-normalised shapes
    Phi, eigenvalues lambda = omega^2): ``Phi' C Phi`` of the element dampers, plus the
    scene's ``[damping]``: Rayleigh ``alpha (I - E_r) + beta diag(lambda)`` (``E_r`` the
    rigid-body modes: the projection of the module notes) and the modal ratios ``ratios``
    (one zeta per mode) as ``diag(2 zeta omega)``. Exact for a result holding every mode;
    with fewer, the damping of the modes kept (modal truncation)."""
    Phi = result.shapes
    C = Phi.T @ (damping_matrix(result.model) @ Phi)
    lam = np.where(np.arange(len(result.eigenvalues)) < result.n_rigid, 0.0,
                   np.maximum(result.eigenvalues, 0.0))
    d = result.model.scene.damping
    diag = 2.0 * np.asarray(ratios, float) * np.sqrt(lam)
    if d is not None:
        diag = diag + d.rayleigh_alpha * (lam > 0) + d.rayleigh_beta * lam
    C = C + np.diag(diag)
    return 0.5 * (C + C.T)
