"""Domain exceptions of the flexible-component package.

Every exception carries the offending value so that a caller (e.g. the scene
loader) can report *which* input was wrong, with its full dotted path.
"""
from __future__ import annotations

from typing import Any, Mapping


class GeometryError(ValueError):
    """A geometry parameter describes a part that cannot exist.

    Attributes
    ----------
    parameter : str
        Dotted name of the parameter, e.g. ``"teeth.n_teeth"`` or
        ``"bodies[2].component.teeth.n_teeth"``.
    value : Any
        The offending value (SI units).
    """

    def __init__(self, parameter: str, value: Any, reason: str):
        self.parameter = parameter
        self.value = value
        self.reason = reason
        super().__init__(f"{parameter} = {value!r}: {reason}")

    def with_prefix(self, prefix: str) -> "GeometryError":
        """Return the same error with ``prefix.`` prepended to the parameter path."""
        if not prefix:
            return self
        return type(self)(f"{prefix}.{self.parameter}", self.value, self.reason)


class MaterialError(GeometryError):
    """A material constant is outside its physical range."""


class MeshingError(RuntimeError):
    """gmsh failed to build or mesh a (valid-looking) geometry.

    Attributes
    ----------
    params : Mapping[str, Any]
        The full parameter set (as a flat dict) that caused the failure.
    """

    def __init__(self, component: str, params: Mapping[str, Any], cause: BaseException | str):
        self.component = component
        self.params = dict(params)
        self.cause = cause
        super().__init__(f"gmsh failed to mesh {component} with parameters {self.params}: {cause}")


class MeshCacheError(RuntimeError):
    """A mesh file on disk cannot be used: missing or wrong content hash, truncated,
    unparsable. Not a meshing failure (that is :class:`MeshingError`): a cache folder treats
    it as a miss (moves the file aside and meshes again); the committed reference meshes
    raise it.

    Attributes
    ----------
    path : str
        The mesh file.
    reason : str
        What failed (e.g. ``"content hash mismatch"``).
    hint : str
        What to do about it ("" if nothing to add).
    """

    def __init__(self, path, reason: str, hint: str = ""):
        self.path = str(path)
        self.reason = reason
        self.hint = hint
        super().__init__(f"mesh file {self.path}: {reason}" + (f"; {hint}" if hint else ""))


class CouplingError(ValueError):
    """An interface coupling cannot be built (e.g. overlapping slave sets)."""

    def __init__(self, interface: str, value: Any, reason: str):
        self.parameter = interface
        self.value = value
        super().__init__(f"interface {interface!r} ({value!r}): {reason}")
