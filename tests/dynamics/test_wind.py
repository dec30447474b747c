"""The rotor-effective wind speed (assembly.dynamics.wind): deterministic series exactly, a
series refused outside its times, and IEC 61400-1 turbulence from pyconturb.

Turbulence checks. pyconturb's fluctuations have no mean (the spectral synthesis has no zero
frequency), so the series' time mean is the disc average of the power-law shear profile
(z / z_hub)^0.2 (IEC 61400-1's normal wind profile) over the grid points inside the disc, to
round-off; a seed gives the same series twice and another seed another; averaging over the disc
lowers the standard deviation below a single point's (the IEC coherence is below 1 for
separated points).
"""
from __future__ import annotations

import numpy as np
import pytest

from assembly.dynamics.wind import WindSeries, constant, iec_turbulence, ramp, steps
from assembly.errors import SceneError


def test_deterministic_series():
    w = constant(11.4, 10.0)
    assert w(0.0) == 11.4 and w(10.0) == 11.4
    s = steps([(0.0, 8.0), (5.0, 12.0)], 10.0)
    assert s(4.999) == 8.0 and s(5.001) == 12.0 and s(10.0) == 12.0
    r = ramp(8.0, 12.0, 2.0, 6.0, 10.0)
    np.testing.assert_allclose(r(np.array([0.0, 2.0, 4.0, 6.0, 9.0])), [8.0, 8.0, 10.0, 12.0, 12.0], rtol=1e-15)


@pytest.mark.parametrize("t", [-0.5, 10.5])
def test_outside_the_series_is_refused(t):
    with pytest.raises(SceneError, match=r"^turbine.wind .*outside the wind series"):
        constant(11.4, 10.0)(t)


@pytest.mark.parametrize("times, speeds, words", [
    ([0.0, 1.0, 1.0], [8.0, 9.0, 10.0], "increasing"),
    ([0.0, 1.0], [8.0, np.nan], "finite"),
    ([0.0, 1.0], [8.0, -1.0], "positive"),
    ([0.0, 1.0], [8.0], "one length"),
])
def test_bad_series_are_one_line(times, speeds, words):
    with pytest.raises(SceneError, match=words):
        WindSeries(np.array(times), np.array(speeds))


def test_iec_turbulence_mean_seed_and_rotor_averaging():
    pytest.importorskip("pyconturb", reason="pyconturb (the wind extra) is not installed")
    from pyconturb import gen_spat_grid, gen_turb
    V, R, H = 16.0, 63.0, 90.0
    w = iec_turbulence(V, "B", R, H, 120.0, 0.1, seed=4, points=5)
    c = np.linspace(-R, R, 5)
    yy, zz = np.meshgrid(c, H + c, indexing="ij")
    inside = yy ** 2 + (zz - H) ** 2 <= R ** 2
    profile = (V * (zz / H) ** 0.2)[inside].mean()
    assert w.speed.mean() == pytest.approx(profile, rel=1e-12)
    again = iec_turbulence(V, "B", R, H, 120.0, 0.1, seed=4, points=5)
    other = iec_turbulence(V, "B", R, H, 120.0, 0.1, seed=5, points=5)
    assert np.array_equal(w.speed, again.speed) and not np.array_equal(w.speed, other.speed)
    hub = gen_turb(gen_spat_grid(np.array([0.0]), np.array([H]), comps=[0]), T=len(w.speed) * 0.1,
                   nt=len(w.speed), u_ref=V, z_ref=H, turb_class="B", seed=4).values[:, 0]
    assert w.speed.std() < hub.std()


def test_a_turbulence_class_that_is_not_iec_is_refused():
    pytest.importorskip("pyconturb", reason="pyconturb (the wind extra) is not installed")
    with pytest.raises(SceneError, match=r"turbine.wind.class .*A, B or C"):
        iec_turbulence(16.0, "D", 63.0, 90.0, 10.0, 0.1, seed=1)
