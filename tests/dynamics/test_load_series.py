"""Load series of the time-domain simulation (assembly.dynamics.load_series) against their
definitions.

* Series: linear interpolation between table points, first / last value held outside
  (np.interp); hand values from ``y_i + (y_{i+1} - y_i) (t - t_i) / (t_{i+1} - t_i)``.
* OpenFAST units to SI by definition: 1 kN m = 1e3 N m, 1 rpm = 2 pi rad / 60 s,
  1 deg = pi / 180 rad.
* HSS brake: ElastoDyn HSSBrMode 1 (Jonkman, FAST User's Guide; ElastoDyn source: frac 0 for
  t < THSSBrDp, (t - THSSBrDp) / HSSBrDT on the ramp, 1 after).
* Gearbox efficiency: ElastoDyn GBoxEffFac = GBoxEff ** sign(previous LSS torque), friction
  factor 1 / GBoxEffFac - 1. The value used, 94.4 %, is the NREL 5 MW turbine's generator
  efficiency (Jonkman et al. 2009, NREL/TP-500-38060), taken as a plausible efficiency: that
  turbine's own ElastoDyn model has GBoxEff = 100 %.
Every error test checks the scene path (``field``) appears in the message.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from assembly.dynamics.load_series import (
    Series,
    brake_torque,
    constant,
    efficiency_factor,
    file_history,
    make_series,
    ramp,
    range_warning,
    read_csv,
    read_openfast_out,
)
from assembly.errors import SceneError
from tests.support.openfast_files import out_text

FIELD = "simulation.loads[0].table"


# ---------------------------------------------------------------- Series / make_series

def test_series_interpolates_between_points_and_holds_ends():
    s = make_series([0.0, 1.0, 3.0], [2.0, 4.0, -2.0], "torque", "N m", FIELD)
    # between points: y_i + (y_{i+1} - y_i) (t - t_i) / (t_{i+1} - t_i)
    assert s(0.5) == pytest.approx(2.0 + 2.0 * 0.5)
    assert s(2.0) == pytest.approx(4.0 - 6.0 * 0.5)
    assert s(1.0) == 4.0                                                  # on a table point
    # beyond the table: the first / last value is held
    assert s(-5.0) == 2.0 and s(10.0) == -2.0
    assert isinstance(s(0.5), float)
    np.testing.assert_allclose(s(np.array([-1.0, 0.5, 2.0, 4.0])), [2.0, 3.0, 1.0, -2.0])


def test_series_is_frozen_and_read_only():
    t, y = np.array([0.0, 1.0]), np.array([1.0, 2.0])
    s = make_series(t, y, "torque", "N m", FIELD)
    t[0] = -1.0                                                           # the series holds copies
    assert s.time_s[0] == 0.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.name = "other"
    with pytest.raises(ValueError):
        s.values[0] = 5.0


def test_single_point_series_is_constant():
    s = make_series([2.0], [7.0], "torque", "N m", FIELD)
    assert s(0.0) == s(2.0) == s(9.0) == 7.0


@pytest.mark.parametrize("t,y,words", [
    ([], [], "no data rows"),
    ([0.0, 1.0], [1.0], "2 times but 1 values"),
    ([0.0, math.nan], [1.0, 2.0], "not finite"),
    ([0.0, 1.0], [1.0, math.inf], "not finite"),
    ([0.0, 0.1, 0.3, 0.2], [0.0] * 4, "time 0.2 s at row 3 does not increase (previous 0.3 s)"),
    ([0.0, 0.5, 0.5], [0.0] * 3, "time 0.5 s at row 2 does not increase (previous 0.5 s)"),
])
def test_make_series_refuses_bad_tables(t, y, words):
    with pytest.raises(SceneError) as err:
        make_series(t, y, "torque", "N m", FIELD)
    assert FIELD in str(err.value) and words in str(err.value)


def test_constant():
    s = constant(1.5e6, "rotor torque", "N m")
    assert s(-1.0) == s(0.0) == s(1e4) == 1.5e6 and s.unit == "N m"
    with pytest.raises(SceneError) as err:
        constant(math.nan, "rotor torque", "N m", field="simulation.loads[1].value")
    assert "simulation.loads[1].value" in str(err.value)


# ---------------------------------------------------------------- ramp

def test_ramp_values():
    s = ramp(100.0, 300.0, 2.0, 6.0, "torque", "N m", FIELD)
    assert s(0.0) == 100.0                                                # before t_start
    assert s(2.0) == 100.0                                                # at t_start
    assert s(4.0) == pytest.approx(200.0)                                 # mid: (100 + 300) / 2
    assert s(5.0) == pytest.approx(100.0 + 200.0 * 3.0 / 4.0)
    assert s(6.0) == 300.0                                                # at t_end
    assert s(60.0) == 300.0                                               # held after


def test_step_is_a_short_ramp():
    dt = 1e-3
    s = ramp(0.0, 1.0, 1.0, 1.0 + dt, "torque", "N m", FIELD)
    assert s(1.0) == 0.0 and s(1.0 + dt) == 1.0 and s(1.0 + dt / 2) == pytest.approx(0.5)


@pytest.mark.parametrize("t_start,t_end", [(1.0, 1.0), (2.0, 1.0), (0.0, math.nan), (math.inf, 1.0)])
def test_ramp_refuses_non_increasing_times(t_start, t_end):
    with pytest.raises(SceneError) as err:
        ramp(0.0, 1.0, t_start, t_end, "torque", "N m", FIELD)
    assert FIELD + ".t_end" in str(err.value)


# ---------------------------------------------------------------- CSV

GOOD_CSV = """# rotor torque from a site measurement
# time in s, torque in kN m
 time , torque_kNm , speed
0.0, 1.0, 10
1.0, 3.0, 11

2.0, 2.0, 12
"""


def test_read_csv_interpolates_and_scales(tmp_path):
    p = tmp_path / "loads.csv"
    p.write_text(GOOD_CSV)
    s = read_csv(p, "torque_kNm", scale=1e3, field=FIELD)                 # kN m -> N m
    np.testing.assert_array_equal(s.time_s, [0.0, 1.0, 2.0])
    np.testing.assert_allclose(s.values, [1e3, 3e3, 2e3])
    assert s(0.5) == pytest.approx(2e3) and s(-1.0) == 1e3 and s(5.0) == 2e3
    assert s.name == "torque_kNm"
    speed = read_csv(p, "speed", time_column="time", field=FIELD)         # scale 1 by default
    assert speed(1.5) == pytest.approx(11.5)


def test_read_csv_other_time_column(tmp_path):
    p = tmp_path / "loads.csv"
    p.write_text("t_s,load\n0,5\n2,9\n")
    assert read_csv(p, "load", time_column="t_s", field=FIELD)(1.0) == pytest.approx(7.0)


BAD_CSV = {
    "missing column": ("time,torque\n0,1\n1,2\n", "speed", "time", "no column 'speed'; the file has time, torque"),
    "missing time column": ("t,speed\n0,1\n1,2\n", "speed", "time", "no column 'time'; the file has t, speed"),
    "text cell": ("time,speed\n0,1\n1,fast\n", "speed", "time", "line 3, column 'speed': 'fast' is not a number"),
    "text time": ("time,speed\n0,1\nlater,2\n", "speed", "time", "'later' is not a number"),
    "empty cell": ("time,speed\n0,1\n1,\n", "speed", "time", "'' is not a number"),
    "decreasing time": ("time,speed\n0,1\n2,2\n1,3\n", "speed", "time",
                        "time 1.0 s at line 4 does not increase (previous 2.0 s)"),
    "repeated time": ("# c\ntime,speed\n0,1\n1,2\n1,3\n", "speed", "time",
                      "time 1.0 s at line 5 does not increase (previous 1.0 s)"),
    "empty data": ("# only a header\ntime,speed\n", "speed", "time", "no data rows"),
    "empty file": ("", "speed", "time", "no header row"),
    "short row": ("time,speed\n0,1\n1\n", "speed", "time", "line 3 has 1 cells, the header 2"),
    "nan value": ("time,speed\n0,1\n1,nan\n", "speed", "time", "not finite"),
    "missing file": (None, "speed", "time", "file not found"),
}


@pytest.mark.parametrize("case", sorted(BAD_CSV))
def test_read_csv_refuses_bad_files(tmp_path, case):
    text, column, time_column, words = BAD_CSV[case]
    p = tmp_path / "loads.csv"
    if text is not None:
        p.write_text(text)
    with pytest.raises(SceneError) as err:
        read_csv(p, column, time_column=time_column, field=FIELD)
    assert str(err.value).startswith(FIELD + " = ") and words in str(err.value)


def test_read_csv_refuses_non_finite_scale(tmp_path):
    p = tmp_path / "loads.csv"
    p.write_text("time,speed\n0,1\n")
    with pytest.raises(SceneError) as err:
        read_csv(p, "speed", scale=math.inf, field=FIELD)
    assert FIELD + ".scale" in str(err.value)


def test_read_csv_refuses_unreadable_file(tmp_path):
    p = tmp_path / "loads.csv"
    p.write_bytes(b"time,speed\n\xff\xfe\x00\x81\n")                       # not UTF-8
    with pytest.raises(SceneError) as err:
        read_csv(p, "speed", field=FIELD)
    assert FIELD in str(err.value) and "cannot read" in str(err.value)


# ---------------------------------------------------------------- OpenFAST .out

OF_FIELD = "simulation.loads[0].openfast"
def _out(tmp_path, names, units, rows, name="run.out"):
    p = tmp_path / name
    p.write_text(out_text(names, units, rows))
    return p


def test_openfast_rottorq_and_rotspeed_in_si(tmp_path):
    rows = [(0.0, 4000.0, 12.1), (0.05, 4100.0, 12.0), (0.1, 3900.0, 11.9)]
    p = _out(tmp_path, ["Time", "RotTorq", "RotSpeed"], ["(s)", "(kN-m)", "(rpm)"], rows)
    tq = read_openfast_out(p, "RotTorq", field=OF_FIELD)
    np.testing.assert_allclose(tq.time_s, [0.0, 0.05, 0.1])
    np.testing.assert_allclose(tq.values, [4.0e6, 4.1e6, 3.9e6])          # 1 kN m = 1000 N m
    assert tq.unit == "N m" and tq.name == "RotTorq"
    assert tq(0.025) == pytest.approx(4.05e6)
    w = read_openfast_out(p, "rotspeed", field=OF_FIELD)                  # case-insensitive name
    np.testing.assert_allclose(w.values, np.array([12.1, 12.0, 11.9]) * 2 * math.pi / 60)   # rpm -> rad/s
    assert w.unit == "rad/s" and w.name == "RotSpeed"


@pytest.mark.parametrize("unit,si,factor", [
    ("(s)", "s", 1.0), ("(N-m)", "N m", 1.0), ("(kN-m)", "N m", 1e3), ("(MN-m)", "N m", 1e6),
    ("(N)", "N", 1.0), ("(kN)", "N", 1e3), ("(MN)", "N", 1e6), ("(rpm)", "rad/s", 2 * math.pi / 60),
    ("(rad/s)", "rad/s", 1.0), ("(deg/s)", "rad/s", math.pi / 180), ("(deg)", "rad", math.pi / 180),
    ("(rad)", "rad", 1.0), ("(kW)", "W", 1e3), ("(W)", "W", 1.0), ("(-)", "-", 1.0),
])
def test_openfast_unit_table(tmp_path, unit, si, factor):
    # factors by the definitions of the SI prefixes, the revolution (2 pi rad) and the degree
    p = _out(tmp_path, ["Time", "Chan"], ["(s)", unit], [(0.0, 2.5), (1.0, -4.0)])
    s = read_openfast_out(p, "Chan", field=OF_FIELD)
    np.testing.assert_allclose(s.values, np.array([2.5, -4.0]) * factor, rtol=1e-14)
    assert s.unit == si


BAD_OUT = {
    "unknown unit": (["Time", "GenTq"], ["(s)", "(lbf-ft)"], [(0.0, 1.0), (1.0, 2.0)], "run.out",
                     "'GenTq' has unit (lbf-ft), which flexgear does not read"),
    "time unit": (["Time", "GenTq"], ["(min)", "(kN-m)"], [(0.0, 1.0), (1.0, 2.0)], "run.out",
                  "'Time' has unit (min)"),
    "time not a time": (["Time", "GenTq"], ["(rpm)", "(kN-m)"], [(0.0, 1.0), (1.0, 2.0)], "run.out",
                        "the first channel 'Time' has unit (rpm): not a time"),
    "missing column": (["Time", "RotTorq", "RotSpeed"], ["(s)", "(kN-m)", "(rpm)"], [(0.0, 1.0, 2.0)], "run.out",
                       "no channel 'GenTq'; the file has Time, RotTorq, RotSpeed"),
    "non-monotonic": (["Time", "GenTq"], ["(s)", "(kN-m)"], [(0.0, 1.0), (0.2, 2.0), (0.1, 3.0)], "run.out",
                      "time 0.1 s at line 11 does not increase (previous 0.2 s)"),
    "repeated time": (["Time", "GenTq"], ["(s)", "(kN-m)"], [(0.0, 1.0), (0.0, 2.0)], "run.out",
                      "does not increase"),
    "text cell": (["Time", "GenTq"], ["(s)", "(kN-m)"], [(0.0, 1.0), (0.1, "abc")], "run.out",
                  "line 10, channel 'GenTq': 'abc' is not a number"),
    "nan row": (["Time", "GenTq"], ["(s)", "(kN-m)"], [(0.0, 1.0), (0.1, "NaN")], "run.out",
                "value nan at line 10 is not finite"),
    "short row": (["Time", "GenTq"], ["(s)", "(kN-m)"], [(0.0, 1.0), (0.1,)], "run.out", "1 values, 2 channels"),
    "unit count": (["Time", "GenTq"], ["(s)"], [(0.0, 1.0)], "run.out", "2 channel names but 1 units"),
    "no data": (["Time", "GenTq"], ["(s)", "(kN-m)"], [], "run.out", "no data rows"),
}


@pytest.mark.parametrize("case", sorted(BAD_OUT))
def test_openfast_refuses_bad_files(tmp_path, case):
    names, units, rows, fname, words = BAD_OUT[case]
    p = _out(tmp_path, names, units, rows, fname)
    with pytest.raises(SceneError) as err:
        read_openfast_out(p, "GenTq", field=OF_FIELD)
    assert str(err.value).startswith(OF_FIELD + " = ") and words in str(err.value)


def test_openfast_refuses_damaged_binary_missing_and_headerless(tmp_path):
    b = tmp_path / "run.outb"
    b.write_bytes(b"\x02\x00\x05\x00\x00\x00" + bytes(range(256)))      # FileFmtID 2, 5 channels, then noise
    cases = [(b, "truncated"), (tmp_path / "absent.out", "file not found")]
    h = tmp_path / "headerless.out"
    h.write_text("0.0 1.0\n0.1 2.0\n")
    cases.append((h, "no channel line starting with 'Time'"))
    for path, words in cases:
        with pytest.raises(SceneError) as err:
            read_openfast_out(path, "RotTorq", field=OF_FIELD)
        assert OF_FIELD in str(err.value) and words in str(err.value)


COLUMN = "simulation.loads[0].column"


@pytest.mark.parametrize("unit,expect,words", [
    ("(kW)", "N m", "unit (kW) is a power, not a torque"),
    ("(W)", "N m", "unit (W) is a power, not a torque"),
    ("(rpm)", "N m", "unit (rpm) is an angular speed, not a torque"),
    ("(deg)", "N m", "unit (deg) is an angle, not a torque"),
    ("(m/s)", "N m", "unit (m/s) is a speed, not a torque"),
    ("(-)", "N m", "unit (-) is dimensionless, not a torque"),
    ("(kN)", "N m", "unit (kN) is a force, not a torque"),
    ("(kN-m)", "N", "unit (kN-m) is a torque, not a force"),
])
def test_openfast_channel_of_the_wrong_kind_is_refused_naming_the_column(tmp_path, unit, expect, words):
    p = _out(tmp_path, ["Time", "Chan"], ["(s)", unit], [(0.0, 1.0), (1.0, 2.0)])
    with pytest.raises(SceneError) as err:
        read_openfast_out(p, "Chan", field=OF_FIELD, expect=expect, column_field=COLUMN)
    assert str(err.value) == f"{COLUMN} = 'Chan': {words}"


@pytest.mark.parametrize("unit,expect,factor", [
    ("(N-m)", "N m", 1.0), ("(kN-m)", "N m", 1e3), ("(MN-m)", "N m", 1e6), ("(N·m)", "N m", 1.0),
    ("(kN·m)", "N m", 1e3), ("(N)", "N", 1.0), ("(kN)", "N", 1e3), ("(MN)", "N", 1e6)])
def test_openfast_channel_of_the_right_kind_is_converted(tmp_path, unit, expect, factor):
    p = _out(tmp_path, ["Time", "Chan"], ["(s)", unit], [(0.0, 2.5), (1.0, -4.0)])
    s = read_openfast_out(p, "Chan", field=OF_FIELD, expect=expect, column_field=COLUMN)
    np.testing.assert_allclose(s.values, np.array([2.5, -4.0]) * factor, rtol=1e-15)   # SI prefixes
    assert s.unit == expect


# ---------------------------------------------------------------- file histories: window, offset, range

class Src:
    """A table's file keys, as TimeLoad and Generator carry them."""

    def __init__(self, **kw):
        self.__dict__.update({"table": None, "openfast": None, "column": None, "time_column": "time", "scale": 1.0,
                              "time_offset": 0.0, "time_window": None, **kw})


def _ramp_file(tmp_path):
    # y = 100 + 10 t at t = 0, 1, ..., 10 s: linear, so any interpolated value is 100 + 10 t exactly
    rows = [(float(t), 100.0 + 10.0 * t) for t in range(11)]
    return _out(tmp_path, ["Time", "GenTq"], ["(s)", "(kN-m)"], rows)


def test_time_window_cuts_and_interpolates_the_ends(tmp_path):
    _ramp_file(tmp_path)
    s = file_history(Src(openfast="run.out", column="GenTq", time_window=(2.5, 7.25)), "simulation.generator",
                     tmp_path, "N m")
    np.testing.assert_allclose(s.time_s, [2.5, 3, 4, 5, 6, 7, 7.25])
    np.testing.assert_allclose(s.values, (100.0 + 10.0 * s.time_s) * 1e3, rtol=1e-14)
    assert s(0.0) == pytest.approx(125e3) and s(9.0) == pytest.approx(172.5e3)       # ends held


def test_time_offset_moves_file_time_to_run_time(tmp_path):
    _ramp_file(tmp_path)
    s = file_history(Src(openfast="run.out", column="GenTq", time_offset=4.0, time_window=(4.0, 9.0), scale=-2.0),
                     "simulation.loads[0]", tmp_path, "N m")
    # run time t is file time t + 4; scale after the kN-m -> N m conversion
    for t in (0.0, 0.3, 2.0, 5.0):
        assert s(t) == pytest.approx(-2.0 * 1e3 * (100.0 + 10.0 * (t + 4.0)), rel=1e-14)
    assert "time_offset 4 s" in s.origin and "run.out" in s.origin and "GenTq" in s.origin


def test_csv_history_takes_window_and_offset_too(tmp_path):
    (tmp_path / "t.csv").write_text("time,T\n0,0\n10,1000\n", encoding="utf-8")
    s = file_history(Src(table="t.csv", column="T", time_offset=-1.0, time_window=(2.0, 4.0)), "p", tmp_path, "N m")
    np.testing.assert_allclose(s.time_s, [3.0, 5.0])
    np.testing.assert_allclose(s.values, [200.0, 400.0])


@pytest.mark.parametrize("window,words", [((5.0, 5.0), "start < end"), ((6.0, 2.0), "start < end"),
                                          ((-1.0, 5.0), "from 0 to 10 s"), ((2.0, 10.5), "from 0 to 10 s")])
def test_bad_time_window_is_refused(tmp_path, window, words):
    _ramp_file(tmp_path)
    with pytest.raises(SceneError) as err:
        file_history(Src(openfast="run.out", column="GenTq", time_window=window), "simulation.loads[2]", tmp_path,
                     "N m")
    assert str(err.value).startswith("simulation.loads[2].time_window = ") and words in str(err.value)


def test_openfast_history_refuses_a_time_column(tmp_path):
    _ramp_file(tmp_path)
    with pytest.raises(SceneError, match=r"^simulation.loads\[0\].time_column = 't': "):
        file_history(Src(openfast="run.out", column="GenTq", time_column="t"), "simulation.loads[0]", tmp_path, "N m")


def test_range_warning_names_both_ranges(tmp_path):
    _ramp_file(tmp_path)
    s = file_history(Src(openfast="run.out", column="GenTq", time_offset=-1.0), "simulation.loads[0]", tmp_path,
                     "N m")                                    # rows at run time 1 .. 11 s
    assert range_warning(s, 11.0) == ("simulation.loads[0] (run.out, channel GenTq, time_offset -1 s): the run (0 "
                                      "to 11 s) leaves the data's time range (1 to 11 s of run time); its first "
                                      "value is held from 0 to 1 s")
    w = range_warning(s, 12.5)
    assert "first value is held from 0 to 1 s and its last value is held from 11 to 12.5 s" in w
    inside = file_history(Src(openfast="run.out", column="GenTq"), "simulation.loads[0]", tmp_path, "N m")
    assert range_warning(inside, 10.0) is None and range_warning(inside, 10.0 + 1e-12) is None
    assert range_warning(inside, 10.001) is not None
    assert range_warning(constant(1.0, "c", "N m"), 50.0) is None          # a constant has no range


# ---------------------------------------------------------------- HSS brake

def test_brake_torque_ramp():
    # ElastoDyn HSSBrMode 1: THSSBrDp = 10 s, HSSBrDT = 0.6 s, HSSBrTqF = 28116.2 N m (the NREL
    # 5 MW full HSS brake torque, Jonkman et al. 2009; any positive value would do)
    dp, dt, full = 10.0, 0.6, 28116.2
    assert brake_torque(0.0, dp, dt, full) == 0.0                         # before deployment
    assert brake_torque(dp, dp, dt, full) == 0.0                          # ramp starts at 0
    assert brake_torque(dp + dt / 2, dp, dt, full) == pytest.approx(full / 2)   # mid-ramp
    assert brake_torque(dp + dt / 4, dp, dt, full) == pytest.approx(full / 4)
    assert brake_torque(dp + dt, dp, dt, full) == pytest.approx(full)     # ramp end
    assert brake_torque(dp + 100.0, dp, dt, full) == full                 # held
    q = brake_torque(np.array([0.0, dp + dt / 2, dp + 5.0]), dp, dt, full)
    np.testing.assert_allclose(q, [0.0, full / 2, full])
    assert isinstance(brake_torque(1.0, dp, dt, full), float)


def test_brake_torque_instant():
    # HSSBrDT = 0: full torque from the deployment time on (THSSBrFl = THSSBrDp)
    assert brake_torque(4.999, 5.0, 0.0, 1e4) == 0.0
    assert brake_torque(5.0, 5.0, 0.0, 1e4) == 1e4
    assert brake_torque(7.0, 5.0, 0.0, 1e4) == 1e4


@pytest.mark.parametrize("args,key", [((1.0, -0.1, 1e4), "ramp_time"), ((1.0, 0.5, -1.0), "full_torque"),
                                      ((math.nan, 0.5, 1.0), "deploy_time"), ((1.0, math.inf, 1.0), "ramp_time"),
                                      ((1.0, 0.5, math.nan), "full_torque")])
def test_brake_torque_refuses_bad_settings(args, key):
    with pytest.raises(SceneError) as err:
        brake_torque(0.0, *args, field="simulation.brake")
    assert f"simulation.brake.{key}" in str(err.value)


# ---------------------------------------------------------------- gearbox efficiency

def test_efficiency_factor_nrel_5mw():
    eta = 0.944                                   # a plausible efficiency (module notes); factor by definition
    assert efficiency_factor(eta, 1.0) == pytest.approx(1 / 0.944 - 1, rel=1e-14)   # rotor -> generator
    assert efficiency_factor(eta, 0.0) == pytest.approx(1 / 0.944 - 1, rel=1e-14)   # >= 0 counts as forward
    assert efficiency_factor(eta, -3.0e6) == pytest.approx(0.944 - 1, rel=1e-14)    # generator -> rotor
    # forward the gearbox passes the generator-side torque divided by eta
    assert 1000.0 * (1 + efficiency_factor(eta, 1.0)) == pytest.approx(1000.0 / eta)
    assert efficiency_factor(1.0, 1.0) == efficiency_factor(1.0, -1.0) == 0.0       # lossless


@pytest.mark.parametrize("eta", [0.0, -0.5, 1.0001, 94.4, math.nan, math.inf])
def test_efficiency_factor_refuses_out_of_range(eta):
    with pytest.raises(SceneError) as err:
        efficiency_factor(eta, 1.0)
    assert "simulation.gearbox_efficiency" in str(err.value)


def test_series_is_exported_type():
    assert isinstance(constant(0.0, "x", "-"), Series)
