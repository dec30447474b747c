"""Property tests of the Craig-Bampton reductor (cms.craig_bampton).

Test models: steel blocks meshed with scikit-fem P2 tetrahedra (tests.support.fe_models.box).
Tolerances are round-off bounds: the asserted identities are exact in exact
arithmetic (references in each test), so they hold to ~1e3 * machine epsilon
times the condition of the quantity compared.
"""
import numpy as np
import pytest
import scipy.linalg as sla
from hypothesis import example, given, settings
from hypothesis import strategies as st

from cms.craig_bampton import CraigBamptonReductor, SolverOptions, guyan
from cms.errors import InteriorMechanismError, ReductionError
from cms.linsolve import cholmod_available
from tests.support.fe_models import box

BACKENDS = ["scipy"] + (["cholmod"] if cholmod_available() else [])
E, NU, RHO = 210e9, 0.3, 7850.0  # steel: Pa, -, kg/m^3


def _dense_rtol(lam_max, lam):
    """Round-off bound of a dense generalized eigh (backward stable): the absolute
    eigenvalue error is ~ eps * lambda_max (Golub & Van Loan 4th ed., sec. 8.7), so
    the relative error of lambda is ~ eps * lambda_max / lambda; factor 10 for n."""
    return 10 * np.finfo(float).eps * lam_max / np.asarray(lam)


def _ends(m, L):
    """DOFs of the faces x = 0 and x = L."""
    return m.dofs_where(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], L))


def _rigid_props(Mrr):
    """Mass (kg), centre of mass (m), inertia about the COM (kg m^2) from the
    6x6 rigid-body mass matrix R^T M R about the origin, R = [I | -p~] per node:
    R^T M R = [[m I, -m c~], [m c~, J_O]] with J_O = J_c - m c~ c~ (parallel axes)."""
    m = Mrr[0, 0]
    cx = Mrr[3:, :3] / m               # = c~
    c = np.array([cx[2, 1], cx[0, 2], cx[1, 0]])
    Jc = Mrr[3:, 3:] + m * cx @ cx
    return m, c, Jc


@settings(max_examples=6, deadline=None)
@given(a=st.floats(0.2, 1.0), b=st.floats(0.05, 0.3), c=st.floats(0.05, 0.3),
       n_modes=st.integers(0, 8))
# slender bar (aspect 18) whose first bending mode is ~1e-6 * lambda_max: it once
# failed an ad-hoc "elastic > 1e-6 lambda_max" bound that had no physical basis
@example(a=1.0, b=0.0625, c=0.0546875, n_modes=0)
def test_free_free_superelement_rigid_modes_and_mass_properties(a, b, c, n_modes):
    m = box(lengths=(a, b, c), divisions=(4, 2, 2))
    se = CraigBamptonReductor(m.K, m.M, _ends(m, a), n_modes=n_modes,
                              node_coords=m.node_coords).reduce()
    # exactly 6 rigid modes: omega^2 = 0 analytically for the 6 rigid motions,
    # numerically ~ eps * lambda_max (dense eigh, Golub & Van Loan sec. 8.7)
    lam = sla.eigh(se.K, se.M, eigvals_only=True)
    n_rigid = np.sum(np.abs(lam) < 1e-9 * lam.max())
    assert n_rigid == 6
    # the 7th is a true elastic mode: Craig-Bampton is a Rayleigh-Ritz projection
    # of the full model, so by the minimax principle (Courant-Fischer) every reduced
    # eigenvalue bounds the full one from above, lambda_i(CB) >= lambda_i(FE),
    # and the full free-free solid has exactly six zero eigenvalues
    lam_fe = sla.eigh(m.K.toarray(), m.M.toarray(), eigvals_only=True)
    assert np.sum(np.abs(lam_fe) < 1e-9 * lam_fe.max()) == 6
    assert lam[6] >= lam_fe[6] * (1 - _dense_rtol(lam_fe.max(), lam_fe[6]))
    # reduced rigid-body mass matrix = full one (Psi R_b = R_i exactly) ...
    R = se.metadata["self_checks"]
    full = np.array(R["rigid_mass_matrix_full"])
    from cms.rigid import rigid_body_basis, solid_dof_layout
    Rf = rigid_body_basis(*solid_dof_layout(m.node_coords))
    Rr = np.zeros((se.K.shape[0], 6))
    Rr[:se.n_boundary] = Rf[se.boundary_dofs]
    red = Rr.T @ se.M @ Rr
    mf, cf, Jf = _rigid_props(full)
    mr, cr, Jr = _rigid_props(red)
    assert abs(mr - mf) <= 1e-10 * mf
    assert np.linalg.norm(cr - cf) <= 1e-10 * np.linalg.norm(cf)
    assert np.abs(Jr - Jf).max() <= 1e-10 * np.abs(Jf).max()
    # ... and both equal the analytic block: m = rho a b c, COM at the centre,
    # J_xx = m (b^2 + c^2) / 12 etc. (P2 consistent mass integrates exactly)
    mass = RHO * a * b * c
    assert abs(mf - mass) <= 1e-10 * mass
    assert np.allclose(cf, [a / 2, b / 2, c / 2], rtol=1e-10, atol=0)
    Jexact = mass / 12 * np.diag([b**2 + c**2, a**2 + c**2, a**2 + b**2])
    assert np.abs(Jf - Jexact).max() <= 1e-10 * np.abs(Jexact).max()


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("n_modes", [0, 5])
def test_static_interface_loads_reproduced_exactly(backend, n_modes):
    # CB contains the exact static response to boundary loads (constraint modes),
    # so K_r q = f_r reproduces the full static solution (Craig & Bampton 1968).
    L = 1.0
    m = box(lengths=(L, 0.1, 0.1), divisions=(10, 2, 2))
    b = _ends(m, L)
    se = CraigBamptonReductor(m.K, m.M, b, n_modes=n_modes, node_coords=m.node_coords,
                              options=SolverOptions(backend=backend)).reduce()
    clamped = np.isclose(m.node_coords[b // 3, 0], 0.0)   # boundary DOFs on x = 0
    rng = np.random.default_rng(1)
    f_b = np.where(clamped, 0.0, rng.standard_normal(len(b)) * 1e3)   # N
    # full model, face x = 0 clamped
    free = np.setdiff1d(np.arange(m.n), b[clamped])
    f = np.zeros(m.n)
    f[b] = f_b
    u = np.zeros(m.n)
    u[free] = sla.solve(m.K[free][:, free].toarray(), f[free], assume_a="pos")
    # reduced model, same clamp
    keep = np.r_[np.flatnonzero(~clamped), se.n_boundary + np.arange(se.n_modes)]
    fr = np.r_[f_b, np.zeros(se.n_modes)]
    q = np.zeros(se.K.shape[0])
    q[keep] = sla.solve(se.K[np.ix_(keep, keep)], fr[keep], assume_a="pos")
    ur = se.reconstruct(q)
    assert np.linalg.norm(ur - u) <= 1e-10 * np.linalg.norm(u)


def test_all_modes_kept_gives_full_eigenvalues():
    # with every fixed-interface mode kept, the CB basis spans R^n: the reduced
    # pencil is congruent to the full one, so the spectra coincide.
    m = box(lengths=(0.3, 0.1, 0.1), divisions=(2, 1, 1))
    b = m.dofs_where(lambda x: np.isclose(x[0], 0.0))
    ni = m.n - len(b)
    se = CraigBamptonReductor(m.K, m.M, b, n_modes=ni, node_coords=m.node_coords).reduce()
    lam_r = sla.eigh(se.K, se.M, eigvals_only=True)
    lam_f = sla.eigh(m.K.toarray(), m.M.toarray(), eigvals_only=True)
    el = slice(6, None)  # rigid modes compared in absolute terms below
    assert np.allclose(lam_r[el], lam_f[el], rtol=1e-9, atol=0)
    assert np.all(np.abs(lam_r[:6]) < 1e-9 * lam_f.max())


def test_frequencies_converge_from_above_as_modes_are_added():
    # nested Ritz subspaces: each reduced eigenvalue is an upper bound of the full
    # one and non-increasing as modes are added (Courant-Fischer min-max).
    # Free-free block with one end face as boundary: elastic modes 7.. compared.
    m = box(lengths=(1.0, 0.1, 0.1), divisions=(8, 2, 2))
    b = m.dofs_where(lambda x: np.isclose(x[0], 0.0))
    full = sla.eigh(m.K.toarray(), m.M.toarray(), eigvals_only=True,
                    subset_by_index=[6, 11])
    prev = None
    for k in [0, 4, 8, 16, 32]:
        se = CraigBamptonReductor(m.K, m.M, b, n_modes=k).reduce()
        lam = sla.eigh(se.K, se.M, eigvals_only=True)[6:12]
        assert np.all(lam >= full * (1 - 1e-10))
        if prev is not None:
            assert np.all(lam <= prev * (1 + 1e-10))
            assert lam.sum() < prev.sum()   # and strictly improving overall
        prev = lam
    assert np.all(prev - full <= 1e-3 * full)   # 32 modes: the first six within 0.1 %


def test_fixed_interface_modes_mass_normalised_and_match_dense():
    m = box(lengths=(1.0, 0.1, 0.1), divisions=(12, 2, 2))
    b = _ends(m, 1.0)
    se = CraigBamptonReductor(m.K, m.M, b, n_modes=10, node_coords=m.node_coords).reduce()
    i = se.interior_dofs
    Mii = m.M[i][:, i]
    assert np.allclose(se.Phi.T @ (Mii @ se.Phi), np.eye(10), atol=1e-10)
    lam_all = sla.eigh(m.K[i][:, i].toarray(), Mii.toarray(), eigvals_only=True)
    lam = lam_all[:10]
    assert np.all(np.abs(se.eigenvalues / lam - 1) <= _dense_rtol(lam_all[-1], lam))
    assert np.allclose(se.mode_frequencies_hz, np.sqrt(se.eigenvalues) / (2 * np.pi),
                       rtol=1e-15)
    assert np.allclose(se.K, se.K.T, rtol=0, atol=1e-12 * np.abs(se.K).max())
    assert np.allclose(se.M, se.M.T, rtol=0, atol=1e-12 * np.abs(se.M).max())


def test_cutoff_frequency_selects_modes_below_it():
    m = box(lengths=(1.0, 0.1, 0.1), divisions=(10, 2, 2))
    b = m.dofs_where(lambda x: np.isclose(x[0], 0.0))
    i = np.setdiff1d(np.arange(m.n), b)
    lam_all = sla.eigh(m.K[i][:, i].toarray(), m.M[i][:, i].toarray(), eigvals_only=True)
    lam = lam_all[:21]
    f = np.sqrt(lam) / (2 * np.pi)
    cut = 0.5 * (f[13] + f[14])          # halfway between modes 14 and 15
    se = CraigBamptonReductor(m.K, m.M, b, cutoff_hz=cut).reduce()
    assert se.n_modes == 14
    assert np.all(np.abs(se.mode_frequencies_hz / f[:14] - 1)
                  <= _dense_rtol(lam_all[-1], lam[:14]))


def test_boundary_order_is_kept_and_guyan_is_zero_mode_case():
    m = box(lengths=(0.5, 0.1, 0.1), divisions=(4, 1, 1))
    b = _ends(m, 0.5)
    perm = np.random.default_rng(3).permutation(len(b))
    names = [f"n{j // 3}:{'xyz'[j % 3]}" for j in range(m.n)]
    se1 = guyan(m.K, m.M, b, dof_names=names)
    se2 = guyan(m.K, m.M, b[perm], dof_names=names)
    assert se2.n_modes == 0
    assert se2.boundary_names == [names[j] for j in b[perm]]
    assert np.allclose(se2.K, se1.K[np.ix_(perm, perm)], rtol=0, atol=1e-12 * np.abs(se1.K).max())
    assert np.allclose(se2.M, se1.M[np.ix_(perm, perm)], rtol=0, atol=1e-12 * np.abs(se1.M).max())


@pytest.mark.parametrize("backend", BACKENDS)
def test_boundary_on_a_line_names_the_free_rotation(backend):
    # nodes on the edge y = z = 0 cannot stop rotation about that edge
    m = box(lengths=(0.5, 0.1, 0.1), divisions=(4, 1, 1))
    b = m.dofs_where(lambda x: np.isclose(x[1], 0.0) & np.isclose(x[2], 0.0))
    with pytest.raises(InteriorMechanismError) as ei:
        CraigBamptonReductor(m.K, m.M, b, n_modes=2, node_coords=m.node_coords,
                             options=SolverOptions(backend=backend)).reduce()
    assert ei.value.motion.startswith("rotation about x through point (")
    assert np.allclose(np.abs(ei.value.components), [0, 0, 0, 1, 0, 0], atol=1e-9)


def test_partial_boundary_names_every_free_motion():
    # holding only u_x on the face x = 0 leaves y, z translation and x rotation free
    m = box(lengths=(0.5, 0.1, 0.1), divisions=(4, 1, 1))
    b = m.dofs_where(lambda x: np.isclose(x[0], 0.0))
    b = b[b % 3 == 0]
    with pytest.raises(InteriorMechanismError) as ei:
        CraigBamptonReductor(m.K, m.M, b, n_modes=0, node_coords=m.node_coords).reduce()
    assert ei.value.motion.count(";") == 2
    assert "rotation about x" in ei.value.motion


@pytest.mark.parametrize("backend", BACKENDS)
def test_unidentified_mechanism_raises_without_rigid_info(backend):
    # two disconnected blocks, boundary on the first only: the second floats.
    import scipy.sparse as sp
    m = box(lengths=(0.5, 0.1, 0.1), divisions=(3, 1, 1))
    K = sp.block_diag([m.K, m.K]).tocsr()
    M = sp.block_diag([m.M, m.M]).tocsr()
    b = m.dofs_where(lambda x: np.isclose(x[0], 0.0))
    with pytest.raises(InteriorMechanismError) as ei:
        CraigBamptonReductor(K, M, b, n_modes=2, options=SolverOptions(backend=backend)).reduce()
    assert "unidentified" in ei.value.motion


def test_bad_inputs_carry_the_value():
    m = box(lengths=(0.5, 0.1, 0.1), divisions=(2, 1, 1))
    with pytest.raises(ReductionError) as ei:
        CraigBamptonReductor(m.K, m.M, [0, 1, m.n], n_modes=1)
    assert ei.value.quantity == "boundary_dofs" and ei.value.value == m.n
    with pytest.raises(ReductionError) as ei:
        CraigBamptonReductor(m.K, m.M, [0, 1, 1], n_modes=1)
    assert ei.value.value == [1]
    with pytest.raises(ReductionError):
        CraigBamptonReductor(m.K, m.M, [0], n_modes=1, cutoff_hz=10.0)
    with pytest.raises(ReductionError) as ei:
        CraigBamptonReductor(m.K, m.M, [0], n_modes=1, options={"tol": 1e-8})
    assert ei.value.quantity == "options" and ei.value.value == {"tol": 1e-8}


@pytest.mark.parametrize("method", ["arpack", "block"])
def test_eigen_methods_agree_with_dense_and_are_mass_normalised(method):
    from cms.eigen import lowest_modes
    m = box(lengths=(1.0, 0.1, 0.1), divisions=(12, 2, 2))
    b = m.dofs_where(lambda x: np.isclose(x[0], 0.0))
    i = np.setdiff1d(np.arange(m.n), b)
    K, M = m.K[i][:, i], m.M[i][:, i]
    r = lowest_modes(K, M, 12, method=method, tol=1e-8)
    lam_all = sla.eigh(K.toarray(), M.toarray(), eigvals_only=True)
    assert np.all(np.abs(r.eigenvalues / lam_all[:12] - 1) <= _dense_rtol(lam_all[-1], lam_all[:12]))
    assert np.allclose(r.vectors.T @ (M @ r.vectors), np.eye(12), atol=1e-10)
    assert r.residuals.max() <= 1e-8
