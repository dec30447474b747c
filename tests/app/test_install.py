"""A non-editable install (a wheel, as `pip install .` builds it) runs from any folder: the
shipped scenes, their STEP parts and the shipped studies are package data, found beside the
installed modules and not in the source tree.

The wheel is built from a copy of the source (so no ``build/`` folder is left in the tree)
with pip's build isolation, i.e. the setuptools that ``[build-system] requires`` names, and
installed without dependencies into a fresh virtual environment whose only other path is
this environment's site-packages (added by a ``.pth`` line, so this environment's editable
install of flexgear is not loaded there: the interpreter must import the installed copy).
"""
from __future__ import annotations

import hashlib
import json
import shutil
import site
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow   # builds and installs a wheel (about 15 s)

ROOT = Path(__file__).resolve().parents[2]
SOURCES = ("pyproject.toml", "README.md", "assembly", "cms", "fe_components")


def _run(args, cwd, timeout=180):
    out = subprocess.run([str(a) for a in args], cwd=cwd, capture_output=True, text=True, timeout=timeout)
    assert out.returncode == 0, f"{args}: exit {out.returncode}\n{out.stdout}\n{out.stderr}"
    return out


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(python, flexgear script, build log, folder outside the source tree) of a fresh install."""
    tmp = tmp_path_factory.mktemp("install")
    src = tmp / "src"
    src.mkdir()
    for name in SOURCES:
        p = ROOT / name
        if p.is_dir():
            shutil.copytree(p, src / name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
        else:
            shutil.copy2(p, src / name)
    wheels = tmp / "wheels"
    build = _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-w", wheels, src], cwd=tmp)
    wheel, = wheels.glob("flexgear-*.whl")
    venv = tmp / "venv"
    _run([sys.executable, "-m", "venv", "--without-pip", venv], cwd=tmp)
    python = venv / "bin" / "python"
    purelib = Path(_run([python, "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"], cwd=tmp)
                   .stdout.strip())
    (purelib / "flexgear_test_deps.pth").write_text("\n".join(site.getsitepackages()) + "\n")
    _run([sys.executable, "-m", "pip", "--python", python, "install", "--no-deps", "--no-index", wheel], cwd=tmp)
    elsewhere = tmp / "elsewhere"
    elsewhere.mkdir()
    return python, venv / "bin" / "flexgear", build.stdout + build.stderr, elsewhere, purelib


def test_the_build_uses_the_current_license_form(installed):
    """`license` is an SPDX string (PEP 639): setuptools' deprecation of the table form is
    not printed (it would stop building in 2027)."""
    log = installed[2]
    assert "project.license" not in log and "Successfully built flexgear" in log


def test_the_installed_copy_is_the_one_imported(installed):
    python, _, _, elsewhere, purelib = installed
    where = _run([python, "-c", "import assembly, cms, fe_components; "
                  "print(assembly.__file__, cms.__file__, fe_components.__file__)"], cwd=elsewhere).stdout.split()
    assert all(Path(w).is_relative_to(purelib) for w in where), where


def test_modes_of_a_shipped_scene_by_name(installed):
    python, flexgear, _, elsewhere, purelib = installed
    out = _run([flexgear, "modes", "lin_parker_n4", "--json"], cwd=elsewhere)
    report = json.loads(out.stdout)
    f = [m["frequency_hz"] for m in report["modes"]]
    # Lin & Parker (J. Vib. Acoust. 121, 1999) Table 3, N = 4: first elastic pair 727.27 Hz
    assert f[0] == pytest.approx(0.0, abs=1e-3) and f[1] == pytest.approx(727.27, abs=0.01)


def test_the_step_carrier_part_is_shipped_and_read(installed):
    """The STEP carrier scene finds its part beside the installed scene, the file is the
    committed one (same SHA-256) and OpenCASCADE reads its solid."""
    python, _, _, elsewhere, purelib = installed
    code = ("import json\n"
            "from assembly import load_scene\n"
            "from fe_components.part.read import part_geometry\n"
            "c = load_scene('planetary_step_carrier').stages[0].carrier.component\n"
            "print(json.dumps({'path': str(c.path), 'sha': c.content_sha256, 'volume': part_geometry(c).volume}))\n")
    got = json.loads(_run([python, "-c", code], cwd=elsewhere).stdout.strip().splitlines()[-1])
    assert Path(got["path"]).is_relative_to(purelib)
    committed = ROOT / "assembly" / "scenes" / "parts" / "carrier_windows.step"
    assert got["sha"] == hashlib.sha256(committed.read_bytes()).hexdigest()
    assert got["volume"] > 0


def test_a_shipped_study_runs_by_name(installed):
    """`flexgear study helix_angle`: the study file and the scene it names are found in the
    installed package; every variant is a row."""
    _, flexgear, _, elsewhere, _ = installed
    _run([flexgear, "study", "helix_angle", "--serial", "--quiet", "--out", elsewhere / "study"], cwd=elsewhere)
    rows = (elsewhere / "study" / "study.csv").read_text().splitlines()
    assert len(rows) == 1 + 31        # header + range = [0, 30, 31] of helix_angle.toml
