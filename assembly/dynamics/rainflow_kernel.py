"""The ASTM E1049-85 rainflow count of a sequence of reversals, compiled (numba, the ``speed``
extra) for long noisy histories: the loop of the package ``rainflow`` 3.2.0's
``extract_cycles`` (section 5.4.4) on arrays, which gives the same cycles in the same order,
bit for bit (tests/dynamics/test_life.py compares them). Without numba
:mod:`assembly.dynamics.cycles` counts with the package itself.

Reading the reversals in order onto a stack: while the stack holds >= 3 points, the range Y
of its points -3, -2 and X of -2, -1; if X < Y read on; else if the stack holds exactly 3
points Y holds the starting point: Y is half a cycle and the first point leaves; else Y is a
cycle and its two points leave. At the end each range left is half a cycle.
"""
from __future__ import annotations

import numpy as np

from .jit import njit


@njit
def count(r):
    """(ranges, means, counts) of the reversals ``r`` (1-D float array, >= 1 point)."""
    n = r.shape[0]
    ranges, means, counts = np.empty(n), np.empty(n), np.empty(n)
    stack = np.empty(n)
    first, top, k = 0, 0, 0               # the stack is stack[first:top]
    for i in range(n):
        stack[top] = r[i]
        top += 1
        while top - first >= 3:
            x1, x2, x3 = stack[top - 3], stack[top - 2], stack[top - 1]
            if abs(x3 - x2) < abs(x2 - x1):
                break
            if top - first == 3:
                a, b = stack[first], stack[first + 1]
                ranges[k], means[k], counts[k] = abs(a - b), 0.5 * (a + b), 0.5
                first += 1
            else:
                ranges[k], means[k], counts[k] = abs(x1 - x2), 0.5 * (x1 + x2), 1.0
                stack[top - 3] = x3
                top -= 2
            k += 1
    while top - first > 1:
        a, b = stack[first], stack[first + 1]
        ranges[k], means[k], counts[k] = abs(a - b), 0.5 * (a + b), 0.5
        first += 1
        k += 1
    return ranges[:k].copy(), means[:k].copy(), counts[:k].copy()
