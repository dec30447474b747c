"""Rigid (RBE2) coupling helper used by the cms tests and benchmark."""
import numpy as np
import scipy.linalg as sla

from cms.craig_bampton import CraigBamptonReductor
from cms.rbe2 import couple_rigid

from tests.support.fe_models import box


def test_rigid_motion_of_masters_moves_the_body_rigidly_and_cb_has_six_rigid_modes():
    m = box(lengths=(0.5, 0.1, 0.1), divisions=(4, 1, 1))
    X = m.node_coords
    ends = [np.flatnonzero(np.isclose(X[:, 0], 0.0)), np.flatnonzero(np.isclose(X[:, 0], 0.5))]
    c = couple_rigid(m.K, m.M, X, ends, master_points=[[0, 0.05, 0.05], [0.5, 0.05, 0.05]],
                     names=["a", "b"])
    R = c.rigid_body_basis
    # T maps the coupled rigid motions onto the solid's rigid motions (exact kinematics)
    from cms.rigid import rigid_body_basis, solid_dof_layout
    assert np.allclose(c.T @ R, rigid_body_basis(*solid_dof_layout(X)), atol=1e-14)
    # and they carry no strain energy: K_c R = 0 to round-off of ||K||
    assert np.abs(c.K @ R).max() <= 1e-12 * abs(c.K).sum(axis=0).max()
    se = CraigBamptonReductor(c.K, c.M, c.boundary_dofs, n_modes=5, dof_layout=c.dof_layout,
                              dof_names=c.boundary_names).reduce()
    assert se.boundary_names[:2] == ["a:ux", "a:uy"] and se.boundary_names[-1] == "b:rz"
    assert np.allclose(se.boundary_points[-1], [0.5, 0.05, 0.05])
    lam = sla.eigh(se.K, se.M, eigvals_only=True)
    assert np.sum(np.abs(lam) < 1e-9 * lam.max()) == 6
    # mass is conserved by the tie (masters massless): m = rho V
    assert abs(se.metadata["self_checks"]["rigid_mass_matrix_full"][0][0] - 7850.0 * 0.5 * 0.01) \
        <= 1e-10 * 7850.0 * 0.5 * 0.01
