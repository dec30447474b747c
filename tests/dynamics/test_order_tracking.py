"""Order tracking (assembly.dynamics.order_tracking) of signals whose orders are known: a shaft
ramping linearly 5 -> 25 Hz over 20 s, sampled at 20 kHz.

The signal is defined in the angle domain, x = sum_k A_k cos(o_k theta(t) + p_k), so each order
is a pure line of the angle spectrum whatever the speed does: no smearing to allow for. The
error bound of a tracked amplitude, summed from its sources:

* Hann leakage: orders 1, 7.5 and 24 with 8 revolutions a block lie on bins 8, 60 and 192,
  whose periodic-Hann spectra are nonzero in their bin and its two neighbours only: no order
  leaks into another's band (nor DC into order 1's, bins 0-1 vs 6-10). 0.
* anti-alias FIR ripple (Kaiser, 100 dB): 1e-5 of the amplitude.
* cubic-spline interpolation of a sinusoid of f Hz sampled at fs: (5/384) (2 pi f / fs)^4 of
  its amplitude at most (the spline's h^4 error constant, de Boor, A Practical Guide to
  Splines, 1978, ch. IV); order 24 at 25 Hz is 600 Hz: 1.6e-5. The angle -> time spline errs
  in phase (a smooth angle: smaller), which lowers an amplitude by its square.

Sum < 1e-4 of the amplitude, below the 1e-3 asserted (the brief's bound).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.dynamics.order_tracking import (
    angle_grid,
    order_cut,
    order_map,
    resonance_passages,
    revolution_samples,
    shaft_angle,
)
from assembly.dynamics.simulate import simulate
from assembly.errors import SceneError
from assembly.scene.schema import scene_from_dict
from tests.support.gear_pair_scene import gear_pair

FS, T, F0, F1 = 20000.0, 20.0, 5.0, 25.0           # Hz, s, shaft Hz at 0 and T
ORDERS = ((1.0, 1.0, 0.0), (7.5, 0.2, 0.3), (24.0, 0.05, 1.0))   # order, amplitude, phase (rad)


def _ramp(t_end=T):
    t = np.arange(0.0, t_end, 1.0 / FS)
    return t, 2 * math.pi * (F0 * t + 0.5 * (F1 - F0) / T * t**2)


def test_known_orders_tracked_over_a_linear_ramp():
    t, theta = _ramp()
    x = sum(a * np.cos(o * theta + p) for o, a, p in ORDERS)
    omap = order_map(t, theta, x, max_order=30, revolutions=8)
    assert omap.max_order >= 30
    for o, a, _ in ORDERS:
        cut = order_cut(omap, o)
        assert np.max(np.abs(cut.amplitude - a)) < 1e-3 * a, o          # band power (order cut)
        assert np.max(np.abs(omap.amplitude[:, round(o * 8)] - a)) < 1e-3 * a, o   # the bin itself
    # speeds: a block's mean speed lies between the ramp's speeds at its ends, all increasing
    assert np.all(np.diff(omap.speed) > 0)
    lo, hi = 2 * math.pi * F0, 2 * math.pi * F1
    assert lo < omap.speed[0] and omap.speed[-1] < hi
    # the ramp f = F0 + a t is linear in time, so a block's mean speed (turns over duration D)
    # is f at its middle instant; ``time`` is its middle turn, reached a D / 2 + a D^2 / 8 after
    # the start in turns, i.e. a D^2 / (8 f) later than the middle instant: a^2 D^2 / (8 f) in
    # speed, D <= 8 / F0 (8 revolutions at the slowest)
    a, d = (F1 - F0) / T, 8 / F0
    f_mid = F0 + a * omap.time
    assert np.all(np.abs(omap.speed / (2 * math.pi) - f_mid) <= 1.01 * a**2 * d**2 / (8 * F0))


def test_one_angle_grid_serves_every_signal_of_a_record():
    # the instants of equal angle made once (angle_grid) give each signal's map bit for bit as
    # the map that makes them itself; a grid of another resolution or record is refused
    t, theta = _ramp(4.0)
    grid = angle_grid(t, theta, revolution_samples(30))
    for o, a, p in ORDERS:
        x = a * np.cos(o * theta + p)
        assert np.array_equal(order_map(t, theta, x, max_order=30, revolutions=8, grid=grid).amplitude,
                              order_map(t, theta, x, max_order=30, revolutions=8).amplitude)
    x = np.cos(theta)
    for bad, why in ((angle_grid(t, theta, revolution_samples(60)), "samples a revolution"),
                     (angle_grid(t, 1.01 * theta, revolution_samples(30)), "another record"), ("grid", "AngleGrid")):
        with pytest.raises(SceneError, match=why):
            order_map(t, theta, x, max_order=30, revolutions=8, grid=bad)


def test_an_order_above_the_band_does_not_alias_into_it():
    """max_order 30 takes 128 samples a revolution (Nyquist order 64): order 110, were it
    sampled there unfiltered, would fold onto 128 - 110 = 18. The angle-domain FIR stops it
    (100 dB: 1e-5 of its 0.5 left), so order 18 stays empty and order 24 keeps its 1e-3."""
    t, theta = _ramp()
    x = 0.05 * np.cos(24 * theta) + 0.5 * np.cos(110 * theta)
    omap = order_map(t, theta, x, max_order=30, revolutions=8)
    assert len(omap.orders) == 8 * 128 // 2 + 1                    # 128 samples a revolution
    assert np.max(order_cut(omap, 18).amplitude) < 1e-5 * 0.5                 # measured 4.5e-7
    assert np.max(np.abs(order_cut(omap, 24).amplitude - 0.05)) < 1e-3 * 0.05


def test_a_mesh_order_lands_in_its_teeth_bin():
    """A gear of z = 97 teeth on the shaft meshes at 97 x the shaft speed: order 97, bin
    97 x revolutions of every block, at every speed of the ramp (97 x 25 Hz = 2425 Hz <
    FS / 2)."""
    t, theta = _ramp()
    x = np.cos(theta) + 0.1 * np.cos(97 * theta + 0.5)
    omap = order_map(t, theta, x, max_order=100, revolutions=4)
    high = omap.orders > 50
    peaks = omap.orders[high][np.argmax(omap.amplitude[:, high], axis=1)]
    assert np.all(peaks == 97.0)
    assert np.max(np.abs(order_cut(omap, 97).amplitude - 0.1)) < 1e-3 * 0.1


def _one_line(err: SceneError, field: str):
    assert err.path == field and "\n" not in str(err) and str(err).startswith(f"{field} = ")


def test_bad_input_refused_naming_the_field():
    t, theta = _ramp(2.0)                        # 2 s: 11 revolutions
    x = np.cos(theta)
    with pytest.raises(SceneError) as e:         # a record of fewer revolutions than a block
        order_map(t[:8000], theta[:8000], x[:8000], max_order=10, revolutions=8)
    _one_line(e.value, "time")
    with pytest.raises(SceneError) as e:         # order 0.1: 0.8 cycles in 8 revolutions
        order_map(t, theta, x, max_order=10, revolutions=8, lowest_order=0.1)
    _one_line(e.value, "revolutions")
    for kw, field in ((dict(max_order=0.0), "max_order"), (dict(max_order=10, lowest_order=-1.0), "lowest_order")):
        with pytest.raises(SceneError) as e:
            order_map(t, theta, x, revolutions=4, **kw)
        _one_line(e.value, field)
    omap = order_map(t, theta, x, max_order=10, revolutions=4)
    for bad in (0.0, -2.0):
        with pytest.raises(SceneError) as e:
            order_cut(omap, bad)
        _one_line(e.value, "order")
    # a coast-down where a run-up is assumed; then a shaft turning back
    down = theta[-1] - theta[::-1]
    with pytest.raises(SceneError) as e:
        order_map(t, down, x, max_order=10, revolutions=4)
    _one_line(e.value, "speed")
    assert order_map(t, down, x, max_order=10, revolutions=4, run_up=False).speed[0] > 0
    back = np.concatenate([theta[:100], theta[100] - (theta[100:] - theta[100])])
    with pytest.raises(SceneError) as e:
        order_map(t, back, x, max_order=10, revolutions=4)
    _one_line(e.value, "angle")
    cut = order_cut(omap, 1.0)
    with pytest.raises(SceneError) as e:
        resonance_passages(cut, [(-3.0, "torsional")])
    _one_line(e.value, "modes[0]")
    # a record from standstill (40 rad/s^2, 12.7 turns): its first interval's speed, 1e-3 rad/s,
    # would need 3.9e6 x 32 angle samples a revolution (1.6e9 in all) to stay as dense as the
    # record's 20 kHz
    with pytest.raises(SceneError) as e:
        order_map(t, 20.0 * t**2, x, max_order=10, revolutions=2, run_up=False)
    _one_line(e.value, "angle")


def test_shaft_angle_from_a_recorded_speed():
    """The trapezoidal rule integrates a linear speed exactly: the ramp's angle to round-off,
    4e5 partial sums up to 1.9e3 rad, eps x 1.9e3 = 4e-13 each, adding as a random walk:
    2.6e-10 (1e-9 asserted; measured 3.4e-12)."""
    t, theta = _ramp()
    speed = 2 * math.pi * (F0 + (F1 - F0) / T * t)
    assert np.max(np.abs(shaft_angle(t, speed) - theta)) < 1e-9
    with pytest.raises(SceneError) as e:
        shaft_angle(t[::-1], speed)
    _one_line(e.value, "time")


def test_a_simulated_run_up_through_the_mesh_resonance():
    """A torsional spur pair (tests/support/gear_pair_scene.py), gear 1 of 20 teeth driven by a
    constant torque from 50 rad/s: the chain accelerates at alpha = T / (J1 + J2 (r1/r2)^2)
    exactly (inertia relief), 100 rad/s^2 here; the mesh stiffness varies by 10 % at the tooth
    passing (k (1 + 0.1 cos(20 theta1))), damped at zeta = 0.05 of the mesh mode f_n =
    sqrt(k / m_e) / 2 pi, m_e = 1 / (r1^2/J1 + r2^2/J2): 342.3 Hz. The mesh force, tracked on
    the angle integrated from the recorded speed:g1, has its strongest order above 1 at 20 in
    every block, and the order-20 cut peaks at the passage speed 2 pi f_n / 20 = 107.5 rad/s
    within one block step (1 revolution at 107.5 rad/s: 5.9 rad/s of the ramp) plus the peak's
    delay (at most 2 ring-down times, 2 / (zeta omega_n): 1.9 rad/s of the ramp)."""
    j1, j2, r1, r2, k, zeta, alpha = 2.0, 0.5, 0.05, 0.15, 1e8, 0.05, 100.0
    me = 1.0 / (r1**2 / j1 + r2**2 / j2)
    wn = math.sqrt(k / me)
    torque = alpha * (j1 + j2 * (r1 / r2) ** 2)
    d = gear_pair(j1, j2, r1, r2, k, teeth=20, amplitudes=[0.1], damping=2 * zeta * math.sqrt(k * me),
                  roles=("rotor", "generator"), simulation={"speed": 50.0, "loads": [{"body": "g1", "value": torque}]})
    run = simulate(scene_from_dict(d), 1.0, 1e-4, ["force:m", "speed:g1"])
    theta = shaft_angle(run.time_s, run.outputs["speed:g1"])
    omap = order_map(run.time_s, theta, run.outputs["force:m"], max_order=50, revolutions=2)
    high = omap.orders > 1.5
    assert np.all(omap.orders[high][np.argmax(omap.amplitude[:, high], axis=1)] == 20.0)
    (p,) = resonance_passages(order_cut(omap, 20.0), [(wn / (2 * math.pi), "torsional")])
    assert abs(p.speed - wn / 20) <= 1e-12 * p.speed
    assert abs(p.peak_speed - p.speed) <= alpha * (2 * math.pi / p.speed) + alpha * 2 / (zeta * wn)
