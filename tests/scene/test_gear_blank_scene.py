"""Scenes whose gears are given by teeth only: mass and inertia from the gear blank
(fe_components.gear_blank; closed forms in tests/fe_components/test_gear_blank.py), the
scene keeping the user's table, and pointed teeth refused naming the profile shift.

Stage data: the NREL 5 MW reference gearbox, Nejad, Guo, Gao, Moan (2016), Wind Energy 19,
1089-1106, Table V, stage 1: teeth 19 / 17 / 56, m_n 45 mm, alpha_n 20 deg, spur, shifts
0.617 / 0.802 / -0.501, face width 491 mm.
"""
import copy
import math
import tomllib

import pytest

from assembly.errors import SceneError
from assembly.scene.save import scene_to_toml
from assembly.scene.schema import scene_from_dict
from fe_components.gear_blank import blank_mass_properties

RHO = 7850.0   # kg/m^3
BEARING = {"k_radial": 1e9, "k_axial": 1e8, "k_tilt": 1e8, "k_torsion": 0.0}
STAGE_1 = {
    "name": "nrel 5 MW stage 1",
    "stages": [{
        "name": "s1", "k_mesh_sun": 1e10, "k_mesh_ring": 1e10, "normal_module": 0.045,
        "normal_pressure_angle_deg": 20.0, "face_width": 0.491,
        "sun": {"teeth": 19, "profile_shift": 0.617, "bearing": BEARING},
        "ring": {"teeth": 56, "profile_shift": -0.501, "support": "fixed"},
        "carrier": {"mass": 5000.0, "polar_inertia": 2000.0, "bearing": BEARING},
        "planets": {"count": 3, "teeth": 17, "profile_shift": 0.802, "bearing": BEARING},
    }],
}
GEAR = {"name": "gear", "teeth": {"n_teeth": 40, "normal_module": 0.004, "pressure_angle_deg": 20.0,
                                  "face_width": 0.03}}


def one_gear(**changes):
    body = {**copy.deepcopy(GEAR), **changes}
    return {"name": "one gear", "bodies": [body], "bearings": [{"body": "gear", **BEARING}]}


def refused(data) -> SceneError:
    with pytest.raises(SceneError) as err:
        scene_from_dict(data)
    return err.value


def test_body_with_teeth_only_takes_the_blank_and_is_written_as_given():
    sc = scene_from_dict(one_gear(blank={"bore_diameter": 0.05}))
    b = sc.bodies[0]
    # d_f = 150 mm, d_a = 168 mm: m = rho b pi/4 (d_f^2 - 0.05^2 + (d_a^2 - d_f^2)/2)
    assert b.mass == pytest.approx(RHO * 0.03 * math.pi / 4 * (0.15 ** 2 - 0.05 ** 2 + (0.168 ** 2 - 0.15 ** 2) / 2),
                                   rel=1e-12)
    assert b.transverse_inertia == blank_mass_properties(40, 0.004, 0.0, 0.0, 0.03,
                                                         blank=sc.as_given("bodies")[0].blank).transverse_inertia
    text = scene_to_toml(sc)
    assert "mass" not in text and "polar_inertia" not in text
    assert scene_from_dict(tomllib.loads(text)) == sc


def test_a_given_transverse_inertia_is_kept():
    sc = scene_from_dict(one_gear(transverse_inertia=0.5))
    assert sc.bodies[0].transverse_inertia == 0.5 and sc.bodies[0].mass is not None


def test_nrel_5mw_stage_1_members_from_their_blanks():
    sc = scene_from_dict(copy.deepcopy(STAGE_1))
    st = sc.stages[0]
    # Tip diameters with the ISO 21771 tip alteration as Nejad et al. (2016), Table V gives
    # them: sun 978.839 mm, planet 905.440 mm (k = -0.241 on both), ring 2475.087 mm (none);
    # ours differ from the table's by at most 0.03 mm (tests/fe_components/test_fe_gear_pair.py),
    # which moves the half-metal tooth zone rho b pi/4 d_a dd_a / 2 by under 0.1 kg: rel 1e-4.
    # sun: d_f = 855 - 90 * 0.633 = 798.03 mm, m = rho b pi/4 (d_f^2 + (d_a^2 - d_f^2)/2) = 2414 kg
    assert st.sun.mass == pytest.approx(RHO * 0.491 * math.pi / 4 * (0.79803 ** 2 + (0.978839 ** 2 - 0.79803 ** 2) / 2),
                                        rel=1e-4)
    # planet: d = 765 mm, d_f = 765 - 90 * 0.448 = 724.68 mm
    assert st.planets.mass == pytest.approx(
        RHO * 0.491 * math.pi / 4 * (0.72468 ** 2 + (0.905440 ** 2 - 0.72468 ** 2) / 2), rel=1e-4)
    # ring: d = 2520 mm, d_a = 2520 - 90 * 0.499 = 2475.09 mm, d_f = 2520 + 90 * 1.751 = 2677.59 mm,
    # rim to d_f + 2 * 1.2 * 2.25 * 45 mm = 2920.59 mm
    assert st.ring.mass == pytest.approx(RHO * 0.491 * math.pi / 4 * (
        (2.67759 ** 2 - 2.47509 ** 2) / 2 + 2.92059 ** 2 - 2.67759 ** 2), rel=1e-12)
    # the file keeps what the user wrote, and the scene expands with the derived numbers
    written = tomllib.loads(scene_to_toml(sc))["stages"][0]
    assert all("mass" not in written[role] and "polar_inertia" not in written[role]
               for role in ("sun", "planets", "ring"))
    assert scene_from_dict(tomllib.loads(scene_to_toml(sc))) == sc
    assert sc.body("s1.planet2").mass == st.planets.mass


def test_stage_without_face_width_is_refused():
    data = copy.deepcopy(STAGE_1)
    del data["stages"][0]["face_width"]
    err = refused(data)
    assert err.path == "stages[0].face_width" and err.value is None
    data["stages"][0]["sun"].update(mass=2479.0, polar_inertia=250.0)   # sun typed: the planets still need it
    assert "planets" in refused(data).reason
    data["stages"][0]["planets"]["blank"] = {"length": 0.491}          # a blank length serves instead
    data["stages"][0]["ring"].update(mass=1e4, polar_inertia=1e4)
    assert scene_from_dict(data).stages[0].planets.mass > 0


def test_planets_without_teeth_still_need_their_mass():
    data = copy.deepcopy(STAGE_1)
    st = data["stages"][0]
    for k in ("normal_module", "normal_pressure_angle_deg", "face_width"):
        del st[k]
    for role in ("sun", "planets", "ring"):
        del st[role]["teeth"], st[role]["profile_shift"]
    st.update(pressure_angle_sun_deg=20.0, pressure_angle_ring_deg=20.0)
    st["sun"].update(base_radius=0.4, mass=1.0, polar_inertia=1.0)
    st["ring"].update(base_radius=1.2, mass=1.0, polar_inertia=1.0)
    st["planets"]["base_radius"] = 0.4
    err = refused(data)
    assert err.path == "stages[0].planets.mass" and err.value is None


@pytest.mark.parametrize("change, path", [
    (lambda d: d["bodies"][0].update(mass=5.0, polar_inertia=0.01, blank={}), "bodies[0].blank"),
    (lambda d: d["bodies"][0].update(blank={"bore_diameter": 0.15}), "bodies[0].blank.bore_diameter"),
    (lambda d: d["bodies"][0].update(blank={"outer_diameter": 0.3}), "bodies[0].blank.outer_diameter"),
    (lambda d: d["bodies"][0].update(blank={"length": -1.0}), "bodies[0].blank.length"),
    (lambda d: d["bodies"][0].pop("teeth") and d["bodies"][0].update(mass=1.0, polar_inertia=1.0, blank={}),
     "bodies[0].blank"),
])
def test_blank_tables_that_cannot_be_used_are_refused(change, path):
    data = one_gear()
    change(data)
    assert refused(data).path == path


@pytest.mark.parametrize("role", ["carrier", "sun"])
def test_stage_blank_where_it_is_not_used(role):
    data = copy.deepcopy(STAGE_1)
    data["stages"][0][role].update(mass=10.0, polar_inertia=1.0, blank={})
    assert refused(data).path == f"stages[0].{role}.blank"


def limit_shift(z):
    """x with tip thickness 0 for z teeth, alpha_n 20 deg (bisection on ISO 21771's
    s_a = d_a (s_t/d + inv(alpha) - inv(alpha_a)) for m_n = 1, spur)."""
    a = math.radians(20)

    def s_a(x):
        d, d_a = z, z + 2 * (1 + x)
        aa = math.acos(d * math.cos(a) / d_a)
        return d_a * ((math.pi / 2 + 2 * x * math.tan(a)) / d + math.tan(a) - a - math.tan(aa) + aa)
    lo, hi = 0.0, 0.99
    for _ in range(60):
        lo, hi = ((lo + hi) / 2, hi) if s_a((lo + hi) / 2) > 0 else (lo, (lo + hi) / 2)
    return lo


def test_pointed_body_teeth_are_refused_at_the_limit_shift():
    x_lim = limit_shift(10)     # 0.6996 for 10 teeth
    ok = one_gear()
    ok["bodies"][0]["teeth"].update(n_teeth=10, profile_shift=x_lim - 1e-4)
    scene_from_dict(ok)
    bad = copy.deepcopy(ok)
    bad["bodies"][0]["teeth"]["profile_shift"] = x_lim + 1e-4
    err = refused(bad)
    assert err.path == "bodies[0].teeth.profile_shift" and err.value == x_lim + 1e-4
    assert "pointed" in err.reason and "tip thickness" in err.reason


def test_pointed_stage_member_names_its_profile_shift():
    data = copy.deepcopy(STAGE_1)
    # 5 planet teeth against the 19-tooth sun (x 0.617) are pointed from x = 0.95 on, with their
    # tips cut with the pair's tip alteration (threshold found by bisection in
    # tests/app/test_bad_stage_data.py); at x = 0.99 they are
    data["stages"][0]["planets"].update(teeth=5, profile_shift=0.99)
    assert refused(data).path == "stages[0].planets.profile_shift"
