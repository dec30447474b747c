"""A rotor's performance surface (assembly.dynamics.rotor_surface) read from ROSCO's NREL 5 MW
table, and the quasi-steady torque and thrust it gives.

Sources: ROSCO's ``Cp_Ct_Cq.NREL5MW.txt`` (the table itself; its header: 36 pitch angles in
degrees, 26 tip-speed ratios); Jonkman, Butterfield, Musial and Scott, NREL/TP-500-38060 (2009),
section 7.3: the peak power coefficient at a tip-speed ratio of 7.55 and 0 deg pitch; the
definitions Cq = Cp / lambda, P = Q Omega (module notes of rotor_surface).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.dynamics.rosco_data import NREL5MW_SURFACE, rosco_file
from assembly.dynamics.rotor_surface import coefficients, read_surface, rotor_loads
from assembly.errors import SceneError

rosco = pytest.importorskip("rosco", reason="the rosco package (turbine extra) is not installed")
R, RHO = 63.0, 1.225               # m, kg/m^3: NREL 5 MW rotor radius and air density (Jonkman 2009)


@pytest.fixture(scope="module")
def surface():
    return read_surface(rosco_file(NREL5MW_SURFACE))


def test_the_table_is_read_as_its_header_says(surface):
    assert surface.cp.shape == surface.ct.shape == surface.cq.shape == (26, 36)
    assert surface.pitch[0] == pytest.approx(math.radians(-5.0)) and surface.pitch[-1] == pytest.approx(
        math.radians(30.0))
    assert surface.tsr[0] == 2.0 and surface.tsr[-1] == 14.5


def test_the_tables_torque_and_power_coefficients_differ_by_a_known_margin(surface):
    # ROSCO computes Cq on its own: against Cp / lambda it is off by at most 0.1 % of the peak Cq
    # around rated (lambda 6-8, pitch -1..5 deg) -- why the torque comes from Cq and the power is
    # Q Omega (module notes); a reader that mixed up the blocks or their rows would be far off
    lam = surface.tsr[:, None]
    near = (np.abs(surface.tsr - 7.0) <= 1.0)[:, None] & (np.abs(np.degrees(surface.pitch) - 2.0) <= 3.0)[None, :]
    off = np.abs(surface.cq - surface.cp / lam)[near]
    assert off.max() <= 1e-3 * surface.cq.max()


def test_peak_power_coefficient_where_jonkman_has_it(surface):
    # the table's maximum lies in a grid cell around Jonkman's optimum (7.55, 0 deg)
    i, j = np.unravel_index(np.argmax(surface.cp), surface.cp.shape)
    dl, db = np.diff(surface.tsr)[0], np.diff(surface.pitch)[0]
    assert abs(surface.tsr[i] - 7.55) <= dl and abs(surface.pitch[j]) <= db


def test_bilinear_values_and_slopes(surface):
    s = surface
    # at the nodes, the table
    for i, j in ((0, 0), (10, 5), (25, 35), (11, 5)):
        c = coefficients(s, s.tsr[i], s.pitch[j])
        assert (c["cp"], c["ct"], c["cq"]) == (s.cp[i, j], s.ct[i, j], s.cq[i, j])
    # inside a cell: linear along each grid direction, so a central difference is the slope
    lam, beta = 7.2, math.radians(2.3)
    c = coefficients(s, lam, beta)
    for name in ("cp", "ct", "cq"):
        h = 1e-3
        fd = (coefficients(s, lam + h, beta)[name] - coefficients(s, lam - h, beta)[name]) / (2 * h)
        assert fd == pytest.approx(c[f"d{name}_dtsr"], rel=1e-9)
        k = math.radians(1e-3)
        fd = (coefficients(s, lam, beta + k)[name] - coefficients(s, lam, beta - k)[name]) / (2 * k)
        assert fd == pytest.approx(c[f"d{name}_dpitch"], rel=1e-9)


def test_rotor_loads_power_torque_and_slopes(surface):
    # at a node of the table (lambda = 7, pitch 0): the table's own Cq and Ct, scaled by the
    # dynamic pressure; the power is the torque's, Q Omega
    V, lam = 11.4, 7.0
    omega = lam * V / R
    ld = rotor_loads(surface, R, RHO, V, omega, 0.0)
    q_dyn = 0.5 * RHO * math.pi * R ** 2 * V ** 2
    i, j = list(surface.tsr).index(7.0), int(np.argmin(np.abs(surface.pitch)))
    assert ld.tsr == pytest.approx(lam, rel=1e-15)
    assert ld.torque == pytest.approx(q_dyn * R * surface.cq[i, j], rel=1e-14)
    assert ld.thrust == pytest.approx(q_dyn * surface.ct[i, j], rel=1e-14)
    assert ld.power == ld.torque * omega
    # inside a cell Q is quadratic in V and linear in Omega at fixed pitch: central differences
    # are the slopes to round-off
    V, omega, beta = 12.0, 1.2, math.radians(3.4)
    ld = rotor_loads(surface, R, RHO, V, omega, beta)
    for attr, arg, h in (("dq_domega", 4, 1e-5), ("dq_dwind", 3, 1e-4), ("dt_domega", 4, 1e-5),
                         ("dt_dwind", 3, 1e-4)):
        lo, hi = [V, omega], [V, omega]
        lo[arg - 3] -= h
        hi[arg - 3] += h
        a, b = rotor_loads(surface, R, RHO, lo[0], lo[1], beta), rotor_loads(surface, R, RHO, hi[0], hi[1], beta)
        key = "torque" if attr.startswith("dq") else "thrust"
        fd = (getattr(b, key) - getattr(a, key)) / (2 * h)
        assert fd == pytest.approx(getattr(ld, attr), rel=1e-6), attr
    # near rated, above the torque coefficient's peak in lambda: the rotor damps (dQ/dOmega < 0)
    assert rotor_loads(surface, R, RHO, 11.4, 1.2671, 0.0).dq_domega < 0.0


@pytest.mark.parametrize("wind, omega, pitch, field", [
    (1.0, 1.2671, 0.0, "tip-speed ratio"),              # lambda = 80: beyond the table
    (11.4, 1.2671, math.radians(40.0), "blade pitch"),
    (0.0, 1.0, 0.0, "wind speed"),
    (-3.0, 1.0, 0.0, "wind speed"),
])
def test_outside_the_surface_is_refused(surface, wind, omega, pitch, field):
    with pytest.raises(SceneError, match=field):
        rotor_loads(surface, R, RHO, wind, omega, pitch)


def test_a_broken_file_is_one_line_naming_the_field(tmp_path, surface):
    text = rosco_file(NREL5MW_SURFACE).read_text()
    lines = text.splitlines()
    last = max(i for i, s in enumerate(lines) if s.strip())          # the torque block's last row
    rng = np.random.default_rng(5)
    cuts = sorted(set(rng.integers(0, last, 25).tolist()) | {0, 3, 5, 12, 40, 70, last})
    for cut in cuts:
        f = tmp_path / f"cut{cut}.txt"
        f.write_text("\n".join(lines[:cut]) + "\n")
        with pytest.raises(SceneError) as err:
            read_surface(f)
        assert str(err.value).startswith("turbine.surface") and "\n" not in str(err.value)
    for bad, words in ((text.replace("(deg)", "(rad)"), "unit"), (text.replace("0.006673", "abc"), "numbers"),
                       (text.replace("-5.0   -4.0", "-4.0   -5.0"), "increasing")):
        f = tmp_path / "bad.txt"
        f.write_text(bad)
        with pytest.raises(SceneError, match=words):
            read_surface(f)
    with pytest.raises(SceneError, match="cannot be read"):
        read_surface(tmp_path / "missing.txt")
