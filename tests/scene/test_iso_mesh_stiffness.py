"""Mesh stiffness left out: ISO 6336-1 method B from the teeth (assembly.scene.gears)."""
import copy
import math
import tomllib

import pytest

from assembly.errors import SceneError
from assembly.scene.gears import iso_stiffnesses
from assembly.scene.save import scene_to_toml
from assembly.scene.schema import SCENE_DIR, scene_from_dict
from fe_components.gear_pair import pair_geometry, tip_alteration, transverse_contact_ratio
from fe_components.mesh_stiffness import mesh_stiffness
from fe_components.params import GearTeeth

DEG = math.radians


def _scene_dict(name: str) -> dict:
    return tomllib.loads((SCENE_DIR / name).read_text())


def _quill(mesh=False, stage=(), face_width=None) -> dict:
    """two_stage_quill.toml with the parallel mesh's stiffness and/or the stage's ``stage``
    stiffnesses left out."""
    d = _scene_dict("two_stage_quill.toml")
    if mesh:
        d["meshes"][0].pop("stiffness")
    for f in stage:
        d["stages"][0].pop(f)
    if face_width is not None:
        d["stages"][0]["face_width"] = face_width
    return d


def _refused(d: dict) -> SceneError:
    with pytest.raises(SceneError) as e:
        scene_from_dict(d)
    return e.value


def test_typed_stiffness_wins():
    sc = scene_from_dict(_quill())
    assert sc.meshes[0].stiffness == 8.4e8
    assert (sc.stages[0].k_mesh_sun, sc.stages[0].k_mesh_ring) == (1.12e9, 1.12e9)
    assert iso_stiffnesses(sc) == []


def test_parallel_mesh_stiffness_is_the_iso_value_of_its_teeth():
    d = _quill(mesh=True)
    sc = scene_from_dict(d)
    # pinion: body teeth; wheel: its component's teeth (both 60 mm wide, 12 deg helix);
    # mesh_stiffness takes the pair's own contact ratio and the smaller face width
    tp = GearTeeth(**{k: v for k, v in d["bodies"][0]["teeth"].items() if not k.endswith("_deg")},
                   pressure_angle=DEG(d["bodies"][0]["teeth"]["pressure_angle_deg"]),
                   helix_angle=DEG(d["bodies"][0]["teeth"]["helix_angle_deg"]))
    wt = d["bodies"][1]["component"]["teeth"]
    tw = GearTeeth(**{k: v for k, v in wt.items() if not k.endswith("_deg")},
                   pressure_angle=DEG(wt["pressure_angle_deg"]), helix_angle=DEG(wt["helix_angle_deg"]))
    eps = pair_geometry(tp, tw).contact_ratio
    want = mesh_stiffness(tp.n_teeth, tw.n_teeth, tp.profile_shift, tw.profile_shift, tp.helix_angle,
                          tp.pressure_angle, eps, min(tp.face_width, tw.face_width))
    assert sc.meshes[0].stiffness == want
    assert iso_stiffnesses(sc) == [("meshes[0].stiffness", want)]


def test_stiffness_scales_with_the_smaller_face_width():
    # k = c_gamma_alpha b: the pinion narrowed from 60 to 45 mm is the smaller face, the
    # contact ratio (transverse) does not change -> k x 45/60
    d = _quill(mesh=True)
    k60 = scene_from_dict(d).meshes[0].stiffness
    d["bodies"][0]["teeth"]["face_width"] = 0.045
    assert scene_from_dict(d).meshes[0].stiffness == pytest.approx(k60 * 0.045 / 0.06, rel=1e-14)
    # the wheel narrower still: its face is the one that counts
    d["bodies"][1]["component"]["teeth"]["face_width"] = 0.03
    assert scene_from_dict(d).meshes[0].stiffness == pytest.approx(k60 * 0.03 / 0.06, rel=1e-14)


def test_as_given_keeps_the_left_out_stiffness_and_round_trips():
    sc = scene_from_dict(_quill(mesh=True, stage=("k_mesh_sun", "k_mesh_ring"), face_width=0.08))
    assert sc.as_given("meshes")[0].stiffness is None
    assert sc.as_given("stages")[0].k_mesh_sun is None
    text = scene_to_toml(sc)
    assert "stiffness" not in text and "k_mesh_" not in text
    back = scene_from_dict(tomllib.loads(text))
    assert back == sc
    assert back.meshes[0].stiffness == sc.meshes[0].stiffness


def test_stage_stiffnesses_are_the_iso_values_of_its_teeth():
    d = _quill(stage=("k_mesh_sun", "k_mesh_ring"), face_width=0.08)
    st = scene_from_dict(d).stages[0]
    # sun 20 (x 0.2), planets 30 (x 0.1), ring 80 (x -0.4), m_n 6 mm, 20 deg spur, b 80 mm
    m_n, a_n = 0.006, DEG(20.0)
    eps_s = transverse_contact_ratio(20, 30, 0.2, 0.1, m_n, a_n, 0.0)
    # the planets' tip circle is cut with the sun pair's tip alteration (ISO 21771), the ring's without
    k_sp = tip_alteration(20, 30, 0.2, 0.1, m_n, a_n, 0.0)
    assert k_sp < 0
    eps_r = transverse_contact_ratio(30, -80, 0.1, -0.4, m_n, a_n, 0.0, (k_sp, 0.0))
    assert st.k_mesh_sun == mesh_stiffness(20, 30, 0.2, 0.1, 0.0, a_n, eps_s, 0.08)
    assert st.k_mesh_ring == mesh_stiffness(30, 80, 0.1, -0.4, 0.0, a_n, eps_r, 0.08, internal=True)
    # the internal pair (z_n2 = inf, concave ring flank) is the stiffer one
    assert st.k_mesh_ring > st.k_mesh_sun


def test_one_stage_stiffness_left_out():
    st = scene_from_dict(_quill(stage=("k_mesh_ring",), face_width=0.08)).stages[0]
    assert st.k_mesh_sun == 1.12e9
    assert st.k_mesh_ring != 1.12e9
    both = scene_from_dict(_quill(stage=("k_mesh_sun", "k_mesh_ring"), face_width=0.08)).stages[0]
    assert st.k_mesh_ring == both.k_mesh_ring


@pytest.mark.parametrize("left_out", [("k_mesh_sun",), ("k_mesh_ring",), ("k_mesh_sun", "k_mesh_ring")])
def test_stage_without_face_width_is_refused(left_out):
    e = _refused(_quill(stage=left_out))
    assert e.path == "stages[0].face_width" and e.value is None
    assert left_out[0] in str(e)


@pytest.mark.parametrize("field", ["k_mesh_sun", "k_mesh_ring"])
def test_stage_without_teeth_needs_its_stiffness(field):
    d = _scene_dict("lin_parker_n3.toml")
    d["stages"][0].pop(field)
    e = _refused(d)
    assert e.path == f"stages[0].{field}" and e.value is None


def test_mesh_without_teeth_on_both_gears_needs_its_stiffness():
    # neither gear has teeth (typed base radii)
    d = _scene_dict("kahraman_beta0.toml")
    i = next(i for i, m in enumerate(d["meshes"]) if "stiffness" in m)
    d["meshes"][i].pop("stiffness")
    e = _refused(d)
    assert e.path == f"meshes[{i}].stiffness" and e.value is None
    # one gear with teeth, the other without: the pinion's teeth taken away
    d = _quill(mesh=True)
    del d["bodies"][0]["teeth"]
    e = _refused(d)
    assert e.path == "meshes[0].stiffness" and "'pinion' has none" in str(e)


def test_changing_the_teeth_derives_a_new_stiffness():
    sc = scene_from_dict(_quill(mesh=True))
    narrower = sc.with_value("bodies[0].teeth.face_width", 0.03)
    assert narrower.meshes[0].stiffness == pytest.approx(sc.meshes[0].stiffness * 0.5, rel=1e-14)
    typed = sc.with_value("meshes[0].stiffness", 5e8)
    assert typed.meshes[0].stiffness == 5e8 and iso_stiffnesses(typed) == []
