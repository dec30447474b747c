"""The solid of a Nastran bulk-data deck (.bdf, .nas): GRID points and CTETRA elements (4 or
10 nodes), in every field format and continuation style; the other element cards are
counted, not read (numpy only).

Why a reader of our own: meshio's (5.3) fails on a CTETRA continued by a blank first field
when the editor stripped the first line's trailing blanks (the common case), reads no
large-field element (``CTETRA*``), needs ``BEGIN BULK``, and ignores a GRID's coordinate
system (positions silently wrong); pyNastran reads everything but is a large dependency for
two cards. Format (MSC/NX Nastran Quick Reference Guide, "Bulk Data Entry formats"):

* a card is rows of 10 fields: field 1 the name (or a continuation marker), fields 2-9 data,
  field 10 a continuation marker. Small field: 8 columns each; large field (the name ends
  with ``*``): fields 2-5 of 16 columns, so two physical lines carry one row's 8 data fields;
  free field: comma-separated (a name ending with ``*``: 4 data fields per line);
* a line continues the card before it when its first field starts with ``+`` or ``*`` or is
  blank; ``$`` starts a comment; ``BEGIN BULK`` (if any) starts and ``ENDDATA`` ends the data;
* a real may leave out the ``E`` of its exponent (``1.5-3``) or write ``D``;
* CTETRA: EID, PID, G1..G4 (corners), G5..G10 on edges G1G2, G2G3, G3G1, G1G4, G2G4, G3G4
  (all or none) -- meshio's/VTK's ``tetra10`` order. ``CTETRA_`` (meshio's writer's name for
  the 10-node card) is read as CTETRA.

Refused (:class:`NastranError`, naming the line): a GRID in a coordinate system other than
the basic one (CP), an ``INCLUDE``, a CTETRA of neither 4 nor 10 nodes or naming a GRID the
deck lacks, a GRID given twice, a field that is not a number, a free-field line of more than
10 fields.
"""
from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

#: Element cards the deck may hold besides CTETRA, by kind (counted and reported, never read).
ELEMENT_KINDS = {
    **dict.fromkeys(("CHEXA", "CPENTA", "CPYRAM", "CPYRA"), "solid"),
    **dict.fromkeys(("CTRIA3", "CTRIA6", "CTRIAR", "CQUAD4", "CQUAD8", "CQUADR", "CQUAD", "CSHEAR"), "shell"),
    **dict.fromkeys(("CBAR", "CBEAM", "CROD", "CONROD", "CTUBE", "CBEND"), "beam"),
    **dict.fromkeys(("CBUSH", "CBUSH1D", "CGAP", "CELAS1", "CELAS2", "CELAS3", "CELAS4", "CDAMP1", "CDAMP2",
                     "CDAMP3", "CDAMP4", "CVISC"), "spring"),
    **dict.fromkeys(("CONM1", "CONM2", "CMASS1", "CMASS2", "CMASS3", "CMASS4"), "mass"),
    **dict.fromkeys(("RBE1", "RBE2", "RBE3", "RBAR", "RROD", "RSPLINE"), "rigid"),
}
_TETRA = ("CTETRA", "CTETRA_")
_REAL = re.compile(r"^([+-]?(?:\d+\.?\d*|\.\d+))([+-]\d+)$")


class NastranError(ValueError):
    """A deck the reader cannot use: ``line`` (1-based) and what is wrong there."""

    def __init__(self, line: int, reason: str):
        self.line = line
        self.reason = reason
        super().__init__(f"line {line}: {reason}")


@dataclass(frozen=True)
class BulkSolid:
    """What a deck holds: GRID points (n, 3) in its numbers, in the deck's GRID order;
    ``tets`` per node count (4 and/or 10: indices into ``points``, the card's node order);
    ``others``: element card -> (kind, count) of every other element card."""

    points: np.ndarray
    tets: dict
    others: dict


def real(text: str, line: int) -> float:
    """A Nastran real (``1.``, ``.5``, ``-1.5E-3``, ``-1.5-3``, ``1.5D+2``) or integer."""
    t = text.strip().upper().replace("D", "E")
    m = _REAL.match(t)
    try:
        return float(f"{m.group(1)}E{m.group(2)}" if m else t)
    except ValueError:
        raise NastranError(line, f"{text.strip()!r} is not a number") from None


def integer(text: str, line: int, what: str) -> int:
    try:
        return int(text.strip())
    except ValueError:
        raise NastranError(line, f"{what} {text.strip()!r} is not an integer") from None


def _fields(raw: str) -> tuple[str, list[str], int]:
    """(field 1, the data fields, number of free fields) of one physical line: 8 data fields
    of a small-field line, 4 of a large-field one (field 1 holds ``*``); the count of
    comma-separated fields of a free-field line (0 for a fixed-field one)."""
    line = raw.split("$", 1)[0].rstrip("\r\n").expandtabs(8)
    if "," in line:
        parts = line.split(",")
        n = 4 if "*" in parts[0] else 8
        data = [p.strip() for p in parts[1:1 + n]]
        return parts[0].strip(), data + [""] * (n - len(data)), len(parts)
    head = line[:8].strip()
    width, n = (16, 4) if "*" in head else (8, 8)
    body = line[8:8 + width * n].ljust(width * n)
    return head, [body[i * width:(i + 1) * width].strip() for i in range(n)], 0


def _cards(text: str):
    """(line number, name, data fields, a free-field line of more than 10 fields or None) of
    every card of the bulk data."""
    lines = text.splitlines()
    start = next((i + 1 for i, s in enumerate(lines) if s.strip().upper().startswith("BEGIN BULK")), 0)
    card = None
    for i in range(start, len(lines)):
        raw = lines[i]
        if not raw.split("$", 1)[0].strip():
            continue   # a blank or comment line
        head, data, n_free = _fields(raw)
        long = i + 1 if n_free > 10 else None
        upper = head.upper()
        if upper.startswith("ENDDATA"):
            break
        if upper.startswith("INCLUDE"):
            raise NastranError(i + 1, "INCLUDE is not read: give the part as one file")
        if head == "" or head[0] in "+*":   # a continuation of the card before
            if card is None:
                raise NastranError(i + 1, "a continuation line before any card")
            card[2].extend(data)
            card[3] = card[3] or long
            continue
        if card is not None:
            yield card
        card = [i + 1, upper.rstrip("*").strip(), list(data), long]
    if card is not None:
        yield card


def read_bulk(path) -> BulkSolid:
    """Read the deck at ``path`` (see the module docstring)."""
    with open(path, "rb") as fh:
        text = fh.read().decode("latin-1")
    ids, xyz, elems, others = {}, [], {}, {}
    for number, name, data, long in _cards(text):
        if long is not None and (name == "GRID" or name in _TETRA):
            raise NastranError(long, "more than 10 comma-separated fields: a free-field line holds at most 10 "
                                     "(continue the card on the next line)")
        if name == "GRID":
            gid = integer(data[0], number, "GRID id")
            if data[1] not in ("", "0"):
                raise NastranError(number, f"GRID {gid}: coordinates in coordinate system CP = {data[1]}: only "
                                           "the basic system (CP blank or 0) is read; export in it")
            if gid in ids:
                raise NastranError(number, f"GRID {gid} is defined twice")
            ids[gid] = len(xyz)
            xyz.append([real(v, number) if v else 0.0 for v in data[2:5]])
        elif name in _TETRA:
            eid = integer(data[0], number, "CTETRA id")
            nodes = data[2:12]
            given = [v for v in nodes if v]
            if len(given) not in (4, 10) or any(not v for v in nodes[:len(given)]):
                raise NastranError(number, f"CTETRA {eid}: {len(given)} grid points: a tetrahedron has 4, or 10 "
                                           "with every edge node")
            elems.setdefault(len(given), []).append((number, eid, [integer(v, number, "grid point") for v in given]))
        elif name in ELEMENT_KINDS:
            kind, count = others.get(name, (ELEMENT_KINDS[name], 0))
            others[name] = (kind, count + 1)
    tets = {}
    for n, rows in elems.items():
        conn = np.empty((len(rows), n), dtype=np.int64)
        for k, (number, eid, grids) in enumerate(rows):
            missing = [g for g in grids if g not in ids]
            if missing:
                raise NastranError(number, f"CTETRA {eid} names GRID {missing[0]}, which the deck does not define")
            conn[k] = [ids[g] for g in grids]
        tets[n] = conn
    return BulkSolid(np.asarray(xyz, float).reshape(-1, 3), tets, others)
