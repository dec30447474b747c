"""A turbine read from its OpenFAST deck (assembly.dynamics.openfast_deck), on the NREL 5 MW
deck that ROSCO's package ships (an OpenFAST 3.5 deck).

Sources:
- Jonkman, Butterfield, Musial and Scott, NREL/TP-500-38060 (2009), "Jonkman 2009": rotor
  diameter 126 m, hub diameter 3 m, hub height 90 m, shaft tilt 5 deg (Table 1-1); hub inertia
  115 926 kg m^2 (section 4); gearbox ratio 97, generator inertia 534.116 kg m^2 on the high-speed
  shaft, drive-shaft spring 867 637 000 N m/rad and damper 6 215 000 N m s/rad, a gearbox without
  loss (the 94.4 % is the generator's) (section 5). Its rotor inertia, 38 759 236 kg m^2, is FAST
  v7's sum over AeroDyn's blade elements: tests/dynamics/test_blade_mass.py checks that sum.
- OpenFAST ElastoDyn's summary file for this deck's ElastoDyn and blade files: rotor inertia
  38 677 040.613 kg m^2 (its 17 equal blade elements), as quoted in welib's tests
  (github.com/ebranlard/welib, welib/fast/tests/test_elastodyn.py).
- The deck's own DISCON.IN (ROSCO 2.8's tuning of this deck): WE_Jtot = 43 702 538.057 kg m^2, the
  rotor's inertia plus the generator's seen through the gearbox, J_rotor + 97^2 x 534.116.
- Air density 1.225 kg/m^3: IEC 61400-1's standard air, the density of Jonkman 2009's analyses.
"""
from __future__ import annotations

import dataclasses
import math
import shutil

import pytest

from assembly.dynamics.openfast_deck import TurbineDeck, read_deck
from assembly.dynamics.rosco_data import NREL5MW_SURFACE, rosco_file, rosco_root
from assembly.errors import SceneError

pytest.importorskip("rosco", reason="the rosco package (its NREL 5 MW deck) is not installed")
DECK = "Examples/Test_Cases/NREL-5MW/NREL-5MW.fst"
ED = "NRELOffshrBsline5MW_Onshore_ElastoDyn.dat"
BLADE = "NRELOffshrBsline5MW_Blade.dat"
SD = "NRELOffshrBsline5MW_Onshore_ServoDyn.dat"


@pytest.fixture(scope="module")
def deck():
    return read_deck(rosco_file(DECK))


def _files(root):
    return sorted((p.relative_to(root), p.stat().st_size, p.stat().st_mtime_ns) for p in root.rglob("*"))


def test_geometry_against_jonkman(deck):
    assert deck.deck == rosco_file(DECK)
    assert deck.radius == 63.0 and deck.hub_radius == 1.5                      # 126 m and 3 m diameters
    # 90 m = TowerHt 87.6 + Twr2Shft 1.96256 + OverHang -5.0191 sin(-5 deg): the deck's last digits
    # of Twr2Shft and OverHang (x sin 5 deg) leave 5e-6 + 4.4e-6 m
    assert deck.hub_height == pytest.approx(90.0, abs=5e-6 + 0.5e-4 * math.sin(math.radians(5)))
    assert deck.tilt == pytest.approx(math.radians(5.0), rel=1e-15)            # rotor end raised
    assert deck.density == 1.225
    assert deck.dt == 0.00625


def test_drivetrain_against_jonkman(deck):
    assert deck.gear_ratio == 97.0
    assert deck.generator_inertia == 534.116
    assert deck.hub_inertia == 115926.0
    assert deck.gearbox_efficiency == 1.0
    assert deck.drivetrain_stiffness == 867637000.0
    assert deck.drivetrain_damping == 6215000.0


def test_rotor_inertia_is_elastodyns_sum_for_this_deck(deck):
    # ElastoDyn's summary prints three decimals: half of the last one
    assert deck.rotor_inertia == pytest.approx(38677040.613, abs=5e-4)
    # the deck's DISCON.IN carries the same rotor inertia in its total drivetrain inertia
    assert deck.rotor_inertia + 97.0 ** 2 * 534.116 == pytest.approx(43702538.057, abs=5e-4)


def test_controller_and_surface_resolved(deck):
    servo = rosco_file(f"Examples/Test_Cases/NREL-5MW/{SD}").parent
    # the library as the ServoDyn file names it, "../../../lib/libdiscon.so" from its folder; the
    # wheel keeps its own at rosco/lib/libdiscon.so: whether either is used is the caller's choice
    assert deck.controller_library == (servo / "../../../lib/libdiscon.so").resolve()
    assert deck.controller_library == rosco_root() / "lib" / "libdiscon.so"
    assert deck.controller_input == rosco_file("Examples/Test_Cases/NREL-5MW/DISCON.IN")
    assert deck.controller_input.is_file()
    assert deck.controller_period == 0.00625                 # DLL_DT "default": the .fst's DT
    assert deck.surface == rosco_file(NREL5MW_SURFACE) and deck.surface.is_file()


def test_sources_name_file_and_key_for_every_field(deck):
    fields = {f.name for f in dataclasses.fields(TurbineDeck)} - {"deck", "sources"}
    assert set(deck.sources) == fields
    expect = {"radius": f"{ED}: TipRad", "hub_radius": f"{ED}: HubRad", "hub_inertia": f"{ED}: HubIner",
              "generator_inertia": f"{ED}: GenIner", "gear_ratio": f"{ED}: GBRatio",
              "gearbox_efficiency": f"{ED}: GBoxEff", "drivetrain_stiffness": f"{ED}: DTTorSpr",
              "drivetrain_damping": f"{ED}: DTTorDmp", "density": "NREL-5MW.fst: AirDens",
              "controller_library": f"{SD}: DLL_FileName", "controller_input": f"{SD}: DLL_InFile",
              "surface": "DISCON.IN: PerfFileName", "dt": "NREL-5MW.fst: DT"}
    for name, text in expect.items():
        assert deck.sources[name] == text
    for name, words in (("hub_height", (ED, "TowerHt", "Twr2Shft", "OverHang", "ShftTilt")),
                        ("tilt", (ED, "ShftTilt")), ("controller_period", ("NREL-5MW.fst: DT", "DLL_DT")),
                        ("rotor_inertia", (ED, "HubIner", "PreCone", BLADE, "BMassDen", "AdjBlMs"))):
        assert all(w in deck.sources[name] for w in words), (name, deck.sources[name])


def test_reading_prints_nothing(capsys):
    read_deck(rosco_file(DECK))
    assert capsys.readouterr() == ("", "")


@pytest.fixture
def copy(tmp_path):
    """The deck's folder copied: (its .fst, the folder)."""
    folder = tmp_path / "NREL-5MW"
    shutil.copytree(rosco_file(DECK).parent, folder)
    return folder / "NREL-5MW.fst", folder


def _refused(path, root, field="turbine.openfast", **kw) -> SceneError:
    before = _files(root)
    with pytest.raises(SceneError) as err:
        read_deck(path, field, **kw)
    assert err.value.path == field and "\n" not in str(err.value)
    assert _files(root) == before                    # nothing written
    return err.value


def test_a_missing_fst_is_refused(tmp_path):
    e = _refused(tmp_path / "no.fst", tmp_path, field="turbine.openfast")
    assert e.value == str(tmp_path / "no.fst") and "no such file" in e.reason


def test_a_missing_elastodyn_file_is_refused(copy):
    fst, folder = copy
    (folder / ED).unlink()
    e = _refused(fst, folder, field="scene.turbine.openfast")
    assert e.value == str((folder / ED).resolve()) and "EDFile" in e.reason and "missing" in e.reason


def test_a_text_file_that_is_no_fst_is_refused(tmp_path):
    text = tmp_path / "notes.txt"
    shutil.copy(rosco_file(NREL5MW_SURFACE), text)
    e = _refused(text, tmp_path)
    assert e.value == str(text.resolve()) and "not an OpenFAST main input file" in e.reason


def test_a_discon_without_performance_table_is_refused_when_the_surface_is_asked(copy):
    fst, folder = copy
    discon = folder / "DISCON.IN"
    discon.write_text("".join(s for s in discon.read_text().splitlines(keepends=True) if "PerfFileName" not in s))
    e = _refused(fst, folder)
    assert e.value == str(discon.resolve()) and "PerfFileName" in e.reason
    d = read_deck(fst, with_surface=False)
    assert d.surface is None and "surface" not in d.sources and d.rotor_inertia > 0


@pytest.mark.parametrize("name,key,line", [(ED, "TipRad", "          0   TipRad"),
                                           (ED, "HubIner", "         -1   HubIner"),
                                           ("NREL-5MW.fst", "AirDens", "          0   AirDens")])
def test_a_non_positive_number_is_refused(copy, name, key, line):
    fst, folder = copy
    f = folder / name
    f.write_text("\n".join(line if s.split()[1:2] == [key] else s for s in f.read_text().splitlines()))
    e = _refused(fst, folder)
    assert e.value == str(f.resolve()) and key in e.reason and "not positive" in e.reason


def test_an_older_deck_takes_the_air_density_from_aerodyn(copy):
    # before the .fst had ENVIRONMENTAL CONDITIONS, AeroDyn's file carried AirDens (this deck's
    # AeroDyn file still has 1.225)
    fst = copy[0]
    fst.write_text("\n".join(s for s in fst.read_text().splitlines() if s.split()[1:2] != ["AirDens"]))
    d = read_deck(fst)
    assert d.density == 1.225
    assert d.sources["density"] == "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat: AirDens"
