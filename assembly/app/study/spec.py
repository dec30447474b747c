"""A design study's variants: scene fields named by path, their values, and the design.

A study names any scene field by its path (:mod:`assembly.scene.edit`: ``bearings[2].k_radial``,
``stages[0].planets.count``, ``bodies.wheel.flex.cutoff_hz``), with ``[*]`` for every item
of a list (``meshes[*].stiffness``: one value set on each). ``path`` may also be a list of
paths that take the same value (a common factor on several stiffnesses); ``name`` names the
parameter's column (default: its path); ``scale = true`` multiplies the scene's own value
at each path instead of replacing it (a bearing stiffness factor). Each parameter gives its
values as one of:

* ``values = [...]``: a list;
* ``range = [start, stop, n]``: n values spaced linearly, both ends included;
* ``log_range = [start, stop, n]``: n values spaced logarithmically (start, stop > 0);
* ``bounds = [low, high]`` (with ``log = true`` for a log scale): for a sampled design.

The design combines them: ``"grid"`` (default; every combination of the parameters' values),
``"lhs"`` (Latin hypercube: ``samples`` points, each parameter's range cut into ``samples``
equal strata with one point in each, strata paired at random) or ``"random"`` (``samples``
independent uniform points); the sampled designs take ``bounds`` and a ``seed``, so a study
gives the same variants every time.

Values are checked against the field they go to when the study is read: a number for a
number (never nan; an integer field such as a planet count takes whole numbers; a sampled
design rounds to them), text for text, true/false for a switch. Every key of a parameter
and design table is checked (:mod:`assembly.app.study.keys`): a key they do not have, or
one that is not read (``log`` without ``bounds``, ``samples`` or ``seed`` of a grid), is
refused. The number of variants is computed from what is written (a range's n, the grid's
product, ``samples``) and refused above :data:`MAX_VARIANTS` before any list of values is
made. Problems raise :class:`assembly.errors.SceneError` naming the study field
(``parameters[1].path``) and, for a path the scene does not have, the nearest one it has.
"""
from __future__ import annotations

import difflib
import itertools
import math
import re
from dataclasses import dataclass, field

import numpy as np

from ...errors import SceneError
from ...scene.edit import get_value, value_kind
from ...scene.schema import to_dict
from .keys import DESIGN, PARAMETER, TABLE, TABLES, check_keys

DESIGNS = ("grid", "lhs", "random")
#: Most variants one study may expand to (a guard against a typo such as n = 1e6). The count
#: is computed from the numbers written (a range's n, the product of the parameters' counts,
#: samples) before any value list is made.
MAX_VARIANTS = 100_000


@dataclass(frozen=True)
class Variant:
    """One variant: its ``index``, ``values`` {scene path: value} (wildcards expanded,
    scale factors applied: what :meth:`Scene.with_values` takes) and ``params``
    {parameter name: value} (the study's own values: the row's columns)."""

    index: int
    values: dict
    params: dict = field(default_factory=dict)


def scene_paths(scene) -> list[str]:
    """Every leaf path of the scene's tables (lists by index), for suggestions."""
    out = []

    def walk(node, prefix):
        if isinstance(node, dict):
            for k, v in node.items():
                walk(v, f"{prefix}.{k}" if prefix else k)
        elif isinstance(node, list) and node and all(isinstance(x, dict) for x in node):
            for i, v in enumerate(node):
                walk(v, f"{prefix}[{i}]")
        else:
            out.append(prefix)
    walk(to_dict(scene), "")
    return out


def expand_path(scene, path: str, field: str) -> list[str]:
    """The concrete paths of ``path`` (``[*]`` -> every index of that list), each checked to
    exist in ``scene``; SceneError at ``field`` naming the nearest path the scene has."""
    if not isinstance(path, str):
        raise SceneError(field, path, "must be a scene path such as 'bearings[2].k_radial'")
    head, star, tail = path.partition("[*]")
    if star:
        try:
            node = get_value(scene, head)
        except SceneError:
            node = None
        if not isinstance(node, list) or not node:
            raise SceneError(field, path, f"{head!r} is not a list of the scene with items" + _nearest(scene, head))
        return [p for i in range(len(node)) for p in expand_path(scene, f"{head}[{i}]{tail}", field)]
    try:
        get_value(scene, path)
    except SceneError as exc:
        raise SceneError(field, path, f"{exc.reason}" + _nearest(scene, path, exc.reason)) from None
    return [path]


def _nearest(scene, path: str, reason: str = "") -> str:
    """`` (nearest valid path: P)``: among the fields the failing table has (listed in
    ``reason`` by :mod:`assembly.scene.edit`), else among the scene's given paths."""
    parent = path.rsplit(".", 1)[0] if "." in path else ""
    fields = re.search(r"it has: ([^;]+)", reason)
    pool = [f"{parent}.{f.strip()}" for f in fields.group(1).split(",")] if fields and parent else []
    near = difflib.get_close_matches(path, pool, n=1, cutoff=0.5) or \
        difflib.get_close_matches(path, scene_paths(scene), n=1, cutoff=0.5)
    return f" (nearest valid path: {near[0]})" if near else ""


def _kind(value) -> str:
    """What a study value is: "bool", "int", "number", "text" or "other"."""
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, int):
        return "int"
    return "number" if isinstance(value, float) else "text" if isinstance(value, str) else "other"


def check_types(kinds: list[str], path: str, values, field: str, scale: bool) -> None:
    """Refuse (SceneError at ``field``) values that do not fit fields of ``kinds``
    (:func:`assembly.scene.edit.value_kind` of each path; ``path`` is the first, named in the
    message): numbers for numbers, whole numbers for an integer field, text for text,
    true/false for a switch; ``scale`` needs number fields."""
    kinds = set(kinds) - {"other"}
    listed = isinstance(values, list)
    for j, v in enumerate(values if listed else values[:2]):
        where = f"{field}.values[{j}]" if listed else f"{field}.bounds"
        if scale and (kinds - {"number", "int"} or _kind(v) not in ("int", "number")):
            raise SceneError(where, v, "scale = true multiplies a number field by a number")
        if _kind(v) == "number" and math.isnan(v) and kinds & {"number", "int"}:
            raise SceneError(where, v, f"{path} takes a number, not nan")
        for k in kinds:
            ok = {"bool": _kind(v) == "bool", "text": _kind(v) == "text",
                  "int": _kind(v) == "int" or (_kind(v) == "number" and float(v).is_integer()),
                  "number": _kind(v) in ("int", "number")}[k]
            if not ok:
                want = {"bool": "true or false", "text": "text", "int": "a whole number",
                        "number": "a number"}[k]
                raise SceneError(where, v, f"{path} takes {want}")


def _number(v, field: str) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise SceneError(field, v, "must be a finite number")
    return float(v)


def parameter_values(p: dict, field: str, design: str) -> list | tuple:
    """A parameter's list of values (grid) or its (low, high, log) bounds (lhs, random)."""
    given = [k for k in ("values", "range", "log_range", "bounds") if k in p]
    if len(given) != 1:
        raise SceneError(field, sorted(p), "give exactly one of values, range, log_range, bounds")
    key = given[0]
    v = p[key]
    if design != "grid":
        if key != "bounds":
            raise SceneError(f"{field}.{key}", v, f"a {design} design samples between bounds = [low, high]")
    elif key == "bounds":
        raise SceneError(f"{field}.bounds", v, "a grid design takes values, range or log_range")
    if "log" in p and key != "bounds":
        raise SceneError(f"{field}.log", p["log"], "log applies to bounds = [low, high] of a sampled design; "
                                                   "a grid takes log_range = [start, stop, n]")
    if key == "values":
        if not isinstance(v, list) or not v:
            raise SceneError(f"{field}.values", v, "must be a non-empty list")
        if len(v) > MAX_VARIANTS:
            raise SceneError(f"{field}.values", f"[{len(v)} values]", f"a study has at most {MAX_VARIANTS} variants")
        return v
    if not isinstance(v, list) or len(v) != (2 if key == "bounds" else 3):
        raise SceneError(f"{field}.{key}", v, "[start, stop, n]" if key != "bounds" else "[low, high]")
    if key == "bounds":
        lo, hi = (_number(x, f"{field}.bounds") for x in v)
        log = p.get("log", False)
        if not lo < hi or (log and lo <= 0):
            raise SceneError(f"{field}.bounds", v, "needs low < high" + (" and low > 0 (log)" if log else ""))
        return lo, hi, log
    a, b = (_number(x, f"{field}.{key}") for x in v[:2])
    n = v[2]
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise SceneError(f"{field}.{key}", v, "n (the third entry) must be an integer >= 1")
    if n > MAX_VARIANTS:      # refused before linspace/geomspace make n values
        raise SceneError(f"{field}.{key}", v, f"n = {n} values; a study has at most {MAX_VARIANTS} variants")
    if key == "log_range":
        if not (a > 0 and b > 0):
            raise SceneError(f"{field}.log_range", v, "start and stop must be > 0")
        return [float(x) for x in np.geomspace(a, b, n)]
    return [float(x) for x in np.linspace(a, b, n)]


def variants(scene, study: dict) -> list[Variant]:
    """The variants of ``study`` (a dict: ``parameters`` list, optional ``design`` table with
    ``kind``, ``samples``, ``seed``) on ``scene``, module notes."""
    if not isinstance(study, dict):
        raise SceneError("study", study, "must be a dict with parameters (a list of tables) and design (a table)")
    check_keys(study, {"parameters": TABLES, "design": TABLE}, "", "")
    params = study.get("parameters")
    if not isinstance(params, list) or not params:
        raise SceneError("parameters", params, "a study needs at least one [[parameters]] table")
    design = study.get("design", {})
    check_keys(design, DESIGN, "design", "[design]")
    kind = design.get("kind", "grid")
    if kind not in DESIGNS:
        raise SceneError("design.kind", kind, f"must be one of {list(DESIGNS)}")
    for key in ("samples", "seed") if kind == "grid" else ():
        if key in design:
            raise SceneError(f"design.{key}", design[key], "a grid design runs every combination of the "
                                                           "parameters' values; samples and seed are for kind = "
                                                           "'lhs' or 'random'")
    paths, values, names, scales, ints = [], [], [], [], []
    for i, p in enumerate(params):
        check_keys(p, PARAMETER, f"parameters[{i}]", "[[parameters]]")
        if "path" not in p:
            raise SceneError(f"parameters[{i}].path", None, "missing: the scene field to vary")
        given = p["path"] if isinstance(p["path"], list) and p["path"] else [p["path"]]
        ps = [q for j, g in enumerate(given)
              for q in expand_path(scene, g, f"parameters[{i}].path" + (f"[{j}]" if len(given) > 1 else ""))]
        name = p.get("name", given[0] if len(given) == 1 else None)
        if not isinstance(name, str) or not name or name in names or name in ("variant", "status", "error"):
            raise SceneError(f"parameters[{i}].name", name, "a parameter with several paths needs a name, unique "
                                                             "and not variant, status or error")
        scale = p.get("scale", False)
        vals = parameter_values(p, f"parameters[{i}]", kind)
        kinds = [value_kind(scene, q) for q in ps]
        check_types(kinds, ps[0], vals, f"parameters[{i}]", scale)
        whole = not scale and "int" in kinds
        if whole and isinstance(vals, list):  # a range of counts: 3.0, 4.0 -> 3, 4
            vals = [int(v) for v in vals]
        paths.append(ps)
        values.append(vals)
        names.append(name)
        if scale:
            base = [get_value(scene, q, given=True) for q in ps]
            unset = [q for q, b in zip(ps, base) if b is None]
            if unset:
                raise SceneError(f"parameters[{i}].scale", True, f"{unset[0]} is not given in the scene (it is "
                                                                 "derived): there is no value to scale; set it instead")
        scales.append(base if scale else None)
        ints.append(whole)
    if kind == "grid":
        n = math.prod(len(v) for v in values)
        if n > MAX_VARIANTS:
            raise SceneError("parameters", n, f"the grid has {n} variants; at most {MAX_VARIANTS}")
        combos = list(itertools.product(*values))
    else:
        n = design.get("samples")
        if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= MAX_VARIANTS:
            raise SceneError("design.samples", n, f"a {kind} design needs samples, an integer in [1, {MAX_VARIANTS}]")
        seed = design.get("seed", 0)
        if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
            raise SceneError("design.seed", seed, "must be an integer >= 0")
        combos = [tuple(int(round(x)) if whole else x for x, whole in zip(c, ints))
                  for c in sample(values, n, kind, seed)]
    if not combos:
        raise SceneError("parameters", 0, "the study has no variants")
    out = []
    for k, combo in enumerate(combos):
        edits = {}
        for ps, v, base in zip(paths, combo, scales):
            edits.update({q: v if base is None else b * v for q, b in zip(ps, base or [None] * len(ps))})
        out.append(Variant(k, edits, dict(zip(names, combo))))
    return out


def sample(bounds: list, n: int, kind: str, seed: int) -> list[tuple]:
    """``n`` points in the box ``bounds`` [(low, high, log), ...]: Latin hypercube ("lhs")
    or independent uniform ("random"), on a log scale where asked, from ``seed``."""
    rng = np.random.default_rng(seed)
    d = len(bounds)
    if kind == "lhs":
        u = (np.array([rng.permutation(n) for _ in range(d)]).T + rng.random((n, d))) / n
    else:
        u = rng.random((n, d))
    cols = []
    for j, (lo, hi, log) in enumerate(bounds):
        cols.append(np.exp(np.log(lo) + u[:, j] * (np.log(hi) - np.log(lo))) if log else lo + u[:, j] * (hi - lo))
    return [tuple(float(c[k]) for c in cols) for k in range(n)]
