"""Bearings with different stiffnesses in the two radial and the two tilt directions.

Stiffnesses of the planet-carrier bearing PLC-A of the NREL 5 MW reference gearbox: Nejad,
Guo, Gao, Moan (2016), Wind Energy 19, 1089-1106, Table VI: K_x (axial) 6.6e4 N/m, K_y 1.7e9
N/m, K_z 1.1e9 N/m, K_beta 5.6e5 N m/rad, K_gamma 1.3e5 N m/rad (his x axial -> our local z;
his y, z -> our x, y; his beta, gamma -> our rx, ry).
"""
import dataclasses
import math
import tomllib

import pytest

from assembly.analysis.modal import solve_modes
from assembly.errors import SceneError
from assembly.model.assemble import assemble
from assembly.scene.save import scene_to_toml
from assembly.scene.schema import load_scene, scene_from_dict, to_dict
from assembly.scene.tables import Bearing, Body, Scene, scale_bearings

PLC_A = dict(k_axial=6.6e4, k_radial_x=1.7e9, k_radial_y=1.1e9, k_tilt_x=5.6e5, k_tilt_y=1.3e5)
M, JP, JT = 1000.0, 40.0, 25.0       # kg, kg m^2, kg m^2 (a round test body)


def one_body(**bearing):
    return Scene(name="one bearing", bodies=(Body(name="b", mass=M, polar_inertia=JP, transverse_inertia=JT),),
                 bearings=(Bearing(body="b", **bearing),))


def hz(k, inertia):
    return math.sqrt(k / inertia) / (2 * math.pi)


def test_anisotropic_bearing_on_a_rigid_body_gives_each_direction_its_own_frequency():
    # A rigid body held at its centre of mass by a diagonal spring: the six DOFs decouple,
    # f_i = sqrt(k_i / m_i) / (2 pi) with m_i = m (x, y, z), J_t (rx, ry), J_p (rz; k_torsion 0 -> 0 Hz).
    f = solve_modes(assemble(one_body(**PLC_A))).frequencies_hz
    want = sorted([0.0, hz(PLC_A["k_radial_x"], M), hz(PLC_A["k_radial_y"], M), hz(PLC_A["k_axial"], M),
                   hz(PLC_A["k_tilt_x"], JT), hz(PLC_A["k_tilt_y"], JT)])
    assert f[0] == pytest.approx(0.0, abs=1e-6 * want[-1])
    assert list(f[1:]) == pytest.approx(want[1:], rel=1e-9)


def test_diagonal_names_the_field_behind_each_entry():
    aniso = Bearing(body="b", **PLC_A)
    assert aniso.diagonal_fields() == ("k_radial_x", "k_radial_y", "k_axial", "k_tilt_x", "k_tilt_y", "k_torsion")
    assert list(aniso.diagonal()) == [1.7e9, 1.1e9, 6.6e4, 5.6e5, 1.3e5, 0.0]
    mixed = Bearing(body="b", k_radial=3e8, k_axial=1e8, k_tilt_x=1e5, k_tilt_y=2e5)
    assert mixed.diagonal_fields() == ("k_radial", "k_radial", "k_axial", "k_tilt_x", "k_tilt_y", "k_torsion")


def test_near_rigid_direction_becomes_a_constraint_of_its_own_field():
    # k_radial_x 1e20 N/m on 1000 kg (1.6e7 Hz against a 3 kHz band) is held exactly; y keeps
    # its spring, so the y mode stays at sqrt(k_y / m) / (2 pi).
    model = assemble(one_body(**{**PLC_A, "k_radial_x": 1e20}))
    assert "b.x" not in model.dof_names and "b.y" in model.dof_names
    f = solve_modes(model).frequencies_hz
    assert min(f, key=lambda v: abs(v - hz(1.1e9, M))) == pytest.approx(hz(1.1e9, M), rel=1e-9)


def test_anisotropic_bearings_round_trip_and_scale():
    sc = one_body(**PLC_A)
    assert scene_from_dict(tomllib.loads(scene_to_toml(sc))) == sc
    twice = scale_bearings(sc, 2.0, ("k_radial",))
    assert (twice.bearings[0].k_radial_x, twice.bearings[0].k_radial_y) == (3.4e9, 2.2e9)
    assert twice.bearings[0].k_tilt_x == PLC_A["k_tilt_x"]


def test_stage_bearing_tables_carry_both_directions_to_the_expanded_bearings():
    data = to_dict(load_scene("lin_parker_n3.toml"))
    data["stages"][0]["planets"]["bearing"] = {"k_radial_x": 1e8, "k_radial_y": 2e8, "k_axial": math.inf,
                                               "k_tilt": math.inf}
    sc = scene_from_dict(data)
    br = next(b for b in sc.expanded().bearings if b.name == "stage.planet1.bearing")
    assert list(br.diagonal()[:2]) == [1e8, 2e8]
    assert scene_from_dict(tomllib.loads(scene_to_toml(sc))) == sc


ISO = dict(k_radial=1e9, k_axial=1e8, k_tilt=1e5)
BAD = [  # (bearing fields, field the error names)
    ({**ISO, "k_radial_x": 1e9}, "k_radial_x"),                 # both ways (radial)
    ({**ISO, "k_radial_y": 1e9, "k_radial_x": 2e9}, "k_radial_x"),
    ({**ISO, "k_tilt_y": 1e5}, "k_tilt_y"),                     # both ways (tilt)
    ({"k_axial": 1e8, "k_tilt": 1e5, "k_radial_x": 1e9}, "k_radial_y"),   # one of a pair
    ({"k_axial": 1e8, "k_tilt": 1e5, "k_radial_y": 1e9}, "k_radial_x"),
    ({"k_axial": 1e8, "k_radial": 1e9, "k_tilt_x": 1e5}, "k_tilt_y"),
    ({"k_axial": 1e8, "k_tilt": 1e5}, "k_radial"),                         # neither
    ({"k_axial": 1e8, "k_radial": 1e9}, "k_tilt"),
    ({"k_radial": 1e9, "k_tilt": 1e5}, "k_axial"),                         # no axial stiffness
]


@pytest.mark.parametrize("fields, named", BAD)
def test_bad_combinations_are_refused_naming_the_field(fields, named):
    with pytest.raises(SceneError) as err:
        one_body(**fields)
    assert err.value.path == f"bearings[0].{named}"


@pytest.mark.parametrize("member", ["sun", "planets"])
@pytest.mark.parametrize("fields, named", BAD)
def test_bad_combinations_in_a_stage_name_its_bearing_table(member, fields, named):
    data = to_dict(load_scene("lin_parker_n3.toml"))
    data["stages"][0][member]["bearing"] = fields
    with pytest.raises(SceneError) as err:
        scene_from_dict(data)
    assert err.value.path == f"stages[0].{member}.bearing.{named}"


def test_bearing_without_its_pair_is_refused_from_python_too():
    sc = one_body(**PLC_A)
    with pytest.raises(SceneError) as err:
        dataclasses.replace(sc, bearings=(dataclasses.replace(sc.bearings[0], k_radial_y=None),))
    assert err.value.path == "bearings[0].k_radial_y"
