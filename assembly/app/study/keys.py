"""The keys a study file may have, table by table, and the TOML type each one takes.

Every key of a study is checked here before its value is read: a key a table does not have
is refused with the nearest one it has (``parameters[0].scael = True: unknown key (did you
mean 'scale'?) ...``), and a value of the wrong TOML type is refused whatever it says: a
switch is ``true`` or ``false`` (``log = "false"`` is text, not false), a count is an
integer (``samples = 5.0`` is refused, ``true`` is no number), a number is a finite
integer or float. In TOML a key belongs to the last table header above it, so a top-level
key written below ``[[parameters]]`` (or ``[keep]``, ``[design]``, ...) is read into that
table: when an unknown key is one of the study's top-level keys, the message says where to
write it. ``name`` is the one key both levels have: below a ``[[parameters]]`` header it
names that parameter's column.

Each table's own rules (ranges, choices, which analysis keeps what) stay with the code that
reads it (:mod:`assembly.app.study.file`, :mod:`assembly.app.study.spec`).
"""
from __future__ import annotations

import difflib
import json
import math
import re

from ...errors import SceneError

TEXT, BOOL, INT, NUMBER, TABLE, TABLES, LIST, TEXTS, PATH = (
    "text", "bool", "int", "number", "table", "tables", "list", "texts", "path")

TOP = {"name": TEXT, "scene": TEXT, "analysis": TEXT, "keep": TABLE, "frf": TABLE, "simulate": TABLE,
       "design": TABLE, "parameters": TABLES}
KEEP = {"modes": INT, "stats": TEXTS, "life": BOOL, "passages": BOOL, "track": BOOL, "classes": TEXTS,
        "band_hz": LIST}
FRF = {"input": TEXT, "outputs": TEXTS, "fmin": NUMBER, "fmax": NUMBER, "points": INT, "log": BOOL,
       "method": TEXT, "modes_hz": NUMBER, "bands": LIST}
SIMULATE = {"t_end": NUMBER, "dt": NUMBER, "outputs": TEXTS, "speed": NUMBER, "unreduced": BOOL}
DESIGN = {"kind": TEXT, "samples": INT, "seed": INT}
PARAMETER = {"path": PATH, "name": TEXT, "scale": BOOL, "values": LIST, "range": LIST, "log_range": LIST,
             "bounds": LIST, "log": BOOL}

WANT = {TEXT: "text (in quotes)", BOOL: "true or false (a TOML boolean, not text)",
        INT: "an integer (not a float, not true/false)", NUMBER: "a finite number (not text, not true/false)",
        TABLE: "a table", TABLES: "tables written as [[parameters]] (two brackets), one per parameter",
        LIST: "a list [...]", TEXTS: "a non-empty list of text", PATH: "a scene path (text) or a list of them"}


def is_number(v) -> bool:
    """A finite TOML integer or float (a bool is not a number)."""
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _fits(kind: str, v) -> bool:
    if kind == TEXT:
        return isinstance(v, str)
    if kind == BOOL:
        return isinstance(v, bool)
    if kind == INT:
        return isinstance(v, int) and not isinstance(v, bool)
    if kind == NUMBER:
        return is_number(v)
    if kind == TABLE:
        return isinstance(v, dict)
    if kind == TABLES:
        return isinstance(v, list) and all(isinstance(x, dict) for x in v)
    if kind == LIST:
        return isinstance(v, list)
    if kind == TEXTS:
        return isinstance(v, list) and bool(v) and all(isinstance(x, str) and x for x in v)
    return isinstance(v, str) or (isinstance(v, list) and bool(v) and all(isinstance(x, str) for x in v))


def check_keys(table: dict, keys: dict, where: str, header: str) -> None:
    """Refuse (:class:`SceneError` at ``where.KEY``) a key of ``table`` that is not in
    ``keys`` {key: kind}, and a value whose TOML type is not its kind. ``where``: the
    table's field path ("" at the top level); ``header``: how the table is written in the
    file (``[[parameters]]``, ``[frf]``), named when a top-level key was written into it."""
    for key, v in table.items():
        shown = key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else json.dumps(key)   # TOML's quoted key, one line
        field = f"{where}.{shown}" if where else shown
        if key not in keys:
            raise SceneError(field, v, unknown_reason(key, keys, where, header))
        if not _fits(keys[key], v):
            raise SceneError(field, v, f"must be {WANT[keys[key]]}")


def check_study(data: dict) -> None:
    """Every key of a study file's tables (:func:`check_keys`), before any value is read."""
    check_keys(data, TOP, "", "")
    for key, keys in (("keep", KEEP), ("frf", FRF), ("simulate", SIMULATE), ("design", DESIGN)):
        check_keys(data.get(key, {}), keys, key, f"[{key}]")
    for i, p in enumerate(data.get("parameters", [])):
        check_keys(p, PARAMETER, f"parameters[{i}]", "[[parameters]]")


def unknown_reason(key: str, keys: dict, where: str, header: str) -> str:
    """Why ``key`` is not read: the nearest known key, a top-level key written below a
    table header, and the keys the table has."""
    if where and key in TOP:
        hint = (f"; {key!r} is a top-level key of the study: write it before the first table header "
                f"(below {header} a key belongs to that table)")
    else:
        near = difflib.get_close_matches(str(key), list(keys), n=1, cutoff=0.6)
        hint = f" (did you mean {near[0]!r}?)" if near else ""
    table = f"a {header} table" if where else "a study"
    return f"unknown key{hint}; {table} has: {', '.join(sorted(keys))}"
