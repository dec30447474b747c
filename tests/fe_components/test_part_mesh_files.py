"""A mesh file with second-order elements keeps its boundary
groups. One P2 (tetra10) mesh of a cylinder, made here with gmsh (physical surfaces
"end_a", "end_b" and a physical volume), read as a user's part from every format it can be
written in: gmsh .msh 4.1 (physical groups), Abaqus .inp written by meshio (groups as
``*ELSET`` of the end faces, or as ``*NSET`` of their nodes; also scaled to mm), .vtu (no
groups: plane rules), Nastran .bdf written by meshio (plane rules), Salome/Code_Aster .med
in MED's own node order (the end faces as MED groups), and Nastran decks in every field
format and continuation style (free field with ``+`` or blank continuations, small field with
markers or a blank first field after a line stripped of its trailing blanks, large field).
Every format gives the same FE model: order 2, the groups' corner and midside nodes as the
interfaces, the mass of the curved P2 cylinder and the same free-free frequencies. A P1
(tetra) file gives an order 1 model."""
from __future__ import annotations

import logging
import math
import types

import meshio
import numpy as np
import pytest
from scipy.spatial import cKDTree

from cms.eigen import count_rigid_modes, free_free_shift, lowest_modes
from fe_components.fe_model import CAD_MASS_TOL, build_component
from fe_components.gmsh_session import gmsh_model
from fe_components.material import STEEL
from fe_components.meshing import read_mesh
from fe_components.part.file import InterfaceRule, PartFile
from tests.support.mesh_writers import med_order, nastran_deck, write_med

R = 0.025            # m: cylinder radius (0.05 m diameter)
LENGTH = 0.1         # m: cylinder length, z in [0, LENGTH]
AXIS = (0.03, 0.03)  # m: the axis's (x, y); every coordinate positive, see _bdf below
MESH_SIZE = 0.012    # m: coarse, a dozen arcs around the rim (2 pi R / 0.012 = 13.1), 762 tetra10
V_EXACT = math.pi * R**2 * LENGTH  # m^3: the CAD cylinder
#: Coordinates survive a format to this (m): meshio's Nastran writer keeps 12 significant
#: digits ("fixed-large" GRID*, numpy precision 11), i.e. at most 5e-13 m on coordinates
#: up to 0.1 m (measured: 5e-14 m); every other format here writes 16-17 digits (exact).
POS_TOL = 1e-12
N_RIGID = 6          # a free solid: 3 translations, 3 rotations
N_ELASTIC = 6        # lowest elastic modes compared between the formats


def _faces_of(tets: np.ndarray) -> np.ndarray:
    """Boundary faces (corner nodes) of tetrahedra: the faces that belong to one only."""
    f = tets[:, [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]].reshape(-1, 3)
    _, inv, count = np.unique(np.sort(f, axis=1), axis=0, return_inverse=True, return_counts=True)
    return f[count[inv.ravel()] == 1]


def _straight_volume(points: np.ndarray, tets: np.ndarray) -> float:
    """Volume (m^3) of the straight tetrahedra on the corner nodes (signed, summed)."""
    p = points[tets[:, :4]]
    return float(np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]).sum() / 6)


def _same_points(a: np.ndarray, b: np.ndarray, tol: float = POS_TOL) -> bool:
    """The two point sets are equal (each point of one within ``tol`` of one of the other)."""
    return len(a) == len(b) and cKDTree(b).query(a)[0].max() < tol and cKDTree(a).query(b)[0].max() < tol


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """The cylinder meshed once by gmsh (P2) and written in every format; the groups' nodes
    as gmsh gives them (corner and midside), the mesh's points and tetrahedra."""
    d = tmp_path_factory.mktemp("p2-cylinder")
    with gmsh_model("p2-cylinder") as gmsh:
        occ = gmsh.model.occ
        vol = occ.addCylinder(AXIS[0], AXIS[1], 0.0, 0.0, 0.0, LENGTH, R)
        occ.synchronize()
        ends = {}
        for _, tag in gmsh.model.getEntities(2):
            z = occ.getCenterOfMass(2, tag)[2]
            if abs(z) < 1e-12:
                ends["end_a"] = tag
            elif abs(z - LENGTH) < 1e-12:
                ends["end_b"] = tag
        groups = {name: gmsh.model.addPhysicalGroup(2, [tag], name=name) for name, tag in ends.items()}
        gmsh.model.addPhysicalGroup(3, [vol], name="solid")
        gmsh.option.setNumber("Mesh.MeshSizeMax", MESH_SIZE)
        gmsh.option.setNumber("Mesh.ElementOrder", 2)
        gmsh.option.setNumber("Mesh.SecondOrderLinear", 0)  # midside nodes on the CAD surface
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.option.setNumber("Mesh.Binary", 0)
        gmsh.model.mesh.generate(3)
        group_nodes, group_corners = {}, {}
        for name, ptag in groups.items():
            _, xyz = gmsh.model.mesh.getNodesForPhysicalGroup(2, ptag)
            group_nodes[name] = np.asarray(xyz).reshape(-1, 3)
            types_, _, conn = gmsh.model.mesh.getElements(2, ends[name])
            assert list(types_) == [9]  # 6-node triangles
            corner_tags = np.unique(np.asarray(conn[0]).reshape(-1, 6)[:, :3])
            group_corners[name] = np.array([gmsh.model.mesh.getNode(int(t))[0] for t in corner_tags])
        msh = d / "cylinder.msh"
        gmsh.write(str(msh))
    assert msh.read_text().startswith("$MeshFormat\n4.1")

    m = meshio.read(msh)
    tets = np.concatenate([c.data for c in m.cells if c.type == "tetra10"])
    out = types.SimpleNamespace(dir=d, msh=msh, points=m.points, tets=tets, group_nodes=group_nodes,
                                group_corners=group_corners)
    # Abaqus: meshio writes the gmsh groups as *ELSET of the end triangles (CPE6 elements)
    out.inp_elset = d / "cylinder_elset.inp"
    meshio.write(out.inp_elset, m)
    text = out.inp_elset.read_text()
    assert "*ELSET, ELSET=end_a" in text and "*ELSET, ELSET=end_b" in text and "C3D10" in text
    # Abaqus: the tetrahedra only, the groups as *NSET of their nodes (corner and midside)
    index = cKDTree(m.points)
    nsets = {k: np.sort(index.query(v)[1]) for k, v in group_nodes.items()}
    out.inp_nset = d / "cylinder_nset.inp"
    meshio.write(out.inp_nset, meshio.Mesh(m.points, [("tetra10", tets)], point_sets=nsets))
    assert out.inp_nset.read_text().count("*NSET") == 2
    # the same Abaqus file in millimetres
    out.inp_mm = d / "cylinder_elset_mm.inp"
    meshio.write(out.inp_mm, meshio.Mesh(m.points * 1e3, m.cells, cell_sets=m.cell_sets))
    out.vtu = d / "cylinder.vtu"
    meshio.write(out.vtu, meshio.Mesh(m.points, [("tetra10", tets)]))
    out.bdf = _bdf(d / "cylinder.bdf", m.points, "tetra10", tets)
    # meshio names the 10-node CTETRA "CTETRA_" (its own fictive card); Nastran's is CTETRA
    text = out.bdf.read_text()
    assert "CTETRA_ " in text
    out.bdf_ctetra = d / "cylinder_ctetra.bdf"
    out.bdf_ctetra.write_text(text.replace("CTETRA_ ", "CTETRA  "))
    # Salome / Code_Aster: MED's node order, the end faces as MED groups (families)
    ends = {name: np.concatenate([b.data[i] for b, i in zip(m.cells, m.cell_sets[name])
                                  if b.type == "triangle6" and i is not None and len(i)]) for name in group_nodes}
    out.med = d / "cylinder.med"
    write_med(out.med, m.points, med_order(m.points, tets), ends)
    out.med_nodes = d / "cylinder_node_groups.med"   # the groups as MED groups of nodes
    write_med(out.med_nodes, m.points, med_order(m.points, tets), nodes=nsets)
    # Nastran decks as other tools write them (tests/support/mesh_writers.py)
    for attr, suffix, grid, tet in (("bdf_free", "bdf", "free", "free-plus"), ("bdf_free_blank", "bdf", "free",
                                    "free-blank"), ("bdf_blank", "bdf", "free", "small-blank"),
                                    ("nas_plus", "nas", "large", "small-plus"), ("bdf_large", "bdf", "large", "large")):
        setattr(out, attr, d / f"cylinder_{attr}.{suffix}")
        getattr(out, attr).write_text(nastran_deck(m.points, tets, grid, tet))
    # P1: the same tetrahedra on their corner nodes only
    corners = np.unique(tets[:, :4])
    remap = np.full(len(m.points), -1)
    remap[corners] = np.arange(len(corners))
    p1_points, p1_tets = m.points[corners], remap[tets[:, :4]]
    out.p1_points, out.p1_tets = p1_points, p1_tets
    p1_index = cKDTree(p1_points)
    out.p1_inp = d / "cylinder_p1.inp"
    meshio.write(out.p1_inp, meshio.Mesh(p1_points, [("tetra", p1_tets)],
                                         point_sets={k: np.sort(p1_index.query(v)[1])
                                                     for k, v in group_corners.items()}))
    out.p1_bdf = _bdf(d / "cylinder_p1.bdf", p1_points, "tetra", p1_tets)
    out.p1_med = d / "cylinder_p1.med"
    write_med(out.p1_med, p1_points, med_order(p1_points, p1_tets))
    out.p1_nas = d / "cylinder_p1.nas"
    out.p1_nas.write_text(nastran_deck(p1_points, p1_tets, "large", "small-blank"))
    return out


def _bdf(path, points, cell_type, cells):
    """A Nastran file written by meshio. Its GRID writer fails (AssertionError in
    ``_float_to_nastran_string``) on any negative coordinate that needs 12 digits, hence the
    cylinder's axis off the origin (every coordinate >= 0)."""
    assert points.min() >= 0.0
    meshio.write(path, meshio.Mesh(points, [(cell_type, cells)]))
    return path


def group_rules() -> tuple:
    return (InterfaceRule("end_a", "group", group="end_a"), InterfaceRule("end_b", "group", group="end_b"))


def plane_rules() -> tuple:
    """The two end planes (m, after the file's unit conversion)."""
    return (InterfaceRule("end_a", "plane", point=(AXIS[0], AXIS[1], 0.0), normal=(0.0, 0.0, 1.0)),
            InterfaceRule("end_b", "plane", point=(AXIS[0], AXIS[1], LENGTH), normal=(0.0, 0.0, 1.0)))


#: format -> (file attribute, units, rules)
P2_FORMATS = {
    "msh": ("msh", "m", group_rules),
    "inp-elset": ("inp_elset", "m", group_rules),
    "inp-nset": ("inp_nset", "m", group_rules),
    "inp-elset-mm": ("inp_mm", "mm", group_rules),
    "vtu": ("vtu", "m", plane_rules),
    "bdf": ("bdf", "m", plane_rules),
    "bdf-ctetra": ("bdf_ctetra", "m", plane_rules),
    "med": ("med", "m", group_rules),
    "med-node-groups": ("med_nodes", "m", group_rules),
    "bdf-free-plus": ("bdf_free", "m", plane_rules),
    "bdf-free-blank": ("bdf_free_blank", "m", plane_rules),
    "bdf-small-blank": ("bdf_blank", "m", plane_rules),
    "nas-small-plus": ("nas_plus", "m", plane_rules),
    "bdf-large": ("bdf_large", "m", plane_rules),
}


class _Models(dict):
    """format -> (FE model, its N_RIGID + N_ELASTIC lowest free-free frequencies, Hz), each
    built when first asked for (a format that cannot be read fails its own tests only)."""

    def __init__(self, files, cache):
        super().__init__()
        self.files, self.cache = files, cache

    def __missing__(self, fmt):
        attr, units, rules = P2_FORMATS[fmt]
        fe = build_component(PartFile(str(getattr(self.files, attr)), rules(), units=units), STEEL,
                             cache_dir=self.cache)
        f = lowest_modes(fe.K, fe.M, N_RIGID + N_ELASTIC, sigma=free_free_shift(fe.K, fe.M)).frequencies_hz
        self[fmt] = (fe, f)
        return self[fmt]

    def all(self):
        return [(fmt, self[fmt]) for fmt in P2_FORMATS]


@pytest.fixture(scope="module")
def models(files, tmp_path_factory):
    return _Models(files, tmp_path_factory.mktemp("p2-cache"))


@pytest.mark.parametrize("fmt", list(P2_FORMATS))
def test_second_order_is_kept(fmt, files, models):
    fe, _ = models[fmt]
    assert fe.order == 2
    assert type(fe.mesh).__name__ == "MeshTet2" and fe.mesh.nelements == len(files.tets)
    raw = read_mesh(fe.mesh_file)          # the converted file in the mesh cache
    assert raw.cell_type == "tetra10" and len(raw.cells) == len(files.tets)
    # every node of the file is an FE node: 4 corners + 6 midside nodes per tetrahedron
    assert fe.n_nodes == len(np.unique(files.tets))
    assert _same_points(fe.nodes, files.points[np.unique(files.tets)])


@pytest.mark.parametrize("fmt", list(P2_FORMATS))
def test_interfaces_are_the_groups_corner_and_midside_nodes(fmt, files, models):
    fe, _ = models[fmt]
    assert list(fe.interfaces) == ["end_a", "end_b"]
    for name in ("end_a", "end_b"):
        want = files.group_nodes[name]
        assert len(want) > len(files.group_corners[name])  # the group holds midside nodes too
        assert _same_points(fe.nodes[fe.interfaces[name].nodes], want), name
    # masters: the area centroid of each end's straight triangles. gmsh divides the circular
    # rim into equal arcs (one constant size), so the rim is a regular polygon whose centroid
    # is the circle's centre: on the axis to the coordinates' rounding
    for name, z in (("end_a", 0.0), ("end_b", LENGTH)):
        assert np.allclose(fe.interfaces[name].master, (AXIS[0], AXIS[1], z), rtol=0, atol=POS_TOL)


def _lateral_edge_angles(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """Angles (rad) about the axis subtended by the edges of the boundary faces lying on the
    cylinder's lateral surface."""
    r = np.hypot(points[:, 0] - AXIS[0], points[:, 1] - AXIS[1])
    z = points[:, 2]
    f = _faces_of(tets)
    on_r = np.abs(r - R) < 1e-9 * R
    lateral = f[on_r[f].all(axis=1) & ~(np.abs(z[f]) < 1e-12).all(axis=1)
                & ~(np.abs(z[f] - LENGTH) < 1e-12).all(axis=1)]
    phi = np.arctan2(points[:, 1] - AXIS[1], points[:, 0] - AXIS[0])
    return np.concatenate([np.abs(np.angle(np.exp(1j * (phi[lateral[:, a]] - phi[lateral[:, b]]))))
                           for a, b in ((0, 1), (1, 2), (2, 0))])


@pytest.mark.parametrize("fmt", list(P2_FORMATS))
def test_mass_is_the_curved_cylinders(fmt, files, models):
    """The P2 model's mass is rho x the volume of the curved P2 elements (integrated exactly:
    their Jacobian is cubic, the mass quadrature of order 4), which misses the exact cylinder
    by the P2 interpolation of its surface only.

    Bound: in a cross-section, the P2 edge through two rim nodes and the node between them
    (gmsh puts it on the cylinder, Mesh.SecondOrderLinear = 0) is the parabola through three
    points of an arc of angle t; the lens between them has area R^2 t^5 / 960 (circular
    segment R^2 (t^3/12 - t^5/240) minus parabolic segment 2/3 chord x sagitta =
    R^2 (t^3/12 - t^5/192)), so arcs no wider than t_max miss at most t_max^4 / 480 of the
    disc, always from inside. Measured: deficit 5.0e-5, t_max = 0.573 rad, bound 2.2e-4
    (at mesh sizes 8 and 6 mm: 1.1e-5 < 4.5e-5 and 3.5e-6 < 9.4e-6: the h^4 rate)."""
    fe, _ = models[fmt]
    deficit = 1.0 - fe.mass / (STEEL.rho * V_EXACT)
    t_max = _lateral_edge_angles(files.points, files.tets).max()
    assert 0.0 < deficit < t_max**4 / 480, (deficit, t_max)


def test_a_mesh_file_has_no_exact_mass_check(files, tmp_path, caplog):
    """A mesh file has no exact geometry: its straight elements miss the chordal lens of every
    rim edge, O(t^2) (2.6e-2 here), far more than the P2 model's O(t^4) (5e-5), so they are no
    reference: ``fe.checks`` stays empty and nothing warns."""
    with caplog.at_level(logging.WARNING, logger="fe_components.fe_model"):
        fe = build_component(PartFile(str(files.vtu), plane_rules(), units="m"), STEEL, cache_dir=tmp_path)
    assert abs(fe.mass / (STEEL.rho * V_EXACT) - 1.0) < CAD_MASS_TOL   # the model is accurate
    assert fe.checks == {}
    assert "refine the mesh" not in caplog.text


def test_free_free_frequencies_agree_between_the_formats(models):
    """Same mesh, same model: the lowest elastic frequencies agree to 1e-9 (the only
    difference: the .bdf's 12-digit coordinates, 5e-13 relative)."""
    ref = None
    for fmt, (_, f) in models.all():
        assert count_rigid_modes(f) == N_RIGID, (fmt, f[:N_RIGID + 1])
        elastic = f[N_RIGID:]
        if ref is None:
            ref = elastic
            assert elastic[0] > 1e3  # Hz: a 0.1 m steel cylinder: its first elastic mode is ~16 kHz
        np.testing.assert_allclose(elastic, ref, rtol=1e-9, err_msg=fmt)


def test_millimetre_file_gives_the_same_model(models):
    """The .inp scaled by 1000 and read with units = "mm" gives the metre file's model."""
    fe_m, f_m = models["inp-elset"]
    fe_mm, f_mm = models["inp-elset-mm"]
    assert np.allclose(fe_mm.nodes, fe_m.nodes, rtol=0, atol=1e-15)  # x 1e3 then x 1e-3: an ulp or so
    assert fe_mm.mass == pytest.approx(fe_m.mass, rel=1e-12)
    for name in ("end_a", "end_b"):
        assert np.array_equal(fe_mm.interfaces[name].nodes, fe_m.interfaces[name].nodes)
    np.testing.assert_allclose(f_mm[N_RIGID:], f_m[N_RIGID:], rtol=1e-9)


@pytest.mark.parametrize("fmt", ["inp", "bdf", "med", "nas"])
def test_first_order_file_gives_an_order_1_model(fmt, files, tmp_path):
    """A P1 (tetra) file: order 1, its interfaces the groups' corner nodes, its mass the
    straight elements' exactly (P1 elements are the straight tetrahedra)."""
    if fmt == "inp":
        part = PartFile(str(files.p1_inp), group_rules(), units="m")
    else:
        part = PartFile(str(getattr(files, f"p1_{fmt}")), plane_rules(), units="m")
    fe = build_component(part, STEEL, cache_dir=tmp_path)
    assert fe.order == 1 and type(fe.mesh).__name__ == "MeshTet1"
    assert read_mesh(fe.mesh_file).cell_type == "tetra"
    assert fe.n_nodes == len(files.p1_points)
    for name in ("end_a", "end_b"):
        assert _same_points(fe.nodes[fe.interfaces[name].nodes], files.group_corners[name]), name
    v_straight = _straight_volume(files.p1_points, files.p1_tets)
    assert fe.mass == pytest.approx(STEEL.rho * v_straight, rel=1e-12)
    assert fe.checks == {}  # no exact geometry to check a mesh file against


@pytest.mark.parametrize("fmt", ["med", "med-node-groups", "bdf-free-plus", "bdf-free-blank", "bdf-small-blank", "nas-small-plus",
                                 "bdf-large"])
def test_med_and_nastran_give_the_gmsh_files_model(fmt, models):
    """The MED file (MED's node order, read in it) and every Nastran style give the model of
    the gmsh file itself: the same volume (mass), centre and inertia, and the same free-free
    frequencies, to 1e-9 (the large-field decks keep 12 digits: 5e-13 relative)."""
    fe, f = models[fmt]
    ref, f_ref = models["msh"]
    assert fe.mass == pytest.approx(ref.mass, rel=1e-9)
    assert np.allclose(fe.center_of_mass, ref.center_of_mass, rtol=0, atol=1e-9 * LENGTH)
    assert np.abs(fe.inertia - ref.inertia).max() < 1e-9 * np.abs(ref.inertia).max()
    np.testing.assert_allclose(f[N_RIGID:], f_ref[N_RIGID:], rtol=1e-9)
    assert fe.read.n_solid == len(ref.mesh.t.T) and fe.read.solid == "tetra10"



def test_linear_file_lifted_keeps_its_node_groups(files, tmp_path):
    """The P1 Abaqus file with its groups as *NSET of corner nodes, lifted to P2 (order = 2):
    each group holds the same faces as the P2 file's (as many nodes: corners and one per face
    edge), every node in its end plane, the corners the group's own."""
    fe = build_component(PartFile(str(files.p1_inp), group_rules(), units="m", order=2), STEEL, cache_dir=tmp_path)
    assert fe.order == 2 and fe.read.lifted
    for name, z in (("end_a", 0.0), ("end_b", LENGTH)):
        p = fe.nodes[fe.interfaces[name].nodes]
        assert len(p) == len(files.group_nodes[name])
        assert np.abs(p[:, 2] - z).max() < 1e-15
        corners = cKDTree(p).query(files.group_corners[name])[0]
        assert corners.max() < POS_TOL
