"""Load a scene from a TOML file (same structure as the dataclasses, SI units)."""
from __future__ import annotations

import tomllib
from pathlib import Path

from .errors import SceneError
from .schema import from_dict
from .scene import Scene

SCENE_DIR = Path(__file__).parent / "scenes"


def resolve_scene_path(path) -> Path:
    """A path as given, or the name of a scene shipped in ``assembly/scenes``."""
    p = Path(path)
    if p.exists():
        return p
    shipped = SCENE_DIR / p.name
    if shipped.exists():
        return shipped
    raise SceneError("scene", str(path), "no such file (nor a shipped example scene of that name)")


def load_scene(path) -> Scene:
    """Read and validate a scene file; :class:`SceneError` names the offending field path."""
    p = resolve_scene_path(path)
    try:
        with open(p, "rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(str(p), "<file>", f"not valid TOML: {exc}") from None
    except OSError as exc:
        raise SceneError("scene", str(p), f"cannot read: {exc.strerror}") from None
    return scene_from_dict(data)


def scene_from_dict(data: dict) -> Scene:
    """Build and validate a scene from a plain dict (e.g. parsed TOML)."""
    return from_dict(Scene, data, "")


def shipped_scenes() -> list[Path]:
    """Example scenes shipped in the package, sorted by name."""
    return sorted(SCENE_DIR.glob("*.toml"))
