"""Hard cases for the multibody solver: near-rigid connections, free-free
assemblies, repeated eigenvalues, extreme scale. Targets are physics limits, not tables."""
import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from assembly import (
    Bearing,
    Body,
    GearMesh,
    Scene,
    Shaft,
    assemble,
    classify_modes,
    load_scene,
    scale_bearings,
    solve_modes,
    with_fidelity,
)


@pytest.mark.parametrize("factor", [1e9, 1e12])
@pytest.mark.parametrize("name", ["kahraman_beta0.toml", "kahraman_beta20.toml", "lin_parker_n4.toml"])
def test_near_rigid_bearings_give_torsional_limit(name, factor):
    # Bearings x1e9 / x1e12: a plain generalized solve puts the rigid-body mode at 1-25 Hz
    # and loses the low modes. Near-rigid directions become constraints (CONSTRAINT_RTOL), so
    # the 0 Hz mode stays below 1e-3 Hz and the elastic modes equal the torsional limit.
    sc = load_scene(name)
    directions = ("k_radial",) if "lin_parker" in name else ("k_radial", "k_axial", "k_tilt")
    r = solve_modes(assemble(scale_bearings(sc, factor, directions)))
    t = solve_modes(assemble(with_fidelity(sc, "torsional")))
    assert r.n_rigid == t.n_rigid == 1
    assert r.frequencies_hz[0] < 1e-3
    k = len(t.frequencies_hz)
    np.testing.assert_allclose(r.frequencies_hz[1:k], t.frequencies_hz[1:k], rtol=1e-6)


def test_naive_solve_of_near_rigid_bearings_is_wrong():
    # The failure mode the rule prevents, measured with the rule switched off: a plain
    # dense solve of the same K, M (springs of 3.5e17 N/m) reports the 0 Hz mode far above 0.
    import assembly.model.constraints as am
    sc = scale_bearings(load_scene("kahraman_beta0.toml"), 1e9)
    old = am.CONSTRAINT_RTOL
    am.CONSTRAINT_RTOL = 0.0
    try:
        m = assemble(sc)
    finally:
        am.CONSTRAINT_RTOL = old
    import scipy.linalg as sla
    lam = sla.eigh(m.K.toarray(), m.M.toarray(), eigvals_only=True)
    f0 = math.sqrt(abs(lam[0])) / (2 * math.pi)
    assert f0 > 1e-3  # naive: the rigid rotation is lost in round-off of 1e17-size springs


def _free_pair():
    C = 0.1 / math.cos(math.radians(20))
    b1 = Body("a", 2.0, polar_inertia=2.9e-3, transverse_inertia=1.45e-3)
    b2 = Body("b", 2.0, polar_inertia=2.9e-3, transverse_inertia=1.45e-3, position=(C, 0, 0))
    m = GearMesh("a", "b", 2e8, 0.05, 0.05, math.radians(20), math.radians(15))
    return Scene("free pair", bodies=(b1, b2), meshes=(m,))


def test_free_free_exact_rigid_mode_count():
    # Two free rigid bodies (12 DOFs) joined by one rank-one mesh spring: 11 zero modes.
    r = solve_modes(assemble(_free_pair()))
    assert r.n_rigid == 11
    assert np.all(np.isfinite(r.frequencies_hz)) and np.all(r.eigenvalues[:11] > -1e-6 * r.eigenvalues[-1])
    assert r.frequencies_hz[:11].max() < 1e-3 and r.frequencies_hz[11] > 1.0
    # adding a spring of all six stiffnesses between them (a bearing of b on a: a shaft must
    # run along a's axis) leaves the 6 assembly motions
    s = Bearing("b", frame="a", k_radial=1e8, k_axial=1e8, k_tilt=1e5, k_torsion=1e5)
    r6 = solve_modes(assemble(dataclasses.replace(_free_pair(), bearings=(s,))))
    assert r6.n_rigid == 6 and r6.frequencies_hz[:6].max() < 1e-3


def test_repeated_eigenvalues_orthonormal_bases():
    # Lin & Parker N = 5: translational pairs and planet modes (multiplicity 2) come back as
    # mass-orthonormal bases of their eigenspaces.
    r = solve_modes(assemble(load_scene("lin_parker_n5.toml")))
    M = r.model.M.toarray()
    G = r.shapes.T @ M @ r.shapes
    np.testing.assert_allclose(G, np.eye(len(G)), atol=1e-10)
    assert any(len(g) == 2 for g in r.groups)


@pytest.mark.parametrize("n", [4, 5])
def test_classification_stable_under_tiny_planet_perturbation(n):
    # Perturbing one planet angle by 1e-9 rad splits repeated frequencies by ~1e-9
    # relative; the grouping tolerance (1e-6) and basis-free group energies keep the classes.
    sc = load_scene(f"lin_parker_n{n}.toml")
    st = sc.stages[0]
    psi = [2 * math.pi * i / n for i in range(n)]
    psi[1] += 1e-9
    pert = dataclasses.replace(sc, stages=(dataclasses.replace(
        st, planets=dataclasses.replace(st.planets, angles=tuple(psi))),))
    a = [(m.mode_class, m.multiplicity) for m in classify_modes(solve_modes(assemble(sc)))]
    b = [(m.mode_class, m.multiplicity) for m in classify_modes(solve_modes(assemble(pert)))]
    assert a == b


def _nrel_line(scale_gen=1.0):
    # NREL 5 MW-like drivetrain (Jonkman et al., NREL/TP-500-38060, 2009):
    # rotor 38 759 236 kg m^2 -- LSS 867 637 000 N m/rad -- gearbox 97:1 -- generator
    # 534.116 kg m^2. Gearbox: a wheel (r_b 0.97 m) and pinion (r_b 0.01 m) with a stiff
    # mesh; small gear inertias.
    rb_w, rb_p = 0.97, 0.01
    C = (rb_w + rb_p) / math.cos(math.radians(20))
    bodies = (Body("rotor", 1.0, polar_inertia=38759236.0, fidelity="torsional"),
              Body("wheel", 1.0, polar_inertia=2000.0, position=(0, 0, 1.0), fidelity="torsional"),
              Body("pinion", 1.0, polar_inertia=0.5, position=(C, 0, 1.0), fidelity="torsional"),
              Body("generator", 1.0, polar_inertia=534.116, position=(C, 0, 2.0), fidelity="torsional"))
    shafts = (Shaft("rotor", "wheel", 867637000.0), Shaft("pinion", "generator", 2.0e6))
    mesh = GearMesh("wheel", "pinion", 2.0e10, rb_w, rb_p, math.radians(20))
    return Scene("NREL-like line", bodies=bodies, shafts=shafts, meshes=(mesh,)), (rb_w, rb_p)


def test_extreme_scale_matches_independently_scaled_solve():
    # Independent solve: the same chain referred to the low-speed shaft (pinion side
    # inertias x ratio^2, mesh as a torsional spring k r_w^2) and made dimensionless with
    # the rotor inertia and the LSS stiffness, so every entry is O(1) -- then scaled back.
    sc, (rw, rp) = _nrel_line()
    f = solve_modes(assemble(sc)).frequencies_hz
    n = rw / rp
    J = np.array([38759236.0, 2000.0, 0.5 * n**2, 534.116 * n**2])
    k = np.array([867637000.0, 2.0e10 * rw**2, 2.0e6 * n**2])
    J0, k0 = J[0], k[0]
    Kd = np.zeros((4, 4))
    for i, ki in enumerate(k / k0):
        Kd[i:i + 2, i:i + 2] += ki * np.array([[1, -1], [-1, 1]])
    Jd = J / J0
    lam = np.linalg.eigvalsh(Kd / np.sqrt(np.outer(Jd, Jd)))
    f_ref = np.sqrt(np.clip(np.sort(lam), 0, None) * k0 / J0) / (2 * math.pi)
    assert f[0] < 1e-3
    np.testing.assert_allclose(f[1:], f_ref[1:], rtol=1e-8)
    assert 0.5 < f[1] < 3.0  # first drivetrain torsion mode of a 5 MW turbine: O(1 Hz)


def test_under_constrained_body_is_named():
    # Kahraman pair with the wheel's axial bearing stiffness removed: one extra zero mode,
    # named as the wheel moving along its axis.
    from assembly.analysis.modal import mechanisms
    sc = load_scene("kahraman_beta0.toml")
    brg = tuple(dataclasses.replace(b, k_axial=0.0) if b.body == "wheel" else b for b in sc.bearings)
    r = solve_modes(assemble(dataclasses.replace(sc, bearings=brg)))
    assert r.n_rigid == 2
    text = mechanisms(r)
    assert any(t.startswith("wheel.z 100 %") for t in text), text


@settings(max_examples=200, deadline=None)
@given(mass=st.floats(allow_nan=True, allow_infinity=True), k=st.floats(allow_nan=True, allow_infinity=True),
       helix=st.floats(-10, 10), name=st.text(max_size=6))
def test_python_api_bad_values_raise_scene_error(mass, k, helix, name):
    # Python API: frozen dataclasses validated at Scene construction, same errors as TOML.
    from assembly.errors import SceneError
    try:
        b1 = Body(name or "a", mass, polar_inertia=1e-3)
        b2 = Body("b", 1.0, polar_inertia=1e-3, position=(0.1 / math.cos(0.35), 0, 0))
        Scene("api", bodies=(b1, b2), bearings=(Bearing("b", k, k, k),),
              meshes=(GearMesh(name or "a", "b", 1e8, 0.05, 0.05, 0.35, helix),))
    except SceneError as exc:
        assert exc.path and "\n" not in str(exc)
