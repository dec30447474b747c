"""Validation of the FE models against analytic solutions (committed meshes, no gmsh run).

References
----------
* Timoshenko beam: S. P. Timoshenko, Phil. Mag. 41 (1921) 744; free-free
  frequency found here from the exact ODE solution (transfer matrix).
* Shear coefficient of a solid circular section: G. R. Cowper, J. Appl. Mech.
  33 (1966) 335, kappa = 6 (1 + nu) / (7 + 6 nu).
* Torsion of a free-free circular shaft: f_1 = (1 / 2L) sqrt(G / rho)
  (exact in 3D elasticity: circular sections do not warp).
* Axial: f_1 = (1 / 2L) sqrt(E / rho) with the Rayleigh-Love lateral-inertia
  correction f = f_1 (1 - nu^2 pi^2 r_p^2 / (2 L^2)), r_p^2 = R^2 / 2
  (A. E. H. Love, Treatise on the Mathematical Theory of Elasticity, 4th ed., sec. 278).
* Mass and inertia of a solid cylinder / annulus: m = rho pi (R^2 - r^2) L,
  I_zz = m (R^2 + r^2) / 2, I_xx = I_yy = m (3 (R^2 + r^2) + L^2) / 12.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.optimize import brentq

from cms.eigen import free_free_shift, lowest_modes
from fe_components.fe_model import build_component, default_mesh_size
from fe_components.material import STEEL
from fe_components.reference import ANNULUS, CASES, CYLINDER, REF_DIR


def timoshenko_free_free_first(E, nu, rho, R, L):
    """First bending frequency [Hz] of a free-free solid circular Timoshenko beam."""
    G = E / (2 * (1 + nu))
    kappa = 6 * (1 + nu) / (7 + 6 * nu)
    A, I = math.pi * R**2, math.pi * R**4 / 4

    def det(omega):
        # y = [w, w', psi, psi']; kappa G A (w'' - psi') + rho A w omega^2 = 0,
        # E I psi'' + kappa G A (w' - psi) + rho I omega^2 psi = 0
        C = np.zeros((4, 4))
        C[0, 1] = 1.0
        C[1, 0] = -rho * omega**2 / (kappa * G)
        C[1, 3] = 1.0
        C[2, 3] = 1.0
        C[3, 1] = -kappa * G * A / (E * I)
        C[3, 2] = (kappa * G * A - rho * I * omega**2) / (E * I)
        P = expm(C * L)
        y0 = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 1.0], [0.0, 0.0]])  # free end: psi' = 0, w' = psi
        bc = np.array([[0.0, 0.0, 0.0, 1.0], [0.0, 1.0, -1.0, 0.0]])
        return np.linalg.det(bc @ P @ y0)

    # Euler-Bernoulli free-free: beta L = 4.7300 (Blevins, Formulas for Natural Frequency, table 8-1)
    w_eb = 4.730041**2 / L**2 * math.sqrt(E * I / (rho * A))
    return brentq(det, 0.85 * w_eb, 1.0 * w_eb) / (2 * math.pi)


@pytest.fixture(scope="module")
def cylinder_model():
    params, options = CASES["cylinder"]
    assert options.size == default_mesh_size(params)  # the committed mesh is the default mesh
    return build_component(params, STEEL, options=options, cache_dir=REF_DIR)


@pytest.fixture(scope="module")
def cylinder_freqs(cylinder_model):
    K, M = cylinder_model.K, cylinder_model.M
    return lowest_modes(K, M, 20, sigma=free_free_shift(K, M)).frequencies_hz


def test_timoshenko_reference_tends_to_euler_bernoulli():
    # Shear and rotary inertia lower the Euler-Bernoulli frequency (beta L = 4.730041, Blevins
    # table 8-1) by a relative amount proportional to (R / L)^2 (Timoshenko 1921): halving R / L
    # must divide the deficit by 4.
    def deficit(R, L):
        f_t = timoshenko_free_free_first(STEEL.E, STEEL.nu, STEEL.rho, R, L)
        f_eb = 4.730041**2 / L**2 * math.sqrt(STEEL.E * R**2 / 4 / STEEL.rho) / (2 * math.pi)
        return 1 - f_t / f_eb

    d1, d2 = deficit(0.01, 1.0), deficit(0.005, 1.0)
    assert 0 < d2 < d1 < 0.01
    assert d1 / d2 == pytest.approx(4.0, rel=0.02)


def test_cylinder_rigid_body_modes(cylinder_freqs):
    f = cylinder_freqs
    assert np.all(np.abs(f[:6]) < 1e-3 * f[6])
    assert f[6] > 100.0


def test_cylinder_bending_vs_timoshenko(cylinder_freqs):
    R, L = CYLINDER.diameter / 2, CYLINDER.length
    f_ref = timoshenko_free_free_first(STEEL.E, STEEL.nu, STEEL.rho, R, L)
    bending = cylinder_freqs[6:8]  # two orthogonal planes, same frequency
    np.testing.assert_allclose(bending, f_ref, rtol=0.01)


def test_cylinder_torsion_and_axial(cylinder_freqs):
    R, L = CYLINDER.diameter / 2, CYLINDER.length
    f_tor = math.sqrt(STEEL.G / STEEL.rho) / (2 * L)
    f_ax = math.sqrt(STEEL.E / STEEL.rho) / (2 * L) * (1 - STEEL.nu**2 * math.pi**2 * (R**2 / 2) / (2 * L**2))
    f = cylinder_freqs[6:]
    assert np.min(np.abs(f / f_tor - 1)) < 0.01
    assert np.min(np.abs(f / f_ax - 1)) < 0.01


@pytest.mark.parametrize("name", ["cylinder", "annulus"])
def test_mass_and_inertia(name):
    params, options = CASES[name]
    model = build_component(params, STEEL, options=options, cache_dir=REF_DIR)
    R, r, L, rho = params.diameter / 2, params.bore_diameter / 2, params.length, STEEL.rho
    m = rho * math.pi * (R**2 - r**2) * L
    Izz = m * (R**2 + r**2) / 2
    Ixx = m * (3 * (R**2 + r**2) + L**2) / 12
    assert model.mass == pytest.approx(m, rel=1e-3)
    np.testing.assert_allclose(model.center_of_mass, [0, 0, L / 2], atol=1e-6 * L)
    np.testing.assert_allclose(np.diag(model.inertia), [Ixx, Ixx, Izz], rtol=1e-3)
    off = model.inertia - np.diag(np.diag(model.inertia))
    assert np.abs(off).max() < 1e-3 * Izz
    # cheap self-check: a rigid translation of the consistent mass matrix carries the mass
    ez = np.zeros(model.n_dofs)
    ez[2::3] = 1.0
    assert ez @ (model.M @ ez) == pytest.approx(model.mass, rel=1e-10)


def _mesh_volume(params, options) -> float:
    """Volume (m^3) of a committed mesh, integrated on its (curved P2) geometry."""
    from skfem import Basis, ElementTetP0, Functional

    from fe_components.fe_model import skfem_mesh
    from fe_components.meshing import mesh_path, read_mesh
    mesh = skfem_mesh(read_mesh(mesh_path(params, options, REF_DIR)))
    return Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(Basis(mesh, ElementTetP0(), intorder=2))


@pytest.mark.parametrize("name", sorted(CASES))
def test_volume_lower_bound(name):
    # volume_lower_bound (used to refuse unbounded Craig-Bampton cutoffs before meshing)
    # never exceeds the meshed volume; for the cylinder and annulus it is the exact
    # pi (R^2 - r^2) L, met by the mesh to its geometric error (1e-3, as for the mass above).
    from fe_components.geometry import volume_lower_bound
    params, options = CASES[name]
    bound, meshed = volume_lower_bound(params), _mesh_volume(params, options)
    if name in ("cylinder", "annulus"):
        assert bound == pytest.approx(math.pi * (params.diameter ** 2 - params.bore_diameter ** 2) / 4 * params.length,
                                      rel=1e-14)
        assert bound == pytest.approx(meshed, rel=1e-3)
    else:
        assert 0 < bound < meshed
