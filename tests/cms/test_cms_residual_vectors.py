"""Craig-Bampton with residual vectors (modal truncation augmentation).

The augmented basis T = [[I, 0], [Psi, [Phi, W]]] contains the plain CB basis, and both
lie inside R^n, so by Courant-Fischer (Rayleigh-Ritz on nested subspaces)
    lambda_k(full) <= lambda_k(CB + W) <= lambda_k(CB)    for every k.
W spans K_ii^-1 (M_ii Psi + M_ib) outside span(Phi): the interior's static response to the
inertia of the interface motion (Dickens, Nakagawa & Wittbrodt, Comput. Struct. 62 (1997)).
Test model: steel block, scikit-fem P2 tetrahedra (tests.support.fe_models.box).
"""
import numpy as np
import scipy.linalg as sla

from cms.craig_bampton import CraigBamptonReductor
from tests.support.fe_models import box

RTOL = 1e-10   # dense generalized eigh round-off on these small, well-scaled models


def _bar():
    m = box(lengths=(1.0, 0.1, 0.1), divisions=(8, 2, 2))
    b = m.dofs_where(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], 1.0))
    full = sla.eigh(m.K.toarray(), m.M.toarray(), eigvals_only=True)
    return m, b, full


def _reduced(m, b, k, rv):
    se = CraigBamptonReductor(m.K, m.M, b, n_modes=k, node_coords=m.node_coords,
                              residual_vectors=rv).reduce()
    return se, sla.eigh(se.K, se.M, eigvals_only=True)


def test_residual_vectors_nested_between_plain_cb_and_full():
    m, b, full = _bar()
    for k in (0, 3, 8):
        se0, lam0 = _reduced(m, b, k, False)
        se1, lam1 = _reduced(m, b, k, True)
        el = slice(6, 6 + se0.K.shape[0] - 6)     # elastic modes both models have
        assert np.all(lam1[el] >= full[el] * (1 - RTOL)), k
        assert np.all(lam1[el] <= lam0[el] * (1 + RTOL)), k
        # and the augmentation is not void: the first elastic modes improve strictly
        assert lam1[6:12].sum() < lam0[6:12].sum(), k
        # free-free: still exactly six rigid modes (W lives in the interior, Psi R_b = R_i)
        assert np.sum(np.abs(lam1) < 1e-9 * lam1.max()) == 6


def test_residual_vectors_are_orthonormal_ritz_vectors_beside_the_modes():
    m, b, _ = _bar()
    se, _ = _reduced(m, b, 4, True)
    n_rv = se.metadata["n_residual_vectors"]
    # at most one per boundary DOF; directions already in span(Phi) or dependent are dropped
    assert 0 < n_rv <= len(b)
    i = se.interior_dofs
    Kii, Mii = m.K[i][:, i], m.M[i][:, i]
    P = se.Phi
    assert np.allclose(P.T @ (Mii @ P), np.eye(P.shape[1]), atol=1e-9)
    KP = P.T @ (Kii @ P)
    assert np.allclose(KP, np.diag(se.eigenvalues), atol=1e-9 * se.eigenvalues.max())
    # the static response to the constraint modes' inertia is reproduced by the basis
    Psi = se.Psi
    G = sla.solve(Kii.toarray(), Mii @ Psi + m.M[i][:, b].toarray(), assume_a="pos")
    coef = P.T @ (Mii @ G)
    # directions are dropped when their part outside span(Phi) is below drop = 1e-6 (in the
    # mass norm of unit columns, craig_bampton._augmentation), so G is reproduced to about
    # that; a factor 10 covers the mass-norm vs 2-norm scale. Plain CB: 2e-2 here.
    assert np.linalg.norm(P @ coef - G) <= 1e-5 * np.linalg.norm(G)


def test_static_interface_loads_still_exact_and_mass_unchanged():
    # the constraint modes are untouched, so the rigid-body mass matrix and the exact
    # static condensation of plain CB are kept (Craig & Bampton 1968)
    m, b, _ = _bar()
    se0, _ = _reduced(m, b, 4, False)
    se1, _ = _reduced(m, b, 4, True)
    nb = se0.n_boundary
    full_rigid = np.array(se1.metadata["self_checks"]["rigid_mass_matrix_full"])
    assert se1.metadata["self_checks"]["rigid_mass_matrix_rel_error"] <= 1e-10
    assert np.allclose(se1.K[:nb, :nb], se0.K[:nb, :nb], rtol=0, atol=1e-12 * np.abs(se0.K).max())
    assert np.allclose(se1.M[:nb, :nb], se0.M[:nb, :nb], rtol=0, atol=1e-12 * np.abs(se0.M).max())
    assert full_rigid[0, 0] > 0
