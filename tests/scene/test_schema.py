"""Scene tables -> dataclasses (one converter for scene and component tables): paths,
degrees, arrays for all-required tables, the carrier's n_planets, self-checking types."""
import dataclasses
import math

import pytest

from assembly.errors import SceneError
from assembly.scene.schema import component_from_table, from_dict
from fe_components.material import STEEL, Material
from fe_components.reference import CARRIER, PINION_SMOOTH

DEG20 = math.radians(20)


def _pinion_table():
    return {"kind": "pinion", "gear_center": 0.12,
            "shaft": [[0.03, 0.03], {"length": 0.05, "diameter": 0.04}, [0.08, 0.05], [0.05, 0.04], [0.03, 0.03]],
            "teeth": {"n_teeth": 20, "normal_module": 0.004, "pressure_angle_deg": 20.0, "face_width": 0.04,
                      "helix_angle_deg": 0.0}}


def test_component_table_paths_and_degrees():
    d = _pinion_table()
    p = component_from_table(d, "bodies[2].component")
    assert p.teeth.pressure_angle == pytest.approx(DEG20)
    assert p == PINION_SMOOTH
    d["teeth"]["n_teeth"] = 12  # undercut: z_min = 2 / sin^2(20 deg) = 17.1 (ISO 21771)
    with pytest.raises(SceneError) as e:
        component_from_table(d, "bodies[2].component")
    assert e.value.path == "bodies[2].component.teeth.n_teeth" and e.value.value == 12
    d["teeth"]["n_teeth"] = 20
    d["shaft"][1]["diameter"] = -1
    with pytest.raises(SceneError) as e:
        component_from_table(d, "bodies[2].component")
    assert e.value.path == "bodies[2].component.shaft[1].diameter"
    with pytest.raises(SceneError) as e:
        component_from_table({"kind": "pinion", "colour": "red"}, "x")
    assert e.value.path == "x.colour"


def test_component_numbers_follow_the_scene_rule():
    # the scene refuses a string where a number belongs; component tables now do too
    d = _pinion_table()
    d["teeth"]["normal_module"] = "0.004"
    with pytest.raises(SceneError) as e:
        component_from_table(d, "bodies[0].component")
    assert e.value.path == "bodies[0].component.teeth.normal_module"


def test_carrier_n_planets():
    d = {f.name: getattr(CARRIER, f.name) for f in dataclasses.fields(CARRIER) if f.name != "planet_angles"}
    d["kind"] = "carrier"
    d["n_planets"] = 3
    c = component_from_table(d, "carrier")
    assert c.planet_angles == pytest.approx(CARRIER.planet_angles)
    d.pop("n_planets")
    d["planet_angles_deg"] = [0, 120, 240]
    assert component_from_table(d, "carrier").planet_angles == pytest.approx(CARRIER.planet_angles)
    d["n_planets"] = 3
    with pytest.raises(SceneError) as e:
        component_from_table(d, "carrier")
    assert e.value.path == "carrier.n_planets"


@pytest.mark.parametrize("kind", [None, "gearbox", ["pinion"], 3])
def test_component_kind_refused(kind):
    with pytest.raises(SceneError) as e:
        component_from_table({"kind": kind}, "bodies[0].component")
    assert e.value.path == "bodies[0].component.kind" and e.value.value == kind


def test_material_table_path():
    assert from_dict(Material, {"E": 2.1e11, "nu": 0.3, "rho": 7850.0}) == STEEL
    assert from_dict(Material, {}) == STEEL  # defaults: steel
    with pytest.raises(SceneError) as e:
        from_dict(Material, {"E": 2.1e11, "nu": 0.7, "rho": 7850.0}, "bodies[1].flex.material")
    assert e.value.path == "bodies[1].flex.material.nu" and e.value.value == 0.7


def test_array_form_needs_every_field():
    from fe_components.params import ShaftSegment
    assert from_dict(ShaftSegment, [0.1, 0.05], "s") == ShaftSegment(0.1, 0.05)
    with pytest.raises(SceneError) as e:
        from_dict(ShaftSegment, [0.1], "shaft[0]")
    assert e.value.path == "shaft[0]"


@pytest.mark.parametrize("deg", [60.0, 45.0, 75.3])
def test_angle_out_of_range_is_named_as_written(deg):
    # a value written in degrees is refused in those degrees (60.0, not 59.99999999999999
    # from the round trip through radians)
    d = _pinion_table()
    d["teeth"]["pressure_angle_deg"] = deg
    with pytest.raises(SceneError) as e:
        component_from_table(d, "bodies[0].component")
    assert e.value.path == "bodies[0].component.teeth.pressure_angle_deg" and e.value.value == deg
