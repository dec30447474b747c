"""Residual vectors on a small model, quick enough for the mutation pass (make mutate): they
are there, they keep their contract, and they lower the reduced frequencies towards the
full model's (the larger study is tests/cms/test_cms_residual_vectors.py).

Contract (cms.craig_bampton, _augmentation): the residual vectors W are M-orthonormal and
K-orthogonal, W' M W = I and W' K W = diag(theta), and M-orthogonal to the kept modes, so the
superelement's modal block stays diag(I) / diag(lambda, theta). Rayleigh-Ritz on nested
subspaces (Courant-Fischer): lambda_k(full) <= lambda_k(CB + W) <= lambda_k(CB).
"""
import numpy as np
import pytest
import scipy.linalg as sla

from cms.craig_bampton import CraigBamptonReductor
from tests.support.fe_models import box

RTOL = 1e-10   # dense generalized eigh round-off on this small, well-scaled model


@pytest.fixture(scope="module")
def bar():
    m = box(lengths=(0.5, 0.1, 0.1), divisions=(4, 1, 1))
    b = m.dofs_where(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], 0.5))
    full = sla.eigh(m.K.toarray(), m.M.toarray(), eigvals_only=True)
    plain = CraigBamptonReductor(m.K, m.M, b, n_modes=4, node_coords=m.node_coords).reduce()
    aug = CraigBamptonReductor(m.K, m.M, b, n_modes=4, node_coords=m.node_coords, residual_vectors=True).reduce()
    return m, b, full, plain, aug


def test_residual_vectors_are_added_and_keep_the_modal_block_diagonal(bar):
    m, b, full, plain, aug = bar
    nb = len(b)
    n_rv = aug.metadata["n_residual_vectors"]
    assert n_rv > 0 and aug.n_modes == plain.n_modes + n_rv
    Mq, Kq = aug.M[nb:, nb:], aug.K[nb:, nb:]
    scale = np.abs(Kq).max()
    np.testing.assert_allclose(Mq, np.eye(aug.n_modes), atol=1e-10)
    np.testing.assert_allclose(Kq - np.diag(np.diag(Kq)), 0.0, atol=1e-10 * scale)
    # the kept modes are the plain reduction's: same eigenvalues on the first diagonal entries
    np.testing.assert_allclose(np.diag(Kq)[:plain.n_modes], np.diag(plain.K[nb:, nb:]), rtol=1e-10)


def test_residual_vectors_lower_the_frequencies_towards_the_full_model(bar):
    m, b, full, plain, aug = bar
    lam0 = sla.eigh(plain.K, plain.M, eigvals_only=True)
    lam1 = sla.eigh(aug.K, aug.M, eigvals_only=True)
    el = slice(6, plain.K.shape[0])                         # the elastic modes both have
    assert np.all(lam1[el] >= full[el] * (1 - RTOL))
    assert np.all(lam1[el] <= lam0[el] * (1 + RTOL))
    assert np.any(lam1[el] < lam0[el] * (1 - 1e-6))         # and they do lower some


def test_residual_vectors_make_the_interface_impedance_exact_to_omega_4(bar):
    """The interface dynamic stiffness of the interior condensed exactly,
    D(w) = K_bb - w^2 M_bb - (K_bi - w^2 M_bi) (K_ii - w^2 M_ii)^-1 (K_ib - w^2 M_ib), expands
    as D0 - w^2 D1 - w^4 D2 - ...; the constraint modes make D0 (Guyan stiffness) and D1
    (Guyan mass) exact, and D2 = G' (M_ii Psi + M_ib) with G = K_ii^-1 (M_ii Psi + M_ib) is
    exact once span(G) is in the basis: what the residual vectors add (Dickens, Nakagawa &
    Wittbrodt 1997). The reduced model's D2 is M_bq Lambda^-1 M_qb (its modal block is
    diagonal). Plain CB with 4 modes misses part of it."""
    m, b, full, plain, aug = bar
    K, M = m.K.toarray(), m.M.toarray()
    i = np.setdiff1d(np.arange(K.shape[0]), b)
    Psi = -np.linalg.solve(K[np.ix_(i, i)], K[np.ix_(i, b)])
    load = M[np.ix_(i, i)] @ Psi + M[np.ix_(i, b)]
    D2 = load.T @ np.linalg.solve(K[np.ix_(i, i)], load)
    nb = len(b)

    def reduced_d2(se):
        lam = np.diag(se.K)[nb:]
        return se.M[:nb, nb:] @ (se.M[nb:, :nb] / lam[:, None])

    scale = np.abs(D2).max()
    np.testing.assert_allclose(reduced_d2(aug), D2, atol=1e-9 * scale)
    assert np.abs(reduced_d2(plain) - D2).max() > 1e-4 * scale
