"""A field naming a body that does not exist is refused naming that field, the unknown
name and the nearest name the scene has -- for every field of the schema that names a body,
through the Python API and the command line, before any rule that needs the body reads it.

Before: ``meshes[0].gear2 = "wheeel"`` was reported as ``meshes[0].base_radius1 = None:
missing: ... ('pinion' has none)``: deriving the gear numbers from teeth ran first and
found no teeth for the unknown gear.

The base scene is the shipped two-stage drive with one field of every kind that names a
body added (a body riding in another body's frame, a bearing to another body, fixed DOFs,
load cases with point loads and supports, a [simulation] table); each case misspells one
of them by one or two random edits (insert, delete, substitute, swap).
"""
from __future__ import annotations

import copy
import dataclasses
import random
import re
import tomllib
import typing

import pytest

from assembly.app.cli import main
from assembly.errors import SceneError
from assembly.scene.save import toml_text
from assembly.scene.schema import SCENE_DIR, scene_from_dict
from assembly.scene.tables import Scene
from tests.support.fuzz import examples

#: Field names that hold the name of a body (or the housing) in any scene table.
BODY_FIELDS = {"body", "body1", "body2", "gear1", "gear2", "frame", "input", "output", "reference"}
#: ... and in the [turbine] table (its other tables' fields of these names are not bodies)
TURBINE_BODY_FIELDS = {"rotor", "generator"}


def _names_body(path: str, key: str) -> bool:
    """Whether the field ``key`` at ``path`` (its table's path) names a body."""
    if path.split(".")[0].split("[")[0] == "turbine":
        return path == "turbine" and key in TURBINE_BODY_FIELDS
    return key in BODY_FIELDS


def naming_scene() -> dict:
    """two_stage_quill.toml with every kind of body-naming field filled."""
    tree = tomllib.loads((SCENE_DIR / "two_stage_quill.toml").read_text())
    tree["bodies"] += [
        {"name": "sensor", "mass": 1.0, "polar_inertia": 1e-3, "position": [0.0, 0.0, -0.2]},
        {"name": "tag", "mass": 0.1, "polar_inertia": 1e-5, "position": [0.0, 0.0, -0.25], "frame": "sensor"},
    ]
    tree["bearings"].append({"body": "sensor", "frame": "pinion", "k_radial": 1e8, "k_axial": 1e8,
                             "k_tilt": 1e5, "k_torsion": 1e4})
    tree["fixed"] = [{"body": "tag"}]
    tree["loads"] = [tree.pop("load"),
                     {"name": "point loads", "forces": [{"body": "wheel", "interface": "bore", "force": [0, 10.0, 0]}],
                      "supports": [{"body": "pinion"}, {"body": "planetary.carrier"}]}]
    tree["simulation"] = {"speed": 10.0, "reference": "pinion",
                          "loads": [{"body": "pinion", "value": 100.0}],
                          "generator": {"body": "planetary.carrier", "torque": 400.0},
                          "brake": {"body": "planetary.carrier", "torque": 500.0},
                          "points": [{"name": "web", "body": "wheel", "point": [0.27, 0.1, 0.0]}],
                          "unbalance": [{"body": "wheel", "mass": 0.01, "radius": 0.05}],
                          "drive": {"body": "pinion", "end_speed": 20.0, "t_end": 1.0}}
    tree["turbine"] = {"rotor": "pinion", "generator": "planetary.carrier"}
    return tree


BASE = naming_scene()


def _leaves(node, prefix=""):
    """(path, value) of every string leaf under a key of BODY_FIELDS."""
    if isinstance(node, dict):
        for k, v in node.items():
            p = f"{prefix}.{k}" if prefix else k
            if _names_body(prefix, k) and isinstance(v, str):
                yield p, v
            else:
                yield from _leaves(v, p)
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _leaves(v, f"{prefix}[{i}]")


REFERENCES = list(_leaves(BASE))
NAMES = ["pinion", "wheel", "sensor", "tag", "housing", "planetary.sun", "planetary.ring", "planetary.carrier",
         *(f"planetary.planet{i}" for i in range(4))]


def _set(tree, path: str, value):
    keys = [int(k) if k.isdigit() else k for k in re.findall(r"[^.\[\]]+", path)]
    node = tree
    for k in keys[:-1]:
        node = node[k]
    node[keys[-1]] = value


def levenshtein(a: str, b: str) -> int:
    """Edit distance (insert, delete, substitute; each 1)."""
    row = list(range(len(b) + 1))
    for i, ca in enumerate(a, 1):
        prev, row[0] = row[0], i
        for j, cb in enumerate(b, 1):
            prev, row[j] = row[j], min(row[j] + 1, row[j - 1] + 1, prev + (ca != cb))
    return row[-1]


ALPHABET = "abcdefghijklmnopqrstuvwxyz0123456789._-"


def typo(rng: random.Random, name: str) -> str:
    """``name`` with one or two random edits, never another name of the scene."""
    while True:
        s = list(name)
        for _ in range(rng.choice((1, 1, 2))):
            op = rng.choice(("insert", "delete", "substitute", "swap"))
            i = rng.randrange(len(s) + (op == "insert"))
            if op == "insert":
                s.insert(i, rng.choice(ALPHABET))
            elif op == "delete" and len(s) > 1:
                del s[i]
            elif op == "substitute":
                s[i] = rng.choice(ALPHABET)
            elif op == "swap" and i + 1 < len(s):
                s[i], s[i + 1] = s[i + 1], s[i]
        out = "".join(s)
        if out not in NAMES and out.strip():
            return out


def _check_reason(exc: SceneError, path: str, bad: str, original: str) -> None:
    assert exc.path == path and exc.value == bad, str(exc)
    m = re.search(r"no body of that name; the nearest is '([^']*)'", exc.reason)
    assert m, str(exc)
    near = m.group(1)
    assert near in NAMES
    # the name offered is at least as close (edits) as the one the typo came from
    assert levenshtein(near.lower(), bad.lower()) <= levenshtein(original.lower(), bad.lower()), str(exc)


def test_base_scene_is_valid_and_names_every_kind_of_field():
    scene_from_dict(copy.deepcopy(BASE))
    # every (table, field) of the schema that names a body appears in the base scene
    seen = {re.sub(r"\[\d+\]", "", p) for p, _ in REFERENCES}
    want = set()

    def visit(cls, path):
        for f in dataclasses.fields(cls):
            tp = typing.get_type_hints(cls)[f.name]
            inner = [a for a in typing.get_args(tp) if dataclasses.is_dataclass(a)] or \
                ([tp] if dataclasses.is_dataclass(tp) else [])
            for sub in inner:
                if sub is not cls:
                    visit(sub, f"{path}.{f.name}" if path else f.name)
            if _names_body(path, f.name) and path.split(".")[0] in ("bodies", "bearings", "meshes", "shafts",
                                                                     "fixed", "load", "loads", "simulation",
                                                                     "turbine"):
                want.add(f"{path}.{f.name}")
    visit(Scene, "")
    want = {w.replace("load.", "loads.", 1) if w.startswith("load.") else w for w in want}
    assert want <= seen, sorted(want - seen)


def test_typo_in_a_mesh_gear_names_the_body_not_a_radius():
    tree = copy.deepcopy(BASE)
    tree["meshes"][0]["gear2"] = "wheeel"
    with pytest.raises(SceneError) as e:
        scene_from_dict(tree)
    _check_reason(e.value, "meshes[0].gear2", "wheeel", "wheel")
    assert e.value.reason.startswith("no body of that name; the nearest is 'wheel'")


N_API = examples(120)


@pytest.mark.parametrize("seed", range(N_API))
def test_typo_in_any_body_field_is_named_api(seed):
    rng = random.Random(seed)
    path, original = REFERENCES[seed % len(REFERENCES)]
    bad = typo(rng, original)
    tree = copy.deepcopy(BASE)
    _set(tree, path, bad)
    with pytest.raises(SceneError) as e:
        scene_from_dict(tree)
    _check_reason(e.value, path, bad, original)


@pytest.mark.parametrize("seed", range(6))
def test_typo_in_a_body_field_is_one_line_exit_2_cli(seed, tmp_path, capsys):
    rng = random.Random(1000 + seed)
    path, original = REFERENCES[rng.randrange(len(REFERENCES))]
    bad = typo(rng, original)
    tree = copy.deepcopy(BASE)
    _set(tree, path, bad)
    f = tmp_path / "typo.toml"
    f.write_text(toml_text(tree))
    assert main(["modes", str(f)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"flexgear: error: {path} = {bad!r}: no body of that name; "
                                               f"the nearest is "), err
