"""``flexgear frf`` at its edges: never a non-finite number with exit code 0, only valid JSON,
warnings on stderr and in every output (see tests/dynamics/test_frf_edges.py for the physics).

The scene: two inertias J1 = 2, J2 = 3 kg m^2 on a torsional shaft k = 1e4 N m/rad, free
otherwise, without a damper (the torsional mode sqrt(k (J1 + J2) / (J1 J2)) / 2 pi = 14.53 Hz
rings undamped) or with c = 30 N m s/rad.
"""
from __future__ import annotations

import json
import math

import pytest

from assembly.app.cli import main
from tests.app.test_frf_cli import J1, J2, SCENE, C, K

F_N = math.sqrt(K * (J1 + J2) / (J1 * J2)) / (2 * math.pi)

def _scene(tmp_path, c):
    """test_frf_cli's two-inertia scene with the shaft damper ``c`` (N m s/rad)."""
    p = tmp_path / f"two_{c}.toml"
    p.write_text(SCENE.replace(f"c_torsion = {C}", f"c_torsion = {c}"))
    return str(p)


def _strict(text: str):
    """json.loads that refuses NaN and Infinity (not JSON)."""
    def bad(token):
        raise ValueError(f"non-JSON constant {token}")
    return json.loads(text, parse_constant=bad)


@pytest.mark.parametrize("fmax", ["1e308", "1e200", "1.7e308"])
@pytest.mark.parametrize("method", ["modal", "direct"])
def test_overflowing_fmax_is_refused_in_one_line(tmp_path, capsys, fmax, method):
    rc = main(["frf", _scene(tmp_path, 30.0), "--input", "torque:a", "--output", "torque:s", "--fmin", "1",
               "--fmax", fmax, "--points", "5", "--method", method, "--json", "-q"])
    cap = capsys.readouterr()
    assert rc == 2 and cap.out == ""
    lines = cap.err.strip().splitlines()
    assert len(lines) == 1 and ("--fmax" in lines[0] or "frequency_hz" in lines[0])


@pytest.mark.parametrize("method", ["modal", "direct"])
def test_undamped_mode_in_band_warns_on_stderr_and_in_json(tmp_path, capsys, method):
    rc = main(["frf", _scene(tmp_path, 0.0), "--input", "torque:a", "--output", "torque:s", "--fmin", "1",
               "--fmax", "30", "--points", "30", "--method", method, "--json", "-q"])
    cap = capsys.readouterr()
    assert rc == 0
    data = _strict(cap.out)
    assert len(data["warnings"]) == 1 and f"({F_N:.6g} Hz)" in data["warnings"][0]
    assert cap.err.count("flexgear: warning:") == 1 and "no damping" in cap.err


def test_undamped_mode_warning_reaches_the_summary_and_the_report(tmp_path, capsys):
    scene = _scene(tmp_path, 0.0)
    assert main(["frf", scene, "--input", "torque:a", "--output", "torque:s", "--fmin", "1", "--fmax", "30",
                 "--points", "30", "-q"]) == 0
    assert "warning:" in capsys.readouterr().out
    out = tmp_path / "res"
    assert main(["frf", scene, "--input", "torque:a", "--output", "torque:s", "--fmin", "1", "--fmax", "30",
                 "--points", "30", "-q", "--out", str(out)]) == 0
    assert "no damping" in (out / "index.html").read_text()
    assert "no damping" in _strict((out / "frf.json").read_text())["warnings"][0]


@pytest.mark.parametrize("modes_hz", ["50", "150", "199.9"])
def test_cutoff_below_twice_fmax_is_refused(tmp_path, capsys, modes_hz):
    out = tmp_path / "never"
    rc = main(["frf", _scene(tmp_path, 30.0), "--input", "torque:a", "--output", "torque:s", "--fmax", "100",
               "--modes-hz", modes_hz, "-q", "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and err[0].startswith(f"flexgear: error: --modes-hz = {float(modes_hz)!r}")
    assert not out.exists()


@pytest.mark.parametrize("method", ["modal", "direct"])
def test_zero_hz_on_a_free_chain_is_refused(tmp_path, capsys, method):
    rc = main(["frf", _scene(tmp_path, 30.0), "--input", "torque:a", "--output", "torque:s", "--fmin", "0",
               "--fmax", "10", "--method", method, "--json", "-q"])
    cap = capsys.readouterr()
    assert rc == 2 and cap.out == "" and "0 Hz" in cap.err
