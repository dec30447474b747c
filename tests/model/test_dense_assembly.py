"""A small rigid model assembled as dense arrays (``assemble(scene, dense=True)``, the path of
``flexgear modes``, which imports no SciPy) holds the very numbers of the default sparse
model: a small rigid model is assembled in dense arithmetic either way and its sparse
matrices are those arrays stored sparsely (assembly/model/assemble.py notes). So the modes
of ``flexgear modes`` and of ``flexgear run`` are the same to the last bit."""
from __future__ import annotations

import numpy as np
import pytest

from assembly import Bearing, Body, Scene, Shaft
from assembly.analysis.modal import solve_modes
from assembly.model.assemble import DENSE_DOFS, assemble
from assembly.model.damping import damping_matrix
from assembly.scene.schema import load_scene

EPS = np.finfo(float).eps
#: rigid scenes: two gears; a planetary stage (planets ride on the carrier's frame); a
#: two-stage box; the 5 MW drivetrain (near-rigid bearing directions made constraints)
SCENES = ("kahraman_beta20", "lin_parker_n3", "two_stage_quill", "nrel5mw")


@pytest.mark.parametrize("name", SCENES)
def test_dense_model_holds_the_sparse_models_numbers(name):
    scene = load_scene(name)
    s, d = assemble(scene), assemble(scene, dense=True)
    assert d.dense and not s.dense
    for field in ("K", "M", "T", "K_abs", "M_abs"):
        assert isinstance(getattr(d, field), np.ndarray)
        np.testing.assert_array_equal(getattr(d, field), getattr(s, field).toarray(), err_msg=field)
    assert d.dof_names == s.dof_names and d.rigidified == s.rigidified
    a, b = solve_modes(s), solve_modes(d)
    np.testing.assert_array_equal(a.frequencies_hz, b.frequencies_hz)
    np.testing.assert_array_equal(a.shapes, b.shapes)


@pytest.mark.parametrize("name", ("lin_parker_n3", "two_stage_quill"))
def test_element_matrices_and_operators_agree_dense_and_sparse(name):
    """Per element: the attachment operator is the same numbers; ``L' A L`` differs by the
    round-off of a sum of at most 2 x 12 products per entry (Higham, Accuracy and Stability
    of Numerical Algorithms, 2nd ed., sec. 3.5: |error| <= gamma_n |L'| |A| |L|, gamma_n ~ n eps)."""
    scene = load_scene(name)
    s, d = assemble(scene), assemble(scene, dense=True)
    for el in s.elements:
        L = d.attachment_operator(el)
        np.testing.assert_array_equal(L, s.attachment_operator(el).toarray())
        bound = 24 * EPS * (np.abs(L).T @ np.abs(el.stiffness()) @ np.abs(L))
        assert np.all(np.abs(d.element_stiffness_abs(el) - s.element_stiffness_abs(el).toarray()) <= bound), el.name
    np.testing.assert_array_equal(np.asarray(damping_matrix(d)), damping_matrix(s).toarray())
    np.testing.assert_array_equal(d.rigid_mass_matrix(), s.rigid_mass_matrix().toarray())


def test_a_rigid_model_above_the_dense_size_stays_sparse():
    n = DENSE_DOFS // 6 + 1                  # 6 absolute DOFs a body: one body too many
    bodies = tuple(Body(name=f"b{i}", mass=1.0, polar_inertia=0.1, position=(0, 0, 0.1 * i)) for i in range(n))
    bearings = tuple(Bearing(body=b.name, k_radial=1e8, k_axial=1e8, k_tilt=1e6) for b in bodies)
    shafts = tuple(Shaft(body1=f"b{i}", body2=f"b{i + 1}", k_torsion=1e4) for i in range(n - 1))
    model = assemble(Scene(name="long chain", bodies=bodies, bearings=bearings, shafts=shafts), dense=True)
    assert model.n_abs == 6 * n > DENSE_DOFS and not model.dense
    assert hasattr(model.K, "toarray")


def test_every_analysis_takes_a_dense_model_with_the_sparse_models_numbers():
    """A model assembled dense (for the modal solve) given to statics, the FRF (modal and
    direct) and the time domain gives the sparse model's numbers exactly: it is re-assembled
    sparse from the same scene, whose matrices are the dense ones (module notes of
    assembly.model.assemble); before, each failed inside on a sparse-only call."""
    import assembly as fg

    sc = fg.load_scene("two_stage_quill.toml")
    md, ms = fg.assemble(sc, dense=True), fg.assemble(sc)
    assert md.dense and not ms.dense
    _, lc = sc.load_cases()[0]
    a, b = fg.solve_static(md, lc), fg.solve_static(ms, lc)
    assert np.array_equal(a.q, b.q)
    f = np.array([10.0, 100.0, 400.0])
    for method in ("modal", "direct"):
        a = fg.frequency_response(md, "torque:pinion", ["torque:quill"], f, method=method)
        b = fg.frequency_response(ms, "torque:pinion", ["torque:quill"], f, method=method)
        assert np.array_equal(a.outputs["torque:quill"], b.outputs["torque:quill"])
    a = fg.simulate(md, 2e-3, 1e-4, outputs=["torque:quill"])
    b = fg.simulate(ms, 2e-3, 1e-4, outputs=["torque:quill"])
    assert np.array_equal(a.outputs["torque:quill"], b.outputs["torque:quill"]) and len(a.time_s) == 21


def test_a_dense_model_keeps_its_own_bodies_when_made_sparse():
    """sparse_model stores the dense model's own arrays sparse: a model built with its own
    body models (here the carrier 10x heavier, passed as ``bodies``) keeps them; the scene's
    re-assembly would have silently given the scene's masses."""
    import dataclasses

    import assembly as fg
    from assembly.model.assemble import sparse_model

    sc = fg.load_scene("lin_parker_n4.toml")
    plain = fg.assemble(sc, dense=True)
    bodies = dict(plain.bodies)
    name = next(n for n in bodies if n.endswith("carrier"))
    bodies[name] = dataclasses.replace(bodies[name], mass=10.0 * bodies[name].mass)
    md = fg.assemble(sc, dense=True, bodies=bodies)
    ms = fg.assemble(sc, bodies=bodies)
    for m in (sparse_model(md),):
        assert not m.dense and m.bodies is md.bodies
        for k in ("K_abs", "M_abs", "T", "K", "M"):
            assert np.array_equal(getattr(m, k).toarray(), getattr(ms, k).toarray())
    assert np.trace(md.M) != pytest.approx(np.trace(plain.M), rel=1e-3)
