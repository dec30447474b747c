"""Rigid-body modes from the structure (assembly.mechanics.nullity.rigid_body_modes): a basis of the
motions that strain no spring and no flexible body, K Phi_r = 0, as many as
rigid_body_count says.

Two torsional chains a-b held radially and in tilt, free to spin: one rigid-body mode (the
common spin). Left free axially too (k_axial = 0, and nothing else acts along z): each body's
axial translation is a coordinate no spring touches, a rigid-body mode on its own; 1 + 2 = 3.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly import Bearing, Body, Scene, Shaft, assemble
from assembly.mechanics.nullity import rigid_body_count, rigid_body_modes
from assembly.scene.schema import load_scene

INF = math.inf


def _chain(k_axial: float) -> Scene:
    bodies = (Body(name="a", mass=10.0, polar_inertia=2.0, position=(0, 0, 0)),
              Body(name="b", mass=10.0, polar_inertia=3.0, position=(0, 0, 1)))
    bearings = tuple(Bearing(body=n, k_radial=INF, k_axial=k_axial, k_tilt=INF) for n in "ab")
    return Scene(name="chain", bodies=bodies, bearings=bearings,
                 shafts=(Shaft(name="s", body1="a", body2="b", k_torsion=1e4),))


@pytest.mark.parametrize("k_axial, count", [(INF, 1), (0.0, 3)])
def test_basis_spans_the_free_motions(k_axial, count):
    model = assemble(_chain(k_axial))
    P = rigid_body_modes(model)
    assert P.shape == (model.K.shape[0], count) == (model.K.shape[0], rigid_body_count(model))
    assert np.linalg.matrix_rank(P) == count
    K = model.K.toarray()
    assert np.abs(K @ P).max() <= 1e-12 * np.abs(K).max() * np.abs(P).max()


@pytest.mark.parametrize("name", ["nrel5mw", "lin_parker_n4", "kahraman_beta20", "two_stage_quill"])
def test_shipped_drivetrains_have_one_rigid_body_mode(name):
    model = assemble(load_scene(name))
    P = rigid_body_modes(model)
    K = model.K.toarray()
    assert P.shape[1] == 1
    assert np.abs(K @ P).max() <= 1e-12 * np.abs(K).max() * np.abs(P).max()
