"""Scene files that vary another (``extends`` + ``[set]``) and the flexible variant of a
rigid scene with components."""
import pytest

from assembly.analysis.compare import variants
from assembly.errors import SceneError
from assembly.scene.schema import SCENE_DIR, load_scene

BASE = "two_stage_quill.toml"   # shipped: a rigid scene whose wheel is a component


def _write(tmp_path, text, name="variant.toml"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def test_variant_changes_only_the_paths_it_sets(tmp_path):
    base = load_scene(BASE)
    p = _write(tmp_path, f'extends = "{SCENE_DIR / BASE}"\nname = "softer quill"\n'
                         '[set]\n"shafts.quill.k_torsion" = 1.0e5\n"bodies.wheel.fidelity" = "flexible"\n')
    sc = load_scene(p)
    assert sc.name == "softer quill"
    assert sc.get_value("shafts.quill.k_torsion") == 1.0e5
    assert sc.body("wheel").fidelity == "flexible"
    # everything else is the base scene's
    assert sc.with_values({"shafts.quill.k_torsion": base.get_value("shafts.quill.k_torsion"),
                           "bodies.wheel.fidelity": "rigid", "name": base.name}) == base


def test_variant_of_a_variant_and_a_shipped_base_by_name(tmp_path):
    _write(tmp_path, f'extends = "{BASE}"\n[set]\n"band_hz" = 2000.0\n', "a.toml")
    sc = load_scene(_write(tmp_path, 'extends = "a.toml"\n[set]\n"stages.planetary.planets.count" = 2\n', "b.toml"))
    assert sc.band_hz == 2000.0 and sc.get_value("stages.planetary.planets.count") == 2


@pytest.mark.parametrize("text, path", [
    (f'extends = "{BASE}"\nband_hz = 10.0\n', "band_hz"),                          # not under [set]
    (f'extends = "{BASE}"\n[set]\n"shafts.quill.k_torsion" = -1.0\n', "set.shafts.quill.k_torsion"),
    (f'extends = "{BASE}"\n[set]\n"shafts.nope.k_torsion" = 1.0\n', "set.shafts.nope.k_torsion"),
    ('extends = ""\n', "extends"),
    ('extends = "missing_scene_file.toml"\n', "scene"),
    ('extends = "variant.toml"\n', "extends"),                                     # extends itself
])
def test_bad_variant_names_the_field(tmp_path, text, path):
    with pytest.raises(SceneError) as exc:
        load_scene(_write(tmp_path, text))
    assert exc.value.path == path


def test_flexible_variant_makes_component_bodies_flexible():
    sc = load_scene(BASE)
    assert set(variants(sc)) == {"torsional", "rigid"}           # the report's comparison: no meshing
    vs = variants(sc, flexible_components=True)
    flex = {b.name for b in vs["flexible"].expanded().bodies if b.fidelity == "flexible"}
    assert flex == {b.name for b in sc.expanded().bodies if b.component is not None} == {"wheel"}
