"""A body's component is its typed fe_components parameter object: built in Python, read
from a TOML table or given as a plain dict, it is the same object and the same model; the
cache keys (params_digest) depend on the parameters only; a planetary stage places its
carrier's pins."""
import dataclasses
import hashlib
import json
import math
import tomllib

import numpy as np
import pytest

from assembly import assemble, solve_modes
from assembly.errors import SceneError
from assembly.scene.save import scene_to_toml
from assembly.scene.schema import SCENE_DIR, load_scene, scene_from_dict, to_dict
from assembly.scene.tables import Body, Scene
from fe_components.errors import GeometryError
from fe_components.gear_pair import pair_geometry
from fe_components.geometry import interface_defs
from fe_components.params import (
    CarrierParams,
    CylinderParams,
    GearTeeth,
    PinionParams,
    ShaftSegment,
    WheelParams,
    params_digest,
)

HS_FILE = SCENE_DIR / "hs_parallel_stage.toml"
HS = load_scene(HS_FILE)
PFC_FILE = SCENE_DIR / "planetary_flexible_carrier.toml"

# hs_parallel_stage.toml's pinion and wheel, typed in Python (the numbers of the file;
# ISO 21771 gear data, degrees converted as the file's ``_deg`` keys are)
PINION = PinionParams(
    teeth=GearTeeth(n_teeth=23, normal_module=0.004, pressure_angle=math.radians(20.0),
                    helix_angle=math.radians(12.0), face_width=0.05, fidelity="smooth"),
    shaft=(ShaftSegment(0.04, 0.04), ShaftSegment(0.22, 0.045), ShaftSegment(0.07, 0.06),
           ShaftSegment(0.03, 0.05), ShaftSegment(0.04, 0.04)),
    gear_center=0.295)
WHEEL = WheelParams(
    teeth=GearTeeth(n_teeth=71, normal_module=0.004, pressure_angle=math.radians(20.0),
                    helix_angle=math.radians(-12.0), face_width=0.05, fidelity="smooth"),
    rim_inner_diameter=0.24, web_thickness=0.015, hub_outer_diameter=0.1, hub_length=0.07,
    bore_diameter=0.06, n_holes=6, hole_diameter=0.04)


def _with_components(scene: Scene, pinion, wheel, output_position=None) -> Scene:
    """``scene`` as given, its first two bodies holding ``pinion`` and ``wheel``, built in
    Python (``output_position``: the third body's, when the wheel moves)."""
    given = {f.name: scene.as_given(f.name) for f in dataclasses.fields(Scene)}
    b0, b1, b2, *rest = given["bodies"]
    if output_position is not None:
        b2 = dataclasses.replace(b2, position=output_position)
    given["bodies"] = (dataclasses.replace(b0, component=pinion), dataclasses.replace(b1, component=wheel), b2, *rest)
    return Scene(**given)


def test_typed_components_are_the_table_components():
    assert HS.bodies[0].component == PINION and HS.bodies[1].component == WHEEL
    typed = _with_components(HS, PINION, WHEEL)
    assert typed == HS
    assert isinstance(typed.bodies[1].component, WheelParams)


def test_typed_component_gives_the_same_model_as_the_table():
    # the same parameters must give the same mesh, FE model and reduction: equal to
    # round-off (1e-12 relative), whatever form the component was given in
    a = assemble(HS)
    b = assemble(_with_components(HS, PINION, WHEEL))
    for name in ("pinion", "wheel"):
        assert b.bodies[name].mass == pytest.approx(a.bodies[name].mass, rel=1e-12)
    fa, fb = solve_modes(a).frequencies_hz, solve_modes(b).frequencies_hz
    elastic = fa > 1.0   # Hz: rigid-body modes (0 Hz) compared absolutely
    assert fb[elastic] == pytest.approx(fa[elastic], rel=1e-12)
    assert np.all(np.abs(fb[~elastic] - fa[~elastic]) < 1e-6)


def test_a_dict_from_python_is_still_accepted():
    table = tomllib.loads(HS_FILE.read_text())["bodies"][1]["component"]
    body = dataclasses.replace(HS.as_given("bodies")[1], component=table)
    sc = _with_components(HS, PINION, table)
    assert isinstance(sc.bodies[1].component, WheelParams) and sc.bodies[1].component == WHEEL
    assert sc == HS
    assert body.component is table        # the caller's Body is left as given


def test_a_dict_from_python_gets_the_table_messages():
    table = tomllib.loads(HS_FILE.read_text())["bodies"][1]["component"]
    table["teeth"]["n_teeth"] = 2
    with pytest.raises(SceneError) as e:
        _with_components(HS, PINION, table)
    assert e.value.path == "bodies[1].component.teeth.n_teeth" and e.value.value == 2
    with pytest.raises(SceneError) as e:
        _with_components(HS, PINION, {"kind": "gear"})
    assert e.value.path == "bodies[1].component.kind" and e.value.value == "gear"


def test_a_component_of_the_wrong_type_is_refused():
    with pytest.raises(SceneError) as e:
        _with_components(HS, PINION, WHEEL.teeth)
    assert e.value.path == "bodies[1].component" and "WheelParams" in e.value.reason


def test_typed_teeth_derive_the_mesh_numbers():
    # the mesh places the wheel by its teeth (ISO 21771: a_w = (r_b1 + r_b2) / cos(alpha_wt)):
    # more wheel teeth, a longer centre distance, as from a table
    wheel = dataclasses.replace(WHEEL, teeth=dataclasses.replace(WHEEL.teeth, n_teeth=72))
    # the output shaft, shrink-fitted in the wheel's bore, moves with it (a shaft runs along
    # its bodies' axis)
    out = (pair_geometry(PINION.teeth, wheel.teeth).centre_distance, 0.0, 0.295)
    sc = _with_components(HS, PINION, wheel, out)
    assert sc.bodies[1].position[0] > HS.bodies[1].position[0]
    assert sc == HS.with_values({"bodies.wheel.component.teeth.n_teeth": 72, "bodies.output_shaft.position": out})


# ---------------------------------------------------------------- stage carrier
def test_stage_carrier_typed_without_pins_gets_them_from_the_stage():
    pfc = load_scene(PFC_FILE)
    comp = pfc.stages[0].carrier.component
    assert isinstance(comp, CarrierParams) and comp.planet_angles is None and comp.pin_pitch_radius is None
    placed = pfc.body("stage.carrier").component
    st = pfc.stages[0]
    assert placed.planet_angles == st.planet_angles() and placed.pin_pitch_radius == st.carrier_radius()
    # the same carrier typed in Python: the same scene
    carrier = dataclasses.replace(st.carrier, component=CarrierParams(**{
        f.name: getattr(comp, f.name) for f in dataclasses.fields(comp)}))
    given = {f.name: pfc.as_given(f.name) for f in dataclasses.fields(Scene)}
    given["stages"] = (dataclasses.replace(given["stages"][0], carrier=carrier),)
    assert Scene(**given) == pfc
    # and as a plain dict in Python: converted with the table's messages
    table = tomllib.loads(PFC_FILE.read_text())["stages"][0]["carrier"]["component"]
    given["stages"] = (dataclasses.replace(given["stages"][0], carrier=dataclasses.replace(carrier, component=table)),)
    assert Scene(**given) == pfc
    table["cheek_thickness"] = -0.015
    with pytest.raises(SceneError) as e:
        Scene(**given)
    assert e.value.path == "stages[0].carrier.component.cheek_thickness" and e.value.value == -0.015


def _carrier_table_error(key: str, value) -> SceneError:
    """The error of planetary_flexible_carrier.toml with ``key = value`` in its carrier table."""
    data = tomllib.loads(PFC_FILE.read_text())
    data["stages"][0]["carrier"]["component"][key] = value
    with pytest.raises(SceneError) as e:
        scene_from_dict(data)
    return e.value


def test_pins_on_a_stage_carrier_are_refused():
    err = _carrier_table_error("n_planets", 3)
    assert err.path == "stages[0].carrier.component.n_planets" and err.value == 3
    err = _carrier_table_error("pin_pitch_radius", 0.1)
    assert err.path == "stages[0].carrier.component.pin_pitch_radius" and "set by the stage" in err.reason


def test_stage_pins_that_break_the_carrier_name_its_table():
    # pins on the carrier radius R_c = (0.0387 + 0.0502) / cos(24.6 deg) = 0.0978 m (the sun
    # mesh): bores of 0.08 m reach past the cheek rim (radius 0.135 m), 0.0978 + 0.04 > 0.135
    err = _carrier_table_error("pin_bore_diameter", 0.08)
    assert err.path == "stages[0].carrier.component.pin_bore_diameter" and err.value == 0.08
    assert "cheek rim" in err.reason


def test_a_carrier_body_without_pins_is_refused_naming_the_field():
    comp = load_scene(PFC_FILE).stages[0].carrier.component
    with pytest.raises(GeometryError) as e:
        interface_defs(comp)                    # fe_components alone: no pins, no geometry
    assert e.value.parameter == "planet_angles"
    body = Body("carrier", component=comp)
    with pytest.raises(SceneError) as e:
        Scene(bodies=(body,), fixed=())
    assert e.value.path == "bodies[0].component.planet_angles" and "planetary stage" in e.value.reason
    with pytest.raises(SceneError) as e:
        Scene(bodies=(dataclasses.replace(body, component=dataclasses.replace(comp, planet_angles=(0.0, math.pi))),))
    assert e.value.path == "bodies[0].component.pin_pitch_radius"


def test_carrier_checks_run_once_the_pins_are_set():
    comp = load_scene(PFC_FILE).stages[0].carrier.component
    with pytest.raises(GeometryError) as e:     # two bores of 0.03 m, 0.02 m apart
        dataclasses.replace(comp, planet_angles=(0.0, 0.2), pin_pitch_radius=0.1)
    assert e.value.parameter == "pin_bore_diameter"


# ---------------------------------------------------------------- cache keys
def _digest_by_hand(type_name: str, fields: dict) -> str:
    """The digest as the caches define it: SHA-256 over the JSON of the type name and every
    field (floats by repr), keys sorted -- the parameters, not the form they were given in."""
    enc = {"__type__": type_name, **{k: repr(v) if isinstance(v, float) else
                                     [repr(x) for x in v] if isinstance(v, tuple) else v
                                     for k, v in fields.items()}}
    return hashlib.sha256(json.dumps([enc], sort_keys=True).encode()).hexdigest()[:16]


def test_digest_depends_on_the_parameters_only():
    cyl = CylinderParams(length=0.2, diameter=0.04)
    assert params_digest(cyl) == _digest_by_hand("CylinderParams", dataclasses.asdict(cyl))
    sc = load_scene(PFC_FILE)
    placed = sc.body("stage.carrier").component
    assert params_digest(placed) == _digest_by_hand("CarrierParams", {
        f.name: getattr(placed, f.name) for f in dataclasses.fields(placed)})
    # the same carrier placed by hand (not by the stage): the same key
    direct = CarrierParams(**{f.name: getattr(placed, f.name) for f in dataclasses.fields(placed)})
    assert params_digest(direct) == params_digest(placed)
    # table, dict and typed forms of the wheel: one key
    table = tomllib.loads(HS_FILE.read_text())["bodies"][1]["component"]
    from_dict_form = _with_components(HS, PINION, table).bodies[1].component
    assert params_digest(HS.bodies[1].component) == params_digest(WHEEL) == params_digest(from_dict_form)
    assert params_digest(dataclasses.replace(WHEEL, n_holes=5)) != params_digest(WHEEL)


def test_components_round_trip_as_tables():
    d = to_dict(load_scene(PFC_FILE))
    carrier = d["stages"][0]["carrier"]["component"]
    assert next(iter(carrier)) == "kind" and "planet_angles" not in carrier
    assert scene_from_dict(d) == load_scene(PFC_FILE)


def test_a_python_built_scene_saves_and_reads_back():
    typed = _with_components(HS, PINION, WHEEL)
    text = scene_to_toml(typed)
    assert scene_from_dict(tomllib.loads(text)) == typed
    assert 'kind = "wheel"' in text
