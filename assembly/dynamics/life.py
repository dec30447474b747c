"""Loads to life: load duration and load revolution distributions, bearing L10, gear damage.

* A history is its samples ``(t_k, y_k)``, each held until the next sample (``y_k`` over
  ``[t_k, t_{k+1})``; the last sample carries no time). The load duration distribution (LDD)
  puts ``t_{k+1} - t_k`` in the bin of ``y_k``; the load revolution distribution (LRD) puts
  the shaft's turn over the same interval, ``|d theta_k| / 2 pi`` with ``d theta_k =
  (omega_k + omega_{k+1}) / 2 (t_{k+1} - t_k)`` (the trapezoid of the shaft's own speed
  omega, rad/s), in the bin of the torque ``y_k``: the revolutions sum to the integrated
  angle / 2 pi (for a shaft that turns one way). Bins: edges given (strictly increasing), or a
  count of equal bins from the least to the largest sample (numpy's ``histogram``: the last
  bin holds its right edge; a constant history gets one bin of width 1 around it, one whose
samples differ by round-off alone bins a few units in the last place wide). What falls
  outside given edges is ``outside``.
* Equivalent load of a spectrum (levels L_i, cycles or revolutions N_i) for exponent p:
  ``L_eq = (sum |L_i|^p N_i / sum N_i)^(1/p)`` (loads as magnitudes).
* Bearing basic rating life (ISO 281:2007): ``L10 = (C / P)^p`` million revolutions, C the
  basic dynamic load rating (N), P the equivalent load of the bearing's force spectrum (N):
  the mean load of a load varying in steps, its levels weighted by their revolutions with
  the life exponent p = 3 (ball bearings) or 10/3 (roller bearings).
* Gear: the equivalent torque ``T_eq`` (the equivalent load with the S-N slope k) and the
  Palmgren-Miner damage ``D = sum N_i / N_f(T_i)`` for the S-N curve ``N_f(T) = N_ref
  (T_ref / T)^k`` above the limit (endurance) torque T_lim and no damage at or below it
  (``T_lim = 0``: no limit). A tooth meets its mate once per revolution of its gear, so a
  gear's LRD gives the tooth's load cycles per level.
Units: SI (s, N, N m, rad/s); revolutions; L10 in 1e6 revolutions.
"""
from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np

from ..arguments import integer, number, refuse
from .cycles import history, power, woehler_exponent

#: The most bins a count may ask for (an LDD of 1e5 bins is already finer than any load's accuracy).
MAX_BINS = 100_000


@dataclass(frozen=True, eq=False)
class LoadDistribution:
    """Time (``unit`` "s", an LDD) or revolutions (``unit`` "rev", an LRD) per load bin:
    ``edges`` (n + 1), ``levels`` the bins' centres (n), ``amounts`` (n), ``outside`` the
    amount outside the edges."""

    edges: np.ndarray
    levels: np.ndarray
    amounts: np.ndarray
    unit: str
    outside: float = 0.0

    def total(self) -> float:
        """The amount in the bins (s or revolutions)."""
        return float(self.amounts.sum())


@dataclass(frozen=True)
class BearingLife:
    """ISO 281 basic rating life: ``equivalent_load_n`` P (N), ``l10_mrev`` (1e6 rev; inf
    for P = 0), ``revolutions`` of the spectrum, ``rating_n`` C and ``exponent`` p."""

    equivalent_load_n: float
    l10_mrev: float
    revolutions: float
    rating_n: float
    exponent: float


def _bins(name: str, bins, y: np.ndarray):
    """Bin edges from ``bins`` (a count up to MAX_BINS, or edges) for the samples ``y``."""
    if isinstance(bins, numbers.Integral) and not isinstance(bins, bool):
        n = integer(name, bins, 1, MAX_BINS)
        lo, hi = float(y.min()), float(y.max())
        need = 4.0 * n * float(np.spacing(max(abs(lo), abs(hi))))
        if 0.0 < hi - lo < need:        # a constant history and its round-off: bins a few ulps wide
            c = 0.5 * (lo + hi)
            return np.linspace(c - 0.5 * need, c + 0.5 * need, n + 1)
        return np.histogram_bin_edges(y, bins=n)
    try:
        edges = np.asarray(bins, dtype=float)
    except (TypeError, ValueError):
        raise refuse(name, bins, "must be a count of bins >= 1 or their edges (numbers)") from None
    if edges.ndim != 1 or edges.size < 2:
        raise refuse(name, bins, "must be a count of bins >= 1 or at least two edges")
    bad = np.flatnonzero(~np.isfinite(edges))
    if bad.size:
        raise refuse(name, bins, f"edge {int(bad[0])} is {float(edges[bad[0]])}: edges must be finite")
    bad = np.flatnonzero(np.diff(edges) <= 0)
    if bad.size:
        i = int(bad[0]) + 1
        raise refuse(name, bins, f"edge {i} ({edges[i]:g}) does not increase (previous {edges[i - 1]:g})")
    return edges


def _times(time_s, n: int) -> np.ndarray:
    t = history("time_s", time_s)
    if t.size != n:
        raise refuse("time_s", time_s, f"{t.size} times but {n} samples")
    if n < 2:
        raise refuse("time_s", time_s, "needs at least two samples (a time step)")
    bad = np.flatnonzero(np.diff(t) <= 0)
    if bad.size:
        i = int(bad[0]) + 1
        raise refuse("time_s", time_s, f"time {t[i]:g} s at sample {i} does not increase (previous {t[i - 1]:g} s)")
    return t


def _distribution(y, weights, bins, unit: str) -> LoadDistribution:
    edges = _bins("bins", bins, y)
    amounts, _ = np.histogram(y, bins=edges, weights=weights)
    outside = float(weights[(y < edges[0]) | (y > edges[-1])].sum())
    levels = 0.5 * (edges[1:] + edges[:-1])
    for a in (edges, levels, amounts):
        a.setflags(write=False)
    return LoadDistribution(edges, levels, amounts, unit, outside)


def load_duration(time_s, values, bins=20) -> LoadDistribution:
    """LDD: the time (s) the history ``values`` at ``time_s`` spends in each load bin
    (module notes; ``bins`` a count or edges)."""
    y = history("values", values)
    t = _times(time_s, y.size)
    return _distribution(y[:-1], np.diff(t), bins, "s")


def revolutions(time_s, speed_rad_s) -> np.ndarray:
    """The revolutions of a shaft turning at ``speed_rad_s`` (rad/s) in each interval of
    ``time_s``: ``|omega_k + omega_{k+1}| / 2 (t_{k+1} - t_k) / 2 pi`` (the trapezoid; module
    notes), n - 1 of them. Arrays of equal length, as :func:`load_revolutions` checks them."""
    t, w = np.asarray(time_s, float), np.asarray(speed_rad_s, float)
    return np.abs(0.5 * (w[1:] + w[:-1]) * np.diff(t)) / (2.0 * np.pi)


def load_revolutions(time_s, values, speed_rad_s, bins=20) -> LoadDistribution:
    """LRD: the revolutions of a shaft turning at ``speed_rad_s`` (rad/s, its own speed
    history) in each bin of the load ``values`` (module notes). A shaft that does not turn
    is refused."""
    y = history("values", values)
    t = _times(time_s, y.size)
    w = history("speed_rad_s", speed_rad_s)
    if w.size != y.size:
        raise refuse("speed_rad_s", speed_rad_s, f"{w.size} speeds but {y.size} samples")
    turns = revolutions(t, w)
    if not turns.sum() > 0.0:
        raise refuse("speed_rad_s", speed_rad_s, "the shaft does not turn: no revolutions to distribute")
    return _distribution(y[:-1], turns, bins, "rev")


def _spectrum(levels, counts, what: str):
    """(|levels|, counts) of a load spectrum: equal lengths, finite, counts >= 0, some > 0."""
    if isinstance(levels, LoadDistribution):
        if counts is not None:
            raise refuse(what, counts, "give a LoadDistribution or levels and their counts, not both")
        levels, counts = levels.levels, levels.amounts
    lv = history("levels", levels)
    n = history(what, counts)
    if n.size != lv.size:
        raise refuse(what, counts, f"{n.size} counts but {lv.size} levels")
    bad = np.flatnonzero(n < 0)
    if bad.size:
        raise refuse(what, counts, f"entry {int(bad[0])} is {float(n[bad[0]])}: counts must be >= 0")
    if not n.sum() > 0:
        raise refuse(what, counts, "the spectrum holds no cycles or revolutions")
    return np.abs(lv), n


def equivalent_load(levels, counts=None, exponent: float = 3.0) -> float:
    """``(sum |L_i|^p N_i / sum N_i)^(1/p)`` of the levels L_i and their counts N_i (or a
    :class:`LoadDistribution`), p = ``exponent`` (module notes)."""
    p = woehler_exponent("exponent", exponent)
    lv, n = _spectrum(levels, counts, "counts")
    top = float(lv.max())
    if top == 0.0:
        return 0.0
    return top * power(np.sum(n * (lv / top) ** p) / n.sum(), 1.0 / p)


def bearing_life(levels, revolutions=None, rating_n: float = 1.0, exponent: float = 3.0) -> BearingLife:
    """ISO 281 ``L10 = (C / P)^p`` (1e6 rev) of a bearing whose force spectrum is ``levels``
    (N) with ``revolutions`` at each (or a :class:`LoadDistribution`, an LRD); C =
    ``rating_n`` (N), p = ``exponent`` (3 ball, 10/3 roller)."""
    c = number("rating_n", rating_n, "N", gt=0.0)
    p = number("exponent", exponent, gt=0.0)
    lv, n = _spectrum(levels, revolutions, "revolutions")
    load = equivalent_load(lv, n, p)
    life = float("inf") if load == 0.0 else power(c / load, p)
    return BearingLife(load, life, float(n.sum()), c, p)


def miner_damage(levels, cycles=None, slope: float = 6.0, torque_ref: float = 1.0, cycles_ref: float = 1e7,
                 torque_limit: float = 0.0) -> float:
    """Palmgren-Miner ``D = sum N_i / N_f(T_i)`` with ``N_f = cycles_ref (torque_ref / T)^slope``
    for ``|T| > torque_limit``, no damage at or below it (module notes); ``levels`` (N m) and
    their ``cycles`` (or a :class:`LoadDistribution`)."""
    k = woehler_exponent("slope", slope)
    t_ref = number("torque_ref", torque_ref, "N m", gt=0.0)
    n_ref = number("cycles_ref", cycles_ref, gt=0.0)
    t_lim = number("torque_limit", torque_limit, "N m", ge=0.0)
    lv, n = _spectrum(levels, cycles, "cycles")
    hurt = (lv > t_lim) & (n > 0)
    with np.errstate(over="ignore"):     # a torque far above T_ref: D = inf
        return float(np.sum(n[hurt] * np.power(lv[hurt] / t_ref, k)) / n_ref)
