"""Domain exceptions of the Craig-Bampton package.

Every exception carries the quantity that failed and its value as attributes,
so a caller can react programmatically and a log line is self-explanatory.
"""
from __future__ import annotations

import numpy as np


class ReductionError(ValueError):
    """A reduction input or result is invalid.

    Attributes
    ----------
    quantity : str
        Name of the offending quantity (e.g. ``"boundary_dofs"``).
    value : object
        The value that failed the check.
    """

    def __init__(self, message: str, quantity: str, value=None):
        super().__init__(f"{message} [{quantity}={value!r}]")
        self.quantity = quantity
        self.value = value


class InteriorMechanismError(ReductionError):
    """The interior stiffness K_ii is singular: fixing the boundary DOFs leaves a
    free (zero-energy) motion of the interior.

    A property of one component and its choice of boundary DOFs (the reduction
    cannot proceed), not of a whole assembled model.

    Attributes
    ----------
    motion : str
        Human-readable name of the free motion, e.g. ``"rotation about z"``
        or ``"translation x + rotation about z"``.
    components : numpy.ndarray, shape (6,)
        Participation of the rigid-body motions [tx, ty, tz, rx, ry, rz] in the
        free motion (unit length), NaN if the motion is not a rigid-body one.
    pivot : float
        The pivot / Rayleigh quotient that revealed the singularity (N/m scale).
    """

    def __init__(self, message: str, motion: str, components=None, pivot=None):
        super().__init__(message, quantity="K_ii free motion", value=motion)
        self.motion = motion
        self.components = (np.full(6, np.nan) if components is None
                           else np.asarray(components, dtype=float))
        self.pivot = pivot


class ModeLimitError(ReductionError):
    """More fixed-interface modes lie below the cutoff than the reductor may keep.

    Attributes
    ----------
    max_modes : int
        The limit (``CraigBamptonReductor(max_modes=...)``).
    highest_hz : float
        The highest frequency found (Hz), still below the cutoff.
    """

    def __init__(self, cutoff_hz: float, max_modes: int, highest_hz: float):
        super().__init__(f"more than {max_modes} fixed-interface modes lie below the cutoff "
                         f"(mode {max_modes + 1} at {highest_hz:.6g} Hz)", "cutoff_hz", cutoff_hz)
        self.max_modes = max_modes
        self.highest_hz = highest_hz


class EigenSolveError(ReductionError):
    """The eigen solver did not reach the requested residual."""


class CacheError(ReductionError):
    """A persisted superelement is unreadable or of an unknown version."""
