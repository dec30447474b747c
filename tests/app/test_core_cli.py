"""The flexgear CLI: mode tables, JSON output, and bad input ending in one clear line."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

from assembly.app.cli import main
from assembly.scene.schema import SCENE_DIR, shipped_scenes

EXPECTED_SCENES = {"peeters_parallel_torsional.toml", "kahraman_beta0.toml", "kahraman_beta20.toml",
                   "lin_parker_n3.toml", "lin_parker_n4.toml", "lin_parker_n5.toml"}


def test_shipped_scene_names():
    assert EXPECTED_SCENES <= {p.name for p in shipped_scenes()}


@pytest.mark.parametrize("name", sorted(EXPECTED_SCENES))
def test_modes_json_lists_all_frequencies_ascending(name, capsys):
    assert main(["modes", str(SCENE_DIR / name), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    f = out["frequencies_hz"]
    assert f == sorted(f) and len(f) == out["n_dofs"] == len(out["modes"])
    assert f[0] >= 0.0 and out["n_rigid_body_modes"] >= 1  # every shipped scene turns freely
    for m in out["modes"]:
        if m["frequency_hz"] > 0 and m["class"] != "rigid-body":
            assert sum(m["kinetic_energy_share"].values()) == pytest.approx(1.0, rel=1e-9)
            assert sum(m["strain_energy_share"].values()) == pytest.approx(1.0, rel=1e-9)


def test_modes_table(capsys):
    assert main(["modes", "lin_parker_n4.toml"]) == 0
    out = capsys.readouterr().out
    assert "planet" in out and "translational" in out and "rotational" in out


BASE = """
[[bodies]]
name = "pinion"
mass = 2.0
polar_inertia = 2.9e-3

[[bodies]]
name = "wheel"
mass = 2.0
polar_inertia = 2.9e-3
position = [0.10641777724759122, 0.0, 0.0]

[[bearings]]
body = "pinion"
k_radial = 3.5e8
k_axial = 1.0e8
k_tilt = 2.775e5

[[bearings]]
body = "wheel"
k_radial = 3.5e8
k_axial = 1.0e8
k_tilt = 2.775e5

[[meshes]]
gear1 = "pinion"
gear2 = "wheel"
stiffness = 2.0e8
base_radius1 = 0.05
base_radius2 = 0.05
pressure_angle_deg = 20.0
"""

PLANETARY = (SCENE_DIR / "lin_parker_n3.toml").read_text()

BAD = {  # case -> (scene text, expected path in the message, expected value text)
    "unknown key": (BASE.replace('mass = 2.0\npolar_inertia = 2.9e-3\n\n[[bodies]]',
                                 'mass = 2.0\nmas = 3\npolar_inertia = 2.9e-3\n\n[[bodies]]', 1),
                    "bodies[0].mas", "3"),
    "missing field": (BASE.replace("stiffness = 2.0e8\n", ""), "meshes[0].stiffness", "None"),
    "wrong type": (BASE.replace("mass = 2.0", 'mass = "heavy"', 1), "bodies[0].mass", "'heavy'"),
    "non-positive mass": (BASE.replace("mass = 2.0", "mass = 0.0", 1), "bodies[0].mass", "0.0"),
    "negative stiffness": (BASE.replace("k_radial = 3.5e8", "k_radial = -1.0", 1), "bearings[0].k_radial", "-1.0"),
    "zero mesh stiffness": (BASE.replace("stiffness = 2.0e8", "stiffness = 0.0"), "meshes[0].stiffness", "0.0"),
    # named as written: the degree key and the degree value
    "helix 90 deg": (BASE + "helix_angle_deg = 90.0\n", "meshes[0].helix_angle_deg", "90.0"),
    "missing body": (BASE.replace('gear2 = "wheel"', 'gear2 = "whee1"'), "meshes[0].gear2", "whee1"),
    "missing frame": (BASE.replace('name = "wheel"', 'name = "wheel"\nframe = "carrier"'), "bodies[1].frame", "carrier"),
    "connected to nothing": (BASE + '\n[[bodies]]\nname = "loose"\nmass = 1.0\npolar_inertia = 1e-3\n',
                             "bodies[2].name", "loose"),
    # the pressure angle echoed as written (degrees), the fields involved and the tolerance named
    "bad centre distance": (BASE.replace("0.10641777724759122", "0.12"), "meshes[0].pressure_angle_deg = 20",
                            "bodies[1].position"),
    "planet count": (PLANETARY.replace("count = 3", "count = 0"), "stages[0].planets.count", "0"),
    "planets overlap": (PLANETARY.replace("count = 3", "count = 9"), "stages[0].planets.count", "9"),
    "planet angles overlap": (PLANETARY.replace("count = 3", "count = 3\nangles_deg = [0.0, 20.0, 180.0]"),
                              "stages[0].planets.angles", "0.0"),
    "ring radius": (PLANETARY.replace("base_radius = 0.1391", "base_radius = 0.1375"),
                    "stages[0].ring.base_radius", "0.1375"),
    "unknown support": (PLANETARY.replace('support = "bearing"', 'support = "glued"', 1),
                        "stages[0].sun.support", "glued"),
    "not toml": ("[[bodies]\nname=", "scene.toml", "<file>"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_input_one_line_exit_2(case, tmp_path, capsys):
    text, path, value = BAD[case]
    f = tmp_path / "scene.toml"
    f.write_text(text)
    rc = main(["modes", str(f)])
    err = capsys.readouterr().err.strip()
    assert rc == 2, err
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert path in err and value in err, err


def test_bad_input_console_script_exit_code(tmp_path):
    f = tmp_path / "scene.toml"
    f.write_text(BAD["planet count"][0])
    p = subprocess.run([sys.executable, "-m", "assembly.app.cli", "modes", str(f)], capture_output=True, text=True)
    assert p.returncode == 2
    assert p.stdout == "" and p.stderr.count("\n") == 1
    assert "stages[0].planets.count = 0" in p.stderr


def test_every_domain_error_of_the_package_is_a_one_line_user_error():
    """Every exception class the packages define for bad input (scene, geometry, meshing,
    coupling, reduction, cache, solver, output) is caught by the CLI's one handler."""
    import importlib
    import inspect

    from assembly.app.errors import user_errors
    handled = user_errors()
    modules = ["assembly.errors", "cms.errors", "fe_components.errors", "assembly.app.output", "assembly.app.cli"]
    found = []
    for name in modules:
        mod = importlib.import_module(name)
        for _, cls in inspect.getmembers(mod, inspect.isclass):
            if issubclass(cls, Exception) and cls.__module__ == name:
                found.append(cls)
                assert issubclass(cls, handled), f"{name}.{cls.__name__} would end in a traceback"
    assert len(found) >= 10   # the classes listed in the three errors modules, output and cli
