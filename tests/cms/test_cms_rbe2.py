"""RBE2 coupling of a solid (fe_components.coupling.couple_nodes) followed by Craig-Bampton:
the masters carry the rigid-body motions, and the superelement keeps exactly six rigid modes."""
import numpy as np
import scipy.linalg as sla

from cms.craig_bampton import CraigBamptonReductor
from cms.rigid import rigid_body_basis, solid_dof_layout
from fe_components.coupling import couple_nodes
from tests.support.fe_models import box


def test_rigid_motion_of_masters_moves_the_body_rigidly_and_cb_has_six_rigid_modes():
    m = box(lengths=(0.5, 0.1, 0.1), divisions=(4, 1, 1))
    X = m.node_coords
    c = couple_nodes(m.K, m.M, X, {"a": (np.flatnonzero(np.isclose(X[:, 0], 0.0)), [0, 0.05, 0.05], "rbe2"),
                                   "b": (np.flatnonzero(np.isclose(X[:, 0], 0.5)), [0.5, 0.05, 0.05], "rbe2")})
    layout = c.dof_layout(X)
    R = rigid_body_basis(*layout)
    # T maps the coupled rigid motions onto the solid's rigid motions (exact kinematics)
    assert np.allclose(c.T @ R, rigid_body_basis(*solid_dof_layout(X)), atol=1e-14)
    # and they carry no strain energy: K_c R = 0 to round-off of ||K||
    assert np.abs(c.K_c @ R).max() <= 1e-12 * abs(c.K_c).sum(axis=0).max()
    se = CraigBamptonReductor(c.K_c, c.M_c, c.boundary_dofs, n_modes=5, dof_layout=layout,
                              dof_names=c.boundary_names).reduce()
    assert se.boundary_names[:2] == ["a:ux", "a:uy"] and se.boundary_names[-1] == "b:rz"
    assert np.allclose(se.boundary_points[-1], [0.5, 0.05, 0.05])
    lam = sla.eigh(se.K, se.M, eigvals_only=True)
    assert np.sum(np.abs(lam) < 1e-9 * lam.max()) == 6
    # mass is conserved by the tie (masters massless): m = rho V
    assert abs(se.metadata["self_checks"]["rigid_mass_matrix_full"][0][0] - 7850.0 * 0.5 * 0.01) \
        <= 1e-10 * 7850.0 * 0.5 * 0.01
