"""Energy per stage, body, mesh, bearing and shaft; global vs stage-local modes (Peeters,
Vandepitte & Sas (2006), Wind Energy 9); one planetary stage on its own (Lin & Parker (1999),
J. Vib. Acoust. 121)."""
from __future__ import annotations

import dataclasses
import math
from collections import Counter

import numpy as np
import pytest
import scipy.sparse as sp

from assembly import Bearing, Body, Scene, Shaft, assemble, classify_modes, load_scene, solve_modes
from assembly.analysis.locality import GLOBAL, LOCAL_SHARE, energy_table, group_shares, rayleigh_error, total_share
from assembly.analysis.modal import solve_modes as _solve
from assembly.app.report.tables import modes_table
from assembly.errors import SceneError
from assembly.scene.stage_alone import stage_alone
from assembly.scene.tables import BearingSpec


@pytest.fixture(scope="module")
def quill():
    return solve_modes(assemble(load_scene("two_stage_quill")))


def test_shares_sum_to_one_per_mode(quill):
    t = energy_table(quill)
    for parts in (False, True):
        k, s = group_shares(t, quill.groups, parts=parts)
        # Shares of a whole: 1 per mode; strain 0 in the rigid-body mode (no strain energy).
        np.testing.assert_allclose(k.sum(axis=1), 1.0, rtol=1e-12)
        np.testing.assert_allclose(s[quill.n_rigid:].sum(axis=1), 1.0, rtol=1e-12)
        assert np.all(s[:quill.n_rigid] == 0.0)
        assert np.all(k >= 0) and np.all(s >= 0)
    # The quill shaft joins the unstaged wheel to the planetary stage: the link group.
    assert t.groups[t.names.index("quill")] == "wheel/planetary"
    assert {t.kinds[t.names.index(n)] for n in ("quill", "pinion-wheel", "planetary.sun-planet0",
                                                 "planetary.carrier.bearing")} == {"shaft", "mesh", "bearing"}


def test_strain_energy_equals_omega2_kinetic(quill):
    # Rayleigh's quotient of an eigenpair: z' K z = omega^2 z' M z exactly, so the springs'
    # and flexible bodies' strain energies add up to omega^2 x the bodies' kinetic energies
    # (the parts hold all the energy). The solver's backward error is below 1e-12
    # (quill.max_residual), so the identity holds to round-off; 1e-9 leaves room for the
    # conditioning of the lowest modes.
    assert quill.max_residual < 1e-12
    err = rayleigh_error(energy_table(quill))[quill.n_rigid:]
    assert err.max() < 1e-9
    # mass-normalised shapes: the bodies' kinetic terms z' M z / 2 sum to 1/2
    np.testing.assert_allclose(energy_table(quill).kinetic.sum(axis=1), 0.5, rtol=1e-10)


def test_element_with_lumped_mass_counts_its_kinetic_energy(quill):
    # A shaft element carrying a lumped mass matrix M_e on its attachment motions w = L z adds
    # L' M_e L to M. Its kinetic energy belongs to the element: without it the Rayleigh identity
    # (strain = omega^2 kinetic) would fail by the element's share of the kinetic energy.
    m = quill.model
    j = [el.kind for el in m.elements].index("shaft")
    el = m.elements[j]
    # half of a 10 kg, 0.05 m radius solid shaft at each end: m/2 translations, J/2 rotations
    mass, r = 10.0, 0.025
    Jp, Jt = 0.5 * mass * r ** 2, mass * (3 * r ** 2 + 0.4 ** 2) / 12
    end = np.diag([mass / 2] * 3 + [Jt / 2, Jt / 2, Jp / 2])
    Me = sp.block_diag([end, end]).toarray()
    elements = list(m.elements)
    elements[j] = dataclasses.replace(el, mass=Me)
    L = m.attachment_operator(el)
    M_abs = (m.M_abs + L.T @ sp.csr_matrix(Me) @ L).tocsr()
    M = (m.T.T @ M_abs @ m.T).tocsr()
    model = dataclasses.replace(m, elements=elements, M_abs=M_abs, M=((M + M.T) * 0.5).tocsr())
    r = _solve(model)
    t = energy_table(r)
    assert rayleigh_error(t)[r.n_rigid:].max() < 1e-9
    k, _ = group_shares(t, r.groups, parts=True)
    assert k[r.n_rigid:, len(m.bodies) + j].max() > 0.01   # the shaft's mass moves in some mode


def _chain(J_b: float, k_c: float) -> Scene:
    """Torsional chain housing -k- a1 -k- a2 -k_c- b1 -k- b2 -k- housing: stage "a" (a1, a2,
    inertia 1 kg m^2 each), stage "b" (b1, b2, inertia J_b each), joined by a shaft k_c."""
    k = 1.0e6
    big = dict(k_radial=1e9, k_axial=1e9, k_tilt=1e9)
    bodies = tuple(Body(n, 10.0, polar_inertia=J, position=(0.0, 0.0, 0.1 * i), stage=n[0], fidelity="torsional")
                   for i, (n, J) in enumerate([("a1", 1.0), ("a2", 1.0), ("b1", J_b), ("b2", J_b)]))
    return Scene(name="two-stage torsional chain", bodies=bodies,
                 bearings=(Bearing("a1", k_torsion=k, **big), Bearing("b2", k_torsion=k, **big)),
                 shafts=(Shaft("a1", "a2", k_torsion=k), Shaft("a2", "b1", k_torsion=k_c, name="link"),
                         Shaft("b1", "b2", k_torsion=k)))


def _scopes(scene):
    r = solve_modes(assemble(scene))
    t = energy_table(r)
    ke, se = group_shares(t, r.groups)
    return r, t, total_share(ke, se), [mi.scope for mi in classify_modes(r)], ke


def test_weakly_coupled_stages_have_local_modes():
    # Each stage alone (one end held by k, the other free) has omega^2 = (k/J)(3 -+ sqrt 5)/2:
    # 0.382 and 2.618 k/J for "a", half that for "b" (J_b = 2): four well separated
    # frequencies (ratios >= 1.46). A link k_c = 1e-4 k mixes them by ~k_c / (k * spacing)
    # ~ 1e-4 in amplitude, 1e-8 in energy, and takes ~1e-4 of the strain energy: each mode
    # stays with its stage, holding > 0.999 of the energy (>= LOCAL_SHARE by far).
    r, t, E, scopes, _ = _scopes(_chain(2.0, 1.0e2))
    assert r.n_rigid == 0 and len(r.frequencies_hz) == 4
    assert Counter(scopes) == {"a": 2, "b": 2}
    names = t.group_names
    for i, s in enumerate(scopes):
        assert E[i, names.index(s)] > 0.999
    lam = np.sort(np.concatenate([[0.382, 2.618], [0.191, 1.309]])) * 1e6
    np.testing.assert_allclose(np.sort(r.eigenvalues), lam, rtol=2e-3)   # 3 digits of (3 -+ sqrt 5)/2


def test_symmetric_strongly_coupled_stages_have_global_modes():
    # J_b = 1, k_c = k: the chain is its own mirror image (a1 <-> b2, a2 <-> b1), so every
    # (non-repeated) mode is symmetric or antisymmetric: each stage holds exactly half of the
    # kinetic energy and at most half of the strain energy (the link holds the rest). Its total
    # share is then at most (0.5 + 0.5) / 2 = 0.5 < LOCAL_SHARE: every mode is global.
    r, t, E, scopes, ke = _scopes(_chain(1.0, 1.0e6))
    assert scopes == [GLOBAL] * 4
    names = t.group_names
    np.testing.assert_allclose(ke[:, [names.index("a"), names.index("b")]], 0.5, rtol=1e-9)
    assert E.max() <= 0.5 + 1e-12 < LOCAL_SHARE


def test_mode_table_has_scope_and_stage_split(quill):
    text = modes_table(quill)
    header = text.splitlines()[0]
    assert "scope" in header and "energy by stage (kinetic%/strain%)" in header
    infos = classify_modes(quill)
    assert {mi.scope for mi in infos} >= {GLOBAL, "planetary"}
    rows = {int(l.split()[0]): l for l in text.splitlines()[1:] if l[:4].strip().isdigit()}
    assert rows
    for mi in infos:
        if mi.index + 1 in rows:
            assert f" {mi.scope} " in rows[mi.index + 1]
    assert "planetary 100/100" in text   # a mode of the planetary stage alone: all its energy


def test_rayleigh_identity_with_a_flexible_body():
    # Same identity with a Craig-Bampton carrier: its strain energy z_b' K_b z_b / 2 counts
    # with the springs' (solver backward error < 1e-12, so 1e-9 as above).
    r = solve_modes(assemble(load_scene("planetary_flexible_carrier.toml")))
    t = energy_table(r)
    assert rayleigh_error(t)[r.n_rigid:].max() < 1e-9
    carrier = t.names.index("stage.carrier")
    assert t.strain[r.n_rigid:, carrier].max() > 0


def _alone(planar=True):
    sc = load_scene("two_stage_quill")
    q = sc.shafts[0]
    # The floating sun, alone: held by the quill shaft with the wheel end held.
    sun = BearingSpec(k_radial=q.k_shear, k_axial=q.k_axial, k_tilt=q.k_bending, k_torsion=q.k_torsion)
    return stage_alone(sc, "planetary", {"sun": sun}, planar=planar)


def test_stage_alone_has_lin_parker_classes():
    # Lin & Parker (1999), planar model, N equally spaced planets: the modes split by the
    # planets' cyclic harmonic. Harmonic 0 (rotational, single): each central member's
    # rotation plus the planets' 3 in-plane DOFs; harmonic 1 (translational, pairs): each
    # central member's in-plane translation plus the planets' 3; harmonics 2..N-2 (planet
    # modes, central members at rest): 3 frequencies of multiplicity N - 3. Here the ring is
    # fixed (sun and carrier remain): 2 + 3 = 5 rotational, 2 + 3 = 5 translational pairs,
    # 3 planet modes of multiplicity 4 - 3 = 1; 3 (3 + N) - 3 = 18 DOFs. The sun's rotation is
    # held by the quill: no rigid-body mode.
    r = solve_modes(assemble(_alone()))
    assert r.model.K.shape[0] == 18 and r.n_rigid == 0
    infos = classify_modes(r)
    counts = Counter((infos[g[0]].mode_class, len(g)) for g in r.groups)
    assert counts == {("rotational", 1): 5, ("translational", 2): 5, ("planet", 1): 3}
    assert {mi.scope for mi in infos} == {"planetary"}


def test_stage_alone_planet_modes_appear_in_the_whole_drivetrain(quill):
    # Planet modes leave the central members at rest (Lin & Parker 1999), so they do not
    # feel anything beyond the stage: the spur stage's in-plane planet modes of the stage
    # alone are planet modes of the whole drivetrain at the same frequencies.
    r = solve_modes(assemble(_alone()))
    alone = [mi.frequency_hz for mi in classify_modes(r) if mi.mode_class == "planet"]
    whole = np.array([mi.frequency_hz for mi in classify_modes(quill) if mi.mode_class == "planet"])
    for f in alone:
        assert np.min(np.abs(whole / f - 1)) < 1e-9, f


@pytest.mark.parametrize("args, path, value", [
    (("nostage",), "stage_name", "nostage"),                       # no stage of that name
    (("planetary",), "stages[0].sun.support", "floating"),         # floating member without a bearing
    (("planetary", {"planet": BearingSpec(1e9, 1e9, 1e6)}), "bearings", "planet"),   # not a member
    (("planetary", {"sun": [1e9]}), "bearings.sun", [1e9]),                       # not a bearing table
    (("planetary", {"sun": {"k_radial": 1e9}}), "bearings.sun.k_axial", None),    # a table without k_axial
    (("planetary", {"sun": {"k_radial": 1e9, "k_axial": 1e9, "k_tilt": 1e6, "c_radal": 1.0}}),
     "bearings.sun.c_radal", 1.0),                                                 # a misspelt field
])
def test_stage_alone_bad_input_names_the_field(args, path, value):
    with pytest.raises(SceneError) as e:
        stage_alone(load_scene("two_stage_quill"), *args)
    assert e.value.path == path and e.value.value == value
