"""OpenFAST (and FAST v7/v8) time-series output files, text ``.out`` and binary ``.outb``,
read into one table: channel names, their units as written, and the rows (time first).

Which format is read is decided by the content, not the name: a file whose first two bytes
are an OpenFAST binary format identifier (1 to 4, either byte order) is binary, any other
is text.

Text (``OutFileFmt = 1``; FAST v7 and v8 alike): free header lines, a channel-name line
starting with ``Time``, a unit line of parenthesised units, then one numeric row per output
time; tab or space separated. UTF-8, else Windows-1252: FAST v7 writes ``(kN·m)`` with
cp1252's middle dot (byte 0xB7) and ``(sec)`` for seconds. A channel FAST v7 could not
compute has the unit ``INVALID``.

Binary (``OutFileFmt = 2``; OpenFAST's NWTC Library, ``WrBinFAST`` writes and ``ReadFASTbin``
reads it; Fortran stream access, no record markers, the machine's byte order)::

    int16  FileFmtID        1 WithTime, 2 WithoutTime, 3 NoCompressWithoutTime, 4 ChanLen_In
    int16  LenName          FileFmtID 4 only (else 10): characters per name and per unit
    int32  NumOutChans      channels besides time
    int32  NT               output times
    float64 TimeScl, TimeOff        FileFmtID 1: packed time = TimeScl t + TimeOff
    float64 TimeOut1, TimeIncr      otherwise: t_i = TimeOut1 + i TimeIncr
    float32 ColScl[NumOutChans], ColOff[NumOutChans]   not in FileFmtID 3
    int32  LenDesc, then LenDesc bytes of description
    (NumOutChans + 1) names, then as many units, LenName bytes each, blank padded, Time first
    int32  packed time[NT]                              FileFmtID 1 only
    data[NT][NumOutChans], time-major: int16 packed (1, 2, 4) or float64 (3)

Packed values decode as ``(packed - ColOff) / ColScl``. The writer maps each channel's
[min, max] onto the int16 range [-32768, 32767] (ColScl = 65535 / (max - min)), so a
compressed channel is quantised to steps of (max - min) / 65535: half a step is the format's
precision. Time (FileFmtID 1) is packed into int32 over [-65536, 65535] only.

Units are parsed by :func:`parse_unit` into an SI unit and a factor: torques ``N-m``,
``kN-m``, ``MN-m`` (also written ``N·m``, ``N*m``, ``N m``, ``Nm``), forces ``N``, ``kN``,
``MN``, powers ``W``, ``kW``, ``MW``, speeds ``rpm``, ``rad/s``, ``deg/s`` (``/sec`` too),
angles ``deg``, ``rad``, times ``s``, ``sec``, lengths, speeds and accelerations in m, and
``-``. Prefixes are case-sensitive: ``MN-m`` is mega, and milli is not read.

Every problem is one :class:`assembly.errors.SceneError` at the caller's ``field`` naming
the file and what is wrong (where in the file), never a traceback.
"""
from __future__ import annotations

import difflib
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import SceneError

#: OpenFAST binary format identifiers (NWTC_IO.f90: FileFmtID_*).
WITH_TIME, WITHOUT_TIME, NO_COMPRESS, CHAN_LEN_IN = 1, 2, 3, 4
#: Characters per channel name and unit before FileFmtID 4 carried its own length.
DEFAULT_NAME_LENGTH = 10

_PREFIX = {"": 1.0, "k": 1e3, "M": 1e6}
_PREFIXED = (
    (re.compile(r"(?P<p>[kM]?)N(?:[-·⋅*. ]?)m"), "N m"),
    (re.compile(r"(?P<p>[kM]?)N"), "N"),
    (re.compile(r"(?P<p>[kM]?)W"), "W"),
)
_DEG = math.pi / 180
_PLAIN = {
    "s": ("s", 1.0), "sec": ("s", 1.0),
    "rpm": ("rad/s", 2 * math.pi / 60), "rad/s": ("rad/s", 1.0), "rad/sec": ("rad/s", 1.0),
    "deg/s": ("rad/s", _DEG), "deg/sec": ("rad/s", _DEG),
    "deg": ("rad", _DEG), "rad": ("rad", 1.0),
    "rad/s^2": ("rad/s^2", 1.0), "deg/s^2": ("rad/s^2", _DEG), "deg/sec^2": ("rad/s^2", _DEG),
    "deg/sec2": ("rad/s^2", _DEG),
    "m": ("m", 1.0), "m/s": ("m/s", 1.0), "m/sec": ("m/s", 1.0),
    "m/s^2": ("m/s^2", 1.0), "m/sec^2": ("m/s^2", 1.0), "m/sec2": ("m/s^2", 1.0),
    "-": ("-", 1.0),
}
#: The units read, as a message lists them (each also with ``·``, ``*``, a space or nothing
#: for the ``-`` of a torque, and ``sec`` for ``s``).
UNITS_READ = ("N-m", "kN-m", "MN-m", "N", "kN", "MN", "W", "kW", "MW", "rpm", "rad/s", "deg/s", "rad/s^2",
              "deg/s^2", "deg", "rad", "s", "m", "m/s", "m/s^2", "-")
#: What an SI unit measures, as a message says it ("unit (kW) is a power").
QUANTITY = {"N m": "a torque", "N": "a force", "W": "a power", "rad/s": "an angular speed", "rad": "an angle",
            "rad/s^2": "an angular acceleration", "s": "a time", "m": "a length", "m/s": "a speed",
            "m/s^2": "an acceleration", "-": "dimensionless"}


def parse_unit(text: str):
    """``(SI unit, factor to SI)`` of a unit as an OpenFAST file writes it, with or without
    its parentheses (``(kN-m)`` -> ``("N m", 1e3)``), or None for a unit not read."""
    u = text.strip()
    if u.startswith("(") and u.endswith(")"):
        u = u[1:-1].strip()
    if u in _PLAIN:
        return _PLAIN[u]
    for pattern, si in _PREFIXED:
        m = pattern.fullmatch(u)
        if m:
            return si, _PREFIX[m.group("p")]
    return None


@dataclass(frozen=True, eq=False)
class OutputFile:
    """An output file's ``names`` (Time first), ``units`` as written (without parentheses),
    ``rows`` (n_t, n_channels) in the file's units, time in column 0; ``lines``: the file line
    of each row (text) or None (binary, rows counted from 0); ``path``, ``kind`` ("text" or
    "binary FileFmtID n")."""

    path: str
    names: tuple
    units: tuple
    rows: np.ndarray
    lines: tuple | None
    kind: str

    def channel(self, name: str, field: str) -> int:
        """Column of channel ``name`` (case-insensitive). A name the file repeats is taken
        when its columns agree; otherwise, or when missing, SceneError at ``field``."""
        hits = _find(self.names, name, self.path, field)
        first = self.rows[:, hits[0]]
        for i in hits[1:]:
            if not np.array_equal(first, self.rows[:, i], equal_nan=True):
                raise SceneError(field, self.path, f"channel {name!r} appears {len(hits)} times, with different "
                                                   "values: which one is meant cannot be told")
        return hits[0]


def _find(names, name: str, path: str, field: str) -> list[int]:
    """Columns of ``names`` called ``name`` (case-insensitive), or SceneError naming the
    file's channels and the nearest names."""
    hits = [i for i, n in enumerate(names) if n.lower() == name.lower()]
    if not hits:
        near = difflib.get_close_matches(name.lower(), [n.lower() for n in names], n=3, cutoff=0.6)
        near = [n for n in names if n.lower() in near]
        hint = f"did you mean {', '.join(near)}? " if near else ""
        shown = ", ".join(names[:12]) + (f", ... ({len(names)} channels)" if len(names) > 12 else "")
        raise SceneError(field, path, f"no channel {name!r}; {hint}the file has {shown}")
    return hits


def _keep(names, channels, path: str, field: str) -> list[int]:
    """Columns to keep: Time and every column of the ``channels`` named (all, for None)."""
    if channels is None:
        return list(range(len(names)))
    return sorted({0, *(i for c in channels for i in _find(names, c, path, field))})


def read_output(path, field: str, channels=None) -> OutputFile:
    """Read an OpenFAST text or binary output file (module notes): Time and the
    ``channels`` named (case-insensitive; None: all). A text file converts only those
    columns (a 100-channel file of 48 000 rows reads in a third of the time); a channel the file
    lacks is refused, naming the file's channels."""
    try:
        raw = Path(path).read_bytes()
    except FileNotFoundError:
        raise SceneError(field, str(path), "file not found") from None
    except OSError as exc:
        raise SceneError(field, str(path), f"cannot read the file: {exc.strerror or exc}") from None
    if not raw.strip():
        raise SceneError(field, str(path), "the file is empty")
    if _binary_order(raw) is not None:
        return _read_binary(raw, str(path), field, channels)
    if str(path).lower().endswith(".outb"):
        if len(raw) < 2:
            raise SceneError(field, str(path), f"the file has {len(raw)} byte: truncated")
        fid = int.from_bytes(raw[:2], "little", signed=True)
        raise SceneError(field, str(path), f"FileFmtID {fid} is not one of OpenFAST's binary formats "
                                           f"{WITH_TIME} to {CHAN_LEN_IN}: not an OpenFAST binary output")
    return _read_text(raw, str(path), field, channels)


def _binary_order(raw: bytes):
    """"<" or ">" when the first two bytes are a binary format identifier, else None."""
    if len(raw) < 2:
        return None
    for order, name in (("<", "little"), (">", "big")):
        if WITH_TIME <= int.from_bytes(raw[:2], name, signed=True) <= CHAN_LEN_IN:
            return order
    return None


def _decode(raw: bytes, path: str, field: str) -> str:
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")) or b"\x00" in raw:
        raise SceneError(field, path, "the file holds NUL bytes (binary data or UTF-16 text): not a text output; "
                                      "save text as UTF-8 or Windows-1252, or give a valid binary .outb")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        pass
    try:
        return raw.decode("cp1252")
    except UnicodeDecodeError as exc:
        raise SceneError(field, path, f"the text is neither UTF-8 nor Windows-1252 (byte 0x{raw[exc.start]:02x} "
                                      f"at offset {exc.start})") from None


_UNIT_TOKEN = re.compile(r"\([^()]*\)|[^\s()]+")


def _read_text(raw: bytes, path: str, field: str, channels=None) -> OutputFile:
    text = _decode(raw, path, field).splitlines()
    head = next((i for i, s in enumerate(text[:-1]) if s.split()[:1] == ["Time"]
                 and text[i + 1].lstrip().startswith("(")), None)
    if head is None:
        raise SceneError(field, path, "no channel line starting with 'Time' followed by a unit line")
    names = text[head].split()
    units = [u[1:-1].strip() if u.startswith("(") else u for u in _UNIT_TOKEN.findall(text[head + 1])]
    if len(units) != len(names):
        raise SceneError(field, path, f"{len(names)} channel names but {len(units)} units (line {head + 2})")
    keep = _keep(names, channels, path, field)
    lines, cells = [], []
    for n, s in enumerate(text[head + 2:], start=head + 3):
        row = s.split()
        if not row:
            continue
        if len(row) != len(names):
            raise SceneError(field, path, f"line {n} has {len(row)} values, {len(names)} channels")
        lines.append(n)
        cells.append([row[i] for i in keep])
    try:
        rows = np.array(cells, dtype=float).reshape(len(cells), len(keep))
    except ValueError:
        for n, row in zip(lines, cells):
            for i, c in zip(keep, row):
                try:
                    float(c)
                except ValueError:
                    raise SceneError(field, path, f"line {n}, channel {names[i]!r}: {c!r} is not a number") from None
        raise
    return OutputFile(path, tuple(names[i] for i in keep), tuple(units[i] for i in keep), rows, tuple(lines),
                      "text")


class _Reader:
    """Sequential reads of typed arrays from the bytes of a binary output, refusing a read
    past the end (a truncated file) in one line naming what was being read."""

    def __init__(self, raw: bytes, order: str, path: str, field: str):
        self.raw, self.order, self.path, self.field, self.pos = raw, order, path, field, 0

    def take(self, dtype: str, count: int, what: str) -> np.ndarray:
        dt = np.dtype(dtype).newbyteorder(self.order)
        end = self.pos + dt.itemsize * count
        if end > len(self.raw):
            raise SceneError(self.field, self.path, f"the file ends at byte {len(self.raw)} inside {what} (bytes "
                                                    f"{self.pos} to {end}): truncated")
        out = np.frombuffer(self.raw, dt, count, self.pos)
        self.pos = end
        return out

    def one(self, dtype: str, what: str):
        return self.take(dtype, 1, what)[0].item()

    def fail(self, reason: str):
        raise SceneError(self.field, self.path, reason)


def _read_binary(raw: bytes, path: str, field: str, channels=None) -> OutputFile:
    r = _Reader(raw, _binary_order(raw), path, field)
    fid = r.one("i2", "FileFmtID")
    kind = f"binary FileFmtID {fid}"
    length = r.one("i2", "LenName") if fid == CHAN_LEN_IN else DEFAULT_NAME_LENGTH
    n_ch, nt = r.one("i4", "NumOutChans"), r.one("i4", "NT")
    if length < 1:
        r.fail(f"LenName = {length}: channel names need at least 1 character")
    if n_ch < 0 or nt < 0:
        r.fail(f"NumOutChans = {n_ch}, NT = {nt}: counts cannot be negative")
    t_a, t_b = r.one("f8", "the time scaling"), r.one("f8", "the time scaling")
    if fid == NO_COMPRESS:
        scl = off = None
    else:
        scl, off = r.take("f4", n_ch, "ColScl").astype(float), r.take("f4", n_ch, "ColOff").astype(float)
    n_desc = r.one("i4", "LenDesc")
    if n_desc < 0:
        r.fail(f"LenDesc = {n_desc} after NumOutChans = {n_ch} scale pairs: a negative length, the header is "
               "damaged (a wrong channel count?)")
    # the size the header promises, checked before any large read: a wrong count is named as such
    item = 8 if fid == NO_COMPRESS else 2
    need = r.pos + n_desc + 2 * (n_ch + 1) * length + (4 * nt if fid == WITH_TIME else 0) + item * nt * n_ch
    if need != len(raw):
        what = "truncated" if need > len(raw) else f"{len(raw) - need} bytes more than those counts hold"
        r.fail(f"{len(raw)} bytes, but NumOutChans = {n_ch} and NT = {nt} ({kind}) make {need}: {what}")
    r.take("u1", n_desc, "the description")
    names = _strings(r, n_ch + 1, length, "channel name")
    units = [u[1:-1].strip() if u.startswith("(") and u.endswith(")") else u
             for u in _strings(r, n_ch + 1, length, "channel unit")]
    if fid == WITH_TIME:
        if not (math.isfinite(t_a) and t_a != 0.0 and math.isfinite(t_b)):
            r.fail(f"TimeScl = {t_a}, TimeOff = {t_b}: the time scaling must be finite, TimeScl non-zero")
        time = (r.take("i4", nt, "the packed time").astype(float) - t_b) / t_a
    else:
        if not (math.isfinite(t_a) and math.isfinite(t_b) and t_b > 0.0):
            r.fail(f"TimeOut1 = {t_a}, TimeIncr = {t_b}: the first time must be finite and the increment > 0")
        time = t_a + t_b * np.arange(nt)
    keep = _keep(names, channels, path, field)
    cols = [i - 1 for i in keep[1:]]
    data = r.take("f8" if fid == NO_COMPRESS else "i2", nt * n_ch, "the channel data").reshape(nt, n_ch)[:, cols]
    if scl is not None:
        scl, off = scl[cols], off[cols]
        bad = np.flatnonzero(~(np.isfinite(scl) & (scl != 0.0) & np.isfinite(off)))
        if len(bad):
            j = bad[0]
            r.fail(f"channel {names[cols[j] + 1]!r}: ColScl = {scl[j]}, ColOff = {off[j]}: the scaling must be "
                   "finite, ColScl non-zero")
        data = (data - off) / scl
    rows = np.column_stack([time, data]).astype(float)
    return OutputFile(path, tuple(names[i] for i in keep), tuple(units[i] for i in keep), rows, None, kind)


def _strings(r: _Reader, count: int, length: int, what: str) -> list[str]:
    """``count`` blank-padded strings of ``length`` bytes; control characters are refused."""
    out = []
    for k in range(count):
        s = r.take("u1", length, f"{what} {k + 1}").tobytes().decode("latin-1").strip()
        if any(ord(c) < 32 or 127 <= ord(c) < 160 for c in s):
            r.fail(f"{what} {k + 1} holds control characters: not an OpenFAST binary output, or a damaged one")
        out.append(s)
    return out
