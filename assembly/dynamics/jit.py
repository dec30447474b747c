"""The optional compiler of the time step: numba's ``njit`` when numba is installed (the
``speed`` extra), else the plain Python function, so that the same code runs either way.

Two switches: :data:`COMPILED`, the laws (mesh forces, shaft torques, Newton's small solve)
run compiled wherever they are called; :data:`ENABLED`, :func:`assembly.dynamics.transient.integrate`
runs its steps in compiled stretches (:mod:`assembly.dynamics.step_kernel`). Both are on
when numba is installed and the environment does not set ``FLEXGEAR_NO_NUMBA``; a test turns
off the step alone (the Python step on the same compiled laws: the same numbers bit for bit)
or both (numba's absence).
"""
from __future__ import annotations

import os

try:                                    # the optional extra
    import numba
except ImportError:                     # pragma: no cover - exercised where numba is absent
    numba = None

#: The laws run compiled (numba installed and not switched off).
COMPILED = numba is not None and not os.environ.get("FLEXGEAR_NO_NUMBA")
#: The steps run in compiled stretches.
ENABLED = COMPILED


def njit(fn):
    """``fn`` compiled by numba (no Python objects, cached on disk), or ``fn`` itself."""
    if numba is None:
        return fn
    return numba.njit(cache=True, nogil=True)(fn)


def pick(fn):
    """The compiled ``fn`` while :data:`COMPILED`, else its plain Python form."""
    return fn if COMPILED else getattr(fn, "py_func", fn)


def plain(fn):
    """The plain Python form of ``fn`` (compiled or not): for calls on arrays of any shape."""
    return getattr(fn, "py_func", fn)


def either(compiled, vectorized):
    """``compiled`` while :data:`COMPILED` and numba compiled it, else ``vectorized`` (the
    same law on numpy arrays, every element at once)."""
    return compiled if COMPILED and hasattr(compiled, "py_func") else vectorized
