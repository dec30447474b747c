"""FE-side hard cases reachable from a scene (the FE rows of tests/hard_cases/README.md)."""
import dataclasses
import logging
from pathlib import Path

import numpy as np
import pytest

from assembly import assemble, load_scene

SCENE = Path(__file__).parent.parent / "support" / "data" / "flex_pair.toml"


def test_cutoff_below_band_warns(caplog):
    sc = load_scene(SCENE)
    b0 = sc.bodies[0]
    low = dataclasses.replace(b0, flex=dataclasses.replace(b0.flex, n_modes=None, cutoff_hz=0.5 * sc.band_hz))
    with caplog.at_level(logging.WARNING, logger="assembly.model.flexible"):
        assemble(dataclasses.replace(sc, bodies=(low,) + sc.bodies[1:]))
    assert any("below the scene's band" in r.getMessage() for r in caplog.records)


def test_more_modes_than_dofs_is_an_error():
    from cms.craig_bampton import CraigBamptonReductor
    from cms.errors import ReductionError
    from tests.support.fe_models import box
    m = box(divisions=(4, 1, 1), order=1)
    n = m.K.shape[0]
    with pytest.raises(ReductionError, match="n_modes"):
        CraigBamptonReductor(m.K, m.M, np.arange(6), n_modes=n)


def test_interface_leaving_a_mechanism_is_named():
    # Boundary = the three translations of one node: the rest of the free body can still
    # rotate about that node, so K_ii is singular; the error names the free motion.
    from cms.craig_bampton import CraigBamptonReductor
    from cms.errors import InteriorMechanismError
    from tests.support.fe_models import box
    m = box(divisions=(4, 1, 1), order=1)
    with pytest.raises(InteriorMechanismError) as exc:
        CraigBamptonReductor(m.K, m.M, np.arange(3), n_modes=2, node_coords=m.node_coords).reduce()
    assert "rotation" in str(exc.value)


def test_nearly_incompressible_p1_warns_and_p2_stays_accurate(caplog):
    # nu = 0.499: P1 tets lock (warned); P2 on the reference cylinder (L = 0.5 m, D = 0.05 m,
    # committed mesh) keeps the free-free torsion and axial frequencies of rod theory:
    # f_t = sqrt(G/rho) / 2L with G = E / 2(1 + nu), f_a = sqrt(E/rho) / 2L (Love's lateral
    # inertia correction ~ (nu pi r / L)^2 / 2 = 0.3 % here, inside the 1 % target).
    import math

    from assembly.model.components import check_locking
    from cms.eigen import free_free_shift, lowest_modes
    from fe_components.fe_model import build_component
    from fe_components.material import Material
    from fe_components.reference import CYLINDER, REF_DIR
    with caplog.at_level(logging.WARNING, logger="assembly.model.components"):
        assert check_locking(1, 0.499)
        assert not check_locking(2, 0.499) and not check_locking(1, 0.3)
    assert any("lock volumetrically" in r.getMessage() for r in caplog.records)
    E, nu, rho, L = 2.1e11, 0.499, 7850.0, 0.5
    fe = build_component(CYLINDER, Material(E, nu, rho), mesh_size=0.0125, cache_dir=REF_DIR)
    f = lowest_modes(fe.K, fe.M, 20, sigma=free_free_shift(fe.K, fe.M)).frequencies_hz
    f = f[np.abs(f) > 1.0]
    f_t = math.sqrt(E / (2 * (1 + nu)) / rho) / (2 * L)
    f_a = math.sqrt(E / rho) / (2 * L)
    assert np.min(np.abs(f / f_t - 1)) < 0.01
    assert np.min(np.abs(f / f_a - 1)) < 0.01


def test_sliver_element_caught_with_worst_element_reported():
    # Two regular-ish tets and one sliver (fourth vertex 1e-6 m off the base plane).
    from fe_components.errors import MeshingError
    from fe_components.quality import check_quality, tet_quality
    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1e-6], [1, 1, 1]], float)
    tets = np.array([[0, 1, 2, 3], [1, 2, 3, 5], [0, 1, 2, 4]])
    regular = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], float)
    assert tet_quality(regular, np.array([[0, 1, 2, 3]]))[0] == pytest.approx(1.0, rel=1e-12)
    with pytest.raises(MeshingError) as exc:
        check_quality(pts, tets)
    msg = str(exc.value)
    assert "'worst_element': 2" in msg and "quality" in msg


def test_shipped_reference_meshes_pass_quality():
    from fe_components.meshing import read_mesh
    from fe_components.quality import MIN_QUALITY, tet_quality
    from fe_components.reference import REF_DIR
    for f in sorted(REF_DIR.glob("*.msh")):
        raw = read_mesh(f)
        assert tet_quality(raw.points, raw.cells).min() > MIN_QUALITY, f.name


def test_cutoff_with_too_many_modes_stops_naming_the_body(monkeypatch, tmp_path):
    # Between what validation can prove before meshing (Weyl's count) and the mode limit,
    # the reduction itself stops after MAX_MODES + 1 modes. With the limit lowered to 3 and
    # a 20 kHz cutoff on the test pinion (first fixed-interface mode near 15 kHz, several
    # below 20 kHz), the run ends in a SceneError naming the field that set the cutoff.
    import assembly.model.flexible as fl
    from assembly.errors import SceneError
    from assembly.model.components import CacheDirs
    monkeypatch.setattr(fl, "MAX_MODES", 3)
    sc = load_scene(SCENE)
    b0 = sc.bodies[0]
    hi = dataclasses.replace(b0, flex=dataclasses.replace(b0.flex, n_modes=None, cutoff_hz=2.0e4))
    with pytest.raises(SceneError) as e:
        assemble(dataclasses.replace(sc, bodies=(hi,) + sc.bodies[1:]),
                 caches=CacheDirs(meshes=tmp_path / "m", superelements=tmp_path / "se"))
    assert e.value.path == "bodies[0].flex.cutoff_hz" and e.value.value == 2.0e4
    assert "'pinion'" in str(e.value) and "4 fixed-interface modes" in str(e.value)


def test_more_modes_than_the_mesh_has_names_the_body(tmp_path):
    # n_modes within MAX_MODES passes validation but may exceed a coarse mesh's interior
    # DOFs, known only after meshing: refused naming the body's table, not a bare n_modes.
    from assembly.errors import SceneError
    from assembly.model.components import CacheDirs
    from assembly.model.flexible import flexible_body
    sc = load_scene(SCENE)
    b0 = sc.bodies[0]
    opts = dataclasses.replace(b0.flex, n_modes=10**6)  # called directly: no scene validation
    with pytest.raises(SceneError) as e:
        flexible_body(b0, opts, 3000.0,
                      caches=CacheDirs(meshes=tmp_path / "m", superelements=tmp_path / "se"), path="bodies[0]")
    assert e.value.path == "bodies[0].flex.n_modes" and "interior DOFs" in str(e.value)
