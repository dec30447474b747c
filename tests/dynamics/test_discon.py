"""A DISCON controller library called through its swap array (assembly.dynamics.discon): ROSCO's
compiled controller with its NREL 5 MW DISCON.IN, the input file's own numbers as the answer.

At the rated generator speed of DISCON.IN (PC_RefSpd = VS_RefSpd = 122.90967 rad/s) and
11.4 m/s its first torque demand is VS_RtTq = 43 093.51876 N m, in float32 (the swap array's
type: relative 2^-24). The pitch demand starts from the measured 0 and stays within the
pitch limits of DISCON.IN (PC_MinPit 0 ... PC_MaxPit 1.5708 rad).
"""
from __future__ import annotations

import subprocess
import sys

import pytest

from assembly.dynamics.discon import Discon
from assembly.dynamics.rosco_data import rosco_file, rosco_root
from assembly.errors import SceneError

pytest.importorskip("rosco", reason="the rosco package (turbine extra) is not installed")
LIB = "rosco/lib/libdiscon.so"
INFILE = "Examples/Test_Cases/NREL-5MW/DISCON.IN"
VS_RTTQ, REF_SPEED = 43093.51876, 122.90967     # N m, rad/s: DISCON.IN
F32 = 2.0 ** -24


def test_rosco_at_rated_demands_the_rated_torque(tmp_path):
    c = Discon(rosco_file(LIB), rosco_file(INFILE), workdir=tmp_path)
    try:
        outs = [c.step(k * 0.00625, 0.00625, REF_SPEED, REF_SPEED / 97.0, 0.0, VS_RTTQ, 11.4) for k in range(8)]
    finally:
        c.close()
    assert abs(outs[0].generator_torque - VS_RTTQ) <= 2 * F32 * VS_RTTQ
    assert all(0.0 <= o.pitch <= 1.5708 for o in outs)
    assert c.calls == 8 and c.times == [k * 0.00625 for k in range(8)]


def test_two_controllers_keep_their_own_state(tmp_path):
    # each loads a private copy of the library: a second controller starts from its first call
    a = Discon(rosco_file(LIB), rosco_file(INFILE), workdir=tmp_path)
    b = Discon(rosco_file(LIB), rosco_file(INFILE), workdir=tmp_path)
    try:
        for k in range(5):
            a.step(k * 0.00625, 0.00625, REF_SPEED, REF_SPEED / 97.0, 0.0, VS_RTTQ, 11.4)
        first_b = b.step(0.0, 0.00625, REF_SPEED, REF_SPEED / 97.0, 0.0, VS_RTTQ, 11.4)
        first_a = Discon(rosco_file(LIB), rosco_file(INFILE), workdir=tmp_path)
        ref = first_a.step(0.0, 0.00625, REF_SPEED, REF_SPEED / 97.0, 0.0, VS_RTTQ, 11.4)
        first_a.close()
    finally:
        a.close()
        b.close()
    assert (first_b.generator_torque, first_b.pitch) == (ref.generator_torque, ref.pitch)


@pytest.mark.parametrize("what", ["library", "input"])
def test_a_missing_file_is_one_line_naming_the_field(tmp_path, what):
    lib, inp = rosco_file(LIB), rosco_file(INFILE)
    args = (tmp_path / "nope.so", inp) if what == "library" else (lib, tmp_path / "nope.IN")
    with pytest.raises(SceneError, match=rf"^turbine.controller.{what} .*is not a file"):
        Discon(*args)


def test_a_file_that_is_no_library_is_refused(tmp_path):
    fake = tmp_path / "libfake.so"
    fake.write_bytes(b"not an ELF file")
    with pytest.raises(SceneError, match=r"^turbine.controller.library .*cannot be loaded"):
        Discon(fake, rosco_file(INFILE))


def test_rosco_ends_the_process_on_an_unreadable_input_which_is_why_it_is_checked_first(tmp_path):
    # the reason for the check above: called directly, ROSCO's Fortran runtime stops the process
    code = (f"import ctypes, numpy as np\n"
            f"fn = ctypes.CDLL({str(rosco_root() / LIB)!r}).DISCON\n"
            "sw = np.zeros(3000, np.float32); f = ctypes.c_int(0); m = ctypes.create_string_buffer(1025)\n"
            "inp, out = b'/nonexistent/DISCON.IN\\0', b'/tmp/x\\0'\n"
            "sw[2] = 0.00625; sw[48], sw[49], sw[50], sw[60], sw[128] = 1024, len(inp), len(out), 3, 3000\n"
            "fn(sw.ctypes.data_as(ctypes.POINTER(ctypes.c_float)), ctypes.byref(f), inp, out, m)\n"
            "print('returned')\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.returncode != 0 and "returned" not in r.stdout


def test_an_input_naming_a_missing_file_is_refused_before_the_library_runs(tmp_path):
    # ROSCO's Fortran runtime ends the process on a file it cannot open: the bridge looks first
    text = rosco_file(INFILE).read_text().replace('"Cp_Ct_Cq.NREL5MW.txt"', '"missing_surface.txt"')
    (tmp_path / "DISCON.IN").write_text(text)
    with pytest.raises(SceneError) as exc:
        Discon(rosco_file(LIB), tmp_path / "DISCON.IN")
    assert exc.value.path == "turbine.controller.input" and "PerfFileName" in exc.value.reason
