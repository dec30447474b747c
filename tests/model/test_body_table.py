"""Every report carries a body table -- mass, polar and transverse inertia about the centre
of mass, centre of mass, and the source of each -- and a component that replaces typed mass
properties with its mesh's says so, with both numbers.

Before: a body made flexible (a component in place of its typed mass and inertia) took the
mesh's numbers without a word (the issue's carrier: 60 kg typed, 30.9 kg of mesh), and no
report said what mass a body had or where it came from.

Closed forms (steel, rho = 7850 kg/m^3): a solid cylinder of radius r and length L has
m = rho pi r^2 L, J_polar = m r^2 / 2, J_transverse = m (3 r^2 + L^2) / 12 about its centre
of mass at L / 2 (e.g. Meriam & Kraige, Engineering Mechanics: Dynamics, appendix D). The P2
mesh of its curved surface holds them to 1e-3 (tests/fe_components/test_fe_validation.py);
measured here 7e-5 (mass) and 1.4e-4 (polar), both from one radius deficit. A beam shaft's station carries half of each of its two elements,
rho A (l_left + l_right) / 2 (lumped mass, assembly/mechanics/beam.py).
"""
from __future__ import annotations

import json
import logging
import math

import numpy as np
import pytest

from assembly.analysis.modal import solve_modes
from assembly.analysis.reactions import static_report
from assembly.analysis.static import solve_static_cases
from assembly.app.cli import main
from assembly.app.report.static_tables import static_json, static_text
from assembly.app.report.tables import modes_json, modes_table
from assembly.model.assemble import assemble
from assembly.model.body_table import AGREEMENT, body_properties
from assembly.scene.save import toml_text
from assembly.scene.schema import load_scene, scene_from_dict

RHO = 7850.0
R, L = 0.025, 0.5
M = RHO * math.pi * R * R * L
J_POLAR = M * R * R / 2
J_TRANSVERSE = M * (3 * R * R + L * L) / 12
#: The rigid rod the user had before making it flexible: typed numbers the mesh replaces.
TYPED = {"mass": 60.0, "polar_inertia": 0.02}


def rod(fidelity="flexible", **typed) -> dict:
    """A steel rod (cylinder component) on a bearing at each end, turned by a torsion
    spring at one, with a point load for the static case."""
    return {"name": "rod", "band_hz": 3000.0,
            "bodies": [{"name": "rod", "fidelity": fidelity, "position": [0.0, 0.0, 1.0], **typed,
                        "component": {"kind": "cylinder", "length": L, "diameter": 2 * R}}],
            "bearings": [{"body": "rod", "interface": "end_a", "k_radial": 1e9, "k_axial": 1e9, "k_tilt": 1e5,
                          "k_torsion": 1e4},
                         {"body": "rod", "interface": "end_b", "k_radial": 1e9, "k_axial": 1e9, "k_tilt": 1e5}],
            "load": {"name": "side load", "forces": [{"body": "rod", "interface": "end_b", "force": [100.0, 0, 0]}]}}


@pytest.fixture(scope="module")
def flexible_rod():
    return assemble(scene_from_dict(rod(**TYPED)))


@pytest.fixture(scope="module")
def rigid_rod():
    """The rod rigid: the same mesh's mass properties, a quick model for the reports."""
    return assemble(scene_from_dict(rod("rigid", **TYPED)))


def test_cylinder_against_closed_forms(flexible_rod):
    (row,) = body_properties(flexible_rod)
    assert row.sources == {"mass": "FE mesh", "polar_inertia": "FE mesh", "transverse_inertia": "FE mesh",
                           "center_of_mass": "FE mesh"}
    dm, dj, dt = row.mass / M - 1, row.polar_inertia / J_POLAR - 1, row.transverse_inertia / J_TRANSVERSE - 1
    assert abs(dm) < 1e-3 and abs(dj) < 1e-3 and abs(dt) < 1e-3
    # the mesh's curved surface falls short of the circle by a radius deficit e: m ~ r^2 and
    # J_polar ~ r^4 lose 2e and 4e, J_transverse (~ L^2 here) as m (measured e = 3.5e-5)
    assert dj == pytest.approx(2 * dm, rel=0.05) and dt == pytest.approx(dm, rel=0.05)
    # the volume the mesh misses, a fraction |dm| of the mass at most L / 2 from the centre,
    # moves the centre of mass by at most |dm| L / 2 (measured 5e-7 m)
    np.testing.assert_allclose(row.center_of_mass, (0.0, 0.0, 1.0 + L / 2), rtol=0, atol=abs(dm) * L / 2)
    # the rigid variant takes the same numbers from the same mesh
    (rigid,) = body_properties(assemble(scene_from_dict(rod("rigid", **TYPED))))
    assert (rigid.mass, rigid.polar_inertia, rigid.transverse_inertia) == pytest.approx(
        (row.mass, row.polar_inertia, row.transverse_inertia), rel=1e-12)


def test_typed_values_the_mesh_replaces_are_reported(flexible_rod, caplog):
    (row,) = body_properties(flexible_rod)
    assert row.typed == TYPED
    assert row.differences()["mass"] == pytest.approx(M / 60.0 - 1, rel=1e-4)
    (info,) = flexible_rod.info["replaced_mass_properties"]
    assert info["body"] == "rod" and info["typed"] == TYPED and info["mass_kg"] == row.mass
    with caplog.at_level(logging.WARNING, logger="assembly.model.assemble"):
        assemble(scene_from_dict(rod(**TYPED)))
    (msg,) = [r.getMessage() for r in caplog.records if r.name == "assembly.model.assemble"]
    assert "body 'rod' (bodies[0])" in msg and "mass 60 -> " in msg and f"{row.mass:.6g}" in msg


def test_typed_values_that_agree_are_no_news():
    # typed as the closed form: the mesh agrees to AGREEMENT, nothing is replaced
    model = assemble(scene_from_dict(rod(mass=M, polar_inertia=J_POLAR)))
    assert model.info["replaced_mass_properties"] == []
    assert abs(body_properties(model)[0].differences()["mass"]) < AGREEMENT


def test_every_report_has_the_table_and_both_numbers(rigid_rod):
    res = solve_modes(rigid_rod)
    text = modes_table(res)
    (row,) = body_properties(rigid_rod)
    assert "bodies: the mass properties the model uses" in text
    assert f"{row.mass:.6g}" in text and "mass 60 (" in text and "FE mesh" in text
    js = json.loads(json.dumps(modes_json(res)))
    assert js["bodies"][0]["mass_kg"] == row.mass and js["bodies"][0]["typed"]["mass"] == 60.0
    reports = [static_report(st) for st in solve_static_cases(rigid_rod)]
    st_text = static_text(reports, model=rigid_rod)
    assert f"{row.mass:.6g}" in st_text and "mass 60 (" in st_text
    assert static_json("rod", reports, rigid_rod)["bodies"][0]["typed"]["mass"] == 60.0


def test_cli_prints_both_numbers(tmp_path, capsys, caplog):
    f = tmp_path / "rod.toml"
    f.write_text(toml_text(rod("rigid", **TYPED)))
    with caplog.at_level(logging.WARNING):     # the command line logs warnings to stderr
        assert main(["modes", str(f)]) == 0
    out, _ = capsys.readouterr()
    assert "mass 60 (" in out and f"{M:.4g}"[:4] in out
    (msg,) = [r.getMessage() for r in caplog.records if "replaces the typed mass properties" in r.getMessage()]
    assert "body 'rod' (bodies[0])" in msg and "mass 60 -> " in msg
    assert main(["static", str(f), "--json"]) == 0
    js = json.loads(capsys.readouterr().out)
    assert js["bodies"][0]["mass_kg"] == pytest.approx(M, rel=1e-4) and js["bodies"][0]["typed"] == TYPED


def test_run_index_and_csv_have_the_table(tmp_path):
    from assembly.app.report.pipeline import RunOptions, run_pipeline
    ctx = run_pipeline(scene_from_dict(rod("rigid", **TYPED)), tmp_path / "out",
                       RunOptions(compare=False, images=False))
    html = (ctx.out_dir / "index.html").read_text()
    assert "Bodies: mass properties" in html and "mass 60 (" in html
    csv = (ctx.out_dir / "bodies.csv").read_text().splitlines()
    assert csv[0].startswith("body,table,mass [kg]") and csv[1].startswith("rod,bodies[0],")


def test_sources_of_plain_bodies():
    # typed (two_stage_quill's pinion, transverse left out: polar/2), a stage's members
    quill = {r.name: r for r in body_properties(assemble(load_scene("two_stage_quill")))}
    assert quill["pinion"].sources["mass"] == "typed"
    assert quill["pinion"].sources["transverse_inertia"] == "polar/2"
    assert quill["pinion"].transverse_inertia == pytest.approx(quill["pinion"].polar_inertia / 2, rel=1e-15)
    assert quill["planetary.sun"].path == "stages[0].sun" and quill["planetary.sun"].mass == 7.103
    assert quill["wheel"].source == "FE mesh"
    # a beam shaft's station: half of each of its two elements (the NREL 5 MW main shaft,
    # 0.7 m, 2 m long here, stations at 0.333 and 1.166 m: inp_a holds half of 0-0.333 and
    # of 0.333-1.166)
    disc = {"mass": 1e4, "polar_inertia": 1e4}
    shaft = scene_from_dict({
        "bodies": [dict(name="hub", position=[0, 0, 0.0], **disc), dict(name="carrier", position=[0, 0, 2.0], **disc)],
        "bearings": [{"body": f"main_shaft.{n}", "k_radial": 3e9, "k_axial": 1e9, "k_tilt": 0.0} for n in ("inp_a",
                                                                                                         "inp_b")],
        "shafts": [{"name": "main_shaft", "body1": "hub", "body2": "carrier", "diameter": 0.7,
                    "stations": [["inp_a", 0.333], ["inp_b", 1.166]]}]})
    rows = {r.name: r for r in body_properties(assemble(shaft))}
    st = rows["main_shaft.inp_a"]
    assert st.source == "beam shaft" and st.path == "shafts[0].stations[0]"
    assert st.mass == pytest.approx(RHO * math.pi * 0.35 ** 2 * 1.166 / 2, rel=1e-12)
    assert rows["hub"].source == "typed (transverse: polar/2)"


def test_fe_masses_are_the_reduced_meshs(flexible_rod):
    # The body table's FE numbers are the component mesh's as the model holds it: the
    # superelement's mass matrix seen by the body's exact rigid motions about its centre of
    # mass (Craig-Bampton constraint modes span rigid motion exactly, so the reduction keeps
    # the mesh's mass and inertia to rounding): R' M R = diag(m, m, m, J) in local axes.
    (row,) = body_properties(flexible_rod)
    bm = flexible_rod.bodies["rod"]
    MR = bm.rigid_local.T @ (bm.M @ bm.rigid_local)
    assert row.mass == pytest.approx(MR[0, 0], rel=1e-9) and row.mass == pytest.approx(MR[2, 2], rel=1e-9)
    assert row.polar_inertia == pytest.approx(MR[5, 5], rel=1e-9)       # local z: the body's axis
    assert row.transverse_inertia == pytest.approx(0.5 * (MR[3, 3] + MR[4, 4]), rel=1e-9)
