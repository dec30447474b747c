"""The scene reference stays complete and current, and its sign conventions hold.

(a) every key the schema accepts -- found here by an independent walk of the scene
dataclasses with ``dataclasses.fields`` (angle fields also as ``<key>_deg``) -- is a row of
docs/scene_reference.md and has a description in ``assembly.scene.docs``; (b) the committed
reference is the generator's output; (c) scene_docs describes no field that does not
exist; (d) the TOML blocks of the walk-through, in order, are the shipped
``two_stage_quill.toml``, the derived numbers its prose quotes are the loaded scene's, and
its load case loads every mesh on the flank the documented drive signs pick.
"""
from __future__ import annotations

import dataclasses
import json
import math
import os
import re
import tomllib
import typing
from pathlib import Path

import numpy as np
import pytest

from assembly.scene import docs as scene_docs
from assembly.scene.tables import Scene
from fe_components.params import COMPONENT_KINDS

ROOT = Path(__file__).resolve().parents[2]
REFERENCE = ROOT / "docs" / "scene_reference.md"
WALKTHROUGH = ROOT / "docs" / "scene_walkthrough.md"
FENCE = re.compile(r"^```toml[ \t]*\n(.*?)^```[ \t]*$", re.MULTILINE | re.DOTALL)


def _dataclasses_in(tp) -> list[type]:
    """Dataclasses an annotation holds (directly, optional, or as tuple entries)."""
    if dataclasses.is_dataclass(tp):
        return [tp]
    return [c for a in typing.get_args(tp) if a is not Ellipsis for c in _dataclasses_in(a)]


def accepted_keys() -> dict[type, set[str]]:
    """Class -> every key a table of it accepts (fields, ``_deg`` forms of angle fields),
    for every dataclass reachable from Scene; a body's ``component`` table is one of
    COMPONENT_KINDS (plus its ``kind`` key)."""
    out: dict[type, set[str]] = {}
    todo = [Scene]
    while todo:
        cls = todo.pop()
        if cls in out:
            continue
        hints = typing.get_type_hints(cls)
        keys = set()
        for f in dataclasses.fields(cls):
            if not f.init:
                continue
            keys.add(f.name)
            if f.metadata.get("angle"):
                keys.add(f.name + "_deg")
            todo += _dataclasses_in(hints[f.name])
            if f.name == "component":
                todo += list(COMPONENT_KINDS.values())
        if cls in COMPONENT_KINDS.values():
            keys.add("kind")
        out[cls] = keys
    return out


def reference_sections(text: str) -> list[set[str]]:
    """Keys of each table section of the reference (its key column and degree column)."""
    sections = []
    for chunk in text.split("\n## ")[1:]:
        keys = set()
        for line in chunk.splitlines():
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", line.strip().strip("|"))]
            if line.startswith("| `") and len(cells) == 7:
                keys.add(cells[0].strip("`"))
                if cells[5]:
                    keys.add(cells[5].strip("`"))
        sections.append(keys)
    return sections


def test_walk_finds_the_scene_tables():
    # guards the walk: a short list would let the coverage test pass vacuously
    names = {c.__name__ for c in accepted_keys()}
    assert {"Scene", "Body", "FlexOptions", "Material", "Bearing", "GearMesh", "Shaft", "Fixed",
            "PlanetaryStage", "Member", "Planets", "BearingSpec", "LoadCase", "GearTeeth", "ShaftSegment",
            "PinionParams", "WheelParams", "CarrierParams", "CylinderParams"} <= names


@pytest.mark.parametrize("cls", sorted(accepted_keys(), key=lambda c: c.__name__), ids=lambda c: c.__name__)
def test_every_accepted_key_is_in_the_reference_and_described(cls):
    keys = accepted_keys()[cls]
    sections = reference_sections(REFERENCE.read_text(encoding="utf-8"))
    best = max(sections, key=lambda s: len(keys & s))
    missing = sorted(keys - best)
    assert not missing, f"{cls.__name__}: keys missing from {REFERENCE.name}: {missing} (run `flexgear reference " \
                        f"--out docs/scene_reference.md` after describing them in assembly/scene/docs.py)"
    docs = scene_docs.FIELDS.get(cls.__name__, {})
    undescribed = sorted(f.name for f in dataclasses.fields(cls) if f.init and not docs.get(f.name, "").strip())
    assert not undescribed, f"{cls.__name__}: no description in assembly/scene/docs.py for {undescribed}"


def test_committed_reference_is_the_generated_one():
    from assembly.app.reference import reference_markdown
    assert REFERENCE.read_text(encoding="utf-8") == reference_markdown(), \
        "docs/scene_reference.md is stale: run `flexgear reference --out docs/scene_reference.md`"


def test_cli_writes_the_reference(tmp_path, capsys):
    from assembly.app.cli import main
    out = tmp_path / "ref.md"
    assert main(["reference", "--out", str(out)]) == 0
    assert main(["reference"]) == 0
    assert out.read_text(encoding="utf-8") == capsys.readouterr().out == REFERENCE.read_text(encoding="utf-8")


@pytest.mark.parametrize("there", ["a user's file", "a link to the reference", "an earlier reference"])
def test_reference_out_replaces_only_an_earlier_reference(tmp_path, capsys, there):
    # nothing of the user's is overwritten: a file flexgear did not write, or any link, is refused
    from assembly.app.cli import main
    out = tmp_path / "ref.md"
    if there == "a user's file":
        out.write_text("# My notes\n")
    elif there == "a link to the reference":
        (tmp_path / "theirs.md").write_text("# Scene reference\n\nsomeone's copy\n")
        out.symlink_to(tmp_path / "theirs.md")
    else:
        out.write_text("# Scene reference\n\nan older one\n")
    before = out.read_bytes()
    rc = main(["reference", "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    if there == "an earlier reference":
        assert rc == 0 and out.read_text(encoding="utf-8") == REFERENCE.read_text(encoding="utf-8")
    else:
        assert rc == 2 and len(err) == 1 and f"--out {out}" in err[0]
        assert out.read_bytes() == before and out.is_symlink() == (there != "a user's file")
        assert not [p for p in os.listdir(tmp_path) if p.endswith(".tmp")]


def test_scene_docs_names_only_existing_fields():
    classes = {c.__name__: c for c in accepted_keys()}
    for table in (scene_docs.FIELDS, scene_docs.NOTES, scene_docs.EXTRA_KEYS):
        stale = sorted(set(table) - set(classes))
        assert not stale, f"assembly/scene/docs.py describes classes that no scene table uses: {stale}"
    for name, fields in scene_docs.FIELDS.items():
        have = {f.name for f in dataclasses.fields(classes[name]) if f.init}
        stale = sorted(set(fields) - have)
        assert not stale, f"assembly/scene/docs.py describes fields {name} no longer has: {stale}"
    for name, keys in scene_docs.EXTRA_KEYS.items():
        assert not set(keys) & accepted_keys()[classes[name]], "an extra key duplicates a field"


def test_extra_carrier_keys_are_accepted():
    # every key EXTRA_KEYS documents is read by the schema: 3 equally spaced planets from 30 deg
    from assembly.scene.schema import component_from_table
    table = {"kind": "carrier", "pin_pitch_radius": 0.0978, "pin_bore_diameter": 0.03, "cheek_diameter": 0.27,
             "cheek_thickness": 0.015, "cheek_spacing": 0.05, "post_diameter": 0.03, "seat_a_diameter": 0.08,
             "seat_a_length": 0.03, "seat_b_diameter": 0.09, "seat_b_length": 0.04, "output_bore_diameter": 0.05}
    assert set(scene_docs.EXTRA_KEYS["CarrierParams"]) == {"n_planets", "first_planet_angle", "first_planet_angle_deg"}
    a = component_from_table({**table, "n_planets": 3, "first_planet_angle_deg": 30.0}, "c").planet_angles
    b = component_from_table({**table, "n_planets": 3, "first_planet_angle": math.radians(30.0)}, "c").planet_angles
    assert np.allclose(a, b) and np.allclose(np.degrees(a), [30.0, 150.0, 270.0])


#: The ```toml blocks of the docs and what each page's blocks are: "variant" (a scene file
#: with ``extends``), "study" (a study file), or the shipped scene whose tables a fragment
#: replaces. The walk-through's blocks are the shipped two_stage_quill.toml (tested below),
#: README's are whole scenes (tests/app/test_readme_examples.py).
SNIPPETS = {"static.md": "hs_parallel_stage.toml", "user_parts.md": "planetary_step_carrier.toml",
            "simulate.md": "variant", "study.md": "study", "turbine.md": "nrel5mw.toml", "campbell.md": "variant"}


def _doc_snippets() -> list[tuple[str, int, str]]:
    """(page, line, block) of every ```toml block of docs/*.md but the walk-through's."""
    out = []
    for page in sorted((ROOT / "docs").glob("*.md")):
        if page == WALKTHROUGH:
            continue
        text = page.read_text(encoding="utf-8")
        out += [(page.name, text.count("\n", 0, m.start()) + 1, m.group(1)) for m in FENCE.finditer(text)]
    return out


def _merged(host, fragment):
    """The host scene's tables with the fragment's keys put in: a table merges key by key, an
    array of named tables entry by entry (the docs show the entries that matter), another
    array replaces the host's, a table given where the host has an array (a
    ``[stages.carrier]`` fragment of a one-stage scene) goes into its first entry; ``loads``
    and ``load`` exclude each other."""
    out = dict(host)
    for key, value in fragment.items():
        if key in ("load", "loads"):
            out.pop("loads" if key == "load" else "load", None)
        old = out.get(key)
        if isinstance(value, dict) and isinstance(old, list) and old and isinstance(old[0], dict):
            out[key] = [_merged(old[0], value)] + old[1:]
        elif isinstance(value, dict) and isinstance(old, dict):
            out[key] = _merged(old, value)
        elif _named(value) and _named(old):                # e.g. interfaces: by name, others kept
            mine = {v["name"]: v for v in value}
            out[key] = [_merged(o, mine.pop(o["name"])) if o["name"] in mine else o for o in old] + list(mine.values())
        else:
            out[key] = value
    return out


def _named(value) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) and "name" in v for v in value)


def _toml(value) -> str:
    """A TOML value (inline tables and arrays): enough to write a scene back."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value) if math.isfinite(value) else ("inf" if value > 0 else "-inf" if value < 0 else "nan")
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return "{" + ", ".join(f"{json.dumps(k)} = {_toml(v)}" for k, v in value.items()) + "}"


def test_docs_toml_snippets_load(tmp_path):
    """Every TOML snippet of the docs is read as what it is (a variant, a study, or a
    fragment put into the shipped scene it comes from) and passes the scene checks; a page
    with snippets must say what they are (SNIPPETS), and finding none fails."""
    from assembly.app.study.file import read_study
    from assembly.scene.schema import SCENE_DIR, load_scene
    found = _doc_snippets()
    assert found, "no ```toml block found in docs/*.md"
    assert {page for page, _, _ in found} == set(SNIPPETS), "say in SNIPPETS what a new page's blocks are"
    (tmp_path / "parts").symlink_to(SCENE_DIR / "parts")          # the STEP carrier's part, beside the scene
    for i, (page, line, block) in enumerate(found):
        kind = SNIPPETS[page]
        path = tmp_path / f"snippet_{i}.toml"
        if kind == "study":
            path.write_text(block, encoding="utf-8")
            study = read_study(path)
            assert study.variants, (page, line)
            continue
        if kind == "variant":
            text = block
        else:
            data = _merged(tomllib.loads((SCENE_DIR / kind).read_text(encoding="utf-8")), tomllib.loads(block))
            text = "".join(f"{json.dumps(k)} = {_toml(v)}\n" for k, v in data.items())
        path.write_text(text, encoding="utf-8")
        try:
            load_scene(path)
        except Exception as exc:
            raise AssertionError(f"docs/{page}:{line}: {exc}") from exc


QUILL = ROOT / "assembly" / "scenes" / "two_stage_quill.toml"
ANY_FENCE = re.compile(r"^```[^\n]*\n.*?^```[ \t]*$", re.MULTILINE | re.DOTALL)


def test_walkthrough_blocks_are_the_shipped_scene():
    # the walk-through reads the shipped example table by table: its TOML blocks, joined by
    # one blank line each, are that file exactly, so neither can change without the other
    blocks = FENCE.findall(WALKTHROUGH.read_text(encoding="utf-8"))
    assert len(blocks) >= 12, "the walk-through lost its TOML blocks"
    assert "\n".join(blocks) == QUILL.read_text(encoding="utf-8")


@pytest.fixture(scope="module")
def quill():
    """(scene, assembled rigid model) of the shipped two-stage example."""
    from assembly import assemble
    from assembly.scene.schema import load_scene
    scene = load_scene(QUILL)
    return scene, assemble(scene)


def _quill_numbers(scene, model) -> dict:
    """Regex of a number the walk-through's prose quotes -> the value the loaded scene has."""
    from assembly.analysis.load_cases import speed_ratio
    mesh, stage = scene.meshes[0], scene.stages[0]
    alpha_t = math.atan(math.tan(scene.bodies[0].teeth.pressure_angle) / math.cos(scene.bodies[0].teeth.helix_angle))
    return {
        r"a_w = (-?\d+(?:\.\d+)?) m": float(scene.body("wheel").position[0]),
        r"carrier radius = (-?\d+(?:\.\d+)?) m": stage.carrier_radius(),
        r"omega_pinion / omega_carrier = (-?\d+(?:\.\d+)?)": speed_ratio(model, scene.load)[0],
        r"alpha_t = (-?\d+(?:\.\d+)?) deg": math.degrees(alpha_t),
        r"alpha_wt = (-?\d+(?:\.\d+)?) deg": math.degrees(mesh.pressure_angle),
        r"r_b1 = (-?\d+(?:\.\d+)?) m": mesh.base_radius1,
        r"r_b2 = (-?\d+(?:\.\d+)?) m": mesh.base_radius2,
        r"helix_angle = (-?\d+(?:\.\d+)?) deg": math.degrees(mesh.helix_angle),
        r"r_b,sun = (-?\d+(?:\.\d+)?) m": stage.sun.base_radius,
        r"pressure_angle_ring = (-?\d+(?:\.\d+)?) deg": math.degrees(stage.pressure_angle_ring),
        r"pressure_angle_sun = pressure_angle_ring = (-?\d+(?:\.\d+)?) deg": math.degrees(stage.pressure_angle_sun),
    }


def test_walkthrough_quotes_the_loaded_scene(quill):
    # every number the prose quotes under these names (outside code blocks) is the loaded
    # scene's, rounded to the digits quoted: half a unit of the last digit
    prose = ANY_FENCE.sub("", WALKTHROUGH.read_text(encoding="utf-8"))
    for pattern, value in _quill_numbers(*quill).items():
        quoted = re.findall(pattern, prose)
        assert quoted, f"the walk-through no longer quotes {pattern!r}"
        for q in quoted:
            digits = len(q.split(".")[1]) if "." in q else 0
            assert abs(float(q) - value) <= 0.5 * 10.0 ** -digits * (1 + 1e-9), (pattern, q, value)


def _mesh_forces(scene) -> dict:
    """Mesh name -> compressive force (N) under the scene's load case."""
    from assembly.analysis.static import solve_static
    st = solve_static(scene, scene.load)
    m = st.model
    return {el.name: float((el.k * (el.B @ (m.attachment_operator(el) @ st.z)))[0])
            for el in m.elements if el.kind == "mesh"}


def test_walkthrough_scene_loads_every_mesh_on_its_flank(quill):
    from assembly import solve_modes
    from assembly.scene.schema import scene_from_dict
    scene, model = quill
    assert solve_modes(model).n_rigid == 1   # pinion-wheel-sun-planets-carrier: one free rotation
    forces = _mesh_forces(scene)
    assert len(forces) == 9 and all(f > 0 for f in forces.values()), forces
    # Statics: tooth normal force T / (r_b cos beta_b) on the pinion; the wheel torque
    # T r_b2 / r_b1 reaches the sun through the quill, whose meshes carry it at the sun base radius.
    mesh = scene.meshes[0]
    T, rb1, rb2 = scene.load.torque, mesh.base_radius1, mesh.base_radius2
    assert forces["pinion-wheel"] == pytest.approx(T / (rb1 * math.cos(mesh.helix_angle)), rel=1e-6)
    sun = sum(f for k, f in forces.items() if "sun-planet" in k)
    assert sun * scene.stages[0].sun.base_radius == pytest.approx(T * rb2 / rb1, rel=1e-6)
    # the other stage drive sign puts the sun meshes on the unloaded flank (in tension)
    data = tomllib.loads(QUILL.read_text(encoding="utf-8"))
    assert data["stages"][0]["drive_sign"] == -1
    data["stages"][0]["drive_sign"] = 1
    flipped = _mesh_forces(scene_from_dict(data))
    assert all(f < 0 for k, f in flipped.items() if "sun-planet" in k)


def test_mesh_helix_is_minus_gear1_teeth_helix():
    """The flank normal of a right-hand gear 1 (GearTeeth.helix_angle > 0: the transverse
    profile turns by tan(beta) / r_p per unit z) is the line of action of a mesh whose
    helix angle is negative, on either flank (involute helicoid: the normal lies in the
    plane of action at the base helix angle, ISO 21771)."""
    from assembly.mechanics.elements import line_of_action
    from fe_components.involute import flank_half_angle
    from fe_components.params import GearTeeth

    t = GearTeeth(23, 0.004, math.radians(20.0), 0.05, helix_angle=math.radians(12.0))
    rp, rb, at = t.pitch_radius, t.base_radius, t.transverse_pressure_angle
    beta_b = math.atan(math.tan(t.helix_angle) * rb / rp)   # base helix angle

    def flank(r, z, side):  # side +1: the flank facing positive rotation
        a = z * math.tan(t.helix_angle) / rp + side * (float(flank_half_angle(t, r)) - float(flank_half_angle(t, rp)))
        return np.array([r * math.cos(a), r * math.sin(a), z])

    h = 1e-7
    for drive_sign in (1, -1):
        d_r = flank(rp + h, 0.0, drive_sign) - flank(rp - h, 0.0, drive_sign)
        d_z = flank(rp, h, drive_sign) - flank(rp, -h, drive_sign)
        normal = np.cross(d_r, d_z)
        normal *= np.sign(normal[1] * drive_sign) / np.linalg.norm(normal)  # out of the tooth
        c2 = (2 * rb / math.cos(at), 0.0, 0.0)
        n_minus, _ = line_of_action((0, 0, 1), (0, 0, 0), c2, rb, rb, at, -beta_b, drive_sign)
        n_plus, _ = line_of_action((0, 0, 1), (0, 0, 0), c2, rb, rb, at, beta_b, drive_sign)
        assert normal @ n_minus == pytest.approx(1.0, abs=1e-6)
        assert normal @ n_plus < 1.0 - 1e-3
