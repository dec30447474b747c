"""Superelement export for other tools: a documented ``.npz`` and Nastran DMIG bulk data.

Both files carry the reduced matrices of a :class:`~cms.superelement.Superelement` in its own
coordinates (boundary DOFs first, in the reductor's order, then the modal coordinates) and the
DOF map: which interface node (Nastran GRID) and component (1..6 = ux, uy, uz, rx, ry, rz) each
boundary DOF is, and which scalar point (Nastran SPOINT) each modal coordinate is.

Units SI: m, kg, s, N, rad. Boundary blocks of K are N/m (force per displacement), N (force per
rotation, moment per displacement) and N m/rad; of M kg, kg m and kg m^2. The modal coordinates
of mass-normalised fixed-interface modes (Phi^T M_ii Phi = I) are in sqrt(kg) m, so the modal
block of M is dimensionless and that of K is in (rad/s)^2.

* :func:`write_npz` / :func:`read_npz`: every array of the export, values bit-exact.
* :func:`is_export`: whether a file is one of these exports (npz ``format`` entry, or the
  DMIG header's description line), for a writer that replaces only its own files.
* :func:`write_dmig`: free-field (comma-separated) Nastran bulk data: GRID cards at the
  interface nodes, SPOINT cards for the modal coordinates and one symmetric real double
  precision DMIG matrix per K and M (IFO = 6, TIN = 2), upper triangle only, exact zeros
  dropped. Every real is Python's shortest round-trip representation (``repr``, at most 17
  significant digits, up to 24 characters), so a reader that parses binary64 gets K and M back
  bit for bit (``field_width=16``: fields of at most 16 characters, >= 10 significant digits,
  for a reader that limits free fields to that). Lines stay within 80 characters.
  :func:`read_dmig` / :func:`read_dmig_points` parse that layout back.

Files are written to a temporary file in the target folder, fsynced and ``os.replace``d: the
target is the old file or the whole new one, never half-written. Layout in
docs/superelement_export.md.
"""
from __future__ import annotations

import logging
import math
import os
import textwrap
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .errors import CacheError, ReductionError
from .superelement import atomic_write

log = logging.getLogger(__name__)

FORMAT = "flexgear.cms.superelement_export"
VERSION = "1"
COMPONENTS = ("ux", "uy", "uz", "rx", "ry", "rz")   # Nastran components 1..6
DEFAULT_FRAME = "the superelement's own coordinates (the component's local axes)"
UNITS = ("SI: m, kg, s, N, rad. K: N/m (translation-translation), N (translation-rotation), "
         "N m/rad (rotation-rotation); M: kg, kg m, kg m^2. Modal coordinates q of the mass-normalised "
         "fixed-interface modes are in sqrt(kg) m: the modal block of M is dimensionless, that of K in "
         "(rad/s)^2, mixed blocks follow from the energies q'Kq/2 (J) and q'Mq/2 (kg m^2). "
         "node_positions, center_of_mass m; mass kg; inertia kg m^2 about the centre of mass; "
         "fixed_interface_frequencies_hz Hz.")
MAX_ID = 99_999_999          # largest Nastran GRID / SPOINT id (8 digits)
LINE_WIDTH = 80              # Nastran bulk data line length
GRID_FIELD = 21              # widest coordinate field of a GRID line that fits 80 characters (8-digit id)
DMIG_HEADER = (0, 6, 2, 0, 0)  # field 3 "0", IFO = 6 symmetric, TIN = 2 real double, TOUT, POLAR
SYMMETRY_RTOL = 1e-12        # largest |K - K'| / |K| accepted as a symmetric (IFO = 6) matrix
DMIG_DESCRIPTION = "Nastran bulk data, free-field. Matrices"  # starts a comment line of every DMIG header
HEADER_LINES = 50            # comment lines of a DMIG header searched for DMIG_DESCRIPTION


# ---- DOF map ------------------------------------------------------------------------------
@dataclass(frozen=True)
class DofMap:
    """The reduced coordinates as Nastran points: interface node ``k`` is GRID
    ``node_ids[k]`` at ``node_positions[k]`` (m); reduced DOF ``j`` is component
    ``dof_component[j]`` (1..6) of node ``dof_node[j]``, or, for a modal coordinate
    (``dof_node = -1``, ``dof_component = 0``), SPOINT ``scalar_ids[j - n_boundary]``."""

    node_names: list
    node_ids: np.ndarray
    node_positions: np.ndarray
    dof_node: np.ndarray
    dof_component: np.ndarray
    scalar_ids: np.ndarray
    dof_names: list

    def keys(self) -> list:
        """(point id, component) of every reduced DOF, in order (component 0: SPOINT)."""
        nb = int(np.sum(self.dof_node >= 0))
        out = [(int(self.node_ids[k]), int(c)) for k, c in zip(self.dof_node[:nb], self.dof_component[:nb])]
        return out + [(int(s), 0) for s in self.scalar_ids]


def dof_map(se, node_ids=None, first_scalar_id: int | None = None) -> DofMap:
    """The :class:`DofMap` of ``se``. ``node_ids``: GRID id of each interface node (default
    1, 2, ...); ``first_scalar_id``: SPOINT id of the first modal coordinate, the others
    following (default: the first id after the next multiple of 1000 above the largest GRID
    id, e.g. 1001 for up to 999 nodes). Nodes and components come from ``boundary_names``
    (``"node:ux"``) or ``boundary_kinds``, positions from ``metadata["masters"]`` or
    ``boundary_points``; a boundary DOF without them raises :class:`ReductionError`."""
    names, dof_node, comp = _boundary_nodes(se)
    positions = np.array([_node_position(se, nm, dof_node == k) for k, nm in enumerate(names)]).reshape(-1, 3)
    ids = np.arange(1, len(names) + 1) if node_ids is None else np.asarray(node_ids, dtype=np.int64)
    if ids.shape != (len(names),):
        raise ReductionError(f"need one GRID id per interface node {names}", "node_ids", list(np.atleast_1d(ids)))
    if first_scalar_id is None:
        first_scalar_id = 1000 * (int(ids.max(initial=0)) // 1000 + 1) + 1
    scalars = np.arange(first_scalar_id, first_scalar_id + se.n_modes, dtype=np.int64)
    _check_ids(ids, scalars)
    n = se.n_boundary + se.n_modes
    bnames = list(se.boundary_names) if len(se.boundary_names) == se.n_boundary else \
        [f"{names[k]}:{COMPONENTS[c - 1]}" for k, c in zip(dof_node, comp)]
    return DofMap(names, ids.astype(np.int64), positions,
                  np.concatenate([dof_node, np.full(se.n_modes, -1)]).astype(np.int64),
                  np.concatenate([comp, np.zeros(se.n_modes, int)]).astype(np.int64), scalars,
                  bnames + [f"q{m}" for m in range(n - se.n_boundary)])


def _component(se, j: int, name: str) -> int:
    """Nastran component (1..6) of boundary DOF ``j`` from its kind or its name's suffix."""
    kinds = np.asarray(se.boundary_kinds)
    kind = int(kinds[j]) if len(kinds) == se.n_boundary and 0 <= kinds[j] <= 5 else None
    suffix = name.rpartition(":")[2]
    named = COMPONENTS.index(suffix) if ":" in name and suffix in COMPONENTS else None
    if kind is not None and named is not None and kind != named:
        raise ReductionError(f"boundary DOF {j} is named {name!r} but has kind {COMPONENTS[kind]}",
                             "boundary_kinds", kind)
    c = kind if kind is not None else named
    if c is None:
        raise ReductionError(f"boundary DOF {j} ({name or 'unnamed'}) has no component: name it 'node:ux' "
                             "... 'node:rz' or give boundary_kinds 0..5", "boundary_names", name)
    return c + 1


def _boundary_nodes(se) -> tuple[list, np.ndarray, np.ndarray]:
    """(node names in order of first appearance, node index and component 1..6 per boundary DOF).
    A node is a name's prefix before ':' or, for unnamed DOFs, a distinct boundary point."""
    names = list(se.boundary_names) if len(se.boundary_names) == se.n_boundary else [""] * se.n_boundary
    pts = np.asarray(se.boundary_points)
    nodes, dof_node, comp = [], [], []
    for j, name in enumerate(names):
        if ":" in name:
            node = name.rpartition(":")[0]
        elif len(pts) == se.n_boundary:
            node = "p(" + ", ".join(repr(float(x)) for x in pts[j]) + ")"
        else:
            raise ReductionError(f"boundary DOF {j} has no node: neither a name 'node:ux' nor a boundary point",
                                 "boundary_names", name)
        if node not in nodes:
            nodes.append(node)
        k, c = nodes.index(node), _component(se, j, name)
        if any(dk == k and dc == c for dk, dc in zip(dof_node, comp)):
            raise ReductionError(f"node {node!r} has component {COMPONENTS[c - 1]} twice", "boundary_names", name)
        dof_node.append(k)
        comp.append(c)
    return nodes, np.array(dof_node, dtype=np.int64), np.array(comp, dtype=np.int64)


def _node_position(se, node: str, its_dofs: np.ndarray) -> np.ndarray:
    """Position (m) of interface node ``node`` (``its_dofs``: mask of its boundary DOFs):
    metadata["masters"], else the boundary point of its first DOF."""
    masters = se.metadata.get("masters") or {}
    if node in masters:
        return np.asarray(masters[node], dtype=float)
    pts = np.asarray(se.boundary_points)
    if len(pts) == se.n_boundary:
        return pts[int(np.flatnonzero(its_dofs)[0])].astype(float)
    raise ReductionError(f"interface node {node!r} has no position (metadata['masters'] or boundary_points)",
                         "node", node)


def _check_ids(node_ids: np.ndarray, scalar_ids: np.ndarray) -> None:
    every = np.concatenate([node_ids, scalar_ids])
    if len(every) and (every.min() < 1 or every.max() > MAX_ID):
        raise ReductionError(f"Nastran point ids must lie in 1..{MAX_ID}", "ids",
                             [int(every.min()), int(every.max())])
    if len(np.unique(every)) != len(every):
        raise ReductionError("GRID and SPOINT ids must all differ", "node_ids", node_ids.tolist())


# ---- npz ---------------------------------------------------------------------------------
def npz_arrays(se, node_ids=None, first_scalar_id: int | None = None, frame: str = DEFAULT_FRAME,
               frame_origin=None, frame_axes=None) -> dict:
    """The arrays :func:`write_npz` stores (see docs/superelement_export.md)."""
    dm = dof_map(se, node_ids, first_scalar_id)
    md = se.metadata
    out = {"format": np.array(FORMAT), "version": np.array(VERSION), "units": np.array(UNITS),
           "frame": np.array(frame),
           "K": np.asarray(se.K, dtype=float), "M": np.asarray(se.M, dtype=float),
           "dof_names": np.array(dm.dof_names, dtype=str), "n_boundary": np.array(se.n_boundary),
           "node_ids": dm.node_ids, "node_names": np.array(dm.node_names, dtype=str),
           "node_positions": dm.node_positions, "dof_node": dm.dof_node, "dof_component": dm.dof_component,
           "scalar_ids": dm.scalar_ids,
           "fixed_interface_frequencies_hz": np.asarray(se.mode_frequencies_hz, dtype=float),
           "n_residual_vectors": np.array(int(md.get("n_residual_vectors", 0)))}
    for key in ("mass", "center_of_mass", "inertia"):
        if key in md:
            out[key] = np.asarray(md[key], dtype=float)
    if "mesh_sha256" in md:
        out["mesh_sha256"] = np.array(str(md["mesh_sha256"]))
    if frame_origin is not None:
        out["frame_origin"] = np.asarray(frame_origin, dtype=float).reshape(3)
    if frame_axes is not None:
        out["frame_axes"] = np.asarray(frame_axes, dtype=float).reshape(3, 3)
    return out


def write_npz(path, se, *, node_ids=None, first_scalar_id: int | None = None, frame: str = DEFAULT_FRAME,
              frame_origin=None, frame_axes=None) -> Path:
    """Write the superelement ``se`` as a documented ``.npz`` (``np.savez_compressed``, no
    pickled objects), atomically. ``frame``: what the coordinates are, in words;
    ``frame_origin`` (m) / ``frame_axes`` (columns = the frame's x, y, z in global axes):
    optional placement, stored when given. Returns the path."""
    arrays = npz_arrays(se, node_ids, first_scalar_id, frame, frame_origin, frame_axes)
    out = atomic_write(path, lambda fh: np.savez_compressed(fh, **arrays))
    log.info("wrote superelement npz (%d boundary DOFs, %d modal) to %s", se.n_boundary, se.n_modes, out)
    return out


def read_npz(path) -> dict:
    """The arrays of a file written by :func:`write_npz` (strings and scalars as Python
    ``str`` / ``int`` / ``float``); a file of another format or version raises
    :class:`~cms.errors.CacheError`, as does a file that is no npz."""
    try:
        with np.load(path, allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
    except (OSError, ValueError) as exc:        # missing, not an npz, or an npz of pickled objects
        raise CacheError(f"cannot read superelement export: {type(exc).__name__}: {exc}", "path",
                         os.fspath(path)) from exc
    fmt, ver = (str(data[k]) if k in data else None for k in ("format", "version"))
    if (fmt, ver) != (FORMAT, VERSION):
        raise CacheError("not a flexgear superelement export of a known version", "format/version", (fmt, ver))
    for k, v in data.items():
        if v.ndim == 0:
            data[k] = v.item()
    return data


# ---- DMIG: writing -------------------------------------------------------------------------
def nastran_real(x: float, width: int | None = None) -> str:
    """``x`` as a Nastran real: the shortest string that reads back to the same binary64
    (``repr``, at most 17 significant digits), with a decimal point and an upper-case exponent
    (``1e-05`` -> ``1.0E-05``). ``width``: at most that many characters (16: a large field);
    when ``repr`` is longer, the most significant digits that fit, in E format (16 characters
    keep at least 10 significant digits, relative error <= 5e-10, for 1e-99 <= |x| < 1e100;
    9 beyond, with a three-digit exponent)."""
    x = float(x)
    if not math.isfinite(x):
        raise ReductionError("a matrix or position is not finite", "value", x)
    mant, e, exp = repr(x).upper().partition("E")
    s = (mant if "." in mant else mant + ".0") + e + exp
    if width is None or len(s) <= width:
        return s
    for digits in range(16, 1, -1):
        t = f"{x:.{digits - 1}E}"
        if len(t) <= width:
            return t
    raise ReductionError("a real does not fit the field width", "width", width)


def _line(fields) -> str:
    """One free-field line; LINE_WIDTH is checked by the caller."""
    return ",".join("" if f is None else str(f) for f in fields)


def _grid_line(gid: int, xyz, width: int | None = None) -> str:
    """``GRID,ID,,X1,X2,X3`` (CP blank: basic system); coordinates as :func:`nastran_real`,
    narrowed to 21 characters (logged) in the rare case the line would exceed 80."""
    line = _line(["GRID", gid, None, *(nastran_real(v, width) for v in xyz)])
    if len(line) > LINE_WIDTH:
        narrow = min(width or GRID_FIELD, GRID_FIELD)
        line = _line(["GRID", gid, None, *(nastran_real(v, narrow) for v in xyz)])
        log.warning("GRID %d: coordinates written in %d characters to fit the 80-character line", gid, narrow)
    return line


def _spoint_lines(ids: np.ndarray) -> list:
    """SPOINT cards of consecutive ids: ``SPOINT,first,THRU,last``."""
    return [] if len(ids) == 0 else [_line(["SPOINT", int(ids[0]), "THRU", int(ids[-1])])]


def _check_symmetric(name: str, A: np.ndarray) -> None:
    scale = np.abs(A).max(initial=0.0)
    asym = np.abs(A - A.T).max(initial=0.0)
    if asym > SYMMETRY_RTOL * scale:
        raise ReductionError(f"matrix {name} is not symmetric (DMIG IFO = 6)", "max |A - A'| / max |A|",
                             asym / scale)


def dmig_lines(name: str, A: np.ndarray, keys: list, width: int | None = None) -> list:
    """DMIG cards of the symmetric matrix ``A`` on points ``keys`` ((id, component) per
    row/column): the header (IFO 6, TIN 2), then per column j the entries of rows i <= j
    (upper triangle), exact zeros dropped, two (G, C, A, blank) groups per line; reals as
    :func:`nastran_real` with ``width``."""
    if not (name[:1].isalpha() and name.isalnum() and len(name) <= 8):
        raise ReductionError("a DMIG name is 1..8 letters or digits, starting with a letter", "name", name)
    A = np.asarray(A, dtype=float)
    if A.shape != (len(keys), len(keys)):
        raise ReductionError(f"matrix {name} does not match the DOF map", "shape", A.shape)
    _check_symmetric(name, A)
    lines = [_line(["DMIG", name, *DMIG_HEADER])]
    for j, (gj, cj) in enumerate(keys):
        rows = [i for i in range(j + 1) if A[i, j] != 0.0]
        if not rows:
            continue
        groups = [[keys[i][0], keys[i][1], nastran_real(A[i, j], width)] for i in rows]
        first = ["DMIG", name, gj, cj, None, *groups[0]]
        lines.append(_line(first))
        for k in range(1, len(groups), 2):
            pair = groups[k] + ([None, *groups[k + 1]] if k + 1 < len(groups) else [])
            lines.append(_line(["+", *pair]))
    return lines


def dmig_text(se, *, k_name: str = "KAAX", m_name: str = "MAAX", node_ids=None,
              first_scalar_id: int | None = None, frame: str = DEFAULT_FRAME, title: str = "",
              field_width: int | None = None) -> str:
    """The bulk data text :func:`write_dmig` writes."""
    dm = dof_map(se, node_ids, first_scalar_id)
    keys = dm.keys()
    head = _dmig_header(se, dm, k_name, m_name, frame, title, field_width)
    body = [_grid_line(int(g), p, field_width) for g, p in zip(dm.node_ids, dm.node_positions)]
    body += _spoint_lines(dm.scalar_ids)
    body += dmig_lines(k_name, se.K, keys, field_width) + dmig_lines(m_name, se.M, keys, field_width)
    too_long = [ln for ln in body if len(ln) > LINE_WIDTH]
    if too_long:
        raise ReductionError(f"a bulk data line exceeds {LINE_WIDTH} characters", "line", too_long[0])
    return "\n".join(head + body) + "\n"


def _comment(text: str) -> list:
    return ["$ " + ln for ln in textwrap.wrap(text, LINE_WIDTH - 2, break_long_words=True)] or ["$"]


def _dmig_header(se, dm: DofMap, k_name: str, m_name: str, frame: str, title: str,
                 field_width: int | None) -> list:
    n_rv = int(se.metadata.get("n_residual_vectors", 0))
    reals = ("the shortest decimal that reads back to the same binary64 (<= 17 digits)" if field_width is None
             else f"in at most {field_width} characters (the most significant digits that fit)")
    out = _comment(title or "flexgear superelement export (Craig-Bampton)")
    out += _comment(f"{DMIG_DESCRIPTION} {k_name} (stiffness) and {m_name} (mass): DMIG, "
                    f"IFO=6 symmetric, TIN=2 real double, upper triangle only, exact zeros dropped; reals "
                    f"written {reals}.")
    out += _comment(f"Use: include this file in the bulk data and put K2GG={k_name} and M2GG={m_name} in case "
                    "control.")
    out += _comment("Units SI: m, kg, s, N, rad. " + UNITS.split(". ", 1)[1])
    out += _comment(f"Coordinates: {frame}. GRID positions and components are in the basic system (CP, CD "
                    "blank), which is this frame.")
    out += _comment("GRID id: interface node (components 1..6 = ux, uy, uz, rx, ry, rz)")
    out += [f"$ {int(g):>8}  {nm}"[:LINE_WIDTH] for g, nm in zip(dm.node_ids, dm.node_names)]
    if len(dm.scalar_ids):
        out += _comment(f"SPOINT {dm.scalar_ids[0]}..{dm.scalar_ids[-1]}: modal coordinates q0..q{se.n_modes - 1} "
                        f"(sqrt(kg) m) of the fixed-interface modes"
                        + (f"; the last {n_rv} are residual vectors" if n_rv else ""))
    return out


def write_dmig(path, se, *, k_name: str = "KAAX", m_name: str = "MAAX", node_ids=None,
               first_scalar_id: int | None = None, frame: str = DEFAULT_FRAME, title: str = "",
               field_width: int | None = None) -> Path:
    """Write ``se`` as Nastran DMIG bulk data (see the module docstring and
    docs/superelement_export.md), atomically; ``node_ids`` / ``first_scalar_id`` as in
    :func:`dof_map`. ``field_width``: None (default) writes every real exactly (up to 24
    characters a field); 16 keeps every field within 16 characters for a reader that limits
    free fields to that, at >= 10 significant digits (:func:`nastran_real`). Returns the path."""
    text = dmig_text(se, k_name=k_name, m_name=m_name, node_ids=node_ids, first_scalar_id=first_scalar_id,
                     frame=frame, title=title, field_width=field_width)
    out = atomic_write(path, lambda fh: fh.write(text.encode("ascii", "replace")))
    log.info("wrote DMIG %s, %s (%d boundary DOFs, %d SPOINTs) to %s", k_name, m_name, se.n_boundary,
             se.n_modes, out)
    return out


def is_export(path) -> bool:
    """Whether the file ``path`` was written by :func:`write_npz` (an npz whose ``format``
    entry is :data:`FORMAT`, any version) or :func:`write_dmig` (a leading comment block with
    the line starting ``$ DMIG_DESCRIPTION``). OSError if it cannot be read."""
    with open(path, "rb") as fh:
        zipped = fh.read(4) == b"PK\x03\x04"           # a zip archive: an npz?
        fh.seek(0)
        if zipped:
            try:
                with np.load(fh, allow_pickle=False) as z:  # reads the one entry asked for
                    return "format" in z.files and str(z["format"]) == FORMAT
            except (ValueError, EOFError, zipfile.BadZipFile):
                return False
        for _ in range(HEADER_LINES):
            raw = fh.readline(LINE_WIDTH + 2)
            if not raw.startswith(b"$"):
                return False
            if raw.startswith(f"$ {DMIG_DESCRIPTION} ".encode()):
                return True
    return False


# ---- DMIG: reading back (the layout written above) -----------------------------------------
def _cards(path) -> list:
    """(name, data fields) of every free-field card of ``path``: '$' comments skipped; each line
    holds fields 1..9 (missing ones blank, a 10th is the continuation mark); a line starting
    with '+' or ',' continues the card before with its fields 2..9."""
    cards = []
    for raw in Path(path).read_text(encoding="ascii").splitlines():
        line = raw.split("$", 1)[0].rstrip()
        if not line:
            continue
        fields = [f.strip() for f in line.split(",")]
        data = (fields[1:9] + [""] * 8)[:8]          # fields 2..9 of the line (10: continuation mark)
        if line[0] in "+,":
            if not cards:
                raise ValueError(f"{path}: continuation before any card: {raw!r}")
            cards[-1][1].extend(data)
        else:
            cards.append((fields[0].upper(), data))
    return cards


def _dmig_entries(cards: list) -> dict:
    """name -> [(column key, row key, value)] of the DMIG cards."""
    out = {}
    for name, f in cards:
        if name != "DMIG":
            continue
        if f[1] == "0":                                   # header: NAME, 0, IFO, TIN, ...
            if (int(f[2]), int(f[3])) != (6, 2):
                raise ValueError(f"DMIG {f[0]}: only IFO=6, TIN=2 is read (got IFO={f[2]}, TIN={f[3]})")
            out.setdefault(f[0], [])
            continue
        col = (int(f[1]), int(f[2] or 0))
        for k in range(4, len(f), 4):                     # groups G, C, A, (B blank)
            if f[k]:
                out[f[0]].append((col, (int(f[k]), int(f[k + 1] or 0)), float(f[k + 2])))
    return out


def read_dmig(path) -> dict:
    """name -> (full symmetric matrix, keys) of the DMIG matrices of a file written by
    :func:`write_dmig`; ``keys``: (point id, component) of each row/column, in order of first
    appearance (column, then its rows). A term given in both triangles raises ValueError."""
    out = {}
    for name, entries in _dmig_entries(_cards(path)).items():
        keys = {}
        for col, row, _ in entries:
            keys.setdefault(col, len(keys))
            keys.setdefault(row, len(keys))
        A = np.zeros((len(keys), len(keys)))
        seen = set()
        for col, row, v in entries:
            i, j = keys[row], keys[col]
            if (min(i, j), max(i, j)) in seen:
                raise ValueError(f"DMIG {name}: term ({row}, {col}) given twice")
            seen.add((min(i, j), max(i, j)))
            A[i, j] = A[j, i] = v
        out[name] = (A, list(keys))
    return out


def read_dmig_points(path) -> tuple[dict, list]:
    """(GRID id -> position (3,) m, SPOINT ids) of a file written by :func:`write_dmig`."""
    grids, spoints = {}, []
    for name, f in _cards(path):
        if name == "GRID":
            grids[int(f[0])] = np.array([float(v) for v in f[2:5]])
        elif name == "SPOINT":
            if len(f) >= 3 and f[1].upper() == "THRU":
                spoints += list(range(int(f[0]), int(f[2]) + 1))
            else:
                spoints += [int(v) for v in f if v]
    return grids, spoints
