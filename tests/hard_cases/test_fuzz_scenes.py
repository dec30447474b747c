"""Property-based fuzzing of scene input: every malformed scene ends in one clear
error naming a field path and the value -- never another exception -- and a failed run
leaves nothing in the output folder."""
import copy
import math
import tomllib

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from assembly.errors import SceneError
from assembly.scene.schema import SCENE_DIR, scene_from_dict
from fe_components.errors import GeometryError
from tests.support.fuzz import examples, tree_paths

BASES = {name: tomllib.loads((SCENE_DIR / name).read_text())
         for name in ("kahraman_beta20.toml", "lin_parker_n3.toml", "hs_parallel_stage.toml",
                      "planetary_flexible_carrier.toml")}

JUNK = st.one_of(st.none(), st.booleans(), st.integers(-10**12, 10**12), st.text(max_size=8),
                 st.floats(allow_nan=True, allow_infinity=True), st.lists(st.integers(-3, 3), max_size=4),
                 st.dictionaries(st.text(max_size=5), st.integers(), max_size=2),
                 st.sampled_from([0.0, -1.0, 1e300, -1e-300, 1e-320, math.inf, -math.inf, math.nan, "1.0",
                                  "housing", "", "x" * 50, "x" * 300, "a\x00b", "a/b", "a\nb"]))


def _set(tree, path, value, delete=False):
    node = tree
    for p in path[:-1]:
        node = node[p]
    if delete:
        del node[path[-1]]
    else:
        node[path[-1]] = value


@st.composite
def mutated(draw):
    name = draw(st.sampled_from(sorted(BASES)))
    tree = copy.deepcopy(BASES[name])
    for _ in range(draw(st.integers(1, 3))):
        paths = list(tree_paths(tree))
        if not paths:
            break
        path = draw(st.sampled_from(paths))
        op = draw(st.sampled_from(["replace", "delete", "extra"]))
        if op == "delete" and not isinstance(path[-1], int):
            _set(tree, path, None, delete=True)
        elif op == "extra":
            parent = tree
            for p in path[:-1]:
                parent = parent[p]
            if isinstance(parent, dict):
                parent[draw(st.text(min_size=1, max_size=6))] = draw(JUNK)
        else:
            _set(tree, path, draw(JUNK))
    return tree


@settings(max_examples=examples(300), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated())
def test_malformed_scene_gives_one_clear_error(tree):
    try:
        scene_from_dict(tree)
    except SceneError as exc:
        assert exc.path and "\n" not in str(exc)
        assert repr(exc.value) in str(exc) or str(exc.value) in str(exc)
    except GeometryError as exc:
        assert exc.parameter and "\n" not in str(exc)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(bad=st.sampled_from([("count = 3", "count = 0"), ("mass = 0.66", "mass = -1.0"),
                            ("k_mesh_sun = 5.0e8", "k_mesh_sun = \"stiff\""), ("count = 3", "count = 3\nfoo = 1")]))
def test_failed_run_leaves_no_partial_output(bad, tmp_path):
    from assembly.app.cli import main
    text = (SCENE_DIR / "lin_parker_n3.toml").read_text().replace(*bad)
    f = tmp_path / "bad.toml"
    f.write_text(text)
    out = tmp_path / "out"
    assert main(["run", str(f), "--out", str(out), "--quiet", "--no-images"]) == 2
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir()] == ["bad.toml"]  # no temp folders left behind
