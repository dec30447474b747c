"""The small-model eigen-solve with NumPy alone (assembly.analysis.modal.numpy_eigh, used up to
SMALL_DENSE DOFs so that ``flexgear modes`` imports no SciPy) gives the modes SciPy's
generalized solver gives, to round-off.

Both solves are backward stable (Cholesky of the mass, the symmetric standard form, a
symmetric eigensolver: Golub & Van Loan, Matrix Computations, 4th ed., sec. 8.7.2): each
eigenvalue is exact for a pencil perturbed by ~eps of its norm, so two of them differ by
~eps lambda_max, relative eps lambda_max / lambda for an elastic mode, and a mode's shape
by ~eps lambda_max / gap (gap: the distance to the nearest other eigenvalue). The scenes
here spread lambda_max / lambda_min,elastic over 15-1.4e3 (checked below), so 1e-10 on the
frequencies and 1 - 1e-10 on the MAC leave a margin of 1e3 or more over that bound.
Repeated frequencies have no one shape: their group's span is compared (the MAC of the
subspaces, the smallest squared cosine of their principal angles).
"""
from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from assembly.analysis import modal
from assembly.analysis.modal import numpy_eigh, solve_modes
from assembly.model.assemble import assemble
from assembly.scene.schema import load_scene

EPS = np.finfo(float).eps
#: Frequencies agree to this relative error, and each mode's (or group's) MAC to 1 minus this.
RTOL = 1e-10
#: Two helical pairs (B = I: rigid bodies at their centres of mass), a planetary stage (three
#: planets, repeated modes; B off-diagonal: planets ride on the carrier) and a two-stage box.
SCENES = ("kahraman_beta20", "lin_parker_n3", "two_stage_quill")


def scaled_pencil(name: str):
    """The unit-mass-diagonal pencil (A, B) of a shipped scene, as the dense solve scales it."""
    m = assemble(load_scene(name))
    K, M = m.K.toarray(), m.M.toarray()
    u = 1.0 / np.sqrt(np.diag(M))
    return u[:, None] * K * u[None, :], u[:, None] * M * u[None, :]


def subspace_mac(X: np.ndarray, Y: np.ndarray, B: np.ndarray) -> float:
    """Smallest squared cosine of the principal angles between the B-orthonormal columns X, Y."""
    return float(np.linalg.svd(X.T @ B @ Y, compute_uv=False).min() ** 2)


@pytest.mark.parametrize("name", SCENES)
def test_numpy_pencil_solve_equals_scipy(name):
    A, B = scaled_pencil(name)
    lam, X = numpy_eigh(A, B)
    lam_s, X_s = sla.eigh(A, B)
    top = lam_s[-1]
    elastic = lam_s > 1e-8 * top               # rigid-body modes: lambda = 0 to round-off of lambda_max
    assert top / lam_s[elastic].min() < 1e4    # the spread the tolerance was derived for (module notes)
    assert np.all(np.abs(lam[~elastic]) <= 1e3 * EPS * top)
    np.testing.assert_allclose(np.sqrt(lam[elastic]), np.sqrt(lam_s[elastic]), rtol=RTOL, atol=0)
    np.testing.assert_allclose(X.T @ B @ X, np.eye(len(lam)), atol=1e3 * EPS)     # B-orthonormal
    # groups of equal eigenvalues (to the round-off bound), compared as subspaces
    edges = np.flatnonzero(np.diff(lam_s) > 1e-9 * top) + 1
    for g in np.split(np.arange(len(lam_s)), edges):
        assert subspace_mac(X[:, g], X_s[:, g], B) >= 1 - RTOL, (name, g)


@pytest.mark.parametrize("name", SCENES)
def test_solve_modes_numpy_and_scipy_paths_agree(name, monkeypatch):
    """The same scene through solve_modes with the NumPy solve (n <= SMALL_DENSE) and with
    the SciPy one (SMALL_DENSE set to 0): frequencies and mass-normalised shapes agree."""
    model = assemble(load_scene(name))
    assert model.K.shape[0] <= modal.SMALL_DENSE
    a = solve_modes(model)
    monkeypatch.setattr(modal, "SMALL_DENSE", 0)
    b = solve_modes(model)
    assert a.n_rigid == b.n_rigid and [len(g) for g in a.groups] == [len(g) for g in b.groups]
    el = slice(a.n_rigid, None)
    np.testing.assert_allclose(a.frequencies_hz[el], b.frequencies_hz[el], rtol=RTOL, atol=0)
    M = model.M.toarray()
    for g in a.groups:
        assert subspace_mac(a.shapes[:, g], b.shapes[:, g], M) >= 1 - RTOL, (name, g)


def test_numpy_solve_of_a_subset_is_the_lowest_modes():
    model = assemble(load_scene("lin_parker_n3"))
    full, low = solve_modes(model), solve_modes(model, n_modes=5)
    np.testing.assert_array_equal(low.frequencies_hz, full.frequencies_hz[:5])
    np.testing.assert_array_equal(low.shapes, full.shapes[:, :5])


def test_mass_not_positive_definite_is_refused():
    A = np.diag([1.0, 2.0])
    with pytest.raises(np.linalg.LinAlgError):
        numpy_eigh(A, np.array([[1.0, 2.0], [2.0, 1.0]]))     # eigenvalues 3 and -1
