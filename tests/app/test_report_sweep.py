"""`flexgear sweep`: helix angle and bearing stiffness factor sweeps into CSV + PNG."""
import csv
import dataclasses
import math

import numpy as np
import pytest

from assembly import assemble, load_scene, scale_bearings, solve_modes
from assembly.app.cli import build_parser, main
from assembly.errors import SceneError
from assembly.app.sweep import parse_values, run_sweep, with_helix_angle


def _parser():
    return build_parser()


def test_helix_sweep_cli(tmp_path):
    out = tmp_path / "helix"
    args = _parser().parse_args(["sweep", "kahraman_beta20.toml", "--param", "helix", "--values", "0:20:3",
                                 "--out", str(out), "-q"])
    assert args.func(args) == 0
    rows = list(csv.DictReader(open(out / "sweep.csv")))
    assert [float(r["helix_angle_deg"]) for r in rows] == [0.0, 10.0, 20.0]
    assert float(rows[2]["helix_angle_rad"]) == pytest.approx(math.radians(20))
    # At 0 and 20 deg the sweep reproduces the shipped 0- and 20-deg scenes (same pair, same convention).
    for row, name in ((rows[0], "kahraman_beta0.toml"), (rows[2], "kahraman_beta20.toml")):
        ref = solve_modes(assemble(load_scene(name))).frequencies_hz
        got = [float(row[f"f{j + 1}_hz"]) for j in range(len(ref))]
        assert got == pytest.approx(np.sort(ref), rel=1e-7, abs=1e-6)
    assert (out / "sweep.png").stat().st_size > 10_000
    assert sorted(p.name for p in tmp_path.iterdir()) == ["helix"]


def test_bearing_factor_sweep(tmp_path):
    out = tmp_path / "bf"
    args = _parser().parse_args(["sweep", "lin_parker_n4.toml", "--param", "bearing-factor",
                                 "--values", "1", "100", "1e4", "--out", str(out), "-q"])
    assert args.func(args) == 0
    rows = list(csv.DictReader(open(out / "sweep.csv")))
    assert [float(r["bearing_factor"]) for r in rows] == [1.0, 100.0, 1e4]
    base = np.sort(solve_modes(assemble(load_scene("lin_parker_n4.toml"))).frequencies_hz)
    assert [float(rows[0][f"f{j + 1}_hz"]) for j in range(len(base))] == pytest.approx(base, rel=1e-7, abs=1e-6)
    stiff = np.sort(solve_modes(assemble(scale_bearings(load_scene("lin_parker_n4.toml"), 1e4))).frequencies_hz)
    assert [float(rows[2][f"f{j + 1}_hz"]) for j in range(len(base))] == pytest.approx(stiff, rel=1e-7, abs=1e-6)


def test_stage_helix_replaced():
    sc = load_scene("lin_parker_n4.toml").with_value("stages.stage.helix_angle_deg", 10.0)
    beta = math.radians(15)
    ex = with_helix_angle(sc, beta).expanded()
    assert {round(m.helix_angle, 12) for m in ex.meshes} == {round(beta, 12), round(-beta, 12)}
    r = run_sweep(sc, "helix", [0.0, 15.0])
    assert r.frequencies_hz.shape == (2, 21)
    assert not np.allclose(r.frequencies_hz[0], r.frequencies_hz[1])


def test_helix_sweep_leaves_spur_meshes_spur(tmp_path, capsys):
    # Two meshes: the shipped helical pair plus a spur pair on a third gear; only the
    # helical one may change.
    k20 = load_scene("kahraman_beta20.toml")
    third = dataclasses.replace(k20.bodies[1], name="idler", position=(-k20.bodies[1].position[0], 0.0, 0.0))
    spur = dataclasses.replace(k20.meshes[0], name="spur", gear2="idler", helix_angle=0.0)
    sc = dataclasses.replace(k20, bodies=k20.bodies + (third,), meshes=k20.meshes + (spur,),
                             bearings=k20.bearings + (dataclasses.replace(k20.bearings[1], body="idler"),))
    out = with_helix_angle(sc, math.radians(5.0))
    assert out.meshes[0].helix_angle == pytest.approx(math.radians(5.0)) and out.meshes[1].helix_angle == 0.0
    # a scene without any helical mesh is refused in one line, before any output exists
    with pytest.raises(SceneError, match="no helical gear mesh"):
        with_helix_angle(load_scene("lin_parker_n4.toml"), 0.1)
    assert main(["sweep", "kahraman_beta0.toml", "--param", "helix", "--out", str(tmp_path / "o"), "-q"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no helical gear mesh" in err
    assert not (tmp_path / "o").exists()


def test_parse_values():
    assert list(parse_values(["0,5", "10"], "helix")) == [0, 5, 10]
    assert parse_values([], "helix")[[0, -1]].tolist() == [0.0, 30.0]
    assert parse_values(["1:1e6:7"], "bearing-factor").tolist() == pytest.approx([1, 10, 100, 1e3, 1e4, 1e5, 1e6])
    for bad, param in ((["x"], "helix"), (["95"], "helix"), (["0"], "bearing-factor"), (["1:2"], "helix")):
        with pytest.raises(ValueError):
            parse_values(bad, param)
    assert main(["sweep", "kahraman_beta0.toml", "--param", "helix", "--values", "abc",
                 "--out", "/nonexistent/x"]) == 2


def test_helix_sweep_of_gears_from_teeth():
    # two_stage_quill.toml: a helical pair from teeth (right-hand pinion, left-hand wheel)
    # and a spur planetary stage. The sweep changes both gears' teeth, keeping their hands;
    # the mesh derives its line of action, minus the pinion's base helix angle,
    # tan(beta_b) = tan(beta) cos(alpha_t) (ISO 21771); the spur stage stays spur.
    sc = load_scene("two_stage_quill.toml")
    beta = math.radians(8.0)
    out = with_helix_angle(sc, beta)
    pinion, wheel = out.body("pinion"), out.body("wheel")
    helix = [pinion.teeth.helix_angle, wheel.component.teeth.helix_angle]  # rad
    assert helix == pytest.approx([beta, -beta], rel=1e-14)
    alpha_t = math.atan(math.tan(math.radians(20.0)) / math.cos(beta))
    assert out.meshes[0].helix_angle == pytest.approx(-math.atan(math.tan(beta) * math.cos(alpha_t)), rel=1e-12)
    assert out.stages[0].helix_angle == 0.0
