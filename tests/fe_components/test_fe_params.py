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


@pytest.mark.parametrize("params,field", [(PINION_SMOOTH, "gear_center"), (WHEEL_SMOOTH, "web_offset"),
                                          (WHEEL_SMOOTH, "hub_offset"), (CARRIER, "cheek_spacing"),
                                          (PINION_SMOOTH.teeth, "profile_shift")])
@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, 1e300, "0.01", True, None])
def test_python_values_checked_before_any_relation(params, field, value):
    # Built in Python: a NaN offset used to pass every comparison (all False) and hang in
    # gmsh; a string or a bool is not a number. Refused first, naming the field.
    with pytest.raises(GeometryError) as e:
        dataclasses.replace(params, **{field: value})
    assert e.value.parameter == field and "finite number" in str(e.value)


def test_numpy_numbers_accepted():
    import numpy as np
    p = dataclasses.replace(PINION_SMOOTH, gear_center=np.float64(0.12))
    assert p.gear_center == 0.12


@pytest.mark.parametrize("field,value,blamed", [
    # face width 0.04 m, web 0.012 m thick: |offset| + 0.006 must stay within 0.02 m
    ("web_offset", 0.015, "web_offset"),
    ("web_offset", -0.015, "web_offset"),
    ("web_thickness", 0.05, "web_thickness"),     # thicker than the face: no offset fits
    # hub 0.05 m long must span the web: |hub_offset - web_offset| + 0.006 <= 0.025 m
    ("hub_offset", 0.03, "hub_offset"),
    ("hub_length", 0.01, "hub_length"),           # shorter than the web is thick
    # holes 0.03 m between hub (r 0.04 m) and rim (r 0.1 m): pitch radius in (0.055, 0.085) m
    ("hole_pitch_diameter", 0.19, "hole_pitch_diameter"),
    ("hole_diameter", 0.07, "hole_diameter"),     # wider than the 0.06 m web annulus
])
def test_wheel_blames_the_field_that_does_not_fit(field, value, blamed):
    with pytest.raises(GeometryError) as e:
        dataclasses.replace(WHEEL_SMOOTH, **{field: value})
    assert e.value.parameter == blamed


def test_offsets_of_either_sign_fit():
    # a web shifted towards -z (inside the face width) and a hub following it are valid parts
    w = dataclasses.replace(WHEEL_SMOOTH, web_offset=-0.01, hub_offset=-0.01)
    assert w.web_offset == -0.01
