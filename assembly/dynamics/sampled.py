"""Loads that Python sets at a sample time and holds in between: a controller in the loop.

A controller runs at its own sample time, not at the integrator's step: a DISCON library
(the Bladed-style interface OpenFAST's ServoDyn calls) every ``DT`` of its input file, a
supervisory law, a table looked up from the state. Its outputs act on the model along fixed
load vectors ``V`` (n x k: a generator torque on the generator's rotation row, a force on a
body) with amplitudes ``u`` (k,) that it sets at ``t_j = j T`` from the state then and holds
until ``t_{j+1}`` (a zero-order hold, as a digital controller's output stage):

    f(t) = f_base(t) + V u_j,   t_j <= t < t_{j+1},   u_j = law(t_j, q(t_j), v(t_j)).

The run's steps go in stretches between visits of Python (:mod:`assembly.dynamics.stretches`);
with sampled loads every sample time ends a stretch, so the law is called between compiled
stretches, once a sample, and never inside one. ``T`` must be a whole number of steps, so
that the samples fall on steps (a controller's DT and the run's dt are chosen together, as in
OpenFAST, whose ServoDyn requires DLL_DT to be a multiple of DT).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..errors import SceneError


@dataclass(frozen=True)
class Sampled:
    """Loads along ``vectors`` (n x k) whose amplitudes ``law(t, q, v) -> (k,)`` sets every
    ``period`` s, held in between (module notes)."""

    vectors: np.ndarray
    period: float
    law: Callable


def sample_steps(period: float, dt: float, field: str = "sampled.period") -> int:
    """Steps of ``dt`` in a sample ``period`` (s): a whole number, else SceneError at ``field``."""
    if not (isinstance(period, (int, float)) and math.isfinite(period) and period > 0.0):
        raise SceneError(field, period, "must be a positive number of seconds")
    steps = round(period / dt)
    if steps < 1 or abs(steps * dt - period) > 1e-9 * period:
        raise SceneError(field, period, f"must be a whole number of steps of dt = {dt:g} s "
                                        f"({period / dt:.6g} steps)")
    return int(steps)


class HeldForce:
    """The run's load with the sampled part held: ``force(t) = base(t) + V u`` (``u`` set by
    :meth:`sample`). A base with load ``vectors`` and time ``histories`` (evaluated a stretch at
    a time) keeps that form, the held amplitudes as constant histories."""

    def __init__(self, base, sampled: Sampled, n: int):
        self.base, self.law = base, sampled.law
        self.V = np.asarray(sampled.vectors, float).reshape(n, -1)
        self.u = np.zeros(self.V.shape[1])
        vecs, hist = getattr(base, "vectors", None), getattr(base, "histories", None)
        if vecs is not None and hist is not None:
            self.vectors = np.hstack([np.asarray(vecs, float).reshape(n, -1), self.V])
            self.histories = (*hist, *(self._held(j) for j in range(self.V.shape[1])))

    def _held(self, j: int):
        return lambda t: np.full(np.shape(t), self.u[j])

    def __call__(self, t: float) -> np.ndarray:
        return np.asarray(self.base(t), float) + self.V @ self.u

    def sample(self, t: float, q: np.ndarray, v: np.ndarray) -> bool:
        """Call the law at ``t`` with the state; False if its amplitudes are not finite
        (kept, for the caller to stop the run)."""
        u = np.asarray(self.law(t, q.copy(), v.copy()), float).reshape(-1)
        if u.shape != self.u.shape:
            raise SceneError("sampled.law", f"{u.shape[0]} values", f"must return {self.u.shape[0]} (one per "
                                                                     "load vector)")
        self.u = u
        return bool(np.all(np.isfinite(u)))
