"""Stress recovery from reduced coordinates against beam theory.

Both cases: reduce the clamped component with Craig-Bampton (boundary = loaded end
face), solve the static problem in reduced coordinates, back-expand, recover P2
nodal stresses and compare with the closed-form solution away from the ends
(Saint-Venant: end effects decay within about one cross-section size).
"""
import os

import meshio
import numpy as np
import scipy.linalg as sla
from skfem import Basis, ElementTetP2, ElementVector, FacetBasis, Functional, LinearForm, asm
from skfem.io.meshio import from_meshio

from cms.craig_bampton import CraigBamptonReductor
from cms.stress import principal, recover_stress, von_mises
from fe_components.coupling import couple_nodes
from tests.support.fe_models import assemble, box

E, NU, RHO = 210e9, 0.3, 7850.0   # steel: Pa, -, kg/m^3
MESHES = os.path.join(os.path.dirname(__file__), "..", "..", "meshes")


def _solve_reduced(m, clamp_dofs, face_dofs, f_face):
    """Clamp ``clamp_dofs``, reduce with the face as boundary, solve K_r q = f_r,
    return the full displacement (zeros on the clamp)."""
    free = np.setdiff1d(np.arange(m.n), clamp_dofs)
    pos = -np.ones(m.n, dtype=int)
    pos[free] = np.arange(len(free))
    b = pos[face_dofs]
    red = CraigBamptonReductor(m.K[free][:, free], m.M[free][:, free], b, n_modes=4)
    se = red.reduce()
    fr = np.r_[f_face, np.zeros(se.n_modes)]   # modal load Phi^T f_i = 0: f acts on boundary only
    q = sla.solve(se.K, fr, assume_a="pos")
    u = np.zeros(m.n)
    u[free] = red.reconstruct(q)
    return u


@Functional
def _polar_moment(w):
    """r^2 about the z axis: its volume integral over a shaft of length L is L J."""
    return w.x[0] ** 2 + w.x[1] ** 2


def test_shaft_in_pure_torsion_tau_equals_T_r_over_J():
    # gmsh cylinder R = 0.025 m, L = 0.1 m, axis z, 10-node (curved) tetrahedra, so
    # the section's J is that of the circle up to O(h^4) geometry error
    mesh = from_meshio(meshio.read(os.path.join(MESHES, "cms_shaft.msh")))
    R, L = 0.025, 0.1                                     # m
    m = assemble(mesh, E, NU, RHO, order=2)
    T = 1.0e3                     # torque, N m
    J = np.pi * R**4 / 2          # polar second moment of area, m^4
    # end face z = L tied rigidly to a master on the axis: pure torsion of a circular
    # shaft keeps cross-sections plane and rigid, so the tie adds no constraint.
    face_nodes = np.flatnonzero(np.isclose(m.node_coords[:, 2], L))
    c = couple_nodes(m.K, m.M, m.node_coords, {"flange": (face_nodes, [0, 0, L], "rbe2")})
    clamped_full = m.dofs_where(lambda x: np.isclose(x[2], 0.0))
    nc = c.K_c.shape[0]
    # coupled index of each clamped solid DOF: the first coordinates are the retained DOFs
    clamp_c = np.flatnonzero(np.isin(c.retained, clamped_full))
    assert len(clamp_c) == len(clamped_full)
    free = np.setdiff1d(np.arange(nc), clamp_c)
    where = -np.ones(nc, dtype=int)
    where[free] = np.arange(len(free))
    red = CraigBamptonReductor(c.K_c[free][:, free], c.M_c[free][:, free], where[c.boundary_dofs],
                               n_modes=4, dof_names=c.boundary_names)
    se = red.reduce()
    assert se.boundary_names[5] == "flange:rz"
    fr = np.zeros(se.K.shape[0])
    fr[5] = T                     # moment about z on the master, N m
    q = sla.solve(se.K, fr, assume_a="pos")
    # the shaft twists by phi = T L / (G J) (Saint-Venant), G = E / (2 (1 + nu)). P2 tetrahedra
    # hold the torsion field u = phi z / L (-y, x, 0) exactly, so what is left is the meshed
    # section: its polar moment (the volume integral of r^2 over the curved P2 mesh, / L) is
    # off by e_J (-7.1e-6 for this mesh), which moves the twist of a prism by -e_J; the
    # section's small variation along an unstructured mesh only stiffens it. So the twist is
    # within |e_J| of T L / (G J) (measured: 1.9e-6).
    G = E / (2 * (1 + NU))
    e_J = asm(_polar_moment, Basis(mesh, ElementTetP2(), intorder=6)) / (L * J) - 1
    assert 1e-7 < abs(e_J) < 1e-4                  # a P2 section's error, O(h^4)
    assert abs(q[5] / (T * L / (G * J)) - 1) <= abs(e_J)
    uc = np.zeros(nc)
    uc[free] = red.reconstruct(q)
    u = c.T @ uc
    s = recover_stress(m.basis, u, E, NU)
    x = s.points
    r = np.hypot(x[:, 0], x[:, 1])
    mid = (x[:, 2] > 0.25 * L) & (x[:, 2] < 0.75 * L)
    tau = T * r / J               # shear stress, Pa (Timoshenko & Goodier, torsion of a circular bar)
    tau_max = T * R / J
    # von Mises of pure shear is sqrt(3) tau; principal stresses (tau, 0, -tau)
    assert np.all(np.abs(s.von_mises[mid] - np.sqrt(3) * tau[mid]) <= 0.02 * np.sqrt(3) * tau_max)
    outer = mid & (r > 0.5 * R)
    assert np.all(np.abs(s.von_mises[outer] / (np.sqrt(3) * tau[outer]) - 1) <= 0.02)
    expected = np.c_[tau, np.zeros_like(tau), -tau][mid]
    assert np.all(np.abs(s.principal[mid] - expected) <= 0.02 * tau_max)


def test_cantilever_in_bending_sigma_equals_M_c_over_I():
    L, b, h = 1.0, 0.1, 0.1       # m
    m = box(lengths=(L, b, h), divisions=(20, 3, 4))
    P = 1.0e4                     # tip load in -z, N
    I = b * h**3 / 12             # second moment of area, m^4
    clamp = m.dofs_where(lambda x: np.isclose(x[0], 0.0))
    face = m.dofs_where(lambda x: np.isclose(x[0], L))
    fb = FacetBasis(m.basis.mesh, ElementVector(ElementTetP2()), intorder=4,
                    facets=m.basis.mesh.facets_satisfying(lambda x: np.isclose(x[0], L)))

    @LinearForm
    def shear(v, w):
        return -P / (b * h) * v[2]    # uniform shear traction on the tip face, Pa

    f = asm(shear, fb)
    u = _solve_reduced(m, clamp, face, f[face])
    s = recover_stress(m.basis, u, E, NU)
    x = s.points
    mid = (x[:, 0] > 0.25 * L) & (x[:, 0] < 0.75 * L)
    fibre = mid & (np.isclose(x[:, 2], 0.0) | np.isclose(x[:, 2], h))
    Mb = P * (L - x[:, 0])        # bending moment, N m
    z = x[:, 2] - h / 2           # distance from the neutral axis, m
    sxx = Mb * z / I              # Euler-Bernoulli: sigma = M c / I (tension on top)
    assert np.all(np.abs(s.sigma[fibre, 0, 0] / sxx[fibre] - 1) <= 0.02)
    # at the outer fibres shear vanishes: von Mises = |sigma_xx|, sigma_1 = max(sigma_xx, 0)
    assert np.all(np.abs(s.von_mises[fibre] / np.abs(sxx[fibre]) - 1) <= 0.02)
    top = fibre & (z > 0)
    assert np.all(np.abs(s.principal[top, 0] / sxx[top] - 1) <= 0.02)


def test_invariants_of_known_tensors():
    # uniaxial sigma: von Mises = |sigma|; pure shear tau: von Mises = sqrt(3) tau
    S = np.zeros((2, 3, 3))
    S[0, 0, 0] = 5.0
    S[1, 0, 1] = S[1, 1, 0] = 2.0
    assert np.allclose(von_mises(S), [5.0, 2.0 * np.sqrt(3)], rtol=1e-14)
    assert np.allclose(principal(S), [[5, 0, 0], [2, 0, -2]], atol=1e-14)


def test_stress_from_any_lagrange_basis_matches_exact_linear_stress():
    """The stress of a quadratic displacement field is linear in x, so its L2 projection onto
    P2 is exact: recover_stress must return it to round-off from every P2 vector basis a user
    may hold, whatever its quadrature order (a stiffness basis integrates at 2p - 2 = 2, too
    low for the P2 mass matrix of the projection; the recovery rebuilds at order 4)."""
    from skfem import Basis, MeshTet
    mesh = MeshTet.init_tensor(*(np.linspace(0.0, 0.1, 3),) * 3)   # 0.1 m cube, m
    a = 1e-2                                                        # 1/m: curvature of the field
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    mu = E / (2 * (1 + NU))
    for intorder in (1, 2, 3, 4, 6):
        b = Basis(mesh, ElementVector(ElementTetP2()), intorder=intorder)
        x, y, _ = b.doflocs[:, 0::3]
        u = np.zeros(b.N)
        u[0::3] = a * x * y          # eps_xx = a y, eps_xy = a x / 2
        u[1::3] = a * x * x / 2      # eps_xy += a x / 2 -> eps_xy = a x
        s = recover_stress(b, u, E, NU)
        X, Y, _ = s.points.T
        sxx = (lam + 2 * mu) * a * Y
        syy = szz = lam * a * Y
        sxy = 2 * mu * a * X
        scale = (lam + 2 * mu) * a * 0.1
        for got, want in ((s.sigma[:, 0, 0], sxx), (s.sigma[:, 1, 1], syy), (s.sigma[:, 2, 2], szz),
                          (s.sigma[:, 0, 1], sxy)):
            assert np.abs(got - want).max() < 1e-9 * scale, intorder


def test_stress_recovery_refuses_a_scalar_basis():
    from skfem import Basis, MeshTet

    from cms.errors import ReductionError
    b = Basis(MeshTet(), ElementTetP2())
    try:
        recover_stress(b, np.zeros(b.N), E, NU)
    except ReductionError as exc:
        assert exc.quantity == "basis"
    else:
        raise AssertionError("a scalar basis was accepted")
