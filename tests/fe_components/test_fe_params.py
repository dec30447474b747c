"""Bad input is refused before meshing, with the parameter's dotted path and value."""
from __future__ import annotations

import dataclasses
import math

import pytest

from fe_components.errors import GeometryError, MaterialError
from fe_components.material import STEEL, Material
from fe_components.params import GearTeeth, PinionParams, ShaftSegment, WheelParams, params_digest
from fe_components.reference import CARRIER, PINION_SMOOTH, WHEEL_SMOOTH

DEG20 = math.radians(20)


def test_material_validation():
    assert STEEL.G == pytest.approx(2.1e11 / 2.6)  # G = E / (2 (1 + nu))
    with pytest.raises(MaterialError) as e:
        Material(2.1e11, 0.5, 7850.0)
    assert e.value.parameter == "nu" and e.value.value == 0.5
    with pytest.raises(MaterialError):
        Material(-1.0, 0.3, 7850.0)
    with pytest.raises(MaterialError):
        Material(2.1e11, 0.3, 0.0)


def test_undercut_limit_spur_20deg():
    # z_min = 2 / sin^2(20 deg) = 17.1 -> 17 teeth is the quoted practical limit (ISO 21771, Niemann)
    GearTeeth(17, 0.004, DEG20, 0.04)
    with pytest.raises(GeometryError) as e:
        GearTeeth(16, 0.004, DEG20, 0.04)
    assert e.value.parameter == "n_teeth" and e.value.value == 16
    assert "undercut" in str(e.value)


def test_undercut_limit_helical_and_shift():
    # helical: z_min = 2 cos(beta) / sin^2(alpha_t), tan(alpha_t) = tan(alpha_n) / cos(beta); beta = 30 deg
    beta = math.radians(30)
    at = math.atan(math.tan(DEG20) / math.cos(beta))
    zmin = math.floor(2 * math.cos(beta) / math.sin(at) ** 2)
    GearTeeth(zmin, 0.004, DEG20, 0.04, helix_angle=beta)
    with pytest.raises(GeometryError):
        GearTeeth(zmin - 1, 0.004, DEG20, 0.04, helix_angle=beta)
    # positive profile shift x = 0.5 lowers the limit to 2 (1 - x) / sin^2(alpha) = 8.5 -> 8
    GearTeeth(10, 0.004, DEG20, 0.04, profile_shift=0.5)


@pytest.mark.parametrize("field,value", [("normal_module", 0.0), ("face_width", -0.01), ("n_teeth", 2)])
def test_non_positive_tooth_sizes(field, value):
    kw = dict(n_teeth=20, normal_module=0.004, pressure_angle=DEG20, face_width=0.04)
    kw[field] = value
    with pytest.raises(GeometryError) as e:
        GearTeeth(**kw)
    assert e.value.parameter == field and e.value.value == value


def test_bore_at_root_circle_refused():
    for base in (PINION_SMOOTH, WHEEL_SMOOTH):
        bad = 2 * base.teeth.root_radius  # bore exactly at the root circle
        with pytest.raises(GeometryError) as e:
            dataclasses.replace(base, bore_diameter=bad)
        assert e.value.parameter == "bore_diameter" and e.value.value == bad


def test_non_positive_shaft_segment():
    with pytest.raises(GeometryError) as e:
        ShaftSegment(0.0, 0.03)
    assert e.value.parameter == "length"


def test_gear_must_lie_between_bearing_seats():
    with pytest.raises(GeometryError) as e:
        dataclasses.replace(PINION_SMOOTH, gear_center=0.01)
    assert e.value.parameter == "gear_center"


def test_overlapping_pin_bores():
    # 3 pins on r = 0.1 m: centre distance 2 r sin(60 deg) = 0.1732 m
    d = 2 * 0.1 * math.sin(math.pi / 3)
    with pytest.raises(GeometryError) as e:
        dataclasses.replace(CARRIER, pin_bore_diameter=d * 1.001, cheek_diameter=0.5, post_radius=0.2,
                            post_diameter=0.01)
    assert e.value.parameter == "pin_bore_diameter"
    # two pins 10 deg apart overlap for a 30 mm bore: 2 * 0.1 * sin(5 deg) = 17.4 mm
    with pytest.raises(GeometryError) as e:
        dataclasses.replace(CARRIER, planet_angles=(0.0, math.radians(10), math.pi))
    assert e.value.parameter == "pin_bore_diameter"


def test_wheel_holes_must_fit():
    with pytest.raises(GeometryError) as e:
        dataclasses.replace(WHEEL_SMOOTH, hole_diameter=0.06)  # (0.2 - 0.08) / 2 = 0.06 m gap
    assert e.value.parameter == "hole_diameter"


def test_digest_covers_every_input():
    a = params_digest(PINION_SMOOTH)
    assert a == params_digest(PINION_SMOOTH)
    b = params_digest(dataclasses.replace(PINION_SMOOTH, bore_diameter=0.01))
    shaft = list(PINION_SMOOTH.shaft)
    shaft[2] = ShaftSegment(0.08, 0.0501)
    c = params_digest(dataclasses.replace(PINION_SMOOTH, shaft=tuple(shaft)))
    assert len({a, b, c}) == 3


def test_wheel_params_type_check():
    with pytest.raises(GeometryError):
        WheelParams(teeth=None, rim_inner_diameter=0.2, web_thickness=0.01, hub_outer_diameter=0.08,
                    hub_length=0.05, bore_diameter=0.05)
    with pytest.raises(GeometryError):
        PinionParams(PINION_SMOOTH.teeth, (ShaftSegment(0.1, 0.03),), gear_center=0.05)
