"""Scenes from teeth (ISO 21771): meshes and planetary stages derive their gear numbers,
meshes place bodies at the working centre distance, typed numbers must agree with the
teeth, and the two-stage example's rigid-body mode is the kinematic chain of its teeth."""
import copy
import dataclasses
import math
import tomllib

import numpy as np
import pytest

from assembly import assemble, solve_modes
from assembly.analysis.compare import compare
from assembly.errors import SceneError
from assembly.scene.gears import RING_CENTRE_TOLERANCE
from assembly.scene.schema import SCENE_DIR, load_scene, scene_from_dict
from assembly.scene.tables import with_fidelity
from fe_components.gear_pair import base_radius, pair_geometry, working_centre_distance
from fe_components.params import GearTeeth

QUILL = SCENE_DIR / "two_stage_quill.toml"
DEG = math.radians


def quill_dict() -> dict:
    return tomllib.loads(QUILL.read_text())


def refused(data: dict) -> SceneError:
    with pytest.raises(SceneError) as e:
        scene_from_dict(data)
    return e.value


# ---------------------------------------------------------------- the example
def test_quill_rigid_body_mode_is_the_kinematic_chain():
    # one rigid-body mode; each body's rotation over the pinion's is the speed ratio of the
    # teeth: wheel -21/83 (external pair), sun = wheel (quill), carrier = sun 20/(20 + 80)
    # (ring fixed), planet (absolute) = carrier - (sun - carrier) 20/30 (Willis)
    sc = load_scene(QUILL)
    for fidelity in ("rigid", "torsional"):
        res = solve_modes(assemble(with_fidelity(sc, fidelity)))
        assert res.n_rigid == 1
        rz = {b.name: res.body_motion(0, b.name)[5] for b in sc.expanded().bodies}
        wheel = -21 / 83
        carrier = wheel * 20 / 100
        want = {"pinion": 1.0, "wheel": wheel, "planetary.sun": wheel, "planetary.carrier": carrier,
                "planetary.ring": 0.0}
        want.update({f"planetary.planet{i}": carrier - (wheel - carrier) * 20 / 30 for i in range(4)})
        for name, ratio in want.items():
            assert rz[name] / rz["pinion"] == pytest.approx(ratio, rel=1e-9, abs=1e-9), (fidelity, name)


def test_quill_geometry_is_derived_from_the_teeth():
    sc = load_scene(QUILL)
    m = sc.meshes[0]
    pinion = sc.bodies[0].teeth
    g = pair_geometry(pinion, GearTeeth(n_teeth=83, normal_module=0.005, pressure_angle=DEG(20),
                                        face_width=0.06, helix_angle=DEG(-12), profile_shift=0.1))
    # line of action of a right-hand pinion: minus its base helix angle,
    # tan(beta_b) = tan(beta) cos(alpha_t) (ISO 21771)
    beta_b = math.atan(math.tan(DEG(12)) * math.cos(math.atan(math.tan(DEG(20)) / math.cos(DEG(12)))))
    assert (m.base_radius1, m.base_radius2, m.pressure_angle) == \
        (g.base_radius1, g.base_radius2, g.working_pressure_angle)
    assert m.helix_angle == pytest.approx(-beta_b, rel=1e-14)
    wheel = sc.body("wheel")
    assert np.allclose(wheel.position, (g.centre_distance, 0.0, 0.0), rtol=0, atol=1e-15)
    # the quill joins coaxial bodies: the stage centre (typed, derived) is on the wheel's axis
    st = sc.stages[0]
    assert np.allclose(st.center[:2], wheel.position[:2], rtol=0, atol=1e-12)
    # carrier radius = sun-planet working centre distance; ring mesh at that distance
    sun = GearTeeth(n_teeth=20, normal_module=0.006, pressure_angle=DEG(20), face_width=0.08, profile_shift=0.2)
    planet = GearTeeth(n_teeth=30, normal_module=0.006, pressure_angle=DEG(20), face_width=0.08, profile_shift=0.1)
    assert st.carrier_radius() == pytest.approx(pair_geometry(sun, planet).centre_distance, rel=1e-14)
    assert st.ring.base_radius == base_radius(80, 0.006, DEG(20), 0.0)


@pytest.mark.slow
def test_quill_runs_at_all_three_fidelities():
    c = compare(with_fidelity(load_scene(QUILL), "flexible", bodies="wheel"), n_rows=12)
    f = c.frequencies()
    assert set(f) == {"torsional", "rigid", "flexible"}
    # Rayleigh-Ritz: each added freedom can only lower the k-th eigenvalue (f^2), up to the
    # round-off of a symmetric eigensolver, a small multiple of eps x the largest eigenvalue
    # (so a zero mode may come out at ~sqrt(eps) f_max, ~1e-4 Hz here)
    for lo, hi in (("rigid", "torsional"), ("flexible", "rigid")):
        lam_lo, lam_hi = np.square(f[lo]), np.square(f[hi])
        for k in range(len(lam_hi)):
            assert lam_lo[k] <= lam_hi[k] * (1 + 1e-9) + 1e-9 * lam_hi[-1], (lo, hi, k)


# ---------------------------------------------------------------- round trip
def _typed(data: dict) -> dict:
    """The same scene with the derived numbers typed and the teeth left out (the wheel's
    component keeps its teeth, which the typed radius must then match)."""
    sc = scene_from_dict(data)
    d = copy.deepcopy(data)
    d["bodies"][0].pop("teeth")
    d["bodies"][1]["position"] = list(sc.body("wheel").position)
    m = sc.meshes[0]
    d["meshes"][0].update(base_radius1=m.base_radius1, base_radius2=m.base_radius2,
                          pressure_angle=m.pressure_angle, helix_angle=m.helix_angle)
    del d["meshes"][0]["place"], d["meshes"][0]["centre_line_angle_deg"]
    st, ds = sc.stages[0], d["stages"][0]
    for k in ("normal_module", "normal_pressure_angle_deg"):
        ds.pop(k)
    for role in ("sun", "ring", "planets"):
        ds[role].pop("teeth"), ds[role].pop("profile_shift")
        ds[role]["base_radius"] = getattr(st, role).base_radius
    ds.update(pressure_angle_sun=st.pressure_angle_sun, pressure_angle_ring=st.pressure_angle_ring)
    return d


def test_teeth_and_typed_numbers_give_the_same_frequencies():
    data = quill_dict()
    with_teeth = solve_modes(assemble(scene_from_dict(data))).frequencies_hz
    typed = solve_modes(assemble(scene_from_dict(_typed(data)))).frequencies_hz
    assert np.allclose(with_teeth, typed, rtol=1e-12, atol=0)


def test_typed_numbers_that_agree_are_accepted_with_the_teeth():
    data = quill_dict()
    t = _typed(data)
    data["meshes"][0].update({k: t["meshes"][0][k] for k in ("base_radius1", "base_radius2", "pressure_angle")})
    data["stages"][0]["sun"]["base_radius"] = t["stages"][0]["sun"]["base_radius"]
    assert scene_from_dict(data).meshes[0].base_radius2 == t["meshes"][0]["base_radius2"]


# ---------------------------------------------------------------- refusals
def test_90_tooth_wheel_component_on_an_80_tooth_mesh():
    d = _typed(quill_dict())
    d["bodies"][1]["component"]["teeth"]["n_teeth"] = 90
    d["bodies"][1]["component"]["rim_inner_diameter"] = 0.40
    d["meshes"][0]["base_radius2"] = base_radius(80, 0.005, DEG(20), DEG(-12))
    err = refused(d)
    assert err.path == "meshes[0].base_radius2" and err.value == d["meshes"][0]["base_radius2"]
    assert "bodies[1].component.teeth" in err.reason and "n_teeth = 90" in err.reason


def test_mismatched_module_is_refused_naming_both_fields():
    d = quill_dict()
    d["bodies"][1]["component"]["teeth"]["normal_module"] = 0.006
    d["bodies"][1]["component"]["rim_inner_diameter"] = 0.44
    err = refused(d)
    assert err.path == "bodies[1].component.teeth.normal_module" and err.value == 0.006
    assert "bodies[0].teeth.normal_module = 0.005" in err.reason and "meshes[0]" in err.reason


def test_helix_of_the_same_hand_on_an_external_pair_is_refused():
    d = quill_dict()
    d["bodies"][1]["component"]["teeth"]["helix_angle_deg"] = 12.0
    err = refused(d)
    assert err.path == "bodies[1].component.teeth.helix_angle_deg" and err.value == 12.0
    assert "opposite" in err.reason and "bodies[0].teeth.helix_angle_deg = 12" in err.reason


def test_body_teeth_must_equal_its_component_teeth():
    d = quill_dict()
    d["bodies"][1]["teeth"] = {**d["bodies"][1]["component"]["teeth"], "n_teeth": 80}
    err = refused(d)
    assert err.path == "bodies[1].teeth.n_teeth" and err.value == 80
    assert "bodies[1].component.teeth.n_teeth = 83" in err.reason
    d["bodies"][1]["teeth"]["n_teeth"] = 83     # the same teeth twice: one definition, accepted
    scene_from_dict(d)


def test_ring_whose_working_centre_distance_disagrees_is_refused():
    # ring shift -0.3 instead of -0.4: planet-ring shift sum -0.2 over z = -50 puts the
    # planets 0.56 mm from where the sun-planet pair does (a_w 0.151728 m), ten times the
    # tolerance of 0.01 m_n = 0.06 mm
    d = quill_dict()
    d["stages"][0]["ring"]["profile_shift"] = -0.3
    err = refused(d)
    assert err.path == "stages[0].ring.teeth" and err.value == 80
    a_sp = working_centre_distance(20, 30, 0.2, 0.1, 0.006, DEG(20), 0.0)
    a_pr = working_centre_distance(30, -80, 0.1, -0.3, 0.006, DEG(20), 0.0)
    assert abs(a_pr - a_sp) > 5 * RING_CENTRE_TOLERANCE * 0.006
    assert f"{a_sp:.9g} m" in err.reason and f"{a_pr:.9g} m" in err.reason
    assert f"tolerance {RING_CENTRE_TOLERANCE * 0.006:.3g} m" in err.reason


def test_typed_pressure_angle_disagreeing_with_the_teeth_is_echoed_in_degrees():
    d = quill_dict()
    d["meshes"][0]["pressure_angle_deg"] = 20.0
    err = refused(d)
    assert err.path == "meshes[0].pressure_angle_deg" and err.value == 20.0
    assert "21.5035032 deg" in err.reason and "bodies[0].teeth" in err.reason


def test_placement_refusals():
    d = quill_dict()
    d["meshes"].append(dict(d["meshes"][0], name="again"))
    err = refused(d)
    assert err.path == "meshes[1].place" and "already placed by meshes[0]" in err.reason
    d = quill_dict()
    d["bodies"][1]["position"] = [0.27, 0.0, 0.0]          # not where the mesh puts it
    err = refused(d)
    assert err.path == "bodies[1].position" and "0.267758156" in err.reason
    # a cycle: pinion placed from the wheel and the wheel from the pinion
    d = quill_dict()
    d["bodies"][0].pop("position")
    d["meshes"].append(dict(d["meshes"][0], name="back", place="gear1"))
    err = refused(d)
    assert err.path == "meshes[1].place" and "cycle" in err.reason


def test_placement_along_the_centre_line_angle():
    d = quill_dict()
    d["meshes"][0]["centre_line_angle_deg"] = 90.0
    sc = scene_from_dict(d)
    wheel = sc.body("wheel").position
    assert np.allclose(wheel, (0.0, 0.2677581560127026, 0.0), rtol=0, atol=1e-15)
    # the stage (coaxial_with = "wheel", axial_offset = 0.4 m) follows the wheel exactly
    assert sc.stages[0].center == (wheel[0], wheel[1], wheel[2] + 0.4)


def test_scene_fidelity_is_the_default_of_every_table():
    d = quill_dict()
    d["fidelity"] = "torsional"
    d["stages"][0]["carrier"]["fidelity"] = "rigid"    # its own wins
    sc = scene_from_dict(d)
    fid = {b.name: b.fidelity for b in sc.expanded().bodies}
    assert fid.pop("planetary.carrier") == "rigid"
    assert set(fid.values()) == {"torsional"}
    d.pop("fidelity")
    assert {b.fidelity for b in scene_from_dict(d).expanded().bodies} == {"rigid"}


def test_hs_stage_from_teeth_equals_its_typed_numbers():
    # hs_parallel_stage.toml gives teeth (23 / 71, m_n 4 mm, 20 deg, 12 deg) and lets the
    # mesh place the wheel; with the numbers its earlier version typed (computed from the
    # same teeth) every mesh number and body is the same float, hence the same model. The
    # helix is the line of action's: minus the right-hand pinion's base helix angle,
    # tan(beta_b) = tan(12 deg) cos(alpha_t) (ISO 21771; the earlier version typed +12 deg)
    d = tomllib.loads((SCENE_DIR / "hs_parallel_stage.toml").read_text())
    from_teeth = scene_from_dict(d)
    typed = copy.deepcopy(d)
    typed["bodies"][1]["position"] = [0.1922000318346255, 0.0, 0.295]
    typed["meshes"][0].pop("place")
    typed["meshes"][0].update(base_radius1=0.04407523468393626, base_radius2=0.13605833315475976,
                              pressure_angle_deg=20.41031175365969,
                              helix_angle=-math.atan(math.tan(DEG(12)) * math.cos(DEG(20.41031175365969))))
    typed = scene_from_dict(typed)
    assert from_teeth.bodies == typed.bodies
    assert dataclasses.replace(from_teeth.meshes[0], place=None) == typed.meshes[0]
