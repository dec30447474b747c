"""Time-dependent loads of a time-domain drivetrain simulation: tables, ramps, brake, friction.

* A :class:`Series` is a table ``(t_i, y_i)`` with strictly increasing, finite times; between
  points it is the linear interpolant ``y = y_i + (y_{i+1} - y_i) (t - t_i) / (t_{i+1} - t_i)``,
  outside the table it holds the first / last value (``np.interp``). A ramp is the two-point
  table ``(t_start, y0), (t_end, y1)``; a step is a ramp with ``t_end = t_start + dt``
  (``t_end <= t_start`` is refused, a table cannot hold two values at one time).
* Tables are read from a CSV file (header row, ``#`` comment lines) or from an OpenFAST text
  output (``.out``): free-text lines, a channel-name line starting with ``Time``, a unit line
  ``(s) (kN-m) (rpm) ...`` and numeric rows. OpenFAST units become SI by :data:`OPENFAST_UNITS`
  (case-sensitive: ``(MN-m)`` is not ``(mN-m)``); rpm -> rad/s is ``2 pi / 60``.
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

log = logging.getLogger(__name__)

#: OpenFAST unit -> (SI unit, factor to SI).
OPENFAST_UNITS = {
    "(s)": ("s", 1.0), "(N-m)": ("N m", 1.0), "(kN-m)": ("N m", 1e3), "(MN-m)": ("N m", 1e6),
    "(N)": ("N", 1.0), "(kN)": ("N", 1e3), "(MN)": ("N", 1e6), "(rpm)": ("rad/s", 2 * math.pi / 60),
    "(rad/s)": ("rad/s", 1.0), "(deg/s)": ("rad/s", math.pi / 180), "(deg)": ("rad", math.pi / 180),
    "(rad)": ("rad", 1.0), "(kW)": ("W", 1e3), "(W)": ("W", 1.0), "(-)": ("-", 1.0),
}


@dataclass(frozen=True, eq=False)
class Series:
    """A load table (module notes); build with :func:`make_series`, which validates it."""

    time_s: np.ndarray
    values: np.ndarray
    name: str
    unit: str

    def __call__(self, t):
        """Value at time ``t`` (s, float or array): linear interpolation, ends held."""
        y = np.interp(t, self.time_s, self.values)
        return float(y) if np.ndim(t) == 0 else y


def _series(time_s, values, name, unit, field, rows=None, where="row") -> Series:
    """:func:`make_series` with ``rows`` naming each point (file line numbers)."""
    t, y = np.array(time_s, dtype=float).ravel(), np.array(values, dtype=float).ravel()
    label = (lambda i: rows[i]) if rows is not None else (lambda i: i)
    if len(t) < 1:
        raise SceneError(field, name, "the table has no data rows")
    if len(t) != len(y):
        raise SceneError(field, name, f"{len(t)} times but {len(y)} values")
    for arr, what in ((t, "time"), (y, "value")):
        bad = np.flatnonzero(~np.isfinite(arr))
        if len(bad):
            raise SceneError(field, name, f"{what} {float(arr[bad[0]])} at {where} {label(bad[0])} is not finite")
    bad = np.flatnonzero(np.diff(t) <= 0)
    if len(bad):
        i = bad[0] + 1
        raise SceneError(field, name, f"time {float(t[i])} s at {where} {label(i)} does not increase "
                                      f"(previous {float(t[i - 1])} s)")
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
    return _series(t, y, column, "", field, rows=lines, where="line")


def read_openfast_out(path, column: str, field: str = "openfast_out") -> Series:
    """Channel ``column`` (case-insensitive) of an OpenFAST text output file, in SI by
    :data:`OPENFAST_UNITS`. Binary ``.outb`` files are refused (set OutFileFmt = 1)."""
    if str(path).lower().endswith(".outb"):
        raise SceneError(field, str(path), "binary OpenFAST output (.outb) is not read; write text output "
                                           "(OutFileFmt = 1) and give the .out file")
    text = _read_lines(path, field)
    head = next((i for i, s in enumerate(text[:-1]) if s.split()[:1] == ["Time"]
                 and text[i + 1].lstrip().startswith("(")), None)
    if head is None:
        raise SceneError(field, str(path), "no channel line starting with 'Time' followed by a unit line")
    names, units = text[head].split(), text[head + 1].split()
    if len(units) != len(names):
        raise SceneError(field, str(path), f"{len(names)} channel names but {len(units)} units")
    ic = _pick(names, column, field, path, "channel", fold=str.lower)
    (_, kt), (unit, kc) = (OPENFAST_UNITS.get(units[i], (None, None)) for i in (0, ic))
    for i, k in ((0, kt), (ic, kc)):
        if k is None:
            raise SceneError(field, str(path), f"channel {names[i]!r} has unit {units[i]!r}, not one of "
                                               f"{' '.join(OPENFAST_UNITS)}")
    lines, t, y = [], [], []
    for n, s in enumerate(text[head + 2:], start=head + 3):
        cells = s.split()
        if not cells:
            continue
        if len(cells) != len(names):
            raise SceneError(field, str(path), f"line {n} has {len(cells)} values, {len(names)} channels")
        lines.append(n)
        t.append(_number(cells[0], field, path, n, names[0]) * kt)
        y.append(_number(cells[ic], field, path, n, names[ic]) * kc)
    log.debug("read %d rows of %s %s from %s", len(t), names[ic], units[ic], path)
    return _series(t, y, names[ic], unit, field, rows=lines, where="line")


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
