"""Time-dependent loads of a time-domain drivetrain simulation: tables, ramps, brake, friction.

* A :class:`Series` is a table ``(t_i, y_i)`` with strictly increasing, finite times; between
  points it is the linear interpolant ``y = y_i + (y_{i+1} - y_i) (t - t_i) / (t_{i+1} - t_i)``,
  outside the table it holds the first / last value (``np.interp``). A ramp is the two-point
  table ``(t_start, y0), (t_end, y1)``; a step is a ramp with ``t_end = t_start + dt``
  (``t_end <= t_start`` is refused, a table cannot hold two values at one time).
* Tables are read from a CSV file (header row, ``#`` comment lines) or from an OpenFAST output
  (text ``.out`` or binary ``.outb``, :mod:`assembly.dynamics.openfast_output`), whose units
  become SI (kN-m -> N m, rpm -> rad/s = 2 pi / 60, ...); a channel read as a torque or force
  must have a unit of that kind (a power or a speed is refused, naming the column).
* A file's history may be cut to ``time_window = [t0, t1]`` (s of the file's time; the ends
  are interpolated) and shifted by ``time_offset`` (s): run time = file time - time_offset.
  Outside its rows a series holds its first / last value; :func:`range_warning` says so when a
  run leaves the rows' time range.
* HSS brake (ElastoDyn, HSSBrMode = 1; Jonkman, FAST User's Guide): with deployment time
  ``THSSBrDp`` and ramp ``HSSBrDT``, ``frac = 0`` for ``t < THSSBrDp``, ``(t - THSSBrDp) /
  HSSBrDT`` while ``t < THSSBrDp + HSSBrDT``, else 1; torque ``frac * HSSBrTqF`` (magnitude;
  the integrator applies it against the shaft's motion).
* Gearbox efficiency (ElastoDyn GBoxEff): ``GBoxEffFac = eta ** s``, ``s = sign`` of the previous
  step's low-speed-shaft torque (+1 if >= 0: power flows rotor -> generator); the friction
  factor ``1 / GBoxEffFac - 1`` scales the generator-side torque into the friction torque.
Units: SI (s, N, N m, rad, rad/s, W) inside.
"""
from __future__ import annotations

import csv
import logging
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import SceneError
from .openfast_output import QUANTITY, UNITS_READ, parse_unit, read_output

log = logging.getLogger(__name__)

#: The noun a message gives a history of an SI unit ("not a torque").
KIND_NOUN = {"N m": "torque", "N": "force"}


@dataclass(frozen=True, eq=False)
class Series:
    """A load table (module notes); build with :func:`make_series`, which validates it.
    ``origin``: for a history read from a file, what it is and where it came from (the
    scene path, file and column), used by :func:`range_warning`; "" otherwise."""

    time_s: np.ndarray
    values: np.ndarray
    name: str
    unit: str
    origin: str = ""

    def __call__(self, t):
        """Value at time ``t`` (s, float or array): linear interpolation, ends held."""
        y = np.interp(t, self.time_s, self.values)
        return float(y) if np.ndim(t) == 0 else y


def _series(time_s, values, name, unit, field, rows=None, where="row", source=None) -> Series:
    """:func:`make_series` with ``rows`` naming each point (file line numbers); ``source``:
    (file, "column" or "channel") of a history read from a file, which an error then names."""
    t, y = np.array(time_s, dtype=float).ravel(), np.array(values, dtype=float).ravel()
    label = (lambda i: rows[i]) if rows is not None else (lambda i: i)

    def fail(reason):
        if source is None:
            raise SceneError(field, name, reason)
        raise SceneError(field, str(source[0]), f"{source[1]} {name!r}: {reason}")

    if len(t) < 1:
        fail("the table has no data rows")
    if len(t) != len(y):
        fail(f"{len(t)} times but {len(y)} values")
    for arr, what in ((t, "time"), (y, "value")):
        bad = np.flatnonzero(~np.isfinite(arr))
        if len(bad):
            fail(f"{what} {float(arr[bad[0]])} at {where} {label(bad[0])} is not finite")
    bad = np.flatnonzero(np.diff(t) <= 0)
    if len(bad):
        i = bad[0] + 1
        fail(f"time {float(t[i])} s at {where} {label(i)} does not increase (previous {float(t[i - 1])} s)")
    t.setflags(write=False)
    y.setflags(write=False)
    return Series(t, y, name, unit)


def make_series(time_s, values, name: str, unit: str, field: str) -> Series:
    """Validated :class:`Series` (copies, read-only): >= 1 point, equal lengths, finite, times
    strictly increasing (the error names the first row index, 0-based, that does not)."""
    return _series(time_s, values, name, unit, field)


def constant(value: float, name: str, unit: str, field: str | None = None) -> Series:
    """The constant ``value`` at all times (error path ``field``, default ``name``)."""
    return make_series([0.0], [value], name, unit, field or name)


def ramp(start_value: float, end_value: float, t_start: float, t_end: float, name: str, unit: str,
         field: str) -> Series:
    """``start_value`` up to ``t_start``, linear to ``end_value`` at ``t_end``, then held; a step
    is ``t_end = t_start + dt``. SceneError at ``field.t_end`` unless ``t_end > t_start``."""
    if not (math.isfinite(t_start) and math.isfinite(t_end) and t_end > t_start):
        raise SceneError(f"{field}.t_end", t_end, f"the ramp must end after it starts (t_start = {t_start} s); "
                                                  "for a step use t_end = t_start + dt")
    return make_series([t_start, t_end], [start_value, end_value], name, unit, field)


def _read_lines(path, field: str) -> list[str]:
    try:
        return Path(path).read_text(encoding="utf-8-sig").splitlines()
    except FileNotFoundError:
        raise SceneError(field, str(path), "file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(field, str(path), f"cannot read the file as text: {exc}") from None


def _number(text: str, field: str, path, line: int, column: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise SceneError(field, str(path), f"line {line}, column {column!r}: {text.strip()!r} is not a number") \
            from None


def _pick(names: list[str], wanted: str, field: str, path, what: str, fold=lambda s: s) -> int:
    hits = [i for i, n in enumerate(names) if fold(n) == fold(wanted)]
    if not hits:
        raise SceneError(field, str(path), f"no {what} {wanted!r}; the file has {', '.join(names)}")
    return hits[0]


def read_csv(path, column: str, time_column: str = "time", scale: float = 1.0, field: str = "table") -> Series:
    """Series ``column * scale`` against ``time_column`` (s) of a comma-separated file with a
    header row (names stripped, matched exactly; blank and ``#`` lines skipped). ``scale``
    must make the values SI; the Series' unit is left "" (the caller knows it)."""
    if not math.isfinite(scale):
        raise SceneError(f"{field}.scale", scale, "the scale must be finite")
    rows = [(n, next(csv.reader([s]))) for n, s in enumerate(_read_lines(path, field), start=1)
            if s.strip() and not s.lstrip().startswith("#")]
    if not rows:
        raise SceneError(field, str(path), "the file has no header row")
    names = [c.strip() for c in rows[0][1]]
    it, iv = (_pick(names, c, field, path, "column") for c in (time_column, column))
    lines, t, y = [], [], []
    for n, cells in rows[1:]:
        if len(cells) != len(names):
            raise SceneError(field, str(path), f"line {n} has {len(cells)} cells, the header {len(names)}")
        lines.append(n)
        t.append(_number(cells[it], field, path, n, time_column))
        y.append(_number(cells[iv], field, path, n, column) * scale)
    log.debug("read %d rows of %s from %s", len(t), column, path)
    return _series(t, y, column, "", field, rows=lines, where="line", source=(path, "column"))


def read_openfast_out(path, column: str, field: str = "openfast_out", expect: str | None = None,
                      column_field: str | None = None) -> Series:
    """Channel ``column`` (case-insensitive) of an OpenFAST output file, text or binary
    (:mod:`assembly.dynamics.openfast_output`), in SI. ``expect``: the SI unit the caller
    needs ("N m", "N"); a channel of another kind is refused at ``column_field`` (default
    ``field``), one of a unit not read at ``field``."""
    out = read_output(path, field, [column])
    ic = out.channel(column, field)
    (kt, tu), (kc, cu) = ((parse_unit(out.units[i]), out.units[i]) for i in (0, ic))
    for i, known, unit in ((0, kt, tu), (ic, kc, cu)):
        if known is None:
            raise SceneError(field, str(path), f"channel {out.names[i]!r} has unit ({unit}), which flexgear does not "
                                               f"read (it reads {', '.join(UNITS_READ)})")
    if kt[0] != "s":
        raise SceneError(field, str(path), f"the first channel {out.names[0]!r} has unit ({tu}): not a time")
    if expect is not None and kc[0] != expect:
        raise SceneError(column_field or field, column, f"unit ({cu}) is {QUANTITY[kc[0]]}, not a "
                                                        f"{KIND_NOUN.get(expect, expect)}")
    log.debug("read %d rows of %s (%s) from %s (%s)", len(out.rows), out.names[ic], cu, path, out.kind)
    rows, where = (out.lines, "line") if out.lines is not None else (None, "record")
    return _series(out.rows[:, 0] * kt[1], out.rows[:, ic] * kc[1], out.names[ic], kc[0], field, rows=rows,
                   where=where, source=(path, "channel"))


def file_history(src, path: str, base_dir, unit: str) -> Series | None:
    """The history a table (a ``[[simulation.loads]]`` entry or the generator) reads from a
    file, or None when it names none: ``table`` (CSV) or ``openfast``, ``column``,
    ``time_column`` (CSV), ``scale`` (applied after the units' conversion to SI), then
    ``time_window`` and ``time_offset`` (module notes). ``unit``: the SI unit the history
    must have (an OpenFAST channel's unit is checked against it; a CSV's ``scale`` must
    make its values that unit). Errors name ``path.<key>``."""
    sources = [k for k in ("table", "openfast") if getattr(src, k) is not None]
    if not sources:
        return None
    if len(sources) > 1:
        raise SceneError(f"{path}.openfast", src.openfast, "give either table or openfast, not both")
    key = sources[0]
    if src.column is None:
        raise SceneError(f"{path}.column", None, f"missing: the column of the {key} file to read")
    file = Path(base_dir) / getattr(src, key)
    if key == "table":
        s = read_csv(file, src.column, src.time_column, src.scale, field=f"{path}.table")
    else:
        if src.time_column.lower() != "time":
            raise SceneError(f"{path}.time_column", src.time_column, "an OpenFAST file's time is its Time channel; "
                                                                     "time_column is for CSV tables")
        s = read_openfast_out(file, src.column, f"{path}.openfast", expect=unit, column_field=f"{path}.column")
        s = Series(s.time_s, src.scale * s.values, s.name, s.unit)
    what = "column" if key == "table" else "channel"
    offset = f", time_offset {src.time_offset:g} s" if src.time_offset else ""
    return shifted(s, src.time_window, src.time_offset, path, f"{path} ({getattr(src, key)}, {what} {s.name}{offset})")


#: The file keys of a history table and their defaults (``[[simulation.loads]]``, generator).
FILE_KEYS = {"table": None, "openfast": None, "column": None, "time_column": "time", "scale": 1.0,
             "time_offset": 0.0, "time_window": None}
#: The generator keys of the constant and PI laws and their defaults.
_LAW_KEYS = {"torque": 0.0, "rated_speed": None, "kp": 0.0, "ki": 0.0, "max_torque": None}


def generator_history(gen, path: str, base_dir) -> Series | None:
    """The recorded torque (N m; positive brakes) of a generator table of law "table", read
    by :func:`file_history`; None for the other laws. A key the law does not use is refused."""
    unused = _LAW_KEYS if gen.law == "table" else FILE_KEYS
    for key, default in unused.items():
        if getattr(gen, key) != default:
            raise SceneError(f"{path}.{key}", getattr(gen, key), f"not used by law = {gen.law!r}"
                             + (" (the file gives the torque)" if gen.law == "table" else
                                "; a recorded torque needs law = 'table'"))
    if gen.law != "table":
        return None
    s = file_history(gen, path, base_dir, "N m")
    if s is None:
        raise SceneError(f"{path}.openfast", None, "missing: law = 'table' reads the torque from a table or "
                                                   "openfast file")
    return s


def shifted(s: Series, window, offset: float, path: str, origin: str) -> Series:
    """``s`` cut to ``window = (t0, t1)`` (s of its own time, or None: all of it; values at
    t0 and t1 interpolated) and moved to run time ``t - offset``; SceneError at
    ``path.time_window`` for a window that is empty or reaches beyond the rows."""
    t, y = s.time_s, s.values
    if window is not None:
        t0, t1 = window
        if not t0 < t1:
            raise SceneError(f"{path}.time_window", list(window), "must be [start, end] with start < end (s)")
        if t0 < t[0] or t1 > t[-1]:
            raise SceneError(f"{path}.time_window", list(window), f"reaches beyond the file's rows, which run "
                                                                  f"from {t[0]:g} to {t[-1]:g} s")
        inside = (t > t0) & (t < t1)
        t = np.concatenate([[t0], t[inside], [t1]])
        y = np.concatenate([[s(t0)], y[inside], [s(t1)]])
    moved = _series(t - offset, y, s.name, s.unit, f"{path}.time_offset" if offset else path)
    return Series(moved.time_s, moved.values, s.name, s.unit, origin)


def range_warning(s: Series, t_end: float) -> str | None:
    """A warning when a run from 0 to ``t_end`` (s) leaves the time range of a history read
    from a file (which then holds its first or last value), else None."""
    if not s.origin:
        return None
    lo, hi = float(s.time_s[0]), float(s.time_s[-1])
    tol = 1e-9 * max(1.0, abs(lo), abs(hi), abs(t_end))
    held = ([f"its first value is held from 0 to {lo:g} s"] if lo > tol else []) + \
           ([f"its last value is held from {hi:g} to {t_end:g} s"] if hi < t_end - tol else [])
    if not held:
        return None
    return (f"{s.origin}: the run (0 to {t_end:g} s) leaves the data's time range ({lo:g} to {hi:g} s of run time); "
            + " and ".join(held))


def require_cover(s: Series, t_end: float, field: str) -> Series:
    """``s`` when its rows cover the whole run, 0 to ``t_end`` (s), else SceneError at ``field``: a
    series that drives the run itself (a wind, a housing's motion) is not held past its ends."""
    if s.time_s[0] > 0.0 or s.time_s[-1] < t_end:
        raise SceneError(field, f"{s.time_s[0]:g} .. {s.time_s[-1]:g} s", f"does not cover the run (0 .. {t_end:g} s)")
    return s


def brake_torque(t, deploy_time: float, ramp_time: float, full_torque: float, field: str = "simulation.brake"):
    """HSS brake torque magnitude (N m) at ``t`` (s, float or array), ElastoDyn HSSBrMode 1:
    0 before ``deploy_time``, linear to ``full_torque`` over ``ramp_time`` (0: at once), held."""
    for key, v in (("deploy_time", deploy_time), ("ramp_time", ramp_time), ("full_torque", full_torque)):
        if not (math.isfinite(v) and (key == "deploy_time" or v >= 0)):
            raise SceneError(f"{field}.{key}", v, "must be finite" + ("" if key == "deploy_time" else " and >= 0"))
    ta = np.asarray(t, dtype=float)
    if ramp_time > 0:
        frac = np.clip((ta - deploy_time) / ramp_time, 0.0, 1.0)
    else:
        frac = (ta >= deploy_time).astype(float)
    q = frac * full_torque
    return float(q) if np.ndim(t) == 0 else q


def efficiency_factor(efficiency: float, lss_torque_sign: float,
                      field: str = "simulation.gearbox_efficiency") -> float:
    """ElastoDyn's gearbox friction factor ``1 / efficiency**s - 1``, ``s = +1`` if the previous
    low-speed-shaft torque is >= 0 (rotor drives generator), else -1; efficiency in (0, 1]."""
    if not (math.isfinite(efficiency) and 0.0 < efficiency <= 1.0):
        raise SceneError(field, efficiency, "the gearbox efficiency must lie in (0, 1]")
    s = 1.0 if lss_torque_sign >= 0 else -1.0
    return 1.0 / efficiency ** s - 1.0
