"""Loads a law sets at its own sample times and holds in between (assembly.dynamics.sampled):
a speed controller on a free inertia, on both steps (tests/dynamics/conftest.py).

Theory. A free inertia J (M = [J], K = C = 0) under a held torque u_j = -kp (w_j - w_ref), set
at t_j = j T from the speed then. The trapezoidal rule (Newmark, beta = 1/4, gamma = 1/2) adds
dt (a_k + a_{k+1}) / 2 to the speed each step, with a_k = f(t_k) / J and f evaluated at the step
points; the hold switches after t_j (the step ending at t_j is the last to see u_{j-1}), so over
one sample (P = T / dt steps) the speed gains ((P - 1/2) u_j + 1/2 u_{j-1}) dt / J: with the
error e_j = w_j - w_ref and g = kp dt / J,
    e_{j+1} = e_j - g ((P - 1/2) e_j + 1/2 e_{j-1}),   e_{-1} = e_0 (u_{-1} = u_0: the first
sample is also the start's load).
The rule is exact for a force linear between the step points, so the run equals this recurrence
to round-off: a few eps per step, 1e-12 of w_ref over the run's 1000 steps.
"""
from __future__ import annotations

import numpy as np
import pytest

from assembly.dynamics.observe_rows import state_rows
from assembly.dynamics.sampled import Sampled
from assembly.dynamics.transient import Diverged, integrate
from assembly.errors import SceneError

pytestmark = pytest.mark.usefixtures("step_path")

J, KP, W_REF = 2.0, 5.0, 10.0       # kg m^2, N m s/rad, rad/s
DT, P = 1e-3, 10                     # s; steps a sample (T = 10 ms)
T = P * DT


class Loads:
    """No load of its own (vectors and histories, as a run's loads are)."""
    vectors, histories = np.zeros((1, 0)), ()

    def __call__(self, t):
        return np.zeros(1)


def _run(law, t_end=1.0, period=T):
    calls = []

    def logged(t, q, v):
        calls.append(t)
        return law(t, q, v)
    run = integrate(np.array([[J]]), None, np.zeros((1, 1)), Loads(), [0.0], [0.0], DT, t_end,
                    observe=state_rows(1, q=True, v=True), sampled=Sampled(np.ones((1, 1)), period, logged))
    return run, calls


def test_a_held_speed_controller_is_the_sampled_recurrence(step_path):
    run, calls = _run(lambda t, q, v: [-KP * (v[0] - W_REF)])
    assert run.info["compiled"] is (step_path == "compiled")
    n = round(1.0 / T)
    # called once a sample, at the sample times, never inside a stretch (the last at 0.99 s)
    np.testing.assert_allclose(calls, np.arange(n) * T, rtol=0, atol=1e-12)
    w = run.y[::P, 1]                                     # the speed at the sample times
    e = np.empty(n + 1)
    e[0] = -W_REF
    g = KP * DT / J
    prev = e[0]
    for j in range(n):
        e[j + 1] = e[j] - g * ((P - 0.5) * e[j] + 0.5 * prev)
        prev = e[j]
    assert np.max(np.abs(w - W_REF - e)) <= 1e-12 * W_REF
    # the recurrence's roots r^2 - (1 - g (P - 1/2)) r + g/2 = 0 are real and in (0, 1) for
    # g P = 0.025: the speed rises to w_ref without overshoot
    assert np.all(np.diff(w) > 0) and np.all(w < W_REF)


def test_a_period_off_the_steps_is_refused():
    with pytest.raises(SceneError, match=r"sampled.period .*whole number of steps"):
        _run(lambda t, q, v: [0.0], period=2.5 * DT)


def test_a_law_of_the_wrong_size_is_refused():
    with pytest.raises(SceneError, match=r"sampled.law .*must return 1"):
        _run(lambda t, q, v: [0.0, 1.0])


def test_a_law_that_is_not_finite_stops_the_run_with_what_it_had():
    with pytest.raises(Diverged, match=r"sampled load at t = 0.5 s is not finite") as err:
        _run(lambda t, q, v: [np.nan if t >= 0.5 - 1e-12 else 1.0])
    p = err.value.partial
    assert not p.complete and p.time_s[-1] == pytest.approx(0.5, abs=1e-12)
