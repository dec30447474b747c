"""A length in the wrong unit is refused naming the field and the unit that fits, as a STEP
part of absurd size is ("did you mean mm?").

Before: ``normal_module = 5`` (mm meant) made a 100 m pinion and ``face_width = 60`` a 60 m
gear, both accepted. The bounds (fe_components/sizes.py, assembly/scene/sizes.py,
assembly/scene/shafts.py) come from what is built -- ISO 54 modules 1 to 50 mm and fine pitch from
0.05 mm, face widths from a watch wheel's 0.1 mm to a marine gear's 1.5 m, face widths of
0.3 to 300 modules (ISO 6336-1 practice 6 to 60), a base radius near its gear's radius of
gyration, shafts at most 500 diameters long, positions within 100 x the largest part -- and
every shipped scene passes them.

The fuzz scales one random length of a shipped scene by 1e3 (a length typed in mm) or 1e-3
(converted to metres twice): normal modules, face widths, typed base radii, beam shaft
diameters, and (x1e3 only) positions, stage centres, shaft end points and pinion shaft
steps. A position or a pinion step 1000 x too small is a plausible place or collar and is
left out.
"""
from __future__ import annotations

import copy
import random
import re
import tomllib

import pytest

from assembly.app.cli import main
from assembly.errors import SceneError
from assembly.scene.save import toml_text
from assembly.scene.schema import SCENE_DIR, load_scene, scene_from_dict, shipped_scenes
from tests.support.fuzz import examples

#: Scenes whose part files are read relative to their folder are loaded from it; the
#: others are scaled as TOML trees.
TREES = {p.name: tomllib.loads(p.read_text()) for p in shipped_scenes() if "step" not in p.name}

BOTH = ("normal_module", "face_width", "base_radius", "base_radius1", "base_radius2")
UP_ONLY = ("position", "center", "position1", "position2")


def _path_text(path) -> str:
    out = ""
    for k in path:
        out += f"[{k}]" if isinstance(k, int) else (f".{k}" if out else k)
    return out


def _lengths(node, prefix=()):
    """(path, factors) of every length the fuzz scales in a TOML tree."""
    if isinstance(node, dict):
        for k, v in node.items():
            p = prefix + (k,)
            if k in BOTH and isinstance(v, (int, float)) and v > 0:
                yield p, (1e3, 1e-3)
            elif k == "diameter" and "shafts" in prefix and isinstance(v, (int, float)):
                yield p, (1e3, 1e-3)
            elif k in UP_ONLY and isinstance(v, list) and any(v):
                yield p, (1e3,)
            elif k == "shaft" and isinstance(v, list) and "component" in prefix:
                for i, step in enumerate(v):
                    for j in range(2):
                        yield p + (i, j), (1e3,)
            else:
                yield from _lengths(v, p)
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _lengths(v, prefix + (i,))


CASES = [(name, path, f) for name, tree in sorted(TREES.items()) for path, fs in _lengths(tree) for f in fs]


def _scaled(name, path, factor):
    tree = copy.deepcopy(TREES[name])
    node = tree
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = [v * factor for v in node[path[-1]]] if isinstance(node[path[-1]], list) else \
        node[path[-1]] * factor
    return tree


def _field(path) -> str:
    """The scene path an error names for a scaled TOML path (a pinion step's array form
    [length, diameter] is named by field)."""
    if path[-2:-1] and isinstance(path[-1], int) and "shaft" in path:
        return _path_text(path[:-1]) + (".length", ".diameter")[path[-1]]
    return _path_text(path)


def test_every_shipped_scene_passes():
    for p in shipped_scenes():
        load_scene(p)


def test_the_issues_slips():
    tree = tomllib.loads((SCENE_DIR / "two_stage_quill.toml").read_text())
    tree["bodies"][0]["teeth"]["normal_module"] = 5
    with pytest.raises(SceneError) as e:
        scene_from_dict(copy.deepcopy(tree))
    assert e.value.path == "bodies[0].teeth.normal_module" and "did you mean 5 mm (0.005 m)?" in e.value.reason
    tree["bodies"][0]["teeth"]["normal_module"] = 0.005
    tree["bodies"][0]["teeth"]["face_width"] = 60
    with pytest.raises(SceneError) as e:
        scene_from_dict(tree)
    assert e.value.path == "bodies[0].teeth.face_width" and "did you mean 60 mm (0.06 m)?" in e.value.reason


N = examples(60)


@pytest.mark.parametrize("seed", range(N))
def test_scaled_length_is_refused_naming_it(seed):
    name, path, factor = random.Random(seed).choice(CASES)
    field = _field(path)
    with pytest.raises(SceneError) as e:
        scene_from_dict(_scaled(name, path, factor))
    exc = e.value
    assert "\n" not in str(exc)
    # the field itself, or a rule between two fields naming it (face width per module: the
    # face width's path, the module named in the message, as a sibling key or a full path)
    parent, leaf = field.rsplit(".", 1)
    assert (exc.path == field or exc.path.startswith(field + "[") or field in exc.reason
            or (exc.path.startswith(parent + ".") and f"{leaf} = " in exc.reason)), (name, field, str(exc))
    assert "did you mean" in exc.reason, (name, field, str(exc))


@pytest.mark.parametrize("seed", range(4))
def test_scaled_length_cli(seed, tmp_path, capsys):
    name, path, factor = random.Random(500 + seed).choice(CASES)
    f = tmp_path / name
    f.write_text(toml_text(_scaled(name, path, factor)))
    assert main(["modes", str(f)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("flexgear: error: ") and "did you mean" in err[0]
    assert re.search(re.escape(_field(path)), err[0]), err[0]


def test_case_count():
    # every kind of length the fuzz scales is drawn from more than one scene
    kinds = {p[-1] if isinstance(p[-1], str) else "shaft step" for _, p, _ in CASES}
    assert kinds >= {"normal_module", "face_width", "base_radius", "base_radius1", "diameter", "position",
                     "center", "position1", "shaft step"}
    assert len(CASES) > 100
