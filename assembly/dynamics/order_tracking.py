"""Order tracking of a run-up: any output resampled at equal shaft angles, its spectrum over
revolutions (an order map), the cut of one order over speed, and the table of resonance passages.

Computed order tracking (Fyfe & Munck, "Analysis of computed order tracking", Mech. Syst.
Signal Process. 11 (1997) 187-205): the time signal is interpolated at the instants the shaft
passes equal angles, so an order (a component at ``order`` cycles a revolution) is a fixed
line of the angle-domain spectrum whatever the speed does. The steps, on numpy/scipy:

1. **Angle grid, oversampled.** The instants of equal angle come from the integrated shaft
   angle (the body's rotation coordinate, :func:`assembly.model.probes.spin_row`; from a
   run's recorded ``speed:BODY`` by :func:`shaft_angle`) by a cubic
   spline of time over angle (``scipy.interpolate.CubicSpline``); the signal at those
   instants by a cubic spline over time, whose error on a component of f Hz sampled at fs is
   at most (5/384) (2 pi f / fs)^4 of its amplitude (1.6e-5 at fs / f = 33, 8 % at fs / f =
   4: record fast enough for the orders to be read). The grid has ``D x samples_per_rev`` points a
   revolution, D the least whole number >= 2 with ``D x samples_per_rev x`` (lowest speed,
   rev/s) >= the record's sample rate: everywhere, the angle grid is at least as dense as the
   time samples, so the interpolation aliases nothing the record holds.
2. **Anti-alias in the angle domain, then decimate by D** (``scipy.signal.resample_poly``
   with a linear-phase FIR from ``scipy.signal.kaiserord`` / ``firwin``): passband to
   ``PASS x samples_per_rev / 2`` orders, stopband from ``samples_per_rev / 2`` (the target
   Nyquist order), ripple and attenuation ``RIPPLE_DB`` (1e-5). The cut-off is in orders, so
   it is the same at every speed: unlike a low-pass in time below the lowest speed's Nyquist,
   it keeps every order up to ``max_order`` over the whole run. The filter's start-up at each
   end (half its length) is dropped.
3. **Spectra over revolutions.** Blocks of ``revolutions`` whole revolutions, Hann window
   (periodic, ``scipy.signal.get_window``), ``overlap`` between blocks, ``numpy.fft.rfft``:
   order resolution ``1 / revolutions``; amplitudes peak-scaled (``2 |X_k| / sum(w)``), exact
   for an order on a bin (``order x revolutions`` whole), whose Hann spectrum is nonzero in
   that bin and its two neighbours only. Each block's speed is its mean: ``revolutions`` turns
   over the time they took (rad/s).

An order cut takes the power of an order's band (its bin and two on either side) with Hann's
noise bandwidth (1.5 bins): exact on a bin; between bins the band holds >= 0.9994 of the
power (half a bin off), the amplitude low by 2.5e-4 at most. Orders closer than 3 bins to one
another are not separated.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import signal
from scipy.integrate import cumulative_trapezoid
from scipy.interpolate import CubicSpline

from .. import arguments
from ..errors import SceneError
from .budget import check_memory

#: passband edge of the angle-domain low-pass, a share of the target Nyquist order
PASS = 0.8
#: ripple (passband) and attenuation (stopband) of the anti-alias FIR, dB: 1e-5
RIPPLE_DB = 100.0
#: least cycles of an order in a block: Hann's main lobe spans two bins either side of DC
MIN_CYCLES = 2
#: band of an order cut: its bin and this many on either side
BAND_BINS = 2
#: Hann's equivalent noise bandwidth, bins (N sum w^2 / (sum w)^2)
HANN_ENBW = 1.5
#: A parametric order's quasi-static level is read from this fraction of ``static_below`` up
#: (:func:`resonance_passages`: below it the damping's share of its low-speed content grows).
PARAMETRIC_FROM = 0.7


@dataclass(frozen=True)
class Resampled:
    """A signal at equal shaft angles: ``angle`` (rad), ``time`` (s) and ``value`` at each,
    ``samples_per_rev`` of them a revolution, band-limited to ``max_order``; ``oversampling``
    (D) and ``fir_taps``: the fine grid's factor and the anti-alias filter's length."""

    angle: np.ndarray
    time: np.ndarray
    value: np.ndarray
    samples_per_rev: int
    max_order: float
    oversampling: int
    fir_taps: int


@dataclass(frozen=True)
class AngleGrid:
    """The instants a record's shaft passes equal angles (module notes, step 1), the same for
    every signal of the record: ``time`` and ``angle`` the record's (checked), ``grid`` the
    fine grid's angles (rad) and ``grid_time`` its instants (s), ``samples_per_rev`` the target
    samples a revolution and ``oversampling`` (D) the fine grid's factor. Made once by
    :func:`angle_grid` and given to :func:`order_map` / :func:`resample_angle` of each signal,
    it spares them the spline of time over angle."""

    time: np.ndarray
    angle: np.ndarray
    grid: np.ndarray
    grid_time: np.ndarray
    samples_per_rev: int
    oversampling: int


@dataclass(frozen=True)
class OrderMap:
    """Amplitude per order over speed: ``amplitude[i, j]`` of order ``orders[j]`` in block i,
    which turned at mean ``speed[i]`` (rad/s) around ``time[i]`` (s, its middle).
    ``revolutions`` a block (order resolution 1/revolutions); orders above ``max_order`` are
    in the anti-alias filter's transition band or beyond and not to be read."""

    orders: np.ndarray
    speed: np.ndarray
    time: np.ndarray
    amplitude: np.ndarray
    revolutions: int
    max_order: float


@dataclass(frozen=True)
class OrderCut:
    """One order's amplitude over speed (rad/s) and time (s, block middles)."""

    order: float
    speed: np.ndarray
    time: np.ndarray
    amplitude: np.ndarray


@dataclass(frozen=True)
class Passage:
    """A resonance passage: ``order`` meets mode ``mode`` (1-based, its ``mode_class``) of
    ``frequency_hz`` at shaft ``speed`` = 2 pi f_n / order (rad/s). ``peak_speed`` and
    ``peak``: the order cut's largest amplitude within the passage's search band;
    ``quasi_static``: the cut's low-speed asymptote (see :func:`resonance_passages`), read over
    the speeds up to ``static_r`` of the passage's; ``amplification`` = peak / quasi_static (None
    without a quasi-static level, or when the peak is the search band's edge: ``note``)."""

    order: float
    mode: int
    mode_class: str
    frequency_hz: float
    speed: float
    peak_speed: float | None
    peak: float | None
    quasi_static: float | None
    amplification: float | None
    static_r: float | None = None
    note: str = ""


def _series(name: str, value, least: int = 4) -> np.ndarray:
    """``value`` as a 1-D float array of at least ``least`` finite numbers."""
    if isinstance(value, (bool, str, bytes)) or value is None:
        raise arguments.refuse(name, value, "must be a 1-D array of numbers")
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise arguments.refuse(name, value, "must be a 1-D array of numbers") from None
    if arr.ndim != 1:
        raise arguments.refuse(name, value, f"must be 1-D (shape {arr.shape})")
    if len(arr) < least:
        raise arguments.refuse(name, value, f"fewer than {least} samples: no record to track")
    if not np.all(np.isfinite(arr)):
        i = int(np.argmin(np.isfinite(arr)))
        raise SceneError(f"{name}[{i}]", float(arr[i]), "must be finite")
    return arr


def _times(value) -> np.ndarray:
    t = _series("time", value)
    dt = np.diff(t)
    if np.any(dt <= 0):
        i = int(np.argmax(dt <= 0))
        raise SceneError("time", float(t[i + 1]), f"not increasing (sample {i + 1})")
    return t


def _check_record(time, angle, value) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    t = _times(time)
    a, x = _series("angle", angle), _series("value", value)
    for name, arr in (("angle", a), ("value", x)):
        if arr.shape != t.shape:
            raise SceneError(name, arguments.shown(arr), f"must have one sample per time ({len(t)})")
    _check_angle(t, a)
    return t, a, x


def _check_angle(t: np.ndarray, a: np.ndarray) -> None:
    da = np.diff(a)
    if np.any(da <= 0):
        i = int(np.argmax(da <= 0))
        raise SceneError("angle", float(a[i + 1]), f"does not increase at t = {t[i + 1]:.6g} s (speed "
                         f"{da[i] / (t[i + 1] - t[i]):.6g} rad/s): order tracking needs the shaft turning one way")


def shaft_angle(time, speed, start: float = 0.0) -> np.ndarray:
    """The shaft angle (rad) from its recorded speed (rad/s, a run's ``speed:BODY``), by the
    trapezoidal rule from ``start`` at ``time[0]``: the rotation coordinate itself, to
    round-off, for a run on the default scheme recorded at every step (Newmark's average
    acceleration advances q by dt (v + v+) / 2, the trapezoid of the speeds); second-order
    accurate otherwise. SceneError at ``time`` where it does not
    increase."""
    t, w = _times(time), _series("speed", speed)
    if w.shape != t.shape:
        raise SceneError("speed", arguments.shown(w), f"must have one sample per time ({len(t)})")
    return arguments.number("start", start, "rad") + cumulative_trapezoid(w, t, initial=0.0)


def revolution_samples(max_order: float) -> int:
    """Samples a revolution of an order map reaching ``max_order``: the least power of two >= 8
    with ``PASS x spr / 2 >= max_order``."""
    max_order = arguments.number("max_order", max_order, gt=0.0)
    spr = 8
    while PASS * spr / 2 < max_order:
        spr *= 2
    return spr


def angle_grid(time, angle, samples_per_rev: int) -> AngleGrid:
    """The :class:`AngleGrid` of a record (``time`` s, the shaft's ``angle`` rad) for
    ``samples_per_rev`` samples a revolution: D x ``samples_per_rev`` points a revolution (module
    notes, step 1) and the instants the shaft passes them. SceneError at ``angle`` where it does
    not increase or where the fine grid (set by the slowest speed) would exceed the memory
    budget, at ``samples_per_rev`` below 8."""
    t = _times(time)
    a = _series("angle", angle)
    if a.shape != t.shape:
        raise SceneError("angle", arguments.shown(a), f"must have one sample per time ({len(t)})")
    _check_angle(t, a)
    spr = arguments.integer("samples_per_rev", samples_per_rev, 8)
    rate = 1.0 / float(np.min(np.diff(t)))                         # samples/s of the record
    slowest = float(np.min(np.diff(a) / np.diff(t))) / (2 * math.pi)   # rev/s
    d = max(2, math.ceil(rate / (slowest * spr)))
    step = 2 * math.pi / (d * spr)
    points = (a[-1] - a[0]) / step
    check_memory("angle", arguments.shown(a), 48.0 * points,       # grid, its times, values, splines' work
                 f"an angle grid of {points:.3g} points ({d} x {spr} a revolution: the record's {rate:.4g} "
                 f"samples/s at its slowest {slowest:.3g} rev/s)", "start the record where the shaft turns")
    grid = a[0] + step * np.arange(int(math.floor((a[-1] - a[0]) / step)) + 1)
    return AngleGrid(t, a, grid, CubicSpline(a, t)(grid), spr, d)


def resample_angle(time, angle, value, samples_per_rev: int, grid: AngleGrid | None = None) -> Resampled:
    """``value`` (sampled at ``time``, s) at equal increments of the shaft ``angle`` (rad),
    ``samples_per_rev`` a revolution, anti-aliased in the angle domain (module notes, steps 1
    and 2). SceneError at ``angle`` where it does not increase or where the fine grid (set
    by the slowest speed) would exceed the memory budget, at ``samples_per_rev`` below 8.
    ``grid``: the record's :class:`AngleGrid` for ``samples_per_rev`` (:func:`angle_grid`), made
    once for many signals of one record (``time`` and ``angle`` must be its own)."""
    t, a, x = _check_record(time, angle, value)
    if grid is None:
        grid = angle_grid(t, a, samples_per_rev)
    else:
        _check_grid(grid, t, a, samples_per_rev)
    d, spr = grid.oversampling, grid.samples_per_rev
    x_grid = CubicSpline(t, x)(grid.grid_time)
    width = (1.0 - PASS) / d                                        # of the fine Nyquist
    taps, beta = signal.kaiserord(RIPPLE_DB, width)
    taps |= 1                                                       # odd: a whole-sample delay
    fir = signal.firwin(taps, (1.0 + PASS) / (2 * d), window=("kaiser", beta))
    y = signal.resample_poly(x_grid, 1, d, window=fir)
    edge = taps // (2 * d) + 1                                      # the filter's start-up, coarse samples
    keep = slice(edge, len(y) - edge)
    idx = (np.arange(len(y)) * d)[keep]                             # output j is fine sample j d
    return Resampled(grid.grid[idx], grid.grid_time[idx], y[keep], spr, PASS * spr / 2, d, taps)


def _check_grid(grid, t: np.ndarray, a: np.ndarray, spr) -> None:
    """SceneError unless ``grid`` is the :class:`AngleGrid` of the record ``t``, ``a`` for
    ``spr`` samples a revolution."""
    arguments.instance("grid", grid, AngleGrid, "an AngleGrid (angle_grid)")
    if grid.samples_per_rev != arguments.integer("samples_per_rev", spr, 8):
        raise SceneError("grid", f"{grid.samples_per_rev} samples a revolution", f"the map needs {spr}: make it "
                         f"with angle_grid(time, angle, {spr})")
    same = all(x is y or (x.shape == y.shape and np.array_equal(x, y)) for x, y in ((grid.time, t), (grid.angle, a)))
    if not same:
        raise SceneError("grid", "an AngleGrid of another record", "make it from this record's time and angle")


def order_map(time, angle, value, *, max_order: float, revolutions: int = 8, overlap: float = 0.5,
              lowest_order: float = 1.0, run_up: bool = True, grid: AngleGrid | None = None) -> OrderMap:
    """Order map of ``value`` over the run (module notes): orders up to at least
    ``max_order`` (samples a revolution the least power of two with ``PASS x spr / 2 >=
    max_order``), blocks of ``revolutions`` turns overlapping by ``overlap``.
    ``lowest_order`` (default 1, the shaft's own order): a block must hold ``MIN_CYCLES``
    cycles of it.

    SceneError, one line naming the field: ``max_order`` / ``lowest_order`` <= 0;
    ``revolutions`` too few for ``lowest_order`` (fewer than ``MIN_CYCLES`` cycles a block) or
    more than the record turns; ``angle`` where it does not increase; ``speed``, with
    ``run_up``, where the block speeds do not increase. ``grid``: the record's
    :class:`AngleGrid` for :func:`revolution_samples` of ``max_order``, made once for many signals
    of one record (:func:`angle_grid`; ``time`` and ``angle`` must be its own)."""
    max_order = arguments.number("max_order", max_order, gt=0.0)
    low = arguments.number("lowest_order", lowest_order, gt=0.0)
    revolutions = arguments.integer("revolutions", revolutions, 1)
    overlap = arguments.number("overlap", overlap, ge=0.0, lt=1.0)
    run_up = arguments.flag("run_up", run_up)
    if low * revolutions < MIN_CYCLES:
        raise SceneError("revolutions", revolutions, f"order {low:g} turns {low * revolutions:g} cycles a block "
                         f"(fewer than {MIN_CYCLES}): take at least {math.ceil(MIN_CYCLES / low)} revolutions")
    t, a, x = _check_record(time, angle, value)
    turns = (a[-1] - a[0]) / (2 * math.pi)
    if turns < revolutions:
        raise SceneError("time", float(t[-1] - t[0]), f"the record turns {turns:.3g} revolutions, fewer than "
                         f"the {revolutions} a block needs for order {low:g}")
    spr = revolution_samples(max_order)
    rs = resample_angle(t, a, x, spr, grid)
    n = revolutions * spr
    if len(rs.value) <= n:
        raise SceneError("time", float(t[-1] - t[0]), f"the record turns {turns:.3g} revolutions: after the "
                         f"anti-alias filter's ends, fewer than the {revolutions} a block needs")
    hop = max(1, int(round(n * (1 - overlap))))
    starts = np.arange(0, len(rs.value) - n, hop)                  # each block's end sample exists
    w = signal.get_window("hann", n)
    blocks = np.lib.stride_tricks.sliding_window_view(rs.value, n)[starts]
    amp = 2.0 * np.abs(np.fft.rfft(blocks * w, axis=1)) / w.sum()
    amp[:, 0] /= 2.0
    speed = 2 * math.pi * revolutions / (rs.time[starts + n] - rs.time[starts])
    if run_up and np.any(np.diff(speed) <= 0):
        i = int(np.argmax(np.diff(speed) <= 0))
        raise SceneError("speed", float(speed[i + 1]), f"not increasing at t = {rs.time[starts[i + 1]]:.6g} s "
                         f"(from {speed[i]:.6g} rad/s): a run-up was assumed (run_up=False for any other run)")
    orders = np.fft.rfftfreq(n, 1.0 / spr)
    return OrderMap(orders, speed, rs.time[starts + n // 2], amp, int(revolutions), rs.max_order)


def order_cut(omap: OrderMap, order: float) -> OrderCut:
    """Amplitude of ``order`` over speed: the band power of its bin and ``BAND_BINS`` either
    side, over Hann's noise bandwidth (module notes). SceneError at ``order`` <= 0, above the
    map's ``max_order``, or with fewer than ``MIN_CYCLES`` cycles a block."""
    arguments.instance("omap", omap, OrderMap, "an OrderMap (order_map)")
    order = arguments.number("order", order, gt=0.0)
    if order > omap.max_order:
        raise SceneError("order", order, f"above the map's anti-aliased band ({omap.max_order:g})")
    k = order * omap.revolutions
    if k < MIN_CYCLES:
        raise SceneError("order", order, f"{k:g} cycles a block of {omap.revolutions} revolutions, fewer than "
                         f"{MIN_CYCLES}: a record of more revolutions a block is needed")
    k0 = int(round(k))
    band = omap.amplitude[:, max(1, k0 - BAND_BINS):k0 + BAND_BINS + 1]
    return OrderCut(float(order), omap.speed, omap.time, np.sqrt(np.sum(band**2, axis=1) / HANN_ENBW))


def resonance_passages(cut: OrderCut, modes, *, band: float = 0.1, static_below: float = 0.5,
                       parametric: bool = False, static_fallback: float = 0.8) -> list[Passage]:
    """Each passage of ``cut``'s order through a natural frequency: ``modes`` a sequence of
    (frequency_hz, mode_class). The passage speed is 2 pi f_n / order (rad/s); the peak is
    the cut's largest amplitude at speeds within ``band`` (relative) of it, or within half the
    way to the nearest other mode of ``modes`` where that is closer; the quasi-static
    level is the cut's low-speed asymptote of one mode: the mean of amplitude x |1 - r^2|,
    r = speed / passage speed, over the speeds r <= ``static_below`` (exact for one undamped
    mode; for one of damping ratio zeta, low by 2 zeta^2 r^2 / (1 - r^2)^2 at most, 2.2e-3 at
    zeta = 0.05 and r = 0.5; other modes' shares are not removed). A passage outside the
    cut's speeds has no peak; one without speeds below ``static_below`` of it no level.
    ``parametric``: the order is a mesh order of a varying mesh stiffness, read in its mesh's
    force. The variation a of k loads the deflection with a F0 (F0 the mean force), and the
    force's order content is a F0 (1 - H), H = 1 / (1 - r^2 + 2 i zeta r) for one mode: it
    vanishes as r^2 at low speed, and its level a F0 is the mean of amplitude x |1 - r^2| / r^2
    over static_below x 0.7 <= r <= ``static_below`` (high by sqrt(1 + 4 zeta^2 / r^2) at most,
    4 % at zeta = 0.05 and r = 0.35), so the amplification is over the mesh's own quasi-static
    excitation a F0 (its peak |1 - H| at r = 1, sqrt(1 + 4 zeta^2) / (2 zeta) for a slow sweep).
    A range too narrow to reach ``static_below`` of a passage (a 5 MW's operating range spans
    1.75 x) reads its level up to ``static_fallback`` instead (r <= 0.8: the one-mode bias
    2 zeta^2 r^2 / (1 - r^2)^2, 2.5 % at zeta = 0.05, and more of the neighbouring modes); the
    passage's ``static_r`` says which. A peak on the search band's edge (the order still rising
    or falling through it) is no resonance maximum: its amplification is None, said in ``note``.
    SceneError at ``modes[i]`` with a frequency <= 0, at ``cut.speed`` not increasing."""
    arguments.instance("cut", cut, OrderCut, "an OrderCut (order_cut)")
    band = arguments.number("band", band, gt=0.0)
    static_below = arguments.number("static_below", static_below, gt=0.0, lt=1.0)
    static_fallback = arguments.number("static_fallback", static_fallback, gt=0.0, lt=1.0)
    if isinstance(modes, (str, bytes, dict)) or not isinstance(modes, (list, tuple)):
        raise arguments.refuse("modes", modes, "must be a list of (frequency Hz, mode class) pairs")
    pairs = []
    for j, m in enumerate(modes):
        if not isinstance(m, (list, tuple)) or len(m) != 2:
            raise arguments.refuse(f"modes[{j}]", m, "must be a (frequency Hz, mode class) pair")
        pairs.append((arguments.number(f"modes[{j}]", m[0], "Hz", gt=0.0), arguments.text(f"modes[{j}]", m[1])))
    if np.any(np.diff(cut.speed) <= 0):
        i = int(np.argmax(np.diff(cut.speed) <= 0))
        raise SceneError("cut.speed", float(cut.speed[i + 1]), "not increasing: resonance passages need a run-up")
    out = []
    freqs = np.array([f for f, _ in pairs])
    for j, (f, cls) in enumerate(pairs):
        s = 2 * math.pi * f / cut.order
        # the search band, no wider than half-way to the next mode either side: a stronger
        # neighbour's peak is not this mode's
        others = np.abs(np.delete(freqs, j) / f - 1.0)
        others = others[others > 0]
        half = min(band, 0.5 * float(others.min())) if others.size else band
        near = np.flatnonzero(np.abs(cut.speed / s - 1.0) <= half)
        peak_speed = peak = None
        note = ""
        if near.size:
            i = int(near[np.argmax(cut.amplitude[near])])
            peak_speed, peak = float(cut.speed[i]), float(cut.amplitude[i])
            inner = (i > near[0] or i == 0) and (i < near[-1] or i == len(cut.speed) - 1)
            if not inner:
                note = f"the peak is the search band's edge (+-{100 * half:.3g} %): the order rises through it"
        r = cut.speed / s
        static, top = None, None
        for top in (static_below, max(static_below, static_fallback)):
            if parametric:
                low = (r <= top) & (r >= PARAMETRIC_FROM * top)
                shape = np.abs(1.0 - r[low]**2) / np.maximum(r[low], 1e-300)**2
            else:
                low = r <= top
                shape = np.abs(1.0 - r[low]**2)
            if np.any(low):
                static = float(np.mean(cut.amplitude[low] * shape))
                break
        top = top if static is not None else None
        amp = peak / static if (peak is not None and static and not note) else None
        out.append(Passage(cut.order, j + 1, cls, float(f), s, peak_speed, peak, static, amp, top, note))
    return out
