"""OpenFAST output files (assembly.dynamics.openfast_output) against the documented formats.

* Binary: files written here by tests/support/openfast_files.py from OpenFAST's WrBinFAST
  (NWTC_IO.f90), every FileFmtID (1 with packed time, 2 and 4 compressed, 3 float64), both
  byte orders, read back to the format's precision: a compressed channel to half its
  quantisation step (0.5 + 2^-10) / ColScl (NINT of a single-precision value below 2^15),
  plus the single-precision rounding of the offset that clamping can expose (3 x 2^-24 x
  (|min| + range)); float64 channels and the time of FileFmtID 2-4 exactly.
* Two real OpenFAST files (tests/support/data/openfast/README.md): the toolbox's published
  value of FASTOutBin.outb's last GenPwr, and ElastoDyn's identity RotPwr = RotTorq x
  rotor speed (ElastoDyn.f90: RotPwr = (QDT(GeAz) + QDT(DrTr)) LSShftMxa; RotSpeed in rpm)
  on FASTOutBin_ID4.outb, to the channels' quantisation.
* Text: FAST v7 outputs in Windows-1252 with ``(kN·m)`` and ``(sec)`` (FAST_IO.f90's unit
  strings), tab or space separated; units by definition of the prefixes, the revolution and
  the degree.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.dynamics.load_series import read_openfast_out
from assembly.dynamics.openfast_output import parse_unit, read_output
from assembly.errors import SceneError
from tests.support.openfast_files import DATA, FAST7_HEADER, OPENFAST_HEADER, out_text, outb_bytes, pack_scales

FIELD = "simulation.loads[0].openfast"
NAMES = ["Time", "RotTorq", "GenTq", "RotSpeed", "BldPitch1"]
UNITS = ["(s)", "(kN-m)", "(kN-m)", "(rpm)", "(deg)"]


def channels(nt=400, dt=0.0125):
    """A plausible 5 MW record: torque with a 3P ripple, a noisy generator torque, a slowly
    varying speed and a constant pitch (a constant channel is a special case of the packing)."""
    t = np.arange(nt) * dt
    rng = np.random.default_rng(7)
    data = np.column_stack([4180.0 + 310.0 * np.sin(2 * math.pi * 0.6 * t), 43.09 + 0.4 * rng.normal(size=nt),
                            12.1 + 0.05 * np.cos(0.3 * t), np.full(nt, 2.5)])
    return t, data


def bound(data, scl=None):
    """Per channel: the decoding error a compressed channel may carry (module notes)."""
    lo, hi = data.min(axis=0), data.max(axis=0)
    scl = scl if scl is not None else pack_scales(data)[0].astype(float)
    return (0.5 + 2 ** -10) / scl + 3 * 2 ** -24 * (np.abs(lo) + (hi - lo))


@pytest.mark.parametrize("order", ["<", ">"], ids=["little-endian", "big-endian"])
@pytest.mark.parametrize("file_id", [1, 2, 3, 4])
def test_binary_round_trip_to_the_formats_precision(tmp_path, file_id, order):
    t, data = channels()
    p = tmp_path / "run.outb"
    p.write_bytes(outb_bytes(NAMES, UNITS, t, data, file_id, order=order))
    out = read_output(p, FIELD)
    assert out.names == tuple(NAMES) and out.units == tuple(u[1:-1] for u in UNITS) and out.lines is None
    err = np.abs(out.rows[:, 1:] - data)
    if file_id == 3:
        np.testing.assert_array_equal(out.rows[:, 1:], data)                  # float64: stored as is
    else:
        assert np.all(err <= bound(data)), (err.max(axis=0), bound(data))
        # and not better than a 16-bit code can be: the ripple's error reaches a good part of half a step
        step = (data.max(axis=0) - data.min(axis=0)) / 65535
        assert err[:, 0].max() > 0.2 * step[0]
    if file_id == 1:                  # time packed into int32 over [-65536, 65535]: half a step of 131071
        half = 0.5 * (t[-1] - t[0]) / 131071
        assert np.abs(out.rows[:, 0] - t).max() <= half * (1 + 1e-6)
    else:                             # TimeOut1 + i TimeIncr
        np.testing.assert_allclose(out.rows[:, 0], t[0] + (t[1] - t[0]) * np.arange(len(t)), rtol=0, atol=0)


def test_binary_series_in_si(tmp_path):
    t, data = channels()
    p = tmp_path / "run.outb"
    p.write_bytes(outb_bytes(NAMES, UNITS, t, data, 3))
    tq = read_openfast_out(p, "rottorq", FIELD, expect="N m")           # case-insensitive name
    np.testing.assert_array_equal(tq.values, data[:, 0] * 1e3)           # 1 kN m = 1000 N m
    w = read_openfast_out(p, "RotSpeed", FIELD)
    np.testing.assert_allclose(w.values, data[:, 2] * 2 * math.pi / 60, rtol=1e-15)   # rpm -> rad/s
    assert (tq.unit, w.unit, tq.name) == ("N m", "rad/s", "RotTorq")


def test_real_openfast_file_fmt2_matches_the_toolbox_value():
    # openfast_toolbox's test reads GenPwr's last value of this file as 40.57663190807828 kW;
    # two decoders of the same int16 code and float32 scale must agree to round-off
    s = read_openfast_out(DATA / "FASTOutBin.outb", "GenPwr", FIELD)
    assert s.unit == "W" and len(s.time_s) == 201
    assert s.values[-1] == pytest.approx(40.57663190807828e3, rel=1e-13)
    np.testing.assert_allclose(s.time_s, 0.005 * np.arange(201), rtol=1e-12, atol=1e-15)


def test_real_openfast_file_fmt4_obeys_elastodyns_power_identity():
    out = read_output(DATA / "FASTOutBin_ID4.outb", FIELD)
    assert out.kind == "binary FileFmtID 4" and out.rows.shape == (11, 236)
    col = {n: out.channel(n, FIELD) for n in ("RotTorq", "RotSpeed", "RotPwr")}
    assert [out.units[col[n]] for n in col] == ["kN-m", "rpm", "kW"]
    T, n, P = (out.rows[:, col[k]] for k in ("RotTorq", "RotSpeed", "RotPwr"))
    qT, qn, qP = (bound(out.rows[:, [col[k]]], 65535 / np.ptp(out.rows[:, [col[k]]], axis=0) / (1 + 1e-4))[0]
                  for k in ("RotTorq", "RotSpeed", "RotPwr"))
    k = 2 * math.pi / 60
    tol = qP + np.abs(n) * k * qT + np.abs(T) * k * qn + k * qT * qn
    assert np.all(np.abs(P - T * n * k) <= tol), np.abs(P - T * n * k) / tol
    # a name the file gives twice (RootFxc1, columns 27 and 28) with equal values is read
    assert out.channel("RootFxc1", FIELD) == out.names.index("RootFxc1")


@pytest.mark.parametrize("delim", ["\t", "  "], ids=["tabs", "spaces"])
def test_fast7_text_in_windows_1252(tmp_path, delim):
    # FAST v7 writes (sec) and (kN·m) with cp1252's middle dot, byte 0xB7: not UTF-8
    rows = [(0.0, 4000.0, 12.1, 43.1), (0.05, 4100.0, 12.0, 43.2), (0.1, 3900.0, 11.9, 42.9)]
    text = out_text(["Time", "RotTorq", "RotSpeed", "GenTq"], ["(sec)", "(kN·m)", "(rpm)", "(kN·m)"], rows,
                    header=FAST7_HEADER, delim=delim)
    p = tmp_path / "fast7.out"
    p.write_bytes(text.encode("cp1252"))
    with pytest.raises(UnicodeDecodeError):
        p.read_bytes().decode("utf-8")                                      # the case this test is about
    s = read_openfast_out(p, "GenTq", FIELD, expect="N m")
    np.testing.assert_allclose(s.values, [43.1e3, 43.2e3, 42.9e3], rtol=1e-15)
    np.testing.assert_allclose(s.time_s, [0.0, 0.05, 0.1], rtol=1e-15)
    assert s.unit == "N m"
    p.write_text(text, encoding="utf-8")                                    # the same file saved as UTF-8
    assert np.array_equal(read_openfast_out(p, "GenTq", FIELD).values, s.values)


@pytest.mark.parametrize("unit,si,factor", [
    ("N-m", "N m", 1.0), ("kN-m", "N m", 1e3), ("MN-m", "N m", 1e6), ("N·m", "N m", 1.0), ("kN·m", "N m", 1e3),
    ("kN*m", "N m", 1e3), ("kN m", "N m", 1e3), ("kNm", "N m", 1e3), ("Nm", "N m", 1.0),
    ("N", "N", 1.0), ("kN", "N", 1e3), ("MN", "N", 1e6), ("W", "W", 1.0), ("kW", "W", 1e3), ("MW", "W", 1e6),
    ("s", "s", 1.0), ("sec", "s", 1.0), ("rpm", "rad/s", 2 * math.pi / 60), ("rad/s", "rad/s", 1.0),
    ("deg/s", "rad/s", math.pi / 180), ("deg/sec", "rad/s", math.pi / 180), ("deg", "rad", math.pi / 180),
    ("rad", "rad", 1.0), ("deg/sec^2", "rad/s^2", math.pi / 180), ("m/sec", "m/s", 1.0), ("-", "-", 1.0),
])
def test_units_by_definition(unit, si, factor):
    # SI prefixes k = 1e3, M = 1e6; 1 rev = 2 pi rad; 1 deg = pi / 180 rad
    assert parse_unit(f"({unit})") == parse_unit(unit) == (si, pytest.approx(factor, rel=1e-15))


@pytest.mark.parametrize("unit", ["mN-m", "lbf-ft", "kN-mm", "kn-m", "INVALID", "", "(kN-m"])
def test_units_not_read(unit):
    assert parse_unit(unit) is None                          # milli and case slips are not guessed


def test_text_with_a_unit_holding_a_space(tmp_path):
    p = tmp_path / "run.out"
    p.write_text(OPENFAST_HEADER + "Time  GenTq\n(s)  (kN m)\n0.0  1.5\n1.0  2.5\n", encoding="utf-8")
    np.testing.assert_allclose(read_openfast_out(p, "GenTq", FIELD, expect="N m").values, [1.5e3, 2.5e3])


def test_a_repeated_channel_name_is_read_only_when_its_columns_agree(tmp_path):
    p = tmp_path / "run.out"
    p.write_text(out_text(["Time", "GenTq", "GenTq"], ["(s)", "(kN-m)", "(kN-m)"], [(0.0, 1.0, 1.0), (1.0, 2.0, 2.0)]))
    np.testing.assert_allclose(read_openfast_out(p, "GenTq", FIELD).values, [1e3, 2e3])
    p.write_text(out_text(["Time", "GenTq", "GenTq"], ["(s)", "(kN-m)", "(kN-m)"], [(0.0, 1.0, 1.0), (1.0, 2.0, 2.5)]))
    with pytest.raises(SceneError, match="channel 'GenTq' appears 2 times, with different values"):
        read_openfast_out(p, "GenTq", FIELD)
