"""Scene -> TOML (assembly.scene.save): exact round trip for every shipped scene and for
fuzzed ones (inf, tuples, nested tables, stages, odd strings); atomic save; typed
component parameters written as a table with their kind."""
import copy
import math
import os
import tomllib

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from assembly.errors import SceneError
from assembly.scene.save import save_scene, scene_to_toml, toml_text
from assembly.scene.schema import component_from_table, load_scene, scene_from_dict, shipped_scenes, to_dict
from fe_components.errors import GeometryError
from fe_components.reference import CARRIER, PINION_SMOOTH
from tests.support.fuzz import examples, number_paths


@pytest.mark.parametrize("path", shipped_scenes(), ids=lambda p: p.name)
def test_shipped_scenes_round_trip(path):
    scene = load_scene(path)
    text = scene_to_toml(scene)
    assert scene_from_dict(tomllib.loads(text)) == scene
    assert "_deg" not in text.replace("pressure_angle_deg", "").replace("helix_angle_deg", "")  # only component tables keep theirs


def test_angles_written_in_radians_exactly():
    scene = load_scene("kahraman_beta20.toml")
    data = tomllib.loads(scene_to_toml(scene))
    assert data["meshes"][0]["helix_angle"] == math.radians(20.0)   # the same double, no rounding
    assert "helix_angle_deg" not in data["meshes"][0]


def test_typed_component_written_with_kind_first():
    for params, kind in ((PINION_SMOOTH, "pinion"), (CARRIER, "carrier")):
        text = toml_text({"component": to_dict(params)})
        assert text.splitlines()[1] == f'kind = "{kind}"'
        assert component_from_table(tomllib.loads(text)["component"], "component") == params


BASES = {p.name: tomllib.loads(p.read_text()) for p in shipped_scenes()
         if p.name in ("kahraman_beta20.toml", "lin_parker_n4.toml", "hs_parallel_stage.toml",
                       "planetary_flexible_carrier.toml", "peeters_parallel_torsional.toml")}
#: Fields that scale a magnitude without touching the geometry (the scene stays valid).
MAGNITUDES = ("mass", "polar_inertia", "transverse_inertia", "stiffness", "k_radial", "k_axial", "k_tilt",
              "k_torsion", "k_bending", "k_shear", "k_mesh_sun", "k_mesh_ring", "torque", "band_hz", "cutoff_hz")


def _tables(node, prefix=()):
    """Paths of the tables that may hold a name or description string."""
    if isinstance(node, dict):
        yield prefix
        for k, v in node.items():
            if k not in ("component", "flex"):
                yield from _tables(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _tables(v, prefix + (i,))


def _at(tree, path):
    for p in path:
        tree = tree[p]
    return tree


@st.composite
def fuzzed_scene(draw):
    tree = copy.deepcopy(BASES[draw(st.sampled_from(sorted(BASES)))])
    leaves = sorted(number_paths(tree, MAGNITUDES))
    for path in draw(st.lists(st.sampled_from(leaves), max_size=5, unique=True)):
        parent = _at(tree, path[:-1])
        if path[-1].startswith("k_") and draw(st.booleans()):
            parent[path[-1]] = math.inf                      # a rigid direction
        else:                                               # any double: repr must round-trip it
            parent[path[-1]] = parent[path[-1]] * draw(st.floats(0.2, 5.0))
    tree["description"] = draw(st.text(max_size=20))       # quotes, backslashes, control characters
    if "stages" in tree and draw(st.booleans()):
        n = tree["stages"][0]["planets"]["count"]
        tree["stages"][0]["planets"]["angles"] = [2 * math.pi * i / n + draw(st.floats(-0.01, 0.01)) for i in range(n)]
    for path in draw(st.lists(st.sampled_from(sorted(_tables(tree))), max_size=2)):
        if "name" in _at(tree, path) and path and path[0] == "meshes":
            _at(tree, path)["name"] = draw(st.text(min_size=1, max_size=10).filter(lambda s: "/" not in s))
    try:
        return scene_from_dict(tree)
    except (SceneError, GeometryError):
        assume(False)


@settings(max_examples=examples(60), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scene=fuzzed_scene())
def test_fuzzed_scenes_round_trip(scene):
    assert scene_from_dict(tomllib.loads(scene_to_toml(scene))) == scene


def test_save_scene_is_atomic_and_reads_back(tmp_path, monkeypatch):
    scene = load_scene("lin_parker_n3.toml").with_value("stages.stage.planets.bearing.k_tilt", 1e6)
    path = save_scene(scene, tmp_path / "study.toml")
    assert load_scene(path) == scene
    assert sorted(p.name for p in tmp_path.iterdir()) == ["study.toml"]   # no temporary file left
    assert os.stat(path).st_mode & 0o777 == 0o644
    before = path.read_bytes()

    def disk_full(fd):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(os, "fsync", disk_full)
    with pytest.raises(OSError):
        save_scene(scene.with_value("band_hz", 100.0), path)
    assert path.read_bytes() == before                                   # the old file, whole
    assert sorted(p.name for p in tmp_path.iterdir()) == ["study.toml"]
