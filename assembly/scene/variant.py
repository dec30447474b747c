"""A scene file that varies another: ``extends`` names the base scene file and ``[set]``
changes fields of it by path (:mod:`assembly.scene.edit`), so a design variant (another fidelity,
a softer bearing, a stiffer shaft) is a few lines instead of a copy of the whole scene::

    extends = "nrel5mw.toml"          # relative to this file's folder, or a shipped scene
    name = "NREL 5 MW, flexible carriers and wheel"
    [set]
    "stages.stage1.carrier.fidelity" = "flexible"
    "bodies.wheel.fidelity" = "flexible"

Only ``extends``, ``name``, ``description`` and ``set`` may appear at the top level of such
a file. The result is an ordinary validated :class:`~assembly.scene.tables.Scene`: errors in a
changed field name the path under ``set``, errors in the base name the base file.
"""
from __future__ import annotations

from pathlib import Path

from ..errors import SceneError

#: Keys a variant file may hold at its top level.
VARIANT_KEYS = ("extends", "name", "description", "set")
#: Longest chain of files extending one another (a cycle is refused before this).
MAX_DEPTH = 8


def is_variant(data: dict) -> bool:
    return isinstance(data, dict) and "extends" in data


def variant_scene(data: dict, where: Path, load, chain: tuple = ()):
    """The scene a variant file describes: ``load(path, chain)`` reads the base (the caller's
    scene loader, so a base may itself be a variant); ``where`` is the variant file."""
    extra = sorted(set(data) - set(VARIANT_KEYS))
    if extra:
        raise SceneError(extra[0], data[extra[0]], f"a scene with 'extends' takes only {list(VARIANT_KEYS)} "
                                                   "at its top level: change other fields under [set]")
    base = data["extends"]
    if not isinstance(base, str) or not base.strip():
        raise SceneError("extends", base, "must name a scene file")
    changes = data.get("set", {})
    if not isinstance(changes, dict):
        raise SceneError("set", changes, "must be a table of {path = value}")
    if len(chain) >= MAX_DEPTH or where.resolve() in chain:
        raise SceneError("extends", base, f"scene files extend one another in a cycle or deeper than {MAX_DEPTH}")
    local = where.parent / base
    scene = load(local if local.exists() else base, chain + (where.resolve(),))
    changes = dict(changes)
    for key in ("name", "description"):
        if key in data:
            changes[key] = data[key]
    if not changes:
        return scene
    try:
        return scene.with_values(changes)
    except SceneError as exc:
        changed = any(exc.path == k or exc.path.startswith((k + ".", k + "[")) for k in changes)
        if changed and exc.path not in ("name", "description"):
            raise SceneError(f"set.{exc.path}", exc.value, exc.reason) from None
        raise
