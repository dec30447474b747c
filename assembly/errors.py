"""Domain exceptions of the multibody core.

Every error carries the scene path of the offending field (e.g. ``stages[0].planets.count``)
and the value that failed, so the CLI can print one clear line and exit with code 2.
"""
from __future__ import annotations


class SceneError(ValueError):
    """A scene (TOML file or Python API) describes something that cannot be modelled."""

    def __init__(self, path: str, value, reason: str):
        self.path = path
        self.value = value
        self.reason = reason
        super().__init__(f"{path} = {value!r}: {reason}")


class MechanismError(RuntimeError):
    """The assembled model has more zero-stiffness motions than the scene allows."""

    def __init__(self, description: str, value=None):
        self.description = description
        self.value = value
        super().__init__(description)


class SolverError(RuntimeError):
    """An eigen solve failed its own accuracy checks."""

    def __init__(self, quantity: str, value, reason: str):
        self.quantity = quantity
        self.value = value
        super().__init__(f"{quantity} = {value!r}: {reason}")
