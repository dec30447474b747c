"""Cutoff selection continues the eigen search (deflation) instead of restarting it: the
result must equal one solve of the same number of modes (exact linear algebra, no table)."""
import numpy as np

from cms.craig_bampton import CraigBamptonReductor
from tests.support.fe_models import box


def test_cutoff_continuation_equals_single_solve():
    m = box(lengths=(1.0, 0.1, 0.1), divisions=(20, 2, 2), order=1)
    end = m.dofs_where(lambda x: x[0] < 1e-9)          # clamp one end face
    f_all = CraigBamptonReductor(m.K, m.M, end, n_modes=40).reduce().mode_frequencies_hz
    cutoff = 0.5 * (f_all[29] + f_all[30])                 # 30 modes below: > 2 batches of 12
    a = CraigBamptonReductor(m.K, m.M, end, cutoff_hz=cutoff).reduce()
    b = CraigBamptonReductor(m.K, m.M, end, n_modes=30).reduce()
    assert a.n_modes == 30
    np.testing.assert_allclose(a.eigenvalues, b.eigenvalues, rtol=1e-10)
    Mii = m.M[a.interior_dofs][:, a.interior_dofs]
    np.testing.assert_allclose(a.Phi.T @ (Mii @ a.Phi), np.eye(30), atol=1e-10)


def test_cutoff_stops_at_max_modes_plus_one():
    # A cutoff with more modes below it than max_modes: the search computes max_modes + 1
    # modes and stops (ModeLimitError, with the last frequency found) instead of every
    # interior mode; exactly max_modes modes below the cutoff are kept.
    import pytest

    import cms.craig_bampton as cb
    from cms.errors import ModeLimitError, ReductionError
    m = box(lengths=(1.0, 0.1, 0.1), divisions=(20, 2, 2), order=1)
    end = m.dofs_where(lambda x: x[0] < 1e-9)
    f_all = CraigBamptonReductor(m.K, m.M, end, n_modes=40).reduce().mode_frequencies_hz
    cutoff = 0.5 * (f_all[29] + f_all[30])                 # 30 modes below the cutoff
    asked = []
    real = cb.lowest_modes

    def counting(K, M, k, **kw):
        asked.append(k)
        return real(K, M, k, **kw)
    cb.lowest_modes = counting
    try:
        with pytest.raises(ModeLimitError) as e:
            CraigBamptonReductor(m.K, m.M, end, cutoff_hz=cutoff, max_modes=20).reduce()
    finally:
        cb.lowest_modes = real
    assert sum(asked) == 21                                 # ARPACK batches deflate: no mode twice
    assert e.value.max_modes == 20 and e.value.highest_hz == pytest.approx(f_all[20], rel=1e-8)
    assert CraigBamptonReductor(m.K, m.M, end, cutoff_hz=cutoff, max_modes=30).reduce().n_modes == 30
    for kw in ({"cutoff_hz": np.inf}, {"cutoff_hz": np.nan}, {"n_modes": 31, "max_modes": 30},
               {"n_modes": 2.0}, {"n_modes": True}):
        with pytest.raises(ReductionError):
            CraigBamptonReductor(m.K, m.M, end, **kw)


def test_cutoff_search_with_the_block_eigensolver_equals_single_solve():
    # The block method does not deflate: each batch solves again for all modes found so far
    # plus the next batch (n_found + k); the cutoff's 30 modes equal one solve of 30.
    from cms.craig_bampton import SolverOptions
    m = box(lengths=(1.0, 0.1, 0.1), divisions=(20, 2, 2), order=1)
    end = m.dofs_where(lambda x: x[0] < 1e-9)
    block = SolverOptions(eigen_method="block")
    f_all = CraigBamptonReductor(m.K, m.M, end, n_modes=40).reduce().mode_frequencies_hz
    cutoff = 0.5 * (f_all[29] + f_all[30])
    a = CraigBamptonReductor(m.K, m.M, end, cutoff_hz=cutoff, options=block).reduce()
    b = CraigBamptonReductor(m.K, m.M, end, n_modes=30).reduce()
    assert a.n_modes == 30
    np.testing.assert_allclose(a.eigenvalues, b.eigenvalues, rtol=1e-9)
