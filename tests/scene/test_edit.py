"""Changing a scene field by path (assembly.scene.edit, Scene.with_value): every path form, one
validation for several changes, errors that name the caller's path."""
import dataclasses
import math

import pytest

from assembly.errors import SceneError
from assembly.scene.edit import get_value, parse_path, with_value, with_values
from assembly.scene.schema import given_in_degrees, load_scene

HS = load_scene("hs_parallel_stage.toml")
LP3 = load_scene("lin_parker_n3.toml")
K20 = load_scene("kahraman_beta20.toml")


def test_parse_path():
    assert parse_path("stages[0].sun.bearing.k_radial") == ["stages", 0, "sun", "bearing", "k_radial"]
    assert parse_path("shafts.wheel-fit.k_torsion") == ["shafts", "wheel-fit", "k_torsion"]
    assert parse_path("bodies['a.b'].mass") == ["bodies", "a.b", "mass"]
    for bad in ("", "a..b", "a[x]", "a b"):
        with pytest.raises(SceneError):
            parse_path(bad)


@pytest.mark.parametrize("scene, path, value, read", [
    (HS, "shafts.wheel-fit.k_torsion", 2e6, lambda s: s.shafts[0].k_torsion),
    (HS, "bearings[2].k_radial", 2.5e9, lambda s: s.bearings[2].k_radial),
    (HS, "bodies.pinion.flex.cutoff_hz", 9000.0, lambda s: s.bodies[0].flex.cutoff_hz),
    (HS, "bodies.wheel.component.teeth.face_width", 0.06, lambda s: s.bodies[1].component.teeth.face_width),
    (K20, "meshes[0].helix_angle_deg", 10.0, lambda s: math.degrees(s.meshes[0].helix_angle)),
    (K20, "meshes.pinion-wheel.helix_angle", 0.1, lambda s: s.meshes[0].helix_angle),
    (LP3, "stages.stage.planets.count", 4, lambda s: s.stages[0].planets.count),
    (LP3, "stages[0].sun.bearing.k_radial", 2e8, lambda s: s.stages[0].sun.bearing.k_radial),
    (K20, "band_hz", 5000.0, lambda s: s.band_hz),
])
def test_with_value_sets_one_field(scene, path, value, read):
    new = scene.with_value(path, value)
    assert read(new) == pytest.approx(value, rel=1e-15)
    assert new.get_value(path) == pytest.approx(value, rel=1e-12)
    assert scene.get_value(path) != pytest.approx(value)   # the original scene is unchanged
    # everything else is unchanged: setting the old value back gives the original scene
    assert with_value(new, path, get_value(scene, path)) == scene


def test_component_of_the_original_is_not_changed():
    before = HS.bodies[1].component
    width = before.teeth.face_width
    new = HS.with_value("bodies.wheel.component.teeth.face_width", 0.07)
    assert HS.bodies[1].component is before and before.teeth.face_width == width
    assert new.bodies[1].component.teeth.face_width == 0.07


def test_angle_held_once_in_rad_or_deg():
    # the component table gives helix_angle_deg; a value in rad replaces it (not both).
    # The pair's hands stay opposite (an external helical pair), so both gears change.
    # (the output shaft, shrink-fitted in the wheel's bore, moves with the wheel)
    from fe_components.gear_pair import pair_geometry
    t1, t2 = (dataclasses.replace(b.component.teeth, helix_angle=math.radians(h))
              for b, h in zip(HS.bodies[:2], (10.0, -10.0)))
    new = HS.with_values({"bodies.pinion.component.teeth.helix_angle": math.radians(10.0),
                          "bodies.wheel.component.teeth.helix_angle_deg": -10.0,
                          "bodies.output_shaft.position": [pair_geometry(t1, t2).centre_distance, 0.0, 0.295]})
    teeth = new.bodies[0].component.teeth
    assert "helix_angle" not in given_in_degrees(teeth) and teeth.helix_angle == math.radians(10.0)
    assert "helix_angle" in given_in_degrees(new.bodies[1].component.teeth)


def test_with_values_validates_once():
    # Centre distance a = (r1 + r2) / cos(alpha) (involute gear geometry, e.g. Maitra,
    # Handbook of Gear Design, 1994): a new base radius needs the wheel moved with it;
    # either change alone is refused.
    r1, r2, alpha = 0.06, 0.05, math.radians(20.0)
    a = (r1 + r2) / math.cos(alpha)
    with pytest.raises(SceneError):
        K20.with_value("meshes[0].base_radius1", r1)
    new = K20.with_values({"meshes[0].base_radius1": r1, "bodies.wheel.position": [a, 0.0, 0.0]})
    assert new.meshes[0].base_radius1 == r1 and new.bodies[1].position == (a, 0.0, 0.0)


def test_errors_name_the_callers_path():
    with pytest.raises(SceneError) as e:
        LP3.with_value("stages.stage.planets.count", 9)   # overlapping planets
    assert e.value.path == "stages.stage.planets.count" and e.value.value == 9
    with pytest.raises(SceneError) as e:
        K20.with_value("meshes.pinion-wheel.helix_angle_deg", 95.0)
    assert e.value.path == "meshes.pinion-wheel.helix_angle_deg" and "90 deg" in e.value.reason
    with pytest.raises(SceneError) as e:
        HS.with_value("bodies.wheel.component.teeth.n_teeth", "many")
    assert e.value.path == "bodies.wheel.component.teeth.n_teeth"


@pytest.mark.parametrize("path, listed", [
    ("shafts.quill.k_torsion", "['wheel-fit']"),
    ("bearings[9].k_radial", "indices 0..3"),
    ("meshes[0].stifness", "stiffness"),
    ("meshes[0].stifness", "helix_angle_deg"),
    ("bodies.wheel.component.teeth.width", "face_width"),
    ("bodies.nope.mass", "['pinion', 'wheel', 'output_shaft']"),
    ("bearings[0]", "k_radial"),
])
def test_bad_path_lists_what_exists(path, listed):
    with pytest.raises(SceneError) as e:
        HS.with_value(path, 1.0)
    assert e.value.path == path and listed in e.value.reason, str(e.value)
    with pytest.raises(SceneError):
        HS.get_value(path)


def test_optional_table_is_created_and_none_removes():
    k = K20.with_value("bodies.pinion.frame", "housing")
    assert k == K20
    assert HS.bodies[1].flex is None and HS.get_value("bodies.wheel.flex.cutoff_hz") is None
    assert HS.with_value("bodies.wheel.flex.cutoff_hz", 9000.0).bodies[1].flex.cutoff_hz == 9000.0
    s = HS.with_value("bodies.output_shaft.flex.cutoff_hz", None)  # no flex table: nothing to remove
    assert s.bodies[2].flex is None
    assert HS.with_value("band_hz", None).band_hz is None


def test_teeth_edit_derives_new_gear_numbers():
    # hs_parallel_stage derives its mesh numbers from the teeth and places the wheel by
    # the mesh; a new tooth count must re-derive them (ISO 21771: r_b = z m_n cos(alpha_t) /
    # (2 cos beta), a_w = (r_b1 + r_b2) / cos(alpha_wt)), not contradict the old numbers.
    from assembly.scene.gears import body_teeth
    from fe_components.gear_pair import pair_geometry
    t1 = dataclasses.replace(HS.bodies[0].component.teeth, n_teeth=24)
    out = [pair_geometry(t1, HS.bodies[1].component.teeth).centre_distance, 0.0, 0.295]   # moves with the wheel
    new = HS.with_values({"bodies.pinion.component.teeth.n_teeth": 24, "bodies.output_shaft.position": out})
    t1, t2 = (b.component.teeth for b in new.bodies[:2])
    assert t1.n_teeth == 24 and t2.n_teeth == 71
    g = pair_geometry(body_teeth(new.bodies[0], "b0")[1], body_teeth(new.bodies[1], "b1")[1])
    assert new.meshes[0].base_radius1 == pytest.approx(g.base_radius1, rel=1e-12)
    assert new.bodies[1].position[0] - new.bodies[0].position[0] == pytest.approx(g.centre_distance, rel=1e-12)
    assert new.bodies[1].position[0] > HS.bodies[1].position[0]   # one more pinion tooth: wheel moves out
