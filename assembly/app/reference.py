"""The scene reference (Markdown), generated from the scene dataclasses.

Walks :class:`assembly.scene.tables.Scene` and every dataclass reachable from its fields (nested
dataclasses become sub-tables, arrays of dataclasses ``[[tables]]``, a ``component`` table
one section per ``kind``) and writes, per table, every key with its type (from the
annotation), unit and allowed range (from the field's :class:`fe_components.fields.Quantity`),
default, degree form and description (:mod:`assembly.scene.docs`). ``flexgear reference``
prints it; ``docs/scene_reference.md`` is its committed output (a test keeps them equal).
"""
from __future__ import annotations

import dataclasses
import math
import types
import typing
from dataclasses import dataclass
from pathlib import Path
from typing import Literal, Union, get_args, get_origin

from fe_components.params import COMPONENT_KINDS

from ..scene import docs as scene_docs
from ..scene.tables import Body, Scene

#: The committed reference, relative to the repository root.
REFERENCE_PATH = Path("docs") / "scene_reference.md"
#: The hand-written multi-stage walk-through the reference links to.
WALKTHROUGH = "scene_walkthrough.md"
#: Dict-typed fields whose table is one of several dataclasses, chosen by its ``kind`` key
#: (:func:`assembly.scene.schema.component_from_table`).
KIND_TABLES = {(Body, "component"): COMPONENT_KINDS}


@dataclass(frozen=True)
class Table:
    """One documented table: the dataclass, the TOML paths it appears at (``bodies.flex``),
    whether it is an array of tables, and the component ``kind`` that selects it."""

    cls: type
    paths: tuple[str, ...]
    array: bool = False
    kind: str | None = None


def _strip_optional(tp):
    if get_origin(tp) in (Union, types.UnionType):
        args = [a for a in get_args(tp) if a is not type(None)]
        if len(args) == 1:
            return args[0]
    return tp


def _dataclass_of(tp):
    """(dataclass, is_array) behind an annotation, or (None, False)."""
    tp = _strip_optional(tp)
    if dataclasses.is_dataclass(tp):
        return tp, False
    if get_origin(tp) is tuple:
        args = get_args(tp)
        if len(args) == 2 and args[1] is Ellipsis and dataclasses.is_dataclass(args[0]):
            return args[0], True
    return None, False


def init_fields(cls) -> list[dataclasses.Field]:
    """The fields a table of ``cls`` accepts as keys."""
    return [f for f in dataclasses.fields(cls) if f.init]


def tables(root=Scene) -> list[Table]:
    """Every table reachable from ``root``, depth first in field order; a class reached at
    several paths (a member's ``bearing``, ``flex``) is one table listing all of them."""
    found: dict[type, dict] = {}
    order: list[type] = []

    def visit(cls, path: str, array: bool, kind=None):
        if cls not in found:
            found[cls] = {"paths": [], "array": array, "kind": kind}
            order.append(cls)
        if path not in found[cls]["paths"]:
            found[cls]["paths"].append(path)
        hints = typing.get_type_hints(cls)
        groups: dict[type, list[str]] = {}
        for f in init_fields(cls):
            sub, arr = _dataclass_of(hints[f.name])
            if sub is not None:
                groups.setdefault((sub, arr), []).append(f.name)
            for k, kcls in KIND_TABLES.get((cls, f.name), {}).items():
                visit(kcls, _join(path, f.name), False, k)
        for (sub, arr), names in groups.items():
            name = names[0] if len(names) == 1 else "<" + "|".join(names) + ">"
            visit(sub, _join(path, name), arr)

    visit(root, "", False)
    return [Table(c, tuple(found[c]["paths"]), found[c]["array"], found[c]["kind"]) for c in order]


def _join(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key


def type_text(tp) -> str:
    """A TOML type in words, from a field annotation."""
    tp = _strip_optional(tp)
    origin = get_origin(tp)
    if origin is Literal:
        return "one of " + ", ".join(f"'{a}'" if isinstance(a, str) else str(a) for a in get_args(tp))
    if origin is tuple:
        args = get_args(tp)
        if len(args) == 2 and args[1] is Ellipsis:
            inner = args[0]
            if dataclasses.is_dataclass(inner):
                req = [f.name for f in init_fields(inner)
                       if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]
                if len(req) == len(init_fields(inner)):
                    return f"array of [{', '.join(req)}] arrays or tables"
                return "array of tables"
            return f"array of {_plural(type_text(inner))}"
        if len(set(args)) == 1:
            return f"array of {len(args)} {_plural(type_text(args[0]))}"
        return "array of " + ", ".join(type_text(a) for a in args)
    if dataclasses.is_dataclass(tp) or tp is dict:
        return "table"
    if origin in (Union, types.UnionType) and all(dataclasses.is_dataclass(a)
                                                  for a in get_args(tp) if a is not type(None)):
        return "table (fields chosen by `kind`)"
    return {float: "number", int: "integer", str: "string", bool: "boolean"}.get(tp, getattr(tp, "__name__", str(tp)))


def _plural(text: str) -> str:
    if text.startswith("array of 3 "):
        return "arrays of 3 " + text[len("array of 3 "):]
    return {"number": "numbers", "integer": "integers", "string": "strings"}.get(text, text)


def default_text(f: dataclasses.Field) -> str:
    """The default in TOML spelling, or ``required``."""
    if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
        return "required"
    value = f.default if f.default is not dataclasses.MISSING else f.default_factory()
    return _toml(value)


def _toml(value) -> str:
    if value is None:
        return "none"
    if dataclasses.is_dataclass(value):
        return "the table's defaults"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and math.isinf(value):
        return "inf"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return repr(value)


def unit_text(f: dataclasses.Field) -> str:
    rule = f.metadata.get("quantity")
    if rule is None:
        return ""
    return rule.unit or "-"


def range_text(f: dataclasses.Field) -> str:
    """Allowed values from the field's rule (angles in degrees), e.g. ``> 0 kg``."""
    rule = f.metadata.get("quantity")
    if rule is None:
        return ""
    bounded = any(getattr(rule, b) is not None for b in ("gt", "ge", "lt", "le", "abs_lt")) or rule.nonzero
    parts = [rule.range_text() if bounded else "any"]
    if rule.integer:
        parts.append("integer")
    if rule.inf_ok:
        parts.append("inf = rigid")
    if rule.hint:
        parts.append(rule.hint)
    if rule.plausible is not None:
        parts.append(rule.plausible.text())
    return "; ".join(parts)


def deg_key(f: dataclasses.Field) -> str:
    """The key that gives this angle in degrees, or ''."""
    return f"{f.name}_deg" if f.metadata.get("angle") else ""


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _heading(t: Table) -> str:
    wrap = ("[[", "]]") if t.array else ("[", "]")
    if not t.paths[0]:
        return "Scene (top level)"
    head = ", ".join(f"`{wrap[0]}{p}{wrap[1]}`" for p in t.paths)
    return f"{head} -- kind = \"{t.kind}\"" if t.kind else head


def table_rows(t: Table) -> list[list[str]]:
    """Key, type, unit, allowed, default, degree key, description of each key of ``t``."""
    hints = typing.get_type_hints(t.cls)
    docs = scene_docs.FIELDS.get(t.cls.__name__, {})
    rows = []
    if t.kind:
        rows.append(["kind", "one of " + ", ".join(f"'{k}'" for k in COMPONENT_KINDS), "", "", "required", "",
                     f"Component kind; \"{t.kind}\" selects this table."])
    for f in init_fields(t.cls):
        rows.append([f.name, type_text(hints[f.name]), unit_text(f), range_text(f), default_text(f),
                     deg_key(f), docs.get(f.name, "**undocumented**")])
    for key, text in scene_docs.EXTRA_KEYS.get(t.cls.__name__, {}).items():
        rows.append([key, "", "", "", "", "", text])
    return rows


def section(t: Table) -> str:
    lines = [f"## {_heading(t)}", ""]
    note = scene_docs.NOTES.get(t.cls.__name__)
    if note:
        lines += [note, ""]
    lines += ["| key | type | unit | allowed | default | in degrees | description |",
              "|---|---|---|---|---|---|---|"]
    for key, *rest in table_rows(t):
        cells = [f"`{key}`"] + [_cell(c) if c else "" for c in rest[:4]]
        cells.append(f"`{rest[4]}`" if rest[4] else "")
        cells.append(_cell(rest[5]))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def reference_markdown() -> str:
    """The whole scene reference as Markdown."""
    ts = tables()
    toc = []
    for t in ts:
        title = _heading(t)
        toc.append(f"- {title}")
    head = [
        "# Scene reference",
        "",
        "Generated by `flexgear reference` from the scene dataclasses (`assembly/scene/tables.py`, "
        "`fe_components/params.py`, `fe_components/material.py`) and their descriptions "
        "(`assembly/scene/docs.py`); do not edit by hand. A worked multi-stage scene, concept by "
        f"concept: [{WALKTHROUGH}]({WALKTHROUGH}).",
        "",
        "Columns: *type* from the field's annotation; *unit* and *allowed* from its declared "
        "quantity (angles shown in degrees); *default* `required` when the key must be given, "
        "`none` when it is optional without a value; *in degrees* the key that gives an angle in "
        "degrees instead.",
        "",
        "Tables:",
        "",
        *toc,
        "",
    ]
    return "\n".join(head) + "\n" + "\n".join(section(t) for t in ts)


#: The reference's first line; ``--out`` replaces only a file that starts with it.
TITLE = "# Scene reference\n"


def is_reference(path) -> bool:
    """Whether the file ``path`` starts with the reference's title line (:data:`TITLE`)."""
    with open(path, "rb") as fh:
        return fh.readline(len(TITLE) + 1) == TITLE.encode()


def write_reference(out: Path | str | None = None) -> str:
    """Write the reference to ``out`` (a file, atomically) and return its text; ``None``: return
    only. A file already at ``out`` is replaced only if it is an earlier reference, and never
    through a symbolic link (:func:`assembly.app.output.check_own_file`)."""
    from ..atomic_file import write_text_atomic
    from .output import check_own_file

    text = reference_markdown()
    if out is not None:
        check_own_file(out, is_reference, f"a scene reference flexgear wrote (first line {TITLE.strip()!r})")
        write_text_atomic(out, text)
    return text
