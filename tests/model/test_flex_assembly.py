"""Flexible multibody assembly: consistency between fidelities (physics, no tables).

Scene: tests/support/data/flex_pair.toml (fe_components' reference pinion and wheel, committed
meshes). Rayleigh-Ritz: the torsional model's motions lie in the rigid model's space,
which lies in the Craig-Bampton space of the flexible one (rigid motions are exact
constraint-mode combinations), with identical mass and springs on the shared motions; so
the k-th frequency obeys flexible <= rigid <= torsional.
"""
import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from assembly import assemble, load_scene, scale_bearings, solve_modes, with_fidelity
from assembly.analysis.compare import compare, variants
from assembly.app.cli import main

SCENE = Path(__file__).parent.parent / "support" / "data" / "flex_pair.toml"


@pytest.fixture(scope="module")
def scene():
    return load_scene(SCENE)


@pytest.fixture(scope="module")
def solved(scene):
    return {k: solve_modes(assemble(sc)) for k, sc in variants(scene).items()}


def test_interlacing_flexible_le_rigid_le_torsional(solved):
    ft, fr, ff = (solved[k].frequencies_hz for k in ("torsional", "rigid", "flexible"))
    tol = 1e-9 * ff.max()
    for k in range(1, len(fr)):
        assert ff[k] <= fr[k] + tol, k
    for k in range(1, len(ft)):
        assert fr[k] <= ft[k] + tol, k
    for r in solved.values():
        assert r.max_residual < 1e-10


def test_rigid_body_mode_counts(scene, solved):
    # Grounded (bearings without torsional stiffness): the pair turns freely -> 1 zero mode.
    assert all(r.n_rigid == 1 for r in solved.values())
    # Free-free (no bearings): two free bodies have 12 rigid motions and the one mesh spring
    # removes one -> 11 zero modes (torsional: 2 spins, one mesh -> 1). Their omega^2 is
    # zero up to the eigensolver's round-off, eps * omega_max^2 (Golub & Van Loan 8.7),
    # so f_rigid ~ sqrt(eps) f_max = 1.5e-8 f_max; 1e-6 f_max allows a condition factor.
    free = dataclasses.replace(scene, bearings=())
    for k, sc in variants(free).items():
        r = solve_modes(assemble(sc))
        assert r.n_rigid == (1 if k == "torsional" else 11), k
        assert len(r.frequencies_hz) == r.model.K.shape[0], k   # all modes: f_max is the model's
        assert np.all(r.frequencies_hz[:r.n_rigid] < 1e-6 * r.frequencies_hz.max()), k
        assert np.all(np.isfinite(r.frequencies_hz)) and r.frequencies_hz.min() >= 0


def test_reduced_mass_and_inertia_equal_mesh(solved):
    # The rigid variant takes mass/inertia from the mesh; the superelement must carry
    # exactly the same rigid-body mass matrix (CB reproduces rigid motion exactly).
    mr = solved["rigid"].model
    mf = solved["flexible"].model
    for name, fb in mf.bodies.items():
        rb = mr.bodies[name]
        P = fb.rigid_local
        Mrig = P.T @ (fb.M @ P)
        assert Mrig[0, 0] == pytest.approx(rb.mass, rel=1e-10)
        R = fb.axes
        np.testing.assert_allclose(R @ Mrig[3:, 3:] @ R.T, rb.inertia, rtol=0, atol=1e-10 * np.abs(rb.inertia).max())
        np.testing.assert_allclose(fb.position, rb.position, atol=1e-12)


def test_flexible_tends_to_rigid_when_stiff(scene, solved, tmp_path):
    # Young's modulus x 1e4: elastic frequencies x 100, so the coupled modes approach the
    # rigid model's (Peeters, Vandepitte & Sas (2006), flexible model: flexibility lowers frequencies; at most 0.5 %).
    stiff = dataclasses.replace(scene, bodies=tuple(
        dataclasses.replace(b, flex=dataclasses.replace(
            b.flex, material=dataclasses.replace(b.flex.material, E=b.flex.material.E * 1e4)))
        for b in scene.bodies))
    fs = solve_modes(assemble(stiff)).frequencies_hz
    fr = solved["rigid"].frequencies_hz
    np.testing.assert_allclose(fs[1:len(fr)], fr[1:], rtol=5e-3)


def test_stiff_bearings_rigid_tends_to_torsional(scene):
    # Peeters, Vandepitte & Sas (2006), Fig. 11a: bearings x 1e6 -> the torsional model of the same data.
    rigid = variants(scene)["rigid"]
    ft = solve_modes(assemble(with_fidelity(rigid, "torsional"))).frequencies_hz
    fr = solve_modes(assemble(scale_bearings(rigid, 1e6))).frequencies_hz
    np.testing.assert_allclose(fr[1:len(ft)], ft[1:], rtol=1e-4)


def test_compare_json(capsys):
    assert main(["compare", str(SCENE), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    f = out["frequencies_hz"]
    assert set(f) == {"torsional", "rigid", "flexible"}
    for v in f.values():
        assert v == sorted(v)
    assert len(f["torsional"]) == 2 and len(f["rigid"]) == 12 and len(f["flexible"]) > 12


def test_flexible_summary_counts_match_the_superelements(solved):
    # reduced coordinates of a body = 6 per interface master + modes + residual vectors
    from assembly.app.report.tables import flexible_summary, modes_json
    r = solved["flexible"]
    summary = flexible_summary(r.model)
    assert set(summary) == {"pinion", "wheel"}
    for name, s in summary.items():
        bm = r.model.bodies[name]
        assert s["reduced"] and s["fe_dofs"] > 0
        assert bm.K.shape[0] == 6 * len(bm.masters) + s["fixed_interface_modes"] + s["residual_vectors"]
        assert 0 < s["residual_vectors"] <= 6 * len(bm.masters)
    assert modes_json(r)["flexible_bodies"] == summary
