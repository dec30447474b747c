"""Bad input to the loads-to-life functions (assembly.dynamics.cycles, assembly.dynamics.life):
each class the brief names (Woehler exponents <= 0, N_eq <= 0, bins not increasing, C or p
<= 0, a shaft that does not turn, non-finite samples) by hand, then random arguments of every
kind (hypothesis). A bad argument is refused by one SceneError line naming it and its value;
an accepted one gives a float >= 0 (inf where a power overflows), never NaN, never another
exception."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from assembly.dynamics.cycles import damage_equivalent_load, rainflow_cycles
from assembly.dynamics.life import bearing_life, equivalent_load, load_duration, load_revolutions, miner_damage
from assembly.errors import SceneError
from tests.support.fuzz import examples

T = np.linspace(0.0, 1.0, 11)
Y = np.sin(7.0 * T)
W = np.full(11, 3.0)
BAD_NUMBERS = [0.0, -1.0, -0.0, math.nan, math.inf, -math.inf, "3", True, None, [3.0]]


def _one_line(err: SceneError, field: str):
    assert err.path == field
    assert "\n" not in str(err) and str(err).startswith(f"{field} = ")


@pytest.mark.parametrize("bad", BAD_NUMBERS)
@pytest.mark.parametrize("call,field", [
    (lambda v: damage_equivalent_load(Y, v, 10.0), "m"),
    (lambda v: damage_equivalent_load(Y, 4.0, v), "n_eq"),
    (lambda v: equivalent_load([1.0, 2.0], [1.0, 1.0], v), "exponent"),
    (lambda v: bearing_life([1.0, 2.0], [1.0, 1.0], v, 3.0), "rating_n"),
    (lambda v: bearing_life([1.0, 2.0], [1.0, 1.0], 10.0, v), "exponent"),
    (lambda v: miner_damage([1.0], [1.0], v), "slope"),
    (lambda v: miner_damage([1.0], [1.0], 6.0, v), "torque_ref"),
    (lambda v: miner_damage([1.0], [1.0], 6.0, 1.0, v), "cycles_ref"),
])
def test_numbers_at_or_below_zero_and_not_numbers_are_refused(call, field, bad):
    with pytest.raises(SceneError) as e:
        call(bad)
    _one_line(e.value, field)


@pytest.mark.parametrize("edges", [[0.0, 0.0, 1.0], [2.0, 1.0], [0.0, math.nan, 2.0], [1.0], [], 0, -3, 10**9, 2.5,
                                   "auto", [[0.0, 1.0]]])
def test_bins_not_increasing_or_not_bins_are_refused(edges):
    for call in (lambda: load_duration(T, Y, edges), lambda: load_revolutions(T, Y, W, edges)):
        with pytest.raises(SceneError) as e:
            call()
        _one_line(e.value, "bins")


@pytest.mark.parametrize("speed", [np.zeros(11), np.r_[np.zeros(10), 5.0] * 0.0])
def test_a_shaft_that_does_not_turn_has_no_lrd(speed):
    with pytest.raises(SceneError) as e:
        load_revolutions(T, Y, speed)
    _one_line(e.value, "speed_rad_s")
    assert "does not turn" in e.value.reason


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
@pytest.mark.parametrize("call,field", [
    (lambda y: rainflow_cycles(y), "values"),
    (lambda y: damage_equivalent_load(y, 4.0, 1.0), "values"),
    (lambda y: load_duration(T, y), "values"),
    (lambda y: load_duration(y, Y), "time_s"),
    (lambda y: load_revolutions(T, Y, y), "speed_rad_s"),
    (lambda y: bearing_life(y[:2], [1.0, 1.0], 10.0), "levels"),
    (lambda y: bearing_life([1.0, 2.0], y[:2], 10.0), "revolutions"),
])
def test_non_finite_samples_are_refused_naming_the_sample(call, field, bad):
    y = np.array(Y if field != "time_s" else T)
    y[1] = bad
    with pytest.raises(SceneError) as e:
        call(y)
    _one_line(e.value, field)
    assert "sample 1 is" in e.value.reason


def test_samples_of_the_wrong_kind_are_refused():
    for bad in (None, "1 2 3", b"12", {"a": 1}, True, [[1.0, 2.0]], [], [1.0, "x"], [1j, 2.0], np.array([1j]),
                [None, 1.0], [[1.0], [2.0, 3.0]]):
        with pytest.raises(SceneError) as e:
            rainflow_cycles(bad)
        _one_line(e.value, "values")


number = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-5, 10 ** 6), st.booleans(),
                   st.none(), st.text(max_size=3), st.sampled_from([1e-300, 1e300, -0.0, 3.0, 10.0 / 3.0]))
samples = st.one_of(st.lists(st.floats(allow_nan=True, allow_infinity=True), min_size=0, max_size=12),
                    st.lists(st.floats(-1e6, 1e6), min_size=1, max_size=12).map(np.array),
                    st.lists(st.integers(-10 ** 30, 10 ** 30), max_size=5), number)
bins = st.one_of(st.integers(-2, 50), st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=5), number)


def _ok(result):
    assert isinstance(result, float) and not math.isnan(result) and result >= 0.0


@settings(max_examples=examples(150), deadline=None)
@given(values=samples, m=number, n_eq=number)
def test_random_del_arguments(values, m, n_eq):
    try:
        _ok(damage_equivalent_load(values, m, n_eq))
    except SceneError as e:
        assert e.path in ("values", "m", "n_eq") and "\n" not in str(e)


@settings(max_examples=examples(150), deadline=None)
@given(time_s=samples, values=samples, speed=samples, b=bins)
def test_random_distribution_arguments(time_s, values, speed, b):
    for call, names in ((lambda: load_duration(time_s, values, b), ("time_s", "values", "bins")),
                        (lambda: load_revolutions(time_s, values, speed, b), ("time_s", "values", "speed_rad_s",
                                                                               "bins"))):
        try:
            d = call()
        except SceneError as e:
            assert e.path in names and "\n" not in str(e)
        else:
            assert np.all(np.isfinite(d.amounts)) and np.all(d.amounts >= 0) and d.edges.size == d.levels.size + 1


@settings(max_examples=examples(150), deadline=None)
@given(levels=samples, counts=samples, a=number, b=number, c=number, d=number)
def test_random_spectrum_arguments(levels, counts, a, b, c, d):
    for call, names in ((lambda: equivalent_load(levels, counts, a), ("levels", "counts", "exponent")),
                        (lambda: bearing_life(levels, counts, a, b).l10_mrev, ("levels", "revolutions", "rating_n",
                                                                               "exponent")),
                        (lambda: miner_damage(levels, counts, a, b, c, d), ("levels", "cycles", "slope",
                                                                            "torque_ref", "cycles_ref",
                                                                            "torque_limit"))):
        try:
            _ok(call())
        except SceneError as e:
            assert e.path in names and "\n" not in str(e)
