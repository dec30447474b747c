"""Scene files: TOML -> plain dicts -> typed, validated dataclasses.

Typed construction of frozen dataclasses from plain dicts (TOML tables).

One generic converter instead of a hand-written parser per table: every dataclass field is
read with its annotated type, unknown keys and missing fields are refused, and every error
names the full scene path (``stages[0].planets.count``) and the offending value. Scene and
component tables (fe_components parameters) go through the same converter, so a string, a
bool or a NaN where a number belongs is refused the same way in both. A ``component``
field holds the parameter object: its table (``kind`` picks the class) is converted once,
here -- also a plain dict given in Python, by :func:`check_instance`.

Field rules declared on the dataclasses are applied to every value before any other rule
uses it: a number's unit and range (:mod:`fe_components.fields`: finite, of physical
magnitude, in range) and a name's rule (:func:`name_problem`). :func:`check_instance`
applies the same types and rules to dataclasses built in Python (``Body(name=3)``,
``Bearing(k_radial="1e8")``), so the Python API gets the messages of a TOML file.

Angle fields (``metadata={"angle": True}``) are SI radians; a TOML file may instead give the
same quantity in degrees under the key ``<field>_deg`` (converted once, here).
"""
from __future__ import annotations

import contextvars
import dataclasses
import functools
import logging
import math
import numbers
import tomllib
import types
import typing
import unicodedata
from pathlib import Path
from typing import Any, Literal, Union, get_args, get_origin, get_type_hints

import numpy as np

from fe_components.errors import GeometryError
from fe_components.fields import value_problem
from fe_components.params import COMPONENT_KINDS, MAX_PLANETS, CarrierParams

from .. import arguments
from ..errors import SceneError
from .tables import MAX_NAME_LENGTH, BearingSpec, Scene

log = logging.getLogger(__name__)

#: Example scenes shipped with the package.
SCENE_DIR = Path(__file__).resolve().parent.parent / "scenes"
#: Folder of the scene file being read: a part file's relative path is relative to it.
_BASE_DIR: contextvars.ContextVar[Path | None] = contextvars.ContextVar("scene_base_dir", default=None)


def join_path(path: str, key: str) -> str:
    """``path.key``, or ``path['key']`` (escaped) for a key that is not a plain name."""
    if isinstance(key, str) and key.isidentifier():
        return f"{path}.{key}" if path else key
    return f"{path}[{key!r}]"


def _type_name(tp) -> str:
    if dataclasses.is_dataclass(tp):
        return "table"
    origin = get_origin(tp)
    if origin is tuple:
        return "array"
    if origin is Literal:
        return " | ".join(repr(a) for a in get_args(tp))
    return getattr(tp, "__name__", str(tp))


def convert(tp, value: Any, path: str, strict: bool = False):
    """Convert ``value`` to the annotated type ``tp`` or raise SceneError at ``path``.

    ``strict``: check a value built in Python instead (a dataclass field must hold an
    instance of its class, whose own fields are checked in turn by :func:`check_instance`;
    only a component or a member's bearing may still be given as a dict, converted as from
    a table).
    Ranges are the field rules' business (:func:`check_rules`), not the type's."""
    origin = get_origin(tp)
    if origin in (Union, types.UnionType):
        args = [a for a in get_args(tp) if a is not type(None)]
        if value is None:
            return None
        if frozenset(args) == _COMPONENT_CLASSES:
            return _component(value, path, strict)
        errors = []
        for a in args:
            try:
                return convert(a, value, path, strict)
            except SceneError as exc:
                errors.append(exc)
        raise errors[0]
    if origin is Literal:
        # type and value: True is not the order 1
        if not any(type(value) is type(a) and value == a for a in get_args(tp)):
            raise SceneError(path, value, f"must be one of {list(get_args(tp))}")
        return value
    if tp is float:
        if isinstance(value, bool) or not isinstance(value, numbers.Real):  # numpy numbers too
            raise SceneError(path, value, "must be a number")
        return float(value)
    if tp is int:
        if isinstance(value, bool) or not isinstance(value, numbers.Integral):
            raise SceneError(path, value, "must be an integer")
        return int(value)
    if tp is bool:
        if not isinstance(value, bool):
            raise SceneError(path, value, "must be true or false")
        return value
    if tp is str:
        if not isinstance(value, str):
            raise SceneError(path, value, "must be a string")
        return value
    if origin is tuple:
        args = get_args(tp)
        if not isinstance(value, (list, tuple, np.ndarray)):
            raise SceneError(path, value, "must be an array")
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(convert(args[0], v, f"{path}[{i}]", strict) for i, v in enumerate(value))
        if len(value) != len(args):
            raise SceneError(path, value, f"must have exactly {len(args)} entries")
        return tuple(convert(a, v, f"{path}[{i}]", strict) for i, (a, v) in enumerate(zip(args, value)))
    if dataclasses.is_dataclass(tp):
        if strict:
            if isinstance(value, dict) and tp is BearingSpec:     # a member's bearing: a table, as in TOML
                return check_instance(from_dict(tp, value, path), path)
            if not isinstance(value, tp):
                raise SceneError(path, value, f"must be a {tp.__name__}")
            return check_instance(value, path)
        return from_dict(tp, value, path)
    if tp is dict:
        if not isinstance(value, dict):
            raise SceneError(path, value, "must be a table")
        return value
    if tp is typing.Any:
        return value
    raise TypeError(f"schema: unsupported annotation {tp!r} at {path}")


#: The fe_components parameter classes a ``component`` field may hold.
_COMPONENT_CLASSES = frozenset(COMPONENT_KINDS.values())


def _component(value, path: str, strict: bool):
    """A component field: a parameter object (checked field by field when built in Python),
    or a table / dict with ``kind``, converted once (:func:`component_from_table`)."""
    if isinstance(value, tuple(_COMPONENT_CLASSES)):
        return check_instance(value, path) if strict else value
    if isinstance(value, dict):
        return component_from_table(value, path)
    names = ", ".join(c.__name__ for c in COMPONENT_KINDS.values())
    raise SceneError(path, value, f"must be a component ({names}) or a table with kind "
                                  f"({', '.join(COMPONENT_KINDS)})")


def from_dict(cls, data: Any, path: str = ""):
    """Build dataclass ``cls`` from ``data`` (a dict), refusing unknown and missing keys.

    A dataclass whose fields are all required may also be given as an array of its fields
    in order (a shaft segment as ``[length, diameter]``)."""
    if isinstance(data, cls):
        return data
    if isinstance(data, (list, tuple)) and _all_required(cls):
        names = [f.name for f in dataclasses.fields(cls) if f.init]
        if len(data) != len(names):
            raise SceneError(path or cls.__name__, list(data), f"must be a table or an array [{', '.join(names)}]")
        data = dict(zip(names, data))
    if not isinstance(data, dict):
        raise SceneError(path or cls.__name__, data, f"must be a table of {cls.__name__} fields")
    hints = field_types(cls)
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    kwargs = {}
    in_degrees = set()
    for key, value in data.items():
        p = join_path(path, key)
        if key in fields:
            name = key
            check_rules(fields[name], value, p)  # first: its message says unit and range
            val = convert(hints[name], value, p)
        elif key.endswith("_deg") and key[:-4] in fields and fields[key[:-4]].metadata.get("angle"):
            name = key[:-4]
            if name in data:
                raise SceneError(p, value, f"give either {name} (rad) or {key} (deg), not both")
            deg = convert(hints[name], value, p)  # same type as the radian field
            if deg is None:
                val = None
            elif isinstance(deg, tuple):
                val = tuple(math.radians(d) for d in deg)
            else:
                val = math.radians(deg)
            check_rules(fields[name], val, p, degrees_as_written)
            in_degrees.add(name)
        else:
            allowed = sorted(fields)
            raise SceneError(p, value, f"unknown key; allowed keys: {', '.join(allowed)}")
        kwargs[name] = val
    for name, f in fields.items():
        if name not in kwargs and f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
            raise SceneError(join_path(path, name), None, f"missing required field ({_type_name(hints[name])})")
    try:
        obj = cls(**kwargs)
    except GeometryError as err:  # a data type that checks its own values (e.g. Material)
        raise SceneError(f"{path}.{err.parameter}" if path else err.parameter, err.value, err.reason) from None
    return keep_degrees(in_degrees, obj)


#: Attribute on a dataclass read from a table: the angle fields given in degrees.
_DEGREES = "_fields_given_in_degrees"


def keep_degrees(source, obj):
    """Mark on ``obj`` the angle fields the user gave in degrees: those of ``source`` (a
    set of field names, or an object read by :func:`from_dict`), so that a message about
    them can show the value in degrees under the key the user wrote. Returns ``obj``."""
    names = source if isinstance(source, (set, frozenset)) else given_in_degrees(source)
    if names and dataclasses.is_dataclass(obj):
        object.__setattr__(obj, _DEGREES, frozenset(names))
    return obj


def given_in_degrees(obj) -> frozenset:
    """The angle fields of ``obj`` that its table gave in degrees (``<field>_deg``)."""
    return getattr(obj, "__dict__", {}).get(_DEGREES, frozenset())


#: Attribute on carrier parameters read from a table that gave ``n_planets``: its value.
_N_PLANETS = "_n_planets_given"


def as_written(obj, field: str, path: str, value=None):
    """(path, value) of ``obj.field`` (or ``value`` of that field) as the user wrote it:
    ``path_deg`` and degrees for an angle given in degrees, a carrier's ``n_planets`` for
    the planet angles it gave, else ``path`` and SI."""
    if field == "planet_angles" and _N_PLANETS in getattr(obj, "__dict__", {}):
        return f"{path.removesuffix(field)}n_planets", obj.__dict__[_N_PLANETS]
    value = getattr(obj, field) if value is None else value
    if field in given_in_degrees(obj) and isinstance(value, (int, float)):
        return f"{path}_deg", degrees_as_written(value)
    if field in given_in_degrees(obj) and isinstance(value, tuple):
        return f"{path}_deg", [degrees_as_written(v) for v in value]
    return path, value


def degrees_as_written(value: float) -> float:
    """An angle (rad) back in the degrees it was read from: 20.0, not 20.000000000000004
    (12 significant digits undo the round trip through radians)."""
    return float(f"{math.degrees(value):.12g}")


@functools.cache
def field_types(cls) -> dict:
    """Resolved field annotations of a dataclass (computed once per class)."""
    return get_type_hints(cls)


def check_rules(f: dataclasses.Field, value, path: str, shown=None) -> None:
    """Apply the rules declared on field ``f`` (a number's unit and range, a name's rule)
    to ``value``; ``shown`` maps a bad number to the value the user wrote (degrees)."""
    rule = f.metadata.get("quantity")
    if rule is not None:
        p = value_problem(rule, value, isinstance(value, (list, tuple, np.ndarray)))
        if p is not None:
            bad = shown(p[1]) if shown is not None and isinstance(p[1], (int, float)) else p[1]
            raise SceneError(path + p[0], bad, p[2])
    if f.metadata.get("name") and value is not None:
        why = name_problem(value)
        if why:
            raise SceneError(path, value, why)


def name_problem(name) -> str | None:
    """Why ``name`` cannot name a body, stage, element or scene (it becomes part of file
    names and of error messages), or None."""
    if not isinstance(name, str):
        return "must be a string"
    if not name:
        return "must not be empty"
    if len(name) > MAX_NAME_LENGTH:
        return f"longer than {MAX_NAME_LENGTH} characters ({len(name)})"
    if any(unicodedata.category(c) in ("Cc", "Cf", "Cs") for c in name):
        return "must not contain control characters"
    if "/" in name or "\\" in name:
        return "must not contain a path separator ('/' or '\\')"
    return None


def check_instance(obj, path: str = ""):
    """Check a dataclass built in Python field by field, as if read from a table: the
    field's rules, then its annotated type (:func:`convert` in strict mode, recursing into
    nested dataclasses). Raises SceneError naming ``path.field``. Returns ``obj``, or a copy
    holding the parameter objects of the components given as dicts (:func:`checked_fields`)."""
    changes = checked_fields(obj, path)
    return keep_degrees(obj, dataclasses.replace(obj, **changes)) if changes else obj


def checked_fields(obj, path: str = "") -> dict:
    """Check ``obj`` as :func:`check_instance` does; returns {field: value} of the fields
    whose value the check converted: a component given as a dict (its parameter object),
    or a table or list holding one."""
    hints = field_types(type(obj))
    changes = {}
    for f in dataclasses.fields(obj):
        if f.init:
            p = join_path(path, f.name)
            value = getattr(obj, f.name)
            check_rules(f, value, p)
            new = convert(hints[f.name], value, p, strict=True)
            if _converted(value, new):
                changes[f.name] = new
    return changes


def _converted(old, new) -> bool:
    """Whether :func:`convert` made a new object worth keeping of ``old``: a component dict
    turned into its parameters, or a dataclass or array holding one (numbers and plain
    tables stay as the caller gave them)."""
    if isinstance(old, dict):
        return not isinstance(new, dict)
    if isinstance(old, (list, tuple)) and isinstance(new, tuple) and len(old) == len(new):
        return any(_converted(a, b) for a, b in zip(old, new))
    return dataclasses.is_dataclass(old) and new is not old


def _all_required(cls) -> bool:
    return all(f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
               for f in dataclasses.fields(cls) if f.init)


def component_from_table(table: Any, path: str):
    """fe_components parameters from a ``component`` table: ``kind`` (pinion, wheel,
    carrier, cylinder, file) picks the parameter class, the other keys are its fields (angles
    may be given in degrees under ``<name>_deg``). A carrier may give ``n_planets`` (and
    ``first_planet_angle``) instead of ``planet_angles``. A ``file`` part's relative path is
    relative to the folder of the scene file being read."""
    kind = table.get("kind") if isinstance(table, dict) else None
    if not isinstance(kind, str) or kind not in COMPONENT_KINDS:
        raise SceneError(f"{path}.kind", kind, f"must be one of {sorted(COMPONENT_KINDS)}")
    data = {k: v for k, v in table.items() if k != "kind"}
    cls = COMPONENT_KINDS[kind]
    if kind == "file" and isinstance(data.get("file"), str) and _BASE_DIR.get() is not None:
        data["file"] = str(_BASE_DIR.get() / Path(data["file"]).expanduser())  # absolute stays absolute
    if cls is CarrierParams and "n_planets" in data:
        params = from_dict(cls, _equally_spaced_planets(data, path), path)
        object.__setattr__(params, _N_PLANETS, data["n_planets"])  # as written, for messages
        return params
    return from_dict(cls, data, path)


def _equally_spaced_planets(data: dict, path: str) -> dict:
    """``n_planets`` (+ ``first_planet_angle`` in rad, or ``_deg``) -> ``planet_angles``."""
    data = dict(data)
    n = data.pop("n_planets")
    if "planet_angles" in data or "planet_angles_deg" in data:
        raise SceneError(f"{path}.n_planets", n, "give either n_planets or planet_angles, not both")
    n = convert(int, n, f"{path}.n_planets")
    if not 2 <= n <= MAX_PLANETS:
        raise SceneError(f"{path}.n_planets", n, f"must be an integer in 2..{MAX_PLANETS}")
    if "first_planet_angle_deg" in data:
        first = math.radians(convert(float, data.pop("first_planet_angle_deg"), f"{path}.first_planet_angle_deg"))
    else:
        first = convert(float, data.pop("first_planet_angle", 0.0), f"{path}.first_planet_angle")
    data["planet_angles"] = [first + 2 * math.pi * i / n for i in range(n)]
    return data


def to_dict(obj, defaults: bool = True, resolved: bool = False) -> dict:
    """Plain-dict view of a dataclass tree (radians kept; None fields dropped; a scene as
    the user gave it, see :meth:`Scene.as_given`, or with ``resolved`` as the model uses it:
    gear numbers derived from teeth, bodies placed; with
    ``defaults=False`` also the fields at their default). A component's parameters
    (fe_components) become a table with its ``kind`` first, as a scene file gives it."""
    from fe_components.params import component_kind
    out = {"kind": component_kind(obj)} if type(obj) in _COMPONENT_CLASSES else {}
    given = functools.partial(getattr, obj) if resolved else \
        getattr(obj, "as_given", functools.partial(getattr, obj))  # a Scene: as written
    for f in dataclasses.fields(obj):
        if not f.init:  # derived on construction (a part file's content hash)
            continue
        v = given(f.name)
        if v is None or not defaults and f.default is not dataclasses.MISSING and _same(v, f.default):
            continue
        out[f.name] = _plain(v, defaults)
    return out


def _plain(v, defaults: bool):
    """A field value as plain data: dataclasses -> dicts, tuples -> lists (recursively)."""
    if dataclasses.is_dataclass(v) and not isinstance(v, type):
        return to_dict(v, defaults)
    if isinstance(v, (tuple, list)):
        return [_plain(x, defaults) for x in v]
    if isinstance(v, dict):
        return {k: _plain(x, defaults) for k, x in v.items()}
    return v


def _same(a, b) -> bool:
    """``a == b`` for field values, of the same type (1 is not 1.0, True is not 1)."""
    try:
        return type(a) is type(b) and bool(a == b)
    except (TypeError, ValueError):
        return False


def is_bare_name(path) -> bool:
    """A file name without any folder part (``kahraman_beta0.toml``, not ``./x.toml``)."""
    return Path(path).name == str(path)


def resolve_scene_path(path) -> Path:
    """The scene file to read: ``path`` as given if it exists; a bare file name (no folder
    part) that does not exist here names a scene shipped in ``assembly/scenes`` (``.toml`` may
    be left out). A path with
    a folder part never falls back to a shipped scene (a typo in the folder must not run an
    example under the user's title)."""
    p = Path(arguments.file_path("scene", path))
    if p.exists():
        return p
    shipped = SCENE_DIR / p.name
    if is_bare_name(path) and not p.suffix and not shipped.exists():
        shipped = shipped.with_suffix(".toml")  # a shipped example named without .toml
    if is_bare_name(path) and shipped.exists():
        log.info("%s: not in the working folder; reading the shipped example %s", path, shipped)
        return shipped
    hint = arguments.nearest(p.stem, [s.stem for s in shipped_scenes()]) if is_bare_name(path) else ""
    if shipped.exists():
        hint = f" (a shipped example of that name exists: give the bare name {p.name!r} to run it)"
    raise SceneError("scene", str(path), f"no such file{hint}")


def load_scene(path, _chain: tuple = ()) -> Scene:
    """Read and validate a scene file (UTF-8 TOML; :func:`resolve_scene_path` finds it);
    :class:`SceneError` names the offending field path, or the file and what is wrong with it.
    A file with ``extends`` varies another scene file (:mod:`assembly.scene.variant`)."""
    p = resolve_scene_path(path)
    try:
        raw = p.read_bytes()
    except OSError as exc:
        raise SceneError("scene", str(p), f"cannot read: {exc.strerror or exc}") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SceneError("scene", str(p), f"not UTF-8 text at byte {exc.start} "
                                          f"(0x{raw[exc.start]:02x}); save the file as UTF-8") from None
    try:
        data = tomllib.loads(text.removeprefix("\ufeff"))  # a BOM some editors write
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(str(p), "<file>", f"not valid TOML: {exc}") from None
    from .variant import is_variant, variant_scene
    token = _BASE_DIR.set(p.parent.absolute())
    try:
        if is_variant(data):
            return variant_scene(data, p, load_scene, _chain)
        return scene_from_dict(data)
    finally:
        _BASE_DIR.reset(token)


def scene_from_dict(data: dict) -> Scene:
    """Build and validate a scene from a plain dict (e.g. parsed TOML)."""
    arguments.table("data", data)
    return from_dict(Scene, data, "")


def shipped_scenes() -> list[Path]:
    """Example scenes shipped in the package, sorted by name."""
    return sorted(SCENE_DIR.glob("*.toml"))
