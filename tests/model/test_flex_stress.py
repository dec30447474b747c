"""Stress recovery in the assembly: a flexible shaft in pure torsion vs tau = T r / J."""
import math
from pathlib import Path

import numpy as np
import pytest

from assembly import load_scene
from assembly.analysis.static import solve_static, stress_summary
from assembly.errors import SceneError

SCENE = Path(__file__).parent.parent / "support" / "data" / "shaft_torsion.toml"
T, D, L = 100.0, 0.05, 0.5   # N m, m, m (scene file)


@pytest.fixture(scope="module")
def static():
    sc = load_scene(SCENE)
    return sc, solve_static(sc, sc.load)


def test_torsion_shear_stress_matches_tau_Tr_over_J(static):
    sc, st = static
    body = st.model.bodies["shaft"]
    s = body.stress(st.body_dofs("shaft"))
    r = np.hypot(s.points[:, 0], s.points[:, 1])
    mid = np.abs(s.points[:, 2] - L / 2) < L / 5          # Saint-Venant: away from the ends
    J = math.pi * D**4 / 32
    tau = T * r / J
    surface = mid & (r > 0.98 * D / 2)
    assert surface.sum() > 100
    # pure shear: von Mises = sqrt(3) tau and the maximum shear stress (s1 - s3)/2 = tau
    np.testing.assert_allclose(s.von_mises[surface], math.sqrt(3) * tau[surface], rtol=0.02)
    max_shear = (s.principal[surface, 0] - s.principal[surface, 2]) / 2
    np.testing.assert_allclose(max_shear, tau[surface], rtol=0.02)


def test_twist_angle_matches_T_L_over_GJ(static):
    # Rotation of end A relative to end B: theta = T L / (G J), G = E / (2 (1 + nu)).
    sc, st = static
    body = st.model.bodies["shaft"]
    zb = st.body_dofs("shaft")
    a, b = body.masters["end_a"][1], body.masters["end_b"][1]
    twist = zb[a[5]] - zb[b[5]]
    E, nu = 2.1e11, 0.3
    G = E / (2 * (1 + nu))
    J = math.pi * D**4 / 32
    assert twist == pytest.approx(T * L / (G * J), rel=0.02)


def test_stress_summary_reports_max_and_location(static):
    sc, st = static
    summ = stress_summary(st.model, st.z[:, None], ["rated torque"])
    row = summ["shaft"][0]
    assert row["max_von_mises_Pa"] >= math.sqrt(3) * 16 * T / (math.pi * D**3) * 0.98
    x, y, z = row["location_m"]
    assert math.hypot(x, y) > 0.45 * D  # the maximum sits at the surface


def test_load_case_errors_name_the_field():
    import dataclasses
    sc = load_scene(SCENE)
    with pytest.raises(SceneError, match=r"load.output"):
        dataclasses.replace(sc, load=dataclasses.replace(sc.load, output="nothing"))
    with pytest.raises(SceneError, match=r"load.torque"):
        dataclasses.replace(sc, load=dataclasses.replace(sc.load, torque=0.0))
