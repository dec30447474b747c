"""Variable-speed generator-torque laws (assembly.dynamics.variable_speed) against Jonkman et
al., NREL/TP-500-38060 (2009), section 7.4: the region-2 constant k = 0.0255764 N m/rpm^2
(25 576.4 N m at 1000 rpm), rated 1173.7 rpm generator speed and 43 093.55 N m, the baseline's
regions; ServoDyn's simple law's transition speed from its closed form."""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.dynamics.variable_speed import (
    NREL5MW_BASELINE,
    RPM,
    SimpleVariableSpeed,
    baseline_torque,
    simple_torque,
)

K_RPM = 0.0255764                 # N m/rpm^2 (Jonkman 2009)
K = K_RPM / RPM ** 2              # N m/(rad/s)^2
SIMPLE = SimpleVariableSpeed(rated_speed=1173.7 * RPM, rated_torque=43093.55, k=K, slip=0.10)


def test_region_2_is_jonkmans_constant():
    assert simple_torque(SIMPLE, 1000.0 * RPM) == pytest.approx(25576.4, rel=1e-12)
    assert baseline_torque(NREL5MW_BASELINE, 1000.0 * RPM) == pytest.approx(25576.4, rel=1e-6)  # k to 7 digits
    # the baseline's k in SI is Jonkman's rpm constant: 2.332287 N m/(rad/s)^2
    assert NREL5MW_BASELINE.k * RPM ** 2 == pytest.approx(K_RPM, rel=1e-6)


def test_simple_law_is_continuous_through_its_regions():
    law = SIMPLE
    wt = law.transition_speed
    # the transition speed is the smaller root of k w^2 = m (w - w_sync)
    assert law.k * wt ** 2 == pytest.approx(law.slope * (wt - law.sync_speed), rel=1e-12)
    assert law.sync_speed < wt < law.rated_speed
    e = 1e-9 * wt
    assert simple_torque(law, wt - e) == pytest.approx(simple_torque(law, wt + e), rel=1e-7)
    # the slip line reaches the rated torque at rated speed: region 3 starts without a jump
    wr = law.rated_speed
    assert simple_torque(law, wr * (1 - 1e-12)) == pytest.approx(law.rated_torque, rel=1e-9)
    assert simple_torque(law, 1.5 * wr) == law.rated_torque
    # monotone non-decreasing in speed
    w = np.linspace(0.0, 1.3 * wr, 2001)
    assert np.all(np.diff([simple_torque(law, x) for x in w]) >= 0.0)


def test_baseline_regions():
    law = NREL5MW_BASELINE
    # region 1: nothing below cut-in; 1 1/2 starts from zero and meets region 2's parabola
    assert baseline_torque(law, 600.0 * RPM) == 0.0
    assert baseline_torque(law, law.cut_in * (1 + 1e-12)) == pytest.approx(0.0, abs=1e-6)
    w2 = law.region2_start
    assert law.slope15 * (w2 - law.cut_in) == pytest.approx(law.k * w2 ** 2, rel=1e-12)
    # region 2 1/2 to rated power at rated speed, then constant power: P = T w = 5.29661 MW
    wr = law.rated_speed
    assert baseline_torque(law, wr * (1 - 1e-12)) * wr == pytest.approx(law.rated_power, rel=1e-9)
    for w in (wr, 1.05 * wr):
        assert baseline_torque(law, w) * w == pytest.approx(law.rated_power, rel=1e-12)
    # pitched past 1 deg: region 3 at any speed, capped at the maximum torque
    assert baseline_torque(law, 0.99 * wr, math.radians(2.0)) == pytest.approx(law.rated_power / (0.99 * wr))
    assert baseline_torque(law, 0.5 * wr, math.radians(2.0)) == law.max_torque
