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
