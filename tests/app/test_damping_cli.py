"""`flexgear modes` with damping: the damping columns appear only for a damped scene, and
bad damping input ends in one line naming the field (exit 2).

Scene: two torsional bodies J1 = 2, J2 = 3 kg m^2 on a shaft k = 1e4 N m/rad, c (N m s/rad).
Relative twist obeys J_eq d'' + c d' + k d = 0, J_eq = J1 J2 / (J1 + J2): the elastic mode's
ratio is zeta = c / (2 sqrt(k J_eq)) and its damped frequency sqrt(k/J_eq) sqrt(1 - zeta^2) / 2 pi.
"""
import json
import math

import pytest

from assembly.app.cli import main

J1, J2, K = 2.0, 3.0, 1.0e4


def scene(shaft_extra: str = "", tail: str = "") -> str:
    bodies = "".join(f'[[bodies]]\nname = "{n}"\nmass = 10.0\npolar_inertia = {J}\nposition = [0.0, 0.0, {z}]\n'
                     f'[[bearings]]\nbody = "{n}"\nk_radial = inf\nk_axial = inf\nk_tilt = inf\n'
                     for n, J, z in (("a", J1, 0.0), ("b", J2, 1.0)))
    return (f'name = "two"\n{bodies}[[shafts]]\nbody1 = "a"\nbody2 = "b"\nk_torsion = {K}\n{shaft_extra}\n'
            f'{tail}')


def _run(tmp_path, text, *args):
    p = tmp_path / "s.toml"
    p.write_text(text)
    return main(["modes", str(p), *args])


def test_columns_only_with_damping(tmp_path, capsys):
    assert _run(tmp_path, scene()) == 0
    assert "damping ratio" not in capsys.readouterr().out
    c = 30.0
    assert _run(tmp_path, scene(f"c_torsion = {c}")) == 0
    out = capsys.readouterr().out
    assert "damping ratio" in out and "damped frequency [Hz]" in out
    J = J1 * J2 / (J1 + J2)
    zeta = c / (2 * math.sqrt(K * J))
    row = next(line.split() for line in out.splitlines() if line.split()[:1] == ["2"])
    assert float(row[2]) == pytest.approx(zeta, abs=5e-5)                      # printed to 4 decimals
    assert float(row[3]) == pytest.approx(math.sqrt(K / J * (1 - zeta ** 2)) / (2 * math.pi), abs=5e-3)


def test_json_carries_damping(tmp_path, capsys):
    assert _run(tmp_path, scene(tail="[damping]\nmodal_ratio = 0.03\n"), "--json") == 0
    modes = json.loads(capsys.readouterr().out)["modes"]
    assert modes[0]["damping_ratio"] == 0.0                  # the rigid-body mode stays undamped
    assert modes[1]["damping_ratio"] == pytest.approx(0.03, rel=1e-14)


BAD = [("c_torsion = -1.0", "", "shafts[0].c_torsion"),
       ("c_axial = nan", "", "shafts[0].c_axial"),
       ("beta = 1e-4", "", "shafts[0].beta"),
       ("", "[damping]\nmodal_ratio = 1.0\n", "damping.modal_ratio"),
       ("", "[damping]\nrayleigh_alpha = -2.0\n", "damping.rayleigh_alpha"),
       ("", "[damping]\nclass_ratios = { rotational = 2.0 }\n", "damping.class_ratios.rotational"),
       ("", "[damping]\nclass_ratios = { spin = 0.1 }\n", "damping.class_ratios"),
       ("", "[damping]\nzeta = 0.1\n", "damping")]


@pytest.mark.parametrize("extra,tail,named", BAD, ids=[b[2] for b in BAD])
def test_bad_damping_one_line_exit_2(extra, tail, named, tmp_path, capsys):
    assert _run(tmp_path, scene(extra, tail)) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and named in err
