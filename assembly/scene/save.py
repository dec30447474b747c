"""Scene -> TOML text and file: the inverse of :func:`assembly.scene.schema.load_scene`.

``scene_from_dict(tomllib.loads(scene_to_toml(scene))) == scene`` for every valid scene:
floats are written by ``repr`` (the shortest text that reads back to the same double;
``inf`` for a rigid direction), angles in radians (no ``_deg`` rounding), fields at their
default left out, a component (its fe_components parameter object) as a table with its
``kind`` first. The writer is generic over dataclasses and plain dicts
(:func:`assembly.scene.schema.to_dict`).
"""
from __future__ import annotations

import json
import math
import re
from pathlib import Path

from .. import arguments
from ..atomic_file import write_text_atomic
from .schema import to_dict
from .tables import Scene, scene_argument

_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")


def _key(k) -> str:
    k = str(k)
    return k if _BARE_KEY.fullmatch(k) else _string(k)


def _string(s: str) -> str:
    """A TOML basic string: JSON's escapes are TOML escapes; TOML also refuses a raw DEL."""
    return json.dumps(s, ensure_ascii=False).replace("\x7f", "\\u007f")


def _value(v) -> str:
    """An inline TOML value (scalar, array, inline table)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return _string(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + " }" if v else "{}"
    raise TypeError(f"cannot write {type(v).__name__} to TOML: {v!r}")


def _is_table_array(v) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def toml_text(data: dict) -> str:
    """TOML text of a plain dict tree: ``[table]`` for a dict, ``[[array]]`` for a
    non-empty list of dicts, inline values otherwise."""
    lines: list[str] = []
    _table(data, (), lines)
    return "\n".join(lines).lstrip("\n") + "\n"


def _table(d: dict, path: tuple, lines: list) -> None:
    for k, v in d.items():  # plain keys first: after a [header] they would belong to it
        if not isinstance(v, dict) and not _is_table_array(v):
            lines.append(f"{_key(k)} = {_value(v)}")
    for k, v in d.items():
        sub = path + (_key(k),)
        if isinstance(v, dict):
            lines += ["", f"[{'.'.join(sub)}]"]
            _table(v, sub, lines)
        elif _is_table_array(v):
            for item in v:
                lines += ["", f"[[{'.'.join(sub)}]]"]
                _table(item, sub, lines)


def scene_to_toml(scene: Scene) -> str:
    """TOML text of ``scene`` (SI units, angles in rad, defaults left out)."""
    scene_argument("scene", scene)
    return toml_text(to_dict(scene, defaults=False))


def save_scene(scene: Scene, path) -> Path:
    """Write ``scene`` as TOML to ``path`` atomically (:func:`assembly.atomic_file.write_text_atomic`):
    the file is the old one or the whole new one, never half-written."""
    scene_argument("scene", scene)
    arguments.file_path("path", path)
    return write_text_atomic(path, scene_to_toml(scene))
