"""Mesh files written the way other tools write them, for the part-file tests: a Salome /
Code_Aster MED file in MED's own node order (with its groups as families), a Nastran bulk
deck in any field format and continuation style, and a structured tetrahedral box.

Node orders are derived here from each format's definition, independently of the reader:

* MED (MED reference elements, as in Salome's SMESH "nodal connectivity of elements" and
  MEDMEM's CELLMODEL): the face N1 N2 N3 of a TETRA4 is numbered so that its normal
  (N2 - N1) x (N3 - N1) points away from N4; TETRA10's N5..N10 lie on the edges N1N2, N2N3,
  N3N1, N1N4, N2N4, N3N4;
* Nastran (MSC Quick Reference Guide, CTETRA): G1..G4 corners, G5..G10 on G1G2, G2G3, G3G1,
  G1G4, G2G4, G3G4; either handedness.
"""
from __future__ import annotations

import random

import meshio
import numpy as np

#: A tetrahedron's edges in the order of its 10-node element's edge nodes (MED, Nastran, VTK).
EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))


def signed_volumes(points, tets) -> np.ndarray:
    p = np.asarray(points)[np.asarray(tets)[:, :4]]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6


def renumbered(tet, corners) -> list:
    """Tetrahedron ``tet`` (4 or 10 nodes, edge nodes in :data:`EDGES` order) with its
    corners taken in the order ``corners`` (indices into its 4 corners); the edge nodes follow."""
    tet = list(tet)
    c = [tet[i] for i in corners]
    if len(tet) == 4:
        return c
    mid = {frozenset((tet[a], tet[b])): tet[4 + k] for k, (a, b) in enumerate(EDGES)}
    return c + [mid[frozenset((c[a], c[b]))] for a, b in EDGES]


def med_order(points, tets) -> np.ndarray:
    """The tetrahedra (VTK order) numbered as MED numbers them: the first face outward."""
    out = []
    for t, v in zip(tets, signed_volumes(points, tets)):
        out.append(renumbered(t, (0, 2, 1, 3)) if v > 0 else list(t))  # VTK's first face points inward
    out = np.array(out)
    p = np.asarray(points)[out[:, :4]]
    normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    assert (np.einsum("ij,ij->i", normal, p[:, 3] - p[:, 0]) < 0).all()  # N4 behind the face N1 N2 N3
    return out


def write_med(path, points, tets_med, faces=None, nodes=None) -> None:
    """A MED file (meshio's HDF5 writer, which keeps the connectivity as given) of the
    tetrahedra ``tets_med`` (already in MED's order) and optionally face groups, ``faces``
    {group name: triangles (3 or 6 nodes)}, each group one family (MED's element families are
    negative), or node groups, ``nodes`` {group name: node indices} (positive families)."""
    ctype = "tetra10" if tets_med.shape[1] == 10 else "tetra"
    cells, tags, families = [(ctype, np.asarray(tets_med))], [np.zeros(len(tets_med), int)], {}
    tri = {}
    for k, (name, t) in enumerate((faces or {}).items()):
        tri.setdefault(t.shape[1], []).append((t, -(k + 1)))
        families[-(k + 1)] = [name]
    for n, blocks in tri.items():
        cells.append(("triangle6" if n == 6 else "triangle", np.vstack([t for t, _ in blocks])))
        tags.append(np.concatenate([np.full(len(t), fam) for t, fam in blocks]))
    point_data, node_families = {}, {}
    if nodes:
        ptags = np.zeros(len(points), int)
        for k, (name, idx) in enumerate(nodes.items()):
            ptags[np.asarray(idx)] = k + 1
            node_families[k + 1] = [name]
        point_data["point_tags"] = ptags
    m = meshio.Mesh(points, cells, cell_data={"cell_tags": tags}, point_data=point_data)
    m.cell_tags = families
    m.point_tags = node_families
    meshio.write(path, m, file_format="med")


# ------------------------------------------------------------------------------- Nastran
def nastran_real(x: float, width: int | None) -> str:
    """``x`` in at most ``width`` characters with Nastran's implicit exponent
    (``-1.2345678901-2``: as many digits as fit), or exactly (``repr``) for ``width`` None."""
    if width is None:
        return repr(float(x))
    if x == 0:
        return "0."
    for digits in range(width, 0, -1):
        mant, exp = f"{x:.{digits}e}".split("e")
        text = f"{mant}{int(exp):+d}"
        if len(text) <= width:
            return text
    raise ValueError(x)


def _small(fields) -> str:
    return "".join(f"{f:<8}" for f in fields)


def _large(fields) -> str:
    return f"{fields[0]:<8}" + "".join(f"{f:>16}" for f in fields[1:])


def grid_lines(gid: int, xyz, style: str) -> list:
    """One GRID card: ``free`` (exact numbers), ``large`` (16 columns, ``*`` continuation)."""
    if style == "free":
        return [f"GRID,{gid},," + ",".join(nastran_real(v, None) for v in xyz)]
    x, y, z = (nastran_real(v, 16) for v in xyz)
    return [_large(["GRID*", str(gid), "", x, y]) + "*G" + str(gid), _large(["*G" + str(gid), z])]


def ctetra_lines(eid: int, nodes, style: str, strip: bool = True) -> list:
    """One CTETRA card (4 or 10 nodes) continued in ``style``: ``free-plus`` (free field,
    ``+`` marker), ``free-blank`` (free field, the continuation's first field empty),
    ``small-plus`` (8 columns, markers in field 10 and 1), ``small-blank`` (8 columns, a blank
    first field; ``strip``: the first line's trailing blanks removed), ``large`` (16 columns,
    ``*`` continuations)."""
    g = [str(int(n)) for n in nodes]
    head = ["CTETRA", str(eid), "1"]
    if style.startswith("free"):
        first, rest = head + g[:6], g[6:]
        if not rest:
            return [",".join(first)]
        mark = "+" if style == "free-plus" else ""
        return [",".join(first) + ("," + "+C" + str(eid) if mark else ""),
                ",".join([mark + ("C" + str(eid) if mark else "")] + rest)]
    if style.startswith("small"):
        first, rest = head + g[:6], g[6:]
        if not rest:
            return [_small(first).rstrip()]
        if style == "small-plus":
            return [_small(first + ["+C" + str(eid)]).rstrip(), _small(["+C" + str(eid)] + rest).rstrip()]
        line = _small(first)
        return [line.rstrip() if strip else line + " " * 8, _small([""] + rest).rstrip()]
    # large field: 4 data fields a line
    data = [str(eid), "1"] + g
    lines = [_large(["CTETRA*"] + data[:4])]
    for k in range(4, len(data), 4):
        lines.append(_large(["*"] + data[k:k + 4]))
    return lines


def nastran_deck(points, tets, grid_style="free", tet_style="small-blank", rng: random.Random | None = None,
                 extra: list | None = None, header: bool = True, flipped=None) -> str:
    """A bulk deck of ``points`` (GRID 1..n) and ``tets`` (VTK order = Nastran's): every card
    in the given styles, or each drawn from ``rng`` (then with comments and blank lines mixed
    in); ``flipped``: which tetrahedra are written left-handed (G2 and G3 swapped); ``extra``:
    lines added before ENDDATA."""
    lines = ["$ written by flexgear's tests", "SOL 103", "CEND", "BEGIN BULK"] if header else []
    for i, p in enumerate(points):
        style = rng.choice(["free", "large"]) if rng else grid_style
        lines += grid_lines(i + 1, p, style)
        if rng and rng.random() < 0.05:
            lines.append(rng.choice(["$ a comment", "", "$"]))
    styles = ["free-plus", "free-blank", "small-plus", "small-blank", "large"]
    for e, t in enumerate(np.asarray(tets) + 1):
        style = rng.choice(styles) if rng else tet_style
        if flipped is not None and flipped[e]:   # Nastran takes either handedness
            t = renumbered(t, (0, 2, 1, 3))
        lines += ctetra_lines(e + 1, t, style, strip=not rng or rng.random() < 0.7)
    lines += list(extra or [])
    lines.append("ENDDATA")
    return "\n".join(lines) + "\n"


# ----------------------------------------------------------------------- structured box
def kuhn_box(size, cells) -> tuple[np.ndarray, np.ndarray]:
    """A box ``size`` (x, y, z in m, from the origin) of ``cells`` (nx, ny, nz) cubes, each
    split into 6 tetrahedra about its main diagonal (Kuhn), positively oriented (VTK order)."""
    nx, ny, nz = cells
    axes = [np.linspace(0.0, s, n + 1) for s, n in zip(size, cells)]
    X, Y, Z = np.meshgrid(*axes, indexing="ij")
    pts = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])
    i, j, k = (a.ravel() for a in np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij"))

    def node(a, b, c):
        return ((i + a) * (ny + 1) + (j + b)) * (nz + 1) + (k + c)
    corner = [node(*d) for d in ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1),
                                 (0, 1, 1))]
    tets = np.concatenate([np.column_stack([corner[q] for q in t]) for t in
                           ((0, 1, 2, 6), (0, 2, 3, 6), (0, 3, 7, 6), (0, 7, 4, 6), (0, 4, 5, 6), (0, 5, 1, 6))])
    flip = signed_volumes(pts, tets) < 0
    tets[flip] = tets[flip][:, [0, 2, 1, 3]]
    return pts, tets
