"""The loads-to-life tables of a run (``[simulation.life]``): every output's rainflow
damage-equivalent loads and its load duration and load revolution distributions, each rated
bearing's ISO 281 L10 and each rated gear's equivalent torque and Miner damage, from the run's
own histories over the table's ``window`` (:mod:`assembly.dynamics.cycles` and
:mod:`assembly.dynamics.life` have the formulas).

* An output: its rainflow cycles (ASTM E1049-85), the DEL for each Woehler exponent m at
  ``cycles_ref`` equivalent cycles (default the window's seconds: a 1 Hz DEL, as OpenFAST's
  post-processors give it), its LDD and its LRD against ``shaft``'s own revolutions (a shaft
  that does not turn: no LRD, said in the table).

* A bearing (:class:`~assembly.scene.time_domain.BearingRating`): its force in its own axes
  (``force:B:x``, ``:y``, ``:z``, the force it exerts on its body) gives at each step
  ``P_k = X hypot(F_x, F_y) + Y |F_z|``; its inner ring turns against its outer at
  ``omega_body - omega_frame`` (``speed:`` of the bearing's body and of the body it is
  mounted in; 0 for the housing). P's mean over those revolutions with exponent p, sample by
  sample (no binning: ``sum P_k^p dn_k / sum dn_k``, dn_k the revolutions of step k by the
  trapezoid of the relative speed), gives ``L10 = (C / P)^p`` 1e6 rev, and in hours at the
  run's mean rate of revolutions ``L10 1e6 / (n / T) / 3600`` (n revolutions in the record's
  T seconds): how long the bearing lasts in this load case.
* A gear (:class:`~assembly.scene.time_domain.GearRating`): the mesh force F (``force:MESH``,
  along the line of action) turns the gear about its axis with the torque ``T = |r_b| cos
  beta_b F`` (r_b its base radius, beta_b the base helix angle: the line of action's
  transverse part is tangent to the base circle). Each tooth is loaded once per revolution
  of the gear relative to the frame the pair rides in (the gears' carrier, else the
  housing): Orders' Willis rule (:mod:`assembly.dynamics.orders`). The damage over the
  record is Miner's sum over the steps with those revolutions as cycles; its life in hours
  ``T / D / 3600``; the equivalent torque with the S-N slope as exponent.

The channels a run records for them are :func:`life_channels`', checked (names, springs,
the tables' fields) before the run starts.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .. import arguments as check
from ..errors import SceneError
from ..scene.tables import HOUSING
from ..scene.time_domain import LifeTables
from .cycles import damage_equivalent_load, power, rainflow_cycles
from .frf_channels import bearing_directions
from .history import span
from .life import LoadDistribution, equivalent_load, load_duration, load_revolutions, miner_damage, revolutions


@dataclass(frozen=True)
class BearingLifeRow:
    """One bearing's line: ``equivalent_load_n`` P (N), ``revolutions`` of the record,
    ``l10_mrev`` (1e6 rev) and ``l10_hours`` (None when the bearing did not turn: ``note``)."""

    bearing: str
    rating_n: float
    exponent: float
    equivalent_load_n: float | None
    peak_load_n: float
    revolutions: float
    l10_mrev: float | None
    l10_hours: float | None
    note: str = ""


@dataclass(frozen=True)
class GearLifeRow:
    """One gear's line: ``torque_eq`` (N m, the slope as exponent), ``peak_torque``,
    ``cycles`` (tooth load cycles of the record), ``damage`` (Miner) and ``life_hours``."""

    mesh: str
    gear: str
    slope: float
    torque_eq: float | None
    peak_torque: float
    cycles: float
    damage: float | None
    life_hours: float | None
    note: str = ""


def _finite(*values) -> tuple:
    """Each value, or None where it is not finite (a table never carries inf or NaN)."""
    return tuple(v if v is not None and math.isfinite(v) else None for v in values)


def _elements(model, kind: str) -> dict:
    return {el.name: el for el in model.elements if el.kind == kind}


def _speed(body) -> list:
    return [] if body is None else [f"speed:{body}"]


def bearing_parts(model, life) -> list:
    """(path, rating, element, body, frame or None, force channel names) of each rated bearing;
    an unknown bearing, or one whose radial (or, with an axial factor, axial) direction is
    rigid, is refused naming its field."""
    els, out = _elements(model, "bearing"), []
    for i, b in enumerate(life.bearings):
        path = f"simulation.life.bearings[{i}]"
        el = els.get(b.bearing)
        if el is None:
            raise SceneError(f"{path}.bearing", b.bearing, f"no such bearing; bearings: {sorted(els)}")
        dirs = bearing_directions(model, el)
        need = ["x", "y"] + (["z"] if b.axial_factor > 0 else [])
        missing = [d for d in need if d not in dirs]
        if missing:
            raise SceneError(f"{path}.bearing", b.bearing, f"its {'/'.join(missing)} direction carries no spring: "
                             "a rigid direction's reaction is not recorded, so its load for the L10 is unknown")
        out.append((path, b, el, el.bodies[0], el.bodies[1], [f"force:{b.bearing}:{d}" for d in need]))
    return out


def gear_parts(model, life) -> list:
    """(path, rating, gear body, frame or None, lever |r_b| cos beta_b (m)) of each rated gear;
    an unknown mesh or a gear not in it is refused naming its field."""
    els, out = _elements(model, "mesh"), []
    frames = {b.name: b.frame for b in model.scene.bodies}
    for i, g in enumerate(life.gears):
        path = f"simulation.life.gears[{i}]"
        el = els.get(g.mesh)
        if el is None:
            raise SceneError(f"{path}.mesh", g.mesh, f"no such mesh; meshes: {sorted(els)}")
        m = model.scene.meshes[el.item[1]]
        gear = m.gear1 if g.gear is None else g.gear
        if gear not in (m.gear1, m.gear2):
            raise SceneError(f"{path}.gear", g.gear, f"is not a gear of mesh {g.mesh!r} ({m.gear1}, {m.gear2})")
        radius = m.base_radius1 if gear == m.gear1 else m.base_radius2
        carriers = [frames[b] for b in (m.gear1, m.gear2) if frames.get(b, HOUSING) != HOUSING]
        out.append((path, g, gear, carriers[0] if carriers else None, abs(radius) * math.cos(m.helix_angle)))
    return out


def life_channels(model, life, shaft: str | None) -> list:
    """The outputs a run records for ``life`` (:class:`~assembly.scene.time_domain.LifeTables`):
    the rated bearings' forces and the speeds of their bodies and frames, the rated meshes'
    forces and their gears' and carriers' speeds, and ``speed:shaft`` (the load revolution
    distributions' shaft). Checked before the run (:func:`bearing_parts`, :func:`gear_parts`)."""
    names = [] if shaft is None else [f"speed:{shaft}"]
    for _, _, _, body, frame, forces in bearing_parts(model, life):
        names += forces + _speed(body) + _speed(frame)
    for _, g, gear, frame, _ in gear_parts(model, life):
        names += [f"force:{g.mesh}"] + _speed(gear) + _speed(frame)
    return list(dict.fromkeys(names))


def _relative(read, body, frame):
    w = np.asarray(read(f"speed:{body}"), float)
    return w if frame is None else w - np.asarray(read(f"speed:{frame}"), float)


def bearing_rows(model, life, time_s, read) -> list:
    """:class:`BearingLifeRow` of each rated bearing; ``read(name)`` -> the history of a
    channel of :func:`life_channels` at ``time_s`` (module notes)."""
    t = np.asarray(time_s, float)
    rows = []
    for _, b, _, body, frame, forces in bearing_parts(model, life):
        f = [np.asarray(read(n), float) for n in forces]
        load = b.radial_factor * np.hypot(f[0], f[1]) + (b.axial_factor * np.abs(f[2]) if len(f) > 2 else 0.0)
        turns = revolutions(t, _relative(read, body, frame))
        n = float(turns.sum())
        if not n > 0.0:
            rows.append(BearingLifeRow(b.bearing, b.rating, b.exponent, None, float(load.max()), 0.0,
                                       None, None, "the bearing does not turn in the record: no L10"))
            continue
        p = equivalent_load(load[:-1], turns, b.exponent)
        if p == 0.0:
            rows.append(BearingLifeRow(b.bearing, b.rating, b.exponent, p, float(load.max()), n, None, None,
                                       "no load in the record: no finite L10"))
            continue
        l10 = power(b.rating / p, b.exponent)
        hours = l10 * 1e6 / (n / float(t[-1] - t[0])) / 3600.0
        rows.append(BearingLifeRow(b.bearing, b.rating, b.exponent, p, float(load.max()), n, *_finite(l10, hours),
                                   "" if math.isfinite(hours) else "the life overflows a float: no finite L10"))
    return rows


def gear_rows(model, life, time_s, read) -> list:
    """:class:`GearLifeRow` of each rated gear (``read`` as :func:`bearing_rows`')."""
    t = np.asarray(time_s, float)
    rows = []
    for _, g, gear, frame, lever in gear_parts(model, life):
        torque = lever * np.abs(np.asarray(read(f"force:{g.mesh}"), float))
        cycles = revolutions(t, _relative(read, gear, frame))
        n = float(cycles.sum())
        if not n > 0.0:
            rows.append(GearLifeRow(g.mesh, gear, g.slope, None, float(torque.max()), 0.0, None, None,
                                    "the gear does not turn against its frame: no load cycles"))
            continue
        d = miner_damage(torque[:-1], cycles, g.slope, g.torque_ref, g.cycles_ref, g.torque_limit)
        t_eq = equivalent_load(torque[:-1], cycles, g.slope)
        if d == 0.0:
            note = "no damage: every torque at or below the limit"
        elif not math.isfinite(d):
            note = "the damage overflows a float: the torque is far above the S-N curve's reference"
        else:
            note = ""
        with np.errstate(over="ignore", divide="ignore"):
            hours = float(np.float64(t[-1] - t[0]) / np.float64(d) / 3600.0) if note == "" else None
        if hours is not None and not math.isfinite(hours):
            note = "the life overflows a float: the damage is below 1e-300"
        rows.append(GearLifeRow(g.mesh, gear, g.slope, t_eq, float(torque.max()), n, *_finite(d, hours), note))
    return rows


@dataclass(frozen=True)
class OutputLife:
    """One output's counts: ``cycles`` (rainflow, full cycles), ``dels`` {m: DEL} in its
    ``unit``, its ``ldd`` and its ``lrd`` (None with ``note`` where the shaft does not turn)."""

    unit: str
    cycles: float
    dels: dict
    ldd: LoadDistribution
    lrd: LoadDistribution | None
    note: str = ""


@dataclass(frozen=True)
class LifeResult:
    """The life tables of a run (module notes): ``window`` (t0, t1) s counted, ``cycles_ref``
    N_eq of the DELs, ``exponents``, ``shaft`` of the LRDs, ``outputs`` {name:
    :class:`OutputLife`}, ``bearings`` (:class:`BearingLifeRow`), ``gears``
    (:class:`GearLifeRow`)."""

    window: tuple
    cycles_ref: float
    exponents: tuple
    shaft: str | None
    outputs: dict
    bearings: tuple
    gears: tuple

    def as_dict(self) -> dict:
        """Plain numbers and lists (JSON): the window, N_eq, exponents, shaft; per output its
        cycles, DELs ``del_mM`` and note; the bearings' and gears' rows."""
        return {"window_s": list(self.window), "n_eq": self.cycles_ref, "exponents": list(self.exponents),
                "shaft": self.shaft,
                "outputs": {k: {"unit": o.unit, "cycles": o.cycles, **{f"del_m{m:g}": o.dels[m] for m in self.exponents},
                                "note": o.note} for k, o in self.outputs.items()},
                "bearings": [dataclasses.asdict(b) for b in self.bearings],
                "gears": [dataclasses.asdict(g) for g in self.gears]}


def check_life(model, life, t_end: float, reference: str | None) -> str | None:
    """``life`` checked against the model and the run's length before it starts (its window in
    the record, its shaft a body, its bearings and gears rated as the tables need); returns the
    shaft of the load revolution distributions (``life.shaft`` or the ``reference``)."""
    check.instance("simulation.life", life, LifeTables, "a LifeTables table")
    if life.window is not None:
        t0, t1 = life.window
        if not 0.0 <= t0 < t1 <= t_end:
            raise check.refuse("simulation.life.window", list(life.window),
                               f"must lie in the record, 0 <= t0 < t1 <= t_end = {t_end:g} s")
    if life.shaft is not None:
        check.one_of("simulation.life.shaft", life.shaft, list(model.bodies))
    bearing_parts(model, life)
    gear_parts(model, life)
    return life.shaft or reference


def _output_life(t, y, unit, exponents, n_eq, bins, speed, name) -> OutputLife:
    cyc = rainflow_cycles(y, name)
    dels = {m: damage_equivalent_load(cyc, m, n_eq) for m in exponents}
    ldd = load_duration(t, y, bins)
    if speed is None or not revolutions(t, speed).sum() > 0.0:
        return OutputLife(unit, float(cyc.counts.sum()), dels, ldd, None, "the shaft does not turn: no LRD")
    return OutputLife(unit, float(cyc.counts.sum()), dels, ldd, load_revolutions(t, y, speed, bins))


def life_result(model, life, time_s, read, units: dict, names, shaft: str | None) -> LifeResult:
    """The :class:`LifeResult` of a run's histories: ``read(name)`` -> the history of a recorded
    channel at ``time_s`` (s); ``names``: the outputs counted (each of them), ``units`` theirs;
    ``shaft``: the LRDs' (:func:`check_life`'s)."""
    t_all = np.asarray(time_s, float)
    t0, t1 = life.window if life.window is not None else (float(t_all[0]), float(t_all[-1]))
    keep = span(t_all, t0, t1)
    if keep.stop - keep.start < 2:
        raise check.refuse("simulation.life.window", [t0, t1], "holds fewer than two samples of the record")
    t = t_all[keep]
    n_eq = float(life.cycles_ref) if life.cycles_ref is not None else float(t[-1] - t[0])

    speeds = {}                 # a body's speed serves every bearing and gear it turns: read it once

    def cut(name):
        if name in speeds:
            return speeds[name]
        y = np.asarray(read(name), float)[keep]
        if name.startswith("speed:"):
            speeds[name] = y
        return y
    speed = None if shaft is None else cut(f"speed:{shaft}")
    outs = {k: _output_life(t, cut(k), units.get(k, ""), tuple(life.exponents), n_eq, life.bins, speed, k)
            for k in names}
    return LifeResult((float(t[0]), float(t[-1])), n_eq, tuple(life.exponents), shaft, outs,
                      tuple(bearing_rows(model, life, t, cut)), tuple(gear_rows(model, life, t, cut)))
