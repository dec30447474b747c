"""The run report's frequency response (assembly.app.report.run_frf) on a small rigid scene:
the Campbell test chain (tests/support/campbell_scene.py) with the pinion driven by a
generator through a coupling and the planetary carrier driving a rotor drum."""
import csv
import tomllib

import numpy as np
import pytest

from assembly.analysis.load_cases import single_rigid_mode
from assembly.app import run_report
from assembly.model.probes import axial_rotation
from assembly.scene.schema import scene_from_dict
from tests.support.campbell_scene import campbell_scene

ENDS = """
[[bodies]]
name = "gen"
role = "generator"
mass = 20.0
polar_inertia = 0.2
position = [0.0, 0.0, -0.3]
[[bearings]]
body = "gen"
k_radial = 1.0e9
k_axial = 1.0e9
k_tilt = 1.0e7
[[shafts]]
name = "coupling"
body1 = "gen"
body2 = "pinion"
k_torsion = 2.0e5
k_bending = 1.0e6
k_axial = 1.0e8
k_shear = 1.0e8
c_torsion = {c}
[[bodies]]
name = "drum"
role = "rotor"
mass = 200.0
polar_inertia = 20.0
position = [0.2677581560127026, 0.0, 0.8]
[[bearings]]
body = "drum"
k_radial = 1.0e9
k_axial = 1.0e9
k_tilt = 1.0e7
[[shafts]]
name = "output"
body1 = "planetary.carrier"
body2 = "drum"
k_torsion = 5.0e5
k_bending = 1.0e6
k_axial = 1.0e8
k_shear = 1.0e8
"""


def _scene(c):
    text = campbell_scene().replace('role = "rotor"\n', "", 1) + ENDS.format(c=c)
    return scene_from_dict(tomllib.loads(text))


def test_run_writes_the_generator_frf(tmp_path):
    ctx = run_report(_scene(50.0), tmp_path / "out", n_modes=1, images=False, compare=False)
    out = tmp_path / "out"
    assert (out / "images" / "frf_generator.png").stat().st_size > 0
    assert "images/frf_generator.png" in (out / "index.html").read_text()
    with open(out / "frf.csv") as fh:
        rows = list(csv.reader(fh))
    # the sun's shaft (quill, wheel to sun) and the fastest toothed body with a shaft: the
    # pinion (83/21 x the wheel's speed), on the coupling
    assert rows[0][1:] [0::4] == ["torque:quill real [N m/(N m)]", "torque:coupling real [N m/(N m)]"]
    f = np.array([float(r[0]) for r in rows[1:]])
    assert f[0] == 1.0 and f[-1] == 1000.0 and len(f) == 400
    assert np.allclose(np.diff(np.log(f)), np.log(1000.0) / 399)
    # at 1 Hz, below every elastic mode (f1), the drivetrain turns as one rigid body Z
    # (scaled to a unit generator rotation): a torque T on the generator accelerates it at
    # T / J, J = Z' M Z the inertia seen at the generator, and the coupling passes on all
    # but what the generator's own inertia takes: H = 1 - J_gen / J, quasi-static to
    # O((1 Hz / f1)^2)
    m = ctx.model
    phi, _ = single_rigid_mode(m)
    Z = m.T @ phi[:, 0]
    Z = Z / axial_rotation(m, Z, "gen")
    J = float(Z @ (m.M_abs @ Z))
    f1 = ctx.result.frequencies_hz[ctx.result.n_rigid]
    assert f1 > 10.0
    h = complex(float(rows[1][5]), float(rows[1][6]))
    assert abs(h) == pytest.approx(1 - 0.2 / J, rel=2 * (1.0 / f1) ** 2)
    assert not any("no frequency response" in n for n in ctx.notes)


def test_undamped_run_skips_the_frf_with_a_note(tmp_path):
    ctx = run_report(_scene(0.0), tmp_path / "out", n_modes=1, images=False, compare=False)
    assert not (tmp_path / "out" / "frf.csv").exists()
    assert any("no frequency response" in n and "no damping" in n for n in ctx.notes)
