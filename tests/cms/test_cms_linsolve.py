"""Linear-solver backends: block solves, fallback without CHOLMOD, singularity."""
import sys

import numpy as np
import pytest
import scipy.sparse as sp

from cms import linsolve
from cms.errors import InteriorMechanismError, ReductionError
from tests.support.fe_models import box


def _spd():
    m = box(lengths=(0.3, 0.1, 0.1), divisions=(3, 1, 1))
    b = m.dofs_where(lambda x: np.isclose(x[0], 0.0))
    i = np.setdiff1d(np.arange(m.n), b)
    return m.K[i][:, i].tocsc()


@pytest.mark.parametrize("backend", ["scipy"] + (["cholmod"] if linsolve.cholmod_available() else []))
def test_block_solve_residual(backend):
    A = _spd()
    B = np.random.default_rng(0).standard_normal((A.shape[0], 7))
    F = linsolve.factor(A, backend=backend)
    X = F.solve(B)
    # backward-stable direct solve: residual ~ eps * cond(A) * ||B||; a clamped P2 block
    # has cond ~ 1e6, so 1e-8 relative is a round-off bound with margin
    assert np.linalg.norm(A @ X - B) <= 1e-8 * np.linalg.norm(B)
    assert F.n_solves == 1 and F.n_rhs == 7


def test_falls_back_to_scipy_without_cholmod(monkeypatch):
    monkeypatch.setitem(sys.modules, "sksparse.cholmod", None)   # import now fails
    assert not linsolve.cholmod_available()
    assert linsolve.default_backend() == "scipy"
    F = linsolve.factor(_spd())
    assert F.backend == "scipy"
    with pytest.raises(ReductionError) as ei:
        linsolve.factor(_spd(), backend="cholmod")
    assert ei.value.value == "cholmod"


@pytest.mark.parametrize("backend", ["scipy"] + (["cholmod"] if linsolve.cholmod_available() else []))
def test_singular_matrix_raises_mechanism_error(backend):
    m = box(lengths=(0.3, 0.1, 0.1), divisions=(3, 1, 1))   # free-free: 6 rigid modes
    with pytest.raises(InteriorMechanismError):
        linsolve.factor(m.K.tocsc(), backend=backend)


def test_unknown_backend_names_the_value():
    with pytest.raises(ReductionError) as ei:
        linsolve.factor(sp.eye(3).tocsc(), backend="mumps")
    assert ei.value.quantity == "backend" and ei.value.value == "mumps"
