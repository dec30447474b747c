"""``flexgear export elastodyn``: the fragment's layout, its numbers read back, atomic write,
one-line errors. The numbers themselves are checked against closed forms in
tests/analysis/test_drivetrain.py; here they must read back equal to two_mass's."""
from __future__ import annotations

import os
import re

import pytest

from assembly import save_scene
from assembly.analysis.two_mass import two_mass
from assembly.app.cli import main
from tests.analysis.test_drivetrain import chain

# ElastoDyn's value line: value, name, "- description (unit)" (OpenFAST ElastoDyn input files)
LINE = re.compile(r"^\s*(\S+)\s+(\w+)\s+- (.+) \((.+)\)$")


def _read(text: str) -> dict:
    """name -> (value, unit) of the value lines; '!' comments and '---' section lines skipped."""
    out = {}
    for line in text.splitlines():
        if line.startswith(("!", "---")):
            continue
        m = LINE.match(line)
        assert m, f"not an ElastoDyn value line: {line!r}"
        out[m.group(2)] = (float(m.group(1)), m.group(4))
    return out


@pytest.fixture
def scene_file(tmp_path):
    return save_scene(chain(), tmp_path / "chain.toml")


def test_export_writes_the_fragment_and_it_reads_back(scene_file, tmp_path, capsys):
    out = tmp_path / "drivetrain.dat"
    assert main(["export", "elastodyn", str(scene_file), "--out", str(out)]) == 0
    stdout = capsys.readouterr().out
    assert "GBRatio" in stdout and str(out) in stdout and len(stdout.splitlines()) == 1
    text = out.read_text()
    tm = two_mass(chain())
    want = {"GenIner": (tm.generator_inertia, "kg m^2"), "GBRatio": (tm.gear_ratio, "-"),
            "DTTorSpr": (tm.stiffness, "N-m/rad")}
    got = _read(text)
    assert {k: u for k, (_, u) in got.items()} == {k: u for k, (_, u) in want.items()}
    for k, (v, _) in want.items():              # 10 significant digits written
        assert got[k][0] == pytest.approx(v, rel=5e-10), k
    lines = text.splitlines()
    # ElastoDyn's section lines (80 characters) before GenIner and before the drivetrain values
    sections = [ln for ln in lines if ln.startswith("---")]
    assert [ln.split()[1:-1] for ln in sections] == [["MASS", "AND", "INERTIA"], ["DRIVETRAIN"]]
    assert all(len(ln) == 80 for ln in sections)
    header = "\n".join(ln for ln in lines if ln.startswith("!"))
    assert "'chain'" in header and "DTTorDmp not derived" in header and "free-free" in header
    assert not any(ln.split()[1:2] == ["DTTorDmp"] for ln in lines if not ln.startswith("!"))
    assert sorted(os.listdir(tmp_path)) == ["chain.toml", "drivetrain.dat"]     # no temporary file left


def test_export_to_stdout_equals_the_file(scene_file, tmp_path, capsys):
    assert main(["export", "elastodyn", str(scene_file)]) == 0
    shown = capsys.readouterr().out
    out = tmp_path / "ed.dat"
    assert main(["export", "elastodyn", str(scene_file), "--out", str(out)]) == 0
    assert shown == out.read_text()


def test_a_failed_write_keeps_the_old_file(scene_file, tmp_path, monkeypatch, capsys):
    out = tmp_path / "ed.dat"                   # an earlier fragment (only flexgear's own is replaced)
    old = "! flexgear 0.0: ElastoDyn drivetrain fragment of scene 'old'\nold\n"
    out.write_text(old)

    def refuse(src, dst):
        raise OSError(28, os.strerror(28), str(dst))

    monkeypatch.setattr(os, "replace", refuse)
    assert main(["export", "elastodyn", str(scene_file), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and str(out) in err and os.strerror(28) in err
    assert out.read_text() == old and sorted(os.listdir(tmp_path)) == ["chain.toml", "ed.dat"]


@pytest.mark.parametrize("args, named", [
    (["--rotor", "nacelle"], "rotor = 'nacelle'"),
    (["--generator", "rotor"], "generator = 'rotor'"),
])
def test_bad_ends_are_one_line_errors(scene_file, args, named, capsys):
    assert main(["export", "elastodyn", str(scene_file), *args]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and named in err


def test_dampers_that_miss_the_torsion_write_no_dttordmp(capsys):
    # nrel5mw.toml's bearings carry Nejad et al. (2016)'s damping set, which has no torsional
    # part: the condensed drivetrain damping is 0, and a DTTorDmp of 0 would silently remove
    # the turbine model's own drivetrain damping. The header says so instead.
    assert main(["export", "elastodyn", "nrel5mw", "-q"]) == 0
    text = capsys.readouterr().out
    assert "do not act on the drivetrain's torsion" in text
    assert "DTTorDmp" not in _read(text)


# --out replaces only a fragment flexgear wrote (its first line), never a user's file (a scene, an
# ElastoDyn input), never through a symbolic link, never a folder: one line naming --out, exit 2,
# the file as it was. Through the command line and write_fragment.
USERS = {"the scene itself": None, "an ElastoDyn input": "------- ELASTODYN v1.03.* INPUT FILE ---\nNREL 5.0 MW\n",
         "a commented note": "! flexgear notes, by hand\n", "empty": "", "binary": b"\x00\xff!\x01 flexgear"}


@pytest.mark.parametrize("api", [False, True], ids=["cli", "api"])
@pytest.mark.parametrize("user", list(USERS))
def test_a_file_flexgear_did_not_write_is_never_replaced(scene_file, tmp_path, capsys, user, api):
    from assembly.app.export.elastodyn import write_fragment
    from assembly.app.output import OutputDirError

    out = scene_file if USERS[user] is None else tmp_path / "drivetrain.dat"
    if USERS[user] is not None:
        data = USERS[user]
        out.write_bytes(data if isinstance(data, bytes) else data.encode())
    before = out.read_bytes()
    if api:
        with pytest.raises(OutputDirError, match="flexgear replaces only files it wrote"):
            write_fragment(out, two_mass(chain()), "chain")
    else:
        assert main(["export", "elastodyn", str(scene_file), "--out", str(out), "-q"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and f"--out {out}" in err[0] and "is not an ElastoDyn fragment flexgear wrote" in err[0]
    assert out.read_bytes() == before
    assert not [p for p in os.listdir(tmp_path) if p.endswith(".tmp")]


def test_an_earlier_fragment_is_replaced(scene_file, tmp_path, capsys):
    out = tmp_path / "ed.dat"
    out.write_text("! flexgear 0.0.1: ElastoDyn drivetrain fragment of scene 'older'\n   1   GBRatio   - x (-)\n")
    assert main(["export", "elastodyn", str(scene_file), "--out", str(out), "-q"]) == 0
    assert "'chain'" in out.read_text().splitlines()[0]


@pytest.mark.parametrize("target", ["a user's file", "an earlier fragment", "a folder", "nothing"])
def test_a_symbolic_link_is_refused_whatever_it_points_to(scene_file, tmp_path, capsys, target):
    # the safer choice: never write through a link, even to flexgear's own file
    real = tmp_path / "real"
    if target == "a folder":
        real.mkdir()
    elif target != "nothing":
        real.write_text("mine\n" if target == "a user's file" else
                        "! flexgear 0.0.1: ElastoDyn drivetrain fragment of scene 'chain'\n")
    out = tmp_path / "link.dat"
    out.symlink_to(real)
    before = real.read_bytes() if real.is_file() else None
    assert main(["export", "elastodyn", str(scene_file), "--out", str(out), "-q"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"--out {out}" in err[0] and "symbolic link" in err[0]
    assert out.is_symlink() and os.readlink(out) == str(real)
    assert (real.read_bytes() if real.is_file() else None) == before and (target != "nothing" or not real.exists())


def test_a_folder_at_out_is_refused(scene_file, tmp_path, capsys):
    (tmp_path / "d").mkdir()
    assert main(["export", "elastodyn", str(scene_file), "--out", str(tmp_path / "d"), "-q"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "is not a regular file" in err[0] and os.listdir(tmp_path / "d") == []
