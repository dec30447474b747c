"""A blade's mass moments and the rotor's inertia (assembly.dynamics.blade_mass) from the
NREL 5 MW blade file of the deck that ROSCO's package ships, summed over ElastoDyn's elements and
over FAST v7's.

Sources:
- OpenFAST ElastoDyn's summary file for this blade file (AdjBlMs 1.04536, BldNodes 17): blade mass
  17 536.614 kg, first and second mass moments about the root 362 132.653 kg m and
  11 752 352.265 kg m^2, as quoted in welib's tests (github.com/ebranlard/welib,
  welib/fast/tests/test_elastodyn.py).
- Jonkman, Butterfield, Musial and Scott, NREL/TP-500-38060 (2009), "Jonkman 2009": the blade's
  mass 17 740 kg and its first and second mass moments about the root, 363 231 kg m and
  11 776 047 kg m^2 (section 2); the blade's aerodynamic elements RNodes, DRNodes (Table 3-1),
  which FAST v7 also summed the blade's mass over; hub inertia 115 926 kg m^2, precone -2.5 deg,
  hub radius 1.5 m, tip radius 63 m; rotor inertia 38 759 236 kg m^2, FAST v7's sum for the model.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.dynamics.blade_mass import blade_mass, rotor_inertia, uniform_elements
from assembly.dynamics.rosco_data import rosco_file

pytest.importorskip("rosco", reason="the rosco package (its NREL 5 MW deck) is not installed")
BLADE = "Examples/Test_Cases/NREL-5MW/NRELOffshrBsline5MW_Blade.dat"
#: Jonkman 2009 Table 3-1: the blade elements' centres from the rotor apex and their widths (m),
#: published to four decimals
RNODES = [2.8667, 5.6000, 8.3333, 11.7500, 15.8500, 19.9500, 24.0500, 28.1500, 32.2500, 36.3500, 40.4500,
          44.5500, 48.6500, 52.7500, 56.1667, 58.9000, 61.6333]
DRNODES = [2.7333] * 3 + [4.1000] * 11 + [2.7333] * 3
HALF_DIGIT = 0.5e-4                 # m: half the last published digit of RNODES and DRNODES


def _blade_table():
    """(BlFract, BMassDen x AdjBlMs) of the deck's blade file, read here independently: its 49
    rows follow the two header lines of DISTRIBUTED BLADE PROPERTIES; AdjBlMs = 1.04536."""
    lines = rosco_file(BLADE).read_text().splitlines()
    i = next(k for k, s in enumerate(lines) if "DISTRIBUTED BLADE PROPERTIES" in s) + 3
    rows = np.array([[float(w) for w in s.split()] for s in lines[i:i + 49]])
    return rows[:, 0], rows[:, 3] * 1.04536


def test_the_blades_mass_moments_are_elastodyns():
    fraction, density = _blade_table()
    b = blade_mass(fraction, density, 61.5, *uniform_elements(17, 61.5))      # BldNodes = 17
    # the summary prints three decimals: half of the last one
    assert (b.mass, b.first, b.second) == pytest.approx((17536.614, 362132.653, 11752352.265), abs=5e-4)


def _rounding_bound(quantity, values, half_digit):
    """How far ``quantity(values)`` can move when each published value moves by its rounding
    (first order, each number on its own, added up)."""
    base, out = quantity(values), 0.0
    for i in range(len(values)):
        moved = list(values)
        moved[i] += half_digit
        out += abs(quantity(moved) - base)
    return out


def test_jonkmans_numbers_are_the_same_sum_over_fast_v7s_elements():
    # FAST v7 summed the blade over AeroDyn's elements (Jonkman 2009 Table 3-1) instead of 17 equal
    # ones: the same rule over those elements gives the published moments and rotor inertia, to
    # what the four-decimal node table and the published last digit allow
    fraction, density = _blade_table()

    def moments(x):
        centres, widths = np.array(x[:17]) - 1.5, np.array(x[17:])
        return blade_mass(fraction, density, 61.5, centres, widths)

    def inertia(x):
        return rotor_inertia(115926.0, 1.5, [(moments(x), math.radians(-2.5))] * 3)

    x = RNODES + DRNODES
    b = moments(x)
    for value, published, name in ((b.mass, 17740.0, "mass"), (b.first, 363231.0, "first"),
                                   (b.second, 11776047.0, "second")):
        bound = _rounding_bound(lambda y, n=name: getattr(moments(y), n), x, HALF_DIGIT) + 0.5
        assert abs(value - published) <= bound, (name, value, published, bound)
    bound = _rounding_bound(inertia, x, HALF_DIGIT) + 0.5
    assert abs(inertia(x) - 38759236.0) <= bound
    assert bound < 1e-4 * 38759236.0         # tight enough to see a cone (0.2 %) or AdjBlMs (4.5 %) left out
