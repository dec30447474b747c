"""A run that stops hands back what it computed, every row with its time
(assembly.dynamics.transient.Diverged.partial): the partial result of a blow-up has as
many times as rows, the times are the steps' own, and it reaches the blow-up.

x'' = x^3 from x = 1, x' = 1/sqrt(2): the energy x'^2/2 - x^4/4 = 0 gives x(t) = 1 / (1 - t /
sqrt 2), which leaves every bound at t = sqrt 2 s."""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.dynamics.transient import Diverged, Nonlinear, integrate


class Cubic(Nonlinear):
    """The force -x^3 along the one coordinate, with its tangent."""

    def __init__(self):
        self.U = np.ones((1, 1))

    def forces(self, t, x, xd):
        return -x ** 3, -3 * x ** 2, np.zeros(1)


def test_the_partial_result_of_a_blow_up_keeps_every_row_with_its_time():
    dt = 1e-3
    with pytest.raises(Diverged) as e:
        integrate(np.eye(1), None, np.zeros((1, 1)), lambda t: np.zeros(1), [1.0], [1 / math.sqrt(2)], dt, 3.0,
                  nonlinear=Cubic(), dof_names=["x"])
    p = e.value.partial
    assert not p.complete
    assert len(p.time_s) == len(p.y) == len(p.iterations) > 1
    np.testing.assert_allclose(p.time_s, np.arange(len(p.time_s)) * dt, rtol=0, atol=1e-12)
    # up to where the closed form is still far from its pole, the rows follow it (to the
    # trapezoidal rule's O(dt^2) error, amplified by the growth): x = 1 / (1 - t / sqrt 2)
    early = p.time_s <= 1.0
    x = 1 / (1 - p.time_s[early] / math.sqrt(2))
    np.testing.assert_allclose(p.y[early, 0], x, rtol=1e-3)
    assert 1.0 < p.time_s[-1] < math.sqrt(2) + 0.05
