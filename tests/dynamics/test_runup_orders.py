"""The orders of a run-up (assembly.dynamics.runup_orders) on a synthetic record.

Theory. Order k of a shaft turning at Omega(t) excites a mode of f_n at the speed 2 pi f_n / k;
a one-mode response to a unit order of amplitude X(r) = 1 / |1 - r^2 + 2 i zeta r|, r = k Omega /
(2 pi f_n), peaks at 1 / (2 zeta sqrt(1 - zeta^2)) and is 1 / (1 - r^2) quasi-statically. Tracked in
blocks of revolutions, the peak is an average over the block's speeds: never above the true one.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.dynamics.runup_orders import excitation_orders, runup_orders

ORDER, FN, ZETA = 10.0, 50.0, 0.05


def test_a_synthetic_run_up_gives_the_passage_and_its_amplification():
    t = np.arange(0.0, 40.0, 2e-4)
    f_shaft = 1.0 + (8.0 - 1.0) * t / t[-1]                       # rev/s: r from 0.2 to 1.6
    theta = 2 * np.pi * (1.0 * t + 0.5 * (8.0 - 1.0) / t[-1] * t ** 2)
    r = ORDER * f_shaft / FN
    X = 1.0 / np.abs(1 - r ** 2 + 2j * ZETA * r)
    y = X * np.cos(ORDER * theta)
    ro = runup_orders(t, 2 * np.pi * f_shaft, {"y": y}, {"k": ORDER}, [(FN, "test mode")])
    (p,) = ro.passages
    assert p["speed_rpm"] == pytest.approx(60.0 * FN / ORDER, rel=1e-12)      # f_n / order
    peak = 1.0 / (2 * ZETA * math.sqrt(1 - ZETA ** 2))
    # the block-averaged peak: below the true one, and not by more than half of it here
    assert 0.5 * peak <= p["peak"] <= 1.01 * peak
    # the quasi-static level of the one-mode response: its low-speed asymptote, 1 (the order's own).
    # Two biases: X |1 - r^2| = 1 / sqrt(1 + (2 zeta r / (1 - r^2))^2) is low by at most
    # 2 zeta^2 r^2 / (1 - r^2)^2 = 2.2e-3 (r <= 0.5); and a block's band amplitude is the RMS of X
    # over the block, whose r spans dr = 10 x (7/40 x 8 / f) / 50 <= 0.19 (8 revolutions at f >= 1.5
    # rev/s where r >= 0.3), high by (dr^2 / 24)((X'/X)^2 + X''/X) <= 0.19^2 / 24 x 8.0 = 1.2 % at
    # r = 0.5 (X = 1/(1 - r^2)). Together within 1.5 %: measured 5.6e-3.
    assert p["quasi_static"] == pytest.approx(1.0, rel=0.015)
    assert p["peak_speed_rpm"] == pytest.approx(p["speed_rpm"], rel=0.1)


def test_excitation_orders_count_per_revolution_of_the_reference():
    # a mesh of 97 Hz on a reference of 1 rev/s is order 97; harmonics 2 and 3 at 194, 291; the
    # rotor orders 1P and 3P; a shaft at 5 rev/s is order 5
    o = excitation_orders({"m": 97.0}, {"rotor": 1.0, "hss": -5.0}, "rotor")
    assert o == {"1P": 1.0, "3P": 3.0, "hss 1x": 5.0, "m x1": 97.0, "m x2": 194.0, "m x3": 291.0}


@pytest.mark.parametrize("zeta", [0.02, 0.05, 0.1])
def test_a_parametric_order_is_amplified_over_its_own_excitation(zeta):
    # one mode's mesh force under a varying mesh stiffness: its order content a F0 (1 - H),
    # H = 1 / (1 - r^2 + 2 i zeta r), sampled finely over the speed; the parametric level is a F0
    # high by sqrt(1 + 4 zeta^2 / r^2) at most over the speeds it reads (r >= 0.35: module notes
    # of order_tracking)
    from assembly.dynamics.order_tracking import PARAMETRIC_FROM, OrderCut, resonance_passages
    aF0, order, fn = 37.0, 20.0, 342.0
    s = 2 * math.pi * fn / order
    r = np.linspace(0.05, 1.5, 29001)
    h = 1.0 / (1 - r ** 2 + 2j * zeta * r)
    cut = OrderCut(order, r * s, r, aF0 * np.abs(1 - h))
    (p,) = resonance_passages(cut, [(fn, "torsional")], parametric=True)
    r_low = PARAMETRIC_FROM * 0.5
    assert aF0 <= p.quasi_static <= aF0 * math.sqrt(1 + 4 * zeta ** 2 / r_low ** 2)
    # the cut's peak: the closed form's maximum near r = 1 (a bounded search; at r = 1 it is
    # sqrt(1 + 4 zeta^2) / (2 zeta)), to the grid's step 5e-5 in r, where |1 - H| is flat to
    # (5e-5 / zeta)^2 < 1e-5
    from scipy.optimize import minimize_scalar
    best = minimize_scalar(lambda x: -abs(1 - 1 / (1 - x ** 2 + 2j * zeta * x)), bounds=(0.8, 1.2),
                           method="bounded", options={"xatol": 1e-10})
    assert p.peak == pytest.approx(-aF0 * best.fun, rel=1e-5)
    assert -best.fun >= math.sqrt(1 + 4 * zeta ** 2) / (2 * zeta)
    # read as an additive order the same cut's level is a F0 r^2 -- the amplification far too high
    (q,) = resonance_passages(cut, [(fn, "torsional")])
    assert q.amplification > 3 * p.amplification


def test_a_narrow_range_reads_its_level_up_to_r_0_8_and_says_so():
    # one additive mode, |H| = 1 / |1 - r^2 + 2 i zeta r|, over r = 0.6 .. 1.3 only (a 5 MW's range
    # spans 1.75 x): the level is read up to r = 0.8, low by at most the one-mode bias
    # 2 zeta^2 r^2 / (1 - r^2)^2 there (the asymptote's module notes)
    from assembly.dynamics.order_tracking import OrderCut, resonance_passages
    zeta, order, fn, a = 0.05, 3.0, 12.0, 2.5
    s = 2 * math.pi * fn / order
    r = np.linspace(0.6, 1.3, 14001)
    cut = OrderCut(order, r * s, r, a / np.abs(1 - r ** 2 + 2j * zeta * r))
    (p,) = resonance_passages(cut, [(fn, "torsional")])
    assert p.static_r == 0.8 and p.note == ""
    bias = 2 * zeta ** 2 * 0.8 ** 2 / (1 - 0.8 ** 2) ** 2
    assert a * (1 - bias) <= p.quasi_static <= a
    # the range starting below half the passage speed: the level from r <= 0.5 as before
    r2 = np.linspace(0.3, 1.3, 20001)
    (q,) = resonance_passages(OrderCut(order, r2 * s, r2, a / np.abs(1 - r2 ** 2 + 2j * zeta * r2)),
                              [(fn, "torsional")])
    assert q.static_r == 0.5


def test_a_peak_on_the_search_bands_edge_has_no_amplification():
    # an order rising through the band (no resonance maximum inside +-10 % of the passage)
    from assembly.dynamics.order_tracking import OrderCut, resonance_passages
    r = np.linspace(0.3, 1.5, 1201)
    (p,) = resonance_passages(OrderCut(2.0, r * 10.0, r, r ** 3), [(10.0 * 2.0 / (2 * math.pi), "x")])
    assert p.peak_speed == pytest.approx(1.1 * 10.0, rel=1e-3) and p.amplification is None
    assert "edge" in p.note


def test_a_neighbouring_modes_peak_is_not_taken_for_this_ones():
    # two modes 6 % apart, the upper 1.5 times stronger (its peak 75 against the lower's 52): within
    # +-10 % of the lower one's passage lies the upper one's peak; the search stops half-way (3 %),
    # where the pair sums to 42, so each passage finds its own
    from assembly.dynamics.order_tracking import OrderCut, resonance_passages
    zeta, order, f1, f2 = 0.01, 2.0, 10.0, 10.6
    s1 = 2 * math.pi * f1 / order
    w = np.linspace(0.3 * s1, 1.4 * s1, 40001)
    amp = np.abs(1 / (1 - (w / s1) ** 2 + 2j * zeta * w / s1)
                 + 1.5 / (1 - (w * f1 / (f2 * s1)) ** 2 + 2j * zeta * w * f1 / (f2 * s1)))
    low, high = resonance_passages(OrderCut(order, w, w, amp), [(f1, "a"), (f2, "b")])
    # each peak inside its own mode's half-power band (+-zeta; the neighbour's skirt shifts it a little)
    assert low.peak_speed == pytest.approx(s1, rel=zeta) and high.peak_speed == pytest.approx(s1 * f2 / f1, rel=zeta)
    assert low.note == "" and high.note == ""
