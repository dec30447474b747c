"""RBE2 / RBE3 couplings: exactness, rigid-body modes, master conventions."""
from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from cms.eigen import free_free_shift, lowest_modes
from fe_components.coupling import couple, couple_nodes, rbe3_operator, rigid_kinematics
from fe_components.errors import CouplingError
from fe_components.fe_model import build_component
from fe_components.material import STEEL
from fe_components.reference import CASES, REF_DIR


def _model(name):
    params, options = CASES[name]
    return build_component(params, STEEL, options=options, cache_dir=REF_DIR)


@pytest.fixture(scope="module")
def cyl():
    return _model("cylinder")


@pytest.fixture(scope="module")
def carrier():
    return _model("carrier")


def _rigid_field(nodes, u0, th):
    return (u0[None, :] + np.cross(th[None, :], nodes)).ravel()


def test_rigid_kinematics_is_small_rotation():
    # u = u0 + theta x r for a point r from the master
    G = rigid_kinematics(np.array([[1.0, 2.0, 3.0]]), np.zeros(3))
    q = np.array([0.1, 0.2, 0.3, 0.01, 0.02, 0.03])
    np.testing.assert_allclose(G @ q, q[:3] + np.cross(q[3:], [1.0, 2.0, 3.0]))


def test_rbe3_reproduces_rigid_motion_and_resultant():
    rng = np.random.default_rng(0)
    pts = rng.normal(size=(30, 3))
    xm = np.array([0.1, -0.2, 0.3])
    A = rbe3_operator(pts, xm)
    np.testing.assert_allclose(A @ rigid_kinematics(pts, xm), np.eye(6), atol=1e-12)
    # a master load f_m is carried by slave forces A^T f_m with the same force and moment about x_m
    fm = np.array([1.0, -2.0, 3.0, 0.4, 0.5, -0.6])
    fs = (A.T @ fm).reshape(-1, 3)
    np.testing.assert_allclose(fs.sum(axis=0), fm[:3], atol=1e-12)
    np.testing.assert_allclose(np.cross(pts - xm, fs).sum(axis=0), fm[3:], atol=1e-12)


def test_rbe3_only_is_exact_change_of_variables(cyl):
    c = couple(cyl, {"end_a": "rbe3", "end_b": "rbe3"})
    assert c.T.shape[0] == c.T.shape[1] == cyl.n_dofs  # square: no DOF removed
    f0 = lowest_modes(cyl.K, cyl.M, 14, sigma=free_free_shift(cyl.K, cyl.M)).frequencies_hz
    f1 = lowest_modes(c.K_c, c.M_c, 14, sigma=free_free_shift(c.K_c, c.M_c)).frequencies_hz
    assert np.all(np.abs(f1[:6]) < 1e-3 * f1[6])
    np.testing.assert_allclose(f1[6:], f0[6:], rtol=1e-8)  # RBE3 adds no stiffness


def test_rbe2_keeps_six_rigid_modes_and_stiffens(cyl):
    c = couple(cyl, {"end_a": "rbe2", "end_b": "rbe2"})
    f0 = lowest_modes(cyl.K, cyl.M, 14, sigma=free_free_shift(cyl.K, cyl.M)).frequencies_hz
    f1 = lowest_modes(c.K_c, c.M_c, 14, sigma=free_free_shift(c.K_c, c.M_c)).frequencies_hz
    assert np.all(np.abs(f1[:6]) < 1e-3 * f1[6])
    # constraints can only raise eigenvalues (Courant-Fischer / Rayleigh's theorem)
    assert np.all(f1[6:] >= f0[6:] * (1 - 1e-9))


@pytest.mark.parametrize("kind", ["rbe2", "rbe3"])
def test_masters_carry_rigid_motion(cyl, kind):
    c = couple(cyl, {"end_a": kind, "end_b": kind})
    u0, th = np.array([1e-3, -2e-3, 3e-4]), np.array([2e-3, 1e-3, -4e-3])
    u = _rigid_field(cyl.nodes, u0, th)
    # the rigid field is representable: T q = u has an exact solution
    q = spla.lsqr(c.T, u, atol=1e-15, btol=1e-15, iter_lim=20000)[0]
    np.testing.assert_allclose(c.T @ q, u, atol=1e-10)
    for name, pos, idx in c.masters:  # and its master coordinates are the rigid motion at the master
        np.testing.assert_allclose(q[idx], np.r_[u0 + np.cross(th, pos), th], atol=1e-9)
    np.testing.assert_allclose(q[: len(c.retained)], u[c.retained], atol=1e-10)


@pytest.mark.slow
def test_rbe3_on_a_large_patch_stays_sparse():
    m = _model("pinion_involute")
    c = couple(m, {"gear_mesh": "rbe3", "bearing_a": "rbe3", "bearing_b": "rbe3"})
    n_patch = 3 * len(m.interfaces["gear_mesh"].nodes)
    assert c.K_c.shape == m.K.shape
    # A single pivot elimination would add a dense n_patch^2 block.  On the binary cluster tree each
    # patch DOF lies in the columns of at most depth + 1 levels (depth = log2(nodes / 3), leaves of
    # >= 3 nodes), each level coupling it to about one row of K: fill <= (depth + 1) rows per DOF.
    row = m.K.nnz / m.n_dofs
    depth = np.log2(n_patch / 3 / 3)
    assert c.K_c.nnz - m.K.nnz < (depth + 1) * row * n_patch < 0.1 * n_patch**2
    f0 = lowest_modes(m.K, m.M, 8, sigma=free_free_shift(m.K, m.M)).frequencies_hz
    f1 = lowest_modes(c.K_c, c.M_c, 8, sigma=free_free_shift(c.K_c, c.M_c)).frequencies_hz
    np.testing.assert_allclose(f1[6:], f0[6:], rtol=1e-8)


def test_carrier_default_coupling_conventions(carrier):
    c = couple(carrier)
    names = [n for n, _, _ in c.masters]
    assert names == ["pin_0", "pin_1", "pin_2", "bearing_a", "bearing_b", "output_bore"]
    assert c.kinds["pin_0"] == "rbe2"
    idx = np.concatenate([i for _, _, i in c.masters])
    np.testing.assert_array_equal(idx, c.boundary_dofs)
    assert c.boundary_dofs.size == 6 * 6 and c.boundary_dofs[-1] == c.K_c.shape[0] - 1
    assert sp.isspmatrix_csr(c.K_c) and sp.isspmatrix_csr(c.M_c)
    f = lowest_modes(c.K_c, c.M_c, 8, sigma=free_free_shift(c.K_c, c.M_c)).frequencies_hz
    assert np.all(np.abs(f[:6]) < 1e-3 * f[6])


def test_overlapping_or_unknown_interfaces_refused(carrier):
    with pytest.raises(CouplingError):
        couple(carrier, {"no_such": "rbe2"})
    with pytest.raises(CouplingError):
        couple(carrier, {"pin_0": "glue"})


def test_couple_nodes_refuses_bad_node_sets_with_the_value(cyl):
    a, b = cyl.interfaces["end_a"], cyl.interfaces["end_b"]
    with pytest.raises(CouplingError) as e:
        couple_nodes(cyl.K, cyl.M, cyl.nodes, {"a": (a.nodes, a.master, "rbe2"), "b": (a.nodes[:3], b.master, "rbe2")})
    assert e.value.parameter == "b" and e.value.value == 3  # three shared nodes
    with pytest.raises(CouplingError) as e:
        couple_nodes(cyl.K, cyl.M, cyl.nodes, {"a": (np.r_[a.nodes, cyl.n_nodes], a.master, "rbe2")})
    assert e.value.parameter == "a" and e.value.value == cyl.n_nodes


def test_dof_layout_places_retained_dofs_at_nodes_and_masters_at_masters(cyl):
    c = couple(cyl, {"end_a": "rbe2", "end_b": "rbe2"})
    points, kinds = c.dof_layout(cyl.nodes)
    n_ret = len(c.retained)
    np.testing.assert_array_equal(points[:n_ret], cyl.nodes[c.retained // 3])
    np.testing.assert_array_equal(kinds[:n_ret], c.retained % 3)
    for name, pos, idx in c.masters:
        np.testing.assert_array_equal(points[idx], np.repeat(pos[None], 6, 0))
        np.testing.assert_array_equal(kinds[idx], np.arange(6))
    assert c.boundary_names[:2] == ["end_a:ux", "end_a:uy"] and c.boundary_names[-1] == "end_b:rz"
    with pytest.raises(CouplingError):  # RBE3 null-space coordinates have no location
        couple(cyl, {"end_a": "rbe3"}).dof_layout(cyl.nodes)


@pytest.mark.parametrize("kinds", [{}, {"end_a": "rbe3", "end_b": "rbe3"}, {"end_a": "rbe2", "end_b": "rbe3"}])
def test_public_rigid_body_basis_is_free_and_carries_the_mesh_mass(cyl, kinds):
    """The coupled model's rigid basis (public, any mix of RBE2/RBE3): no strain energy
    (K_c R = 0 to round-off of the K assembly) and R' M_c R equals the rigid-body mass matrix
    of the full mesh (mass, first moments, inertia: T R_c is the exact rigid field, so
    R' M_c R = R_full' M R_full exactly)."""
    c = couple(cyl, kinds)
    ref = np.array([0.01, -0.02, 0.2])                    # any reference point, m
    R = c.rigid_body_basis(ref)
    Kn = abs(c.K_c).sum(axis=0).max()
    assert np.abs(c.K_c @ R).max() < 1e-9 * Kn * np.abs(R).max()
    Rfull = rigid_kinematics(cyl.nodes, ref)
    np.testing.assert_allclose(R.T @ (c.M_c @ R), Rfull.T @ (cyl.M @ Rfull), rtol=1e-10,
                               atol=1e-12 * cyl.mass)
    np.testing.assert_allclose((R.T @ (c.M_c @ R))[0, 0], cyl.mass, rtol=1e-10)


def test_reductor_runs_its_rigid_checks_with_the_public_basis_and_warns_without(cyl, caplog):
    """With the coupled model's rigid basis the reductor checks rigid mass; without any
    rigid-body information it says so in a warning and in its self-checks."""
    from cms.craig_bampton import CraigBamptonReductor
    c = couple(cyl, {"end_a": "rbe3", "end_b": "rbe2"})
    se = CraigBamptonReductor(c.K_c, c.M_c, c.boundary_dofs, n_modes=4,
                              rigid_body_basis=c.rigid_body_basis(cyl.center_of_mass)).reduce()
    assert "rigid_basis_residual" in se.metadata["self_checks"]
    with caplog.at_level("WARNING"):
        se = CraigBamptonReductor(c.K_c, c.M_c, c.boundary_dofs, n_modes=4).reduce()
    assert se.metadata["self_checks"]["rigid_body_checks"].startswith("skipped")
    assert any("rigid-body information" in r.getMessage() for r in caplog.records)
