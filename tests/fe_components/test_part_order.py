"""A linear (P1) tetrahedral mesh file: reported, and lifted to P2 on request (``order = 2``).

* Lifting puts a node at the middle of every edge: the model is the one of the same mesh that
  gmsh makes second order with straight edges (``Mesh.SecondOrderLinear = 1``), to 1e-10.
* On a slender free-free beam the lifted P2 model reaches Timoshenko's first bending
  frequency within the beam theory's own error and the mesh's, while the P1 model of the same
  mesh is 30 % too stiff (the figure the warning quotes).
* A P1 file without ``order`` warns, naming the file; ``order = 1`` keeps it linear without a
  warning; ``order = 1`` on a quadratic file and ``order`` on a CAD file are refused.
"""
from __future__ import annotations

import logging
import math

import meshio
import numpy as np
import pytest
from scipy.spatial import cKDTree

from assembly.errors import SceneError
from assembly.scene.schema import SCENE_DIR, from_dict
from cms.eigen import count_rigid_modes, free_free_shift, lowest_modes
from fe_components.fe_model import build_component
from fe_components.gmsh_session import gmsh_model
from fe_components.material import STEEL
from fe_components.part.file import PartFile, PartFileError
from fe_components.part.read import P1_STIFFER, part_geometry
from tests.support.mesh_writers import kuhn_box

BEAM = (0.3, 0.01, 0.01)   # m: a steel beam 300 x 10 x 10 mm, L/h = 30
BETA_L = 4.730040744862704  # first root of cos(bL) cosh(bL) = 1: free-free beam, mode 1


def _free_free(fe, n_elastic=4) -> np.ndarray:
    f = lowest_modes(fe.K, fe.M, 6 + n_elastic, sigma=free_free_shift(fe.K, fe.M)).frequencies_hz
    assert count_rigid_modes(f) == 6
    return np.sort(f)[6:]


@pytest.fixture(scope="module")
def gmsh_pair(tmp_path_factory):
    """The beam meshed once by gmsh (linear), written as P1, then made second order with
    straight edges by gmsh itself and written as P2: the same elements."""
    d = tmp_path_factory.mktemp("gmsh-pair")
    with gmsh_model("beam") as gmsh:
        gmsh.model.occ.addBox(0, 0, 0, *BEAM)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.01)   # m: coarse, one element through the thickness
        gmsh.model.mesh.generate(3)
        gmsh.write(str(d / "p1.msh"))
        gmsh.option.setNumber("Mesh.SecondOrderLinear", 1)   # midside nodes on the straight edges
        gmsh.model.mesh.setOrder(2)
        gmsh.write(str(d / "p2.msh"))
        gmsh.option.setNumber("Mesh.SecondOrderLinear", 0)   # gmsh's default back, should the session go on
    return d / "p1.msh", d / "p2.msh"


def test_lifted_linear_mesh_is_gmshs_straight_p2(gmsh_pair, tmp_path):
    """order = 2 on the P1 file gives the model of gmsh's own straight-edged P2 of the same
    mesh: the same nodes, mass and free-free frequencies (to 1e-10: the same matrices up to
    node numbering)."""
    p1, p2 = gmsh_pair
    lifted = build_component(PartFile(str(p1), units="m", order=2), STEEL, cache_dir=tmp_path)
    direct = build_component(PartFile(str(p2), units="m"), STEEL, cache_dir=tmp_path)
    assert lifted.order == direct.order == 2 and lifted.read.lifted and not direct.read.lifted
    assert lifted.n_nodes == direct.n_nodes
    dist, idx = cKDTree(direct.nodes).query(lifted.nodes)
    assert dist.max() < 1e-15 and len(set(idx)) == len(idx)   # the same points, one to one
    assert lifted.mass == pytest.approx(direct.mass, rel=1e-12)
    np.testing.assert_allclose(_free_free(lifted), _free_free(direct), rtol=1e-10)
    # the lifted mesh keeps the file's geometry: its mass is the straight P1 elements'
    p1_model = build_component(PartFile(str(p1), units="m", order=1), STEEL, cache_dir=tmp_path)
    assert lifted.mass == pytest.approx(p1_model.mass, rel=1e-12)
    assert lifted.mass == pytest.approx(STEEL.rho * math.prod(BEAM), rel=1e-12)   # a box: exact


def _timoshenko_first_bending() -> tuple[float, float]:
    """(first bending frequency Hz, its relative model error) of the free-free square beam.

    Euler-Bernoulli: f = (b L)^2 / (2 pi L^2) sqrt(E I / (rho A)), b L = 4.7300408. Timoshenko
    to first order (Rayleigh quotient with the Euler-Bernoulli mode shape w): rotary inertia and
    shear lower omega by the factor 1 - (r^2 / 2) (<w'^2>/<w^2> + E/(kappa G) <w'''^2>/<w''^2>)
    (r^2 = I / A; for a sine these ratios are both k^2: the simply supported textbook result),
    kappa = 10 (1 + nu) / (12 + 11 nu) (Cowper 1966, rectangle). Model error: the neglected
    second-order terms, of order (r^2 b^2 (1 + E/(kappa G)))^2 = 6.5e-5, and Cowper's kappa
    against 5/6 (2 %) on the shear part (1.7e-3): 3.5e-5; together 1e-4."""
    L, b = BEAM[0], BEAM[1]
    E, nu, rho = STEEL.E, STEEL.nu, STEEL.rho
    beta = BETA_L / L
    r2 = b * b / 12.0
    s = (math.cosh(BETA_L) - math.cos(BETA_L)) / (math.sinh(BETA_L) - math.sin(BETA_L))
    x = np.linspace(0.0, L, 200001)
    bx = beta * x
    w = np.cosh(bx) + np.cos(bx) - s * (np.sinh(bx) + np.sin(bx))
    w1 = beta * (np.sinh(bx) - np.sin(bx) - s * (np.cosh(bx) + np.cos(bx)))
    w2 = beta ** 2 * (np.cosh(bx) - np.cos(bx) - s * (np.sinh(bx) - np.sin(bx)))
    w3 = beta ** 3 * (np.sinh(bx) + np.sin(bx) - s * (np.cosh(bx) - np.cos(bx)))
    ratio = lambda f, g: np.trapezoid(f * f, x) / np.trapezoid(g * g, x)  # noqa: E731
    e_kg = E / (10 * (1 + nu) / (12 + 11 * nu) * E / (2 * (1 + nu)))
    f_eb = BETA_L ** 2 / (2 * math.pi * L ** 2) * math.sqrt(E * r2 / rho)
    correction = 0.5 * r2 * (ratio(w1, w) + e_kg * ratio(w3, w2))
    assert 3e-3 < correction < 5e-3
    return f_eb * (1.0 - correction), 1e-4


@pytest.fixture(scope="module")
def beams(tmp_path_factory):
    """{n: (P1 frequencies, lifted P2 frequencies)} of the beam's structured mesh with n
    tetrahedron layers through the thickness (cubes of 10/n mm, 6 tetrahedra each)."""
    d = tmp_path_factory.mktemp("beam")
    out = {}
    for n in (1, 2):
        pts, tets = kuhn_box(BEAM, (30 * n, n, n))
        path = d / f"beam{n}.vtu"
        meshio.write(path, meshio.Mesh(pts, [("tetra", tets)]))
        p1 = build_component(PartFile(str(path), units="m", order=1), STEEL, cache_dir=d)
        p2 = build_component(PartFile(str(path), units="m", order=2), STEEL, cache_dir=d)
        out[n] = (_free_free(p1), _free_free(p2))
    return out


@pytest.mark.slow   # the beams: 3 s of CPU, up to 6 s on a loaded machine
def test_lifted_beam_reaches_timoshenko(beams):
    """The two first (bending, y and z) frequencies of the lifted P2 beam two layers thick
    against Timoshenko, within the model error (1e-4) plus the discretisation error: P2's
    eigenvalue error falls as h^4 (Strang & Fix), at least h^3 pre-asymptotically (measured
    h^3.6 between one, two and four layers), so the two-layer error is at most
    |f(1 layer) - f(2 layers)| / (2^3 - 1). Measured: 1.1e-4 and 1.3e-4 against bounds of 1.5e-4
    and 1.8e-4."""
    f_t, model = _timoshenko_first_bending()
    f1, f2 = beams[1][1][:2], beams[2][1][:2]
    assert np.all(f1 > f2)   # P2 converges from above (a conforming Ritz method)
    bound = model + np.abs(f1 - f2) / 7 / f_t
    err = np.abs(f2 / f_t - 1)
    assert np.all(err < bound), (err, bound)


@pytest.mark.slow
def test_linear_beam_is_too_stiff_by_the_warnings_figure(beams):
    """The same two-layer mesh run as P1: the first bending frequency 30 % above the lifted P2
    one (measured 762.3 Hz against 588.4 Hz), the figure the P1 warning quotes; one layer:
    90 % (shear locking of linear tetrahedra in bending)."""
    p1, p2 = beams[2]
    assert round(100 * (p1[0] / p2[0] - 1)) == P1_STIFFER
    assert beams[1][0][0] / beams[1][1][0] - 1 > 0.8


# ------------------------------------------------------------------------ what is reported
@pytest.fixture
def p1_file(tmp_path):
    pts, tets = kuhn_box((0.1, 0.02, 0.02), (5, 1, 1))
    path = tmp_path / "bar.vtu"
    meshio.write(path, meshio.Mesh(pts, [("tetra", tets)]))
    return path


def _read_log(caplog, part) -> list:
    with caplog.at_level(logging.INFO, logger="fe_components.part.read"):
        geo = part_geometry(part)
    return geo, [r for r in caplog.records if r.name == "fe_components.part.read"]


def test_linear_mesh_warns_naming_the_file_and_the_error(p1_file, caplog):
    geo, records = _read_log(caplog, PartFile(str(p1_file), units="m"))
    (rec,) = records
    assert rec.levelno == logging.WARNING
    text = rec.getMessage()
    assert text.startswith("bar.vtu: read 30 tetra")
    assert f"+{P1_STIFFER} %" in text and "order = 2" in text
    assert geo.read.order == 1 and not geo.read.lifted


def test_order_1_keeps_a_linear_mesh_without_a_warning(p1_file, caplog):
    geo, records = _read_log(caplog, PartFile(str(p1_file), units="m", order=1))
    assert [r.levelno for r in records] == [logging.INFO]
    assert geo.read.order == 1 and geo.read.linear_ok


def test_order_2_lifts_and_says_so(p1_file, caplog, tmp_path):
    part = PartFile(str(p1_file), units="m", order=2)
    geo, records = _read_log(caplog, part)
    assert [r.levelno for r in records] == [logging.INFO]
    assert "lifted to P2" in records[0].getMessage()
    fe = build_component(part, STEEL, cache_dir=tmp_path / "cache")
    assert fe.order == 2 and fe.read.lifted and type(fe.mesh).__name__ == "MeshTet2"
    # 6 cubes' worth of edges: every edge of the 30 tetrahedra has its one midside node
    edges = {tuple(sorted(e)) for t in kuhn_box((0.1, 0.02, 0.02), (5, 1, 1))[1]
             for e in ((t[0], t[1]), (t[1], t[2]), (t[0], t[2]), (t[0], t[3]), (t[1], t[3]), (t[2], t[3]))}
    assert fe.n_nodes == 6 * 2 * 2 + len(edges)


def _tet10(pts, tets):
    """The tetrahedra with a node at the middle of each edge (meshio's tetra10 order)."""
    pts, mids, out = list(pts), {}, []
    for t in tets:
        row = list(t)
        for a, b in ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)):
            key = tuple(sorted((t[a], t[b])))
            if key not in mids:
                mids[key] = len(pts)
                pts.append((pts[key[0]] + pts[key[1]]) / 2)
            row.append(mids[key])
        out.append(row)
    return np.array(pts), np.array(out)


def test_order_1_on_a_quadratic_file_is_refused(tmp_path):
    path = tmp_path / "bar_p2.vtu"
    pts, tets = _tet10(*kuhn_box((0.1, 0.02, 0.02), (5, 1, 1)))
    meshio.write(path, meshio.Mesh(pts, [("tetra10", tets)]))
    with pytest.raises(PartFileError) as err:
        part_geometry(PartFile(str(path), units="m", order=1))
    assert err.value.parameter == "order" and "bar_p2.vtu" in str(err.value)
    assert "holds quadratic tetrahedra" in str(err.value)


def test_order_on_a_cad_part_is_refused():
    with pytest.raises(PartFileError) as err:
        PartFile(str(SCENE_DIR / "parts" / "carrier_windows.step"), order=2)
    assert err.value.parameter == "order" and "carrier_windows.step" in str(err.value)


@pytest.mark.parametrize("value", [3, 0, True, "2", 2.0])
def test_order_from_a_table_is_checked(value, p1_file):
    with pytest.raises((SceneError, PartFileError)) as err:
        from_dict(PartFile, {"file": str(p1_file), "units": "m", "order": value}, "component")
    assert "order" in str(err.value)


def test_order_from_a_table(p1_file):
    part = from_dict(PartFile, {"file": str(p1_file), "units": "m", "order": 2}, "component")
    assert part.order == 2
