"""Read and change one field of a scene by its path, as a design study does.

A path names tables as in the TOML file and list items by index or by ``name``::

    shafts.quill.k_torsion                    stages.stage1.planets.count
    bearings[2].k_radial                      stages[0].sun.bearing.k_radial
    bodies.wheel.flex.cutoff_hz               bodies.wheel.component.teeth.face_width
    meshes[0].helix_angle_deg                 (an angle in degrees, as in TOML)

:func:`with_values` changes the plain-dict form of the scene (:func:`assembly.scene.schema.to_dict`)
and builds it again with :func:`assembly.scene.schema.scene_from_dict`, so a new value gets the
same checks and messages as a TOML file; an error about a changed field names the path the
caller gave. A path that does not exist raises :class:`SceneError` naming it and listing
what exists at the step that failed.
"""
from __future__ import annotations

import dataclasses
import re
import types
import typing
from typing import Any, get_args, get_origin

from .. import arguments
from ..errors import SceneError
from .schema import field_types, join_path, scene_from_dict, to_dict
from .tables import Scene, scene_argument

_STEP = re.compile(r"\s*(?:([^.\[\]\s]+)|\[\s*(-?\d+)\s*\]|\[\s*'([^']*)'\s*\]|\[\s*\"([^\"]*)\"\s*\])\s*")


def parse_path(path: str) -> list:
    """``"stages[0].sun.bearing"`` -> ``["stages", 0, "sun", "bearing"]`` (ints: list
    indices; ``['odd name']`` quotes a name with dots or brackets)."""
    if not isinstance(path, str) or not path.strip():
        raise SceneError("path", path, "must be a non-empty string such as 'bearings[0].k_radial'")
    steps, pos, need_dot = [], 0, False
    while pos < len(path):
        if need_dot and path[pos] == ".":
            pos += 1
        elif need_dot and path[pos] != "[":
            raise SceneError(path, None, f"path: expected '.' or '[' at character {pos}")
        m = _STEP.match(path, pos)
        if m is None or m.end() == pos:
            raise SceneError(path, None, f"path: cannot read a name or [index] at character {pos}")
        name, index, q1, q2 = m.groups()
        steps.append(int(index) if index is not None else name if name is not None else q1 if q1 is not None else q2)
        pos, need_dot = m.end(), True
    return steps


def _dataclass_of(tp):
    """The dataclass inside ``Optional[...]``, or None (also for a union of several, such
    as a component: its table's ``kind`` names the class)."""
    if dataclasses.is_dataclass(tp):
        return tp
    found = [a for a in (get_args(tp) if get_origin(tp) in (typing.Union, types.UnionType) else ())
             if dataclasses.is_dataclass(a)]
    return found[0] if len(found) == 1 else None


def _item_type(tp):
    """The element dataclass of ``tuple[X, ...]`` (a list of tables), or None."""
    for a in get_args(tp) if get_origin(tp) is tuple else ():
        if dataclasses.is_dataclass(a):
            return a
    return None


def _component_class(table: dict):
    from fe_components.params import COMPONENT_KINDS
    return COMPONENT_KINDS.get(table.get("kind")) if isinstance(table, dict) else None


def _angle_fields(cls) -> set:
    return {f.name for f in dataclasses.fields(cls) if f.metadata.get("angle")} if cls else set()


def _keys_text(cls, node) -> str:
    """What may follow a table: its fields (or the keys it has) and the angles' _deg forms."""
    keys = [f.name for f in dataclasses.fields(cls) if f.init] if cls else sorted(node)
    text = ", ".join(keys)
    angles = sorted(_angle_fields(cls))
    if angles:
        text += "; angles also in degrees as " + ", ".join(f"{a}_deg" for a in angles)
    return text


def _items_text(items: list) -> str:
    names = [it.get("name") for it in items if isinstance(it, dict) and it.get("name") is not None]
    text = f"indices 0..{len(items) - 1}" if items else "no items"
    return text + (f" or names {names}" if names else "")


def _locate(data: dict, steps: list, user_path: str, create: bool, value=None):
    """Walk ``steps`` down the plain-dict scene. Returns (parent node, last key, the
    field's class context, canonical schema path). ``create``: make a missing optional
    table (e.g. ``flex``) on the way; ``value``: the value being set, shown in errors."""
    node, cls, canon = data, Scene, ""
    for k, step in enumerate(steps):
        here = "".join(f"[{s}]" if isinstance(s, int) else f".{s}" for s in steps[:k]).lstrip(".") or "<scene>"
        last = k == len(steps) - 1
        if isinstance(node, list):
            item_cls = cls
            if isinstance(step, int):
                if not -len(node) <= step < len(node):
                    raise SceneError(user_path, value, f"no item [{step}] in {here}: it has {_items_text(node)}")
                i = step % len(node)
            else:
                found = [j for j, it in enumerate(node) if isinstance(it, dict) and it.get("name") == step]
                if not found:
                    raise SceneError(user_path, value, f"no item named {step!r} in {here}: it has {_items_text(node)}")
                i = found[0]
            canon = f"{canon}[{i}]"
            if last:
                raise SceneError(user_path, value, f"names a whole item of {here}; give one of its fields: "
                                                  f"{_keys_text(item_cls, node[i])}")
            node, cls = node[i], item_cls
            continue
        if not isinstance(node, dict) or not isinstance(step, str):
            raise SceneError(user_path, value, f"{here} is a value, not a table or list")
        if cls is None and "kind" in node:  # a component table: its fields come from its kind
            cls = _component_class(node)
        if cls is not None:
            fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
            base = step[:-4] if step.endswith("_deg") else None
            if step not in fields and not (base in fields and fields[base].metadata.get("angle")) \
                    and not (cls.__module__.startswith("fe_components") and step in node):
                raise SceneError(user_path, value, f"no field {step!r} in {here}; it has: {_keys_text(cls, node)}")
            tp = field_types(cls)[step] if step in fields else None
        elif step not in node and not last:
            raise SceneError(user_path, value, f"no key {step!r} in {here}; it has: {_keys_text(None, node)}")
        else:
            tp = None
        canon = join_path(canon, step)
        if last:
            return node, step, cls, canon
        child = node.get(step)
        if child is None:
            sub = _dataclass_of(tp) if tp is not None else None
            if value is None and sub is not None:
                return None  # reading or removing below a table not given: nothing there
            if not create or sub is None:
                raise SceneError(user_path, value, f"{here}.{step} is not given (nothing to read below it)")
            child = node[step] = {}
        node, cls = child, (_item_type(tp) if isinstance(child, list) else _dataclass_of(tp)) if tp else None
    raise AssertionError("unreachable")


def get_value(scene: Scene, path: str, given: bool = False) -> Any:
    """The value at ``path`` as the model uses it (angles in rad; ``<angle>_deg`` in
    degrees; a table as a plain dict; a field left at its default gives the default): as
    typed in the scene, or, for a field left out that the scene derives (a mesh stiffness
    from ISO 6336-1, base radii and pressure angles from teeth, a gear blank's mass), the
    derived value. ``given``: only what the scene types (None for a derived field)."""
    import math
    scene_argument("scene", scene)
    steps = parse_path(arguments.text("path", path))
    given = arguments.flag("given", given)
    found = _locate(to_dict(scene), steps, path, create=False)
    if found is None:  # an optional table on the way is not given
        return None
    node, key, cls, _ = found
    if key in node:
        return node[key]
    if not given:
        derived = _locate(to_dict(scene, resolved=True), steps, path, create=False)
        if derived is not None and derived[1] in derived[0]:
            return derived[0][derived[1]]
        if derived is not None:
            node = derived[0]
    if key.endswith("_deg") and cls is not None and key[:-4] in _angle_fields(cls):
        rad = node.get(key[:-4])
        return None if rad is None else tuple(map(math.degrees, rad)) if isinstance(rad, list) else math.degrees(rad)
    if cls is not None:
        for f in dataclasses.fields(cls):
            if f.name == key:
                return None if f.default is dataclasses.MISSING else f.default
    return None


def value_kind(scene: Scene, path: str) -> str:
    """What the field at ``path`` holds: "bool", "int", "number" (a float; an angle in
    degrees), "text" or "other" (a table, a list, a union), from its value or, for a field
    not given, from its declared type."""
    value = get_value(scene, path)
    if value is None:
        found = _locate(to_dict(scene), parse_path(path), path, create=True, value=0)  # on a copy
        cls, key = found[2], found[1]
        if cls is None or not dataclasses.is_dataclass(cls):
            return "other"
        if key.endswith("_deg"):
            return "number"
        tp = field_types(cls).get(key)
        args = [a for a in get_args(tp) if a is not type(None)] if get_origin(tp) in (typing.Union, types.UnionType) \
            else [tp]
        tp = args[0] if len(args) == 1 else None
        return {bool: "bool", int: "int", float: "number", str: "text"}.get(tp, "other")
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, int):
        return "int"
    if isinstance(value, float):
        return "number"
    return "text" if isinstance(value, str) else "other"


def with_value(scene: Scene, path: str, value) -> Scene:
    """New validated scene with the field at ``path`` set to ``value`` (``None`` removes
    an optional field: its default applies)."""
    scene_argument("scene", scene)
    return with_values(scene, {arguments.text("path", path): value})


def with_values(scene: Scene, changes: dict) -> Scene:
    """New scene with every ``{path: value}`` of ``changes`` set, validated once."""
    scene_argument("scene", scene)
    for path in arguments.table("changes", changes):
        arguments.text("changes", path)
    data = to_dict(scene)
    canon = {}
    for path, value in changes.items():
        found = _locate(data, parse_path(path), path, create=True, value=value)
        if found is None:
            continue
        node, key, cls, c = found
        # an angle is held once: in rad under its name, or in deg under name_deg
        other = key[:-4] if key.endswith("_deg") else f"{key}_deg"
        node.pop(other, None)
        if value is None:
            node.pop(key, None)
        else:
            node[key] = to_dict(value) if dataclasses.is_dataclass(value) and not isinstance(value, type) else value
        canon[c] = path
    try:
        return scene_from_dict(data)
    except SceneError as exc:
        raise _user_error(exc, canon, changes) from None


def _user_error(exc: SceneError, canon: dict, changes: dict) -> SceneError:
    """``exc`` renamed to the path the caller gave, when it is about a changed field;
    otherwise it says which change led to it."""
    best = max((c for c in canon if exc.path == c or exc.path.startswith((c + ".", c + "["))), key=len, default=None)
    if best is not None:
        return SceneError(canon[best] + exc.path[len(best):], exc.value, exc.reason)
    told = ", ".join(f"{p} = {v!r}" for p, v in changes.items())
    return SceneError(exc.path, exc.value, f"{exc.reason} (after setting {told})")
