"""Strict JSON for every result flexgear writes or prints: no bare ``NaN`` or ``Infinity``
(they are not JSON, and a non-finite number never leaves with exit code 0).

:func:`dumps` is ``json.dumps(..., allow_nan=False)`` that, instead of ``json``'s generic
ValueError, raises :class:`assembly.errors.SolverError` naming the path of the first
non-finite number (``outputs.torque:s[12]``), which the command line reports in one line.
"""
from __future__ import annotations

import json
import math

from ..errors import SolverError


def dumps(obj, **kwargs) -> str:
    """``json.dumps(obj, allow_nan=False, **kwargs)``; SolverError naming the first
    non-finite number's path."""
    try:
        return json.dumps(obj, allow_nan=False, **kwargs)
    except ValueError:
        where = first_non_finite(obj)
        if where is None:
            raise
        raise SolverError(where, "NaN/inf", "the result holds a number that is not finite: nothing is written") \
            from None


def first_non_finite(obj, path: str = "result"):
    """Path of the first float of ``obj`` (dicts, lists, tuples) that is NaN or infinite."""
    if isinstance(obj, float):
        return None if math.isfinite(obj) else path
    if isinstance(obj, dict):
        items = ((f"{path}.{k}" if path else str(k), v) for k, v in obj.items())
    elif isinstance(obj, (list, tuple)):
        items = ((f"{path}[{i}]", v) for i, v in enumerate(obj))
    else:
        return None
    for p, v in items:
        hit = first_non_finite(v, p)
        if hit is not None:
            return hit
    return None
