"""Fuzzing ``--out``: nothing a user owns is overwritten (rules: assembly/app/output.py, and
docs/output.md).

Generated situations at ``--out`` -- missing (also several folders deep), an empty folder, a
user's file, a user's folder of files (named like flexgear's own files too), an earlier
result of the same command with files the user added, a symbolic link to a user's file or
folder, a read-only folder of the user's, a folder whose lock another run holds -- crossed
with every command that writes there: ``simulate``, ``simulate`` whose run stops (partial
result), ``frf``, ``campbell``, ``export elastodyn`` (a file) and ``export superelement`` (a
folder of ``<body>.npz`` / ``<body>.dmig``), through the command line or the Python API
(``sim_to_dir``, ``frf_to_dir``, ``campbell_to_dir``, ``write_fragment``, ``write_body``).

Each case: the exit code (0; 1 for the stopped run; 2 when refused) or the API's
OutputDirError is what the rules say; every byte of every user file and every link is as
before (SHA-256 of each file before and after); a refused case leaves the whole tree as it
was, a successful one leaves no work folder, lock or temporary file behind. Runs are tiny
(a two-gear torsional scene, 20 steps, 5 frequencies; a 14-DOF superelement) so a case takes
a fraction of a second.
"""
from __future__ import annotations

import contextlib
import hashlib
import os
import random
from pathlib import Path

import pytest

from assembly.app.cli import main
from assembly.app.export import superelement as export_superelement
from assembly.app.output import MANIFEST, OutputDirError
from tests.app.test_simulate_cli import pair_file
from tests.support.fuzz import examples
from tests.support.out_lock import held_elsewhere
from tests.support.tiny_runs import stop_after, tiny_body

SIM = ["--t-end", "0.002", "--dt", "1e-4", "--output", "force:m"]
ARGS = {  # command line after the scene; --out and -q are added
    "simulate": ["simulate", "{scene}", *SIM],
    "stopped": ["simulate", "{scene}", *SIM],
    "frf": ["frf", "{scene}", "--input", "torque:generator", "--output", "force:m", "--points", "5"],
    "campbell": ["campbell", "{scene}", "--speed-range", "0", "100"],
    "elastodyn": ["export", "elastodyn", "{scene}"],
    "superelement": ["export", "superelement", "{scene}", "--body", "bar"],
}
FOLDER_COMMANDS = ("simulate", "stopped", "frf", "campbell")
SITUATIONS = ("missing", "deep", "empty", "user_file", "user_folder", "earlier", "link_file", "link_folder",
              "read_only", "held")
# names a user's files may have: their own, and names flexgear writes (a foreign folder is never
# emptied, whatever its files are called)
NAMES = ("notes.txt", "data.csv", "summary.json", "index.html", "simulation.h5", "partial_simulation.h5",
         "frf.csv", "campbell.png", "trace_01.png", "bar.npz", "bar.dmig", "sub/deep.txt")
ROOT = os.geteuid() == 0 if hasattr(os, "geteuid") else False

def _tree(root: Path) -> dict:
    """relative path -> ("dir",) | ("link", target) | ("file", sha256) of everything under root."""
    out = {}
    for dirpath, dirnames, filenames in os.walk(root):
        for name in dirnames + filenames:
            p = Path(dirpath) / name
            rel = p.relative_to(root).as_posix()
            if p.is_symlink():
                out[rel] = ("link", os.readlink(p))
            elif p.is_dir():
                out[rel] = ("dir",)
            else:
                out[rel] = ("file", hashlib.sha256(p.read_bytes()).hexdigest())
    return out


def _write(folder: Path, files: dict) -> None:
    for name, data in files.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_bytes(data)


@pytest.fixture(scope="module")
def body():
    return tiny_body()


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    """The scene and, for the API, each command's result computed once."""
    from assembly.analysis.two_mass import two_mass
    from assembly.dynamics.campbell import campbell
    from assembly.dynamics.frf import frequency_response
    from assembly.dynamics.simulate import simulate
    from assembly.dynamics.transient import Diverged
    from assembly.model.assemble import assemble
    from assembly.scene.schema import load_scene

    scene_path = pair_file(tmp_path_factory.mktemp("scene"))
    scene = load_scene(scene_path)
    sim = simulate(scene, 0.002, 1e-4, ["force:m"])
    with pytest.MonkeyPatch.context() as mp:
        import assembly.dynamics.simulate as sim_mod
        mp.setattr(sim_mod, "integrate", stop_after(5))
        with pytest.raises(Diverged) as stopped:
            simulate(scene, 0.002, 1e-4, ["force:m"])
    frf = frequency_response(assemble(scene), "torque:generator", ["force:m"], [1.0, 10.0, 100.0])
    return {"scene_path": scene_path, "scene": scene, "simulate": sim, "stopped": stopped.value.partial, "frf": frf,
            "campbell": campbell(scene, (0.0, 100.0)), "elastodyn": two_mass(scene)}


def _api(command: str, out: Path, results: dict, body) -> None:
    """What the command writes, through the Python API."""
    from assembly.app.export.elastodyn import write_fragment
    from assembly.app.report.campbell import campbell_to_dir
    from assembly.app.report.frf import frf_to_dir
    from assembly.app.report.simulate import sim_to_dir

    r = results.get(command)
    if command in ("simulate", "stopped"):
        sim_to_dir(r, out, "pair")
    elif command == "frf":
        frf_to_dir(r, out, "pair")
    elif command == "campbell":
        campbell_to_dir(r, out)
    elif command == "elastodyn":
        write_fragment(out, r, "pair")
    else:
        export_superelement.write_body(body, "pair", out)


def _cli(command: str, out: Path, results: dict, body, capsys) -> int:
    import assembly.dynamics.simulate as sim_mod

    argv = [a.format(scene=results["scene_path"]) for a in ARGS[command]] + ["--out", str(out), "-q"]
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(export_superelement, "reduced_body", lambda scene, name: body)
        if command == "stopped":
            mp.setattr(sim_mod, "integrate", stop_after(5))
        capsys.readouterr()
        rc = main(argv)
    err = capsys.readouterr().err
    if rc != 0:
        lines = [ln for ln in err.splitlines() if ln.startswith("flexgear: error:")]
        assert len(lines) == 1, err
    return rc


def _earlier(command: str, out: Path, results: dict, body) -> None:
    """An earlier result of ``command`` at ``out`` (a complete one for the stopped run)."""
    _api("simulate" if command == "stopped" else command, out, results, body)


def _expected(command: str, situation: str, files: dict) -> bool:
    """Whether the rules let the command write (True) or refuse it (False)."""
    if command == "elastodyn":              # --out is a file: only a missing one or an earlier fragment
        return situation in ("missing", "earlier", "held")       # (exports take no lock)
    if situation in ("missing", "deep", "empty", "earlier"):
        return True
    if situation == "held":                 # another run writes the folder; exports take no lock
        return command == "superelement"
    if command == "superelement" and situation in ("user_folder", "link_folder", "read_only"):
        clash = "bar.npz" in files or "bar.dmig" in files        # the files are checked, not the folder
        return not clash and (situation != "read_only" or ROOT)  # root writes into a read-only folder
    return False


def _situation(situation: str, base: Path, out: Path, command: str, files: dict, results, body) -> set:
    """Build the situation; returns the relative paths (under base) that are the user's."""
    mine = base / "mine"
    if situation == "user_file":
        out.write_bytes(b"".join(files.values()) or b"x")
    elif situation in ("user_folder", "read_only", "link_folder"):
        target = mine if situation == "link_folder" else out
        target.mkdir()
        _write(target, files)
        if situation == "link_folder":
            out.symlink_to(mine, target_is_directory=True)
    elif situation == "link_file":
        mine.write_bytes(b"".join(files.values()) or b"x")
        out.symlink_to(mine)
    elif situation == "empty":
        out.mkdir()
    elif situation == "earlier":
        if command == "superelement":
            out.mkdir()
        _earlier(command, out, results, body)
        if command != "elastodyn":               # the user adds files to the earlier result
            theirs = {f"user_{k.replace('/', '_')}": v for k, v in files.items()}
            _write(out, theirs)
            return {f"out/{n}" for n in theirs}
        return set()
    before = _tree(base)
    return {p for p, v in before.items() if v[0] != "dir" and p != "scene.toml"}


def _files(rng: random.Random, clash: bool) -> dict:
    """1-4 user files, named from NAMES, of 0-48 random bytes; ``clash``: one of them named as
    an exported body's file."""
    names = rng.sample(NAMES, rng.randint(1, 4))
    if clash and not {"bar.npz", "bar.dmig"} & set(names):
        names[0] = rng.choice(["bar.npz", "bar.dmig"])
    return {n: rng.randbytes(rng.randint(0, 48)) for n in names}


@pytest.mark.parametrize("situation", SITUATIONS)
@pytest.mark.parametrize("command", list(ARGS))
def test_no_user_file_changes_and_the_exit_code_is_the_rules(command, situation, results, body, capsys, tmp_path):
    rng = random.Random(f"{command}/{situation}")
    for k in range(examples(2)):                   # the command line and the Python API in turn
        _case(command, situation, _files(rng, k % 4 == 0), k % 2 == 1, tmp_path / str(k), results, body, capsys)


def _case(command: str, situation: str, files: dict, api: bool, base: Path, results, body, capsys) -> None:
    """One situation at --out, the command (``api``: through the Python API), the checks."""
    base.mkdir()
    out = base / ("a/b/out" if situation == "deep" else "out")
    if command == "elastodyn":
        out = out.with_suffix(".dat")
    users = _situation(situation, base, out, command, files, results, body)
    if situation == "read_only":
        out.chmod(0o555)
    before = _tree(base)
    try:
        with held_elsewhere(out) if situation == "held" else contextlib.nullcontext():
            if api:
                try:
                    _api(command, out, results, body)
                    code = 0
                except (OutputDirError, OSError):   # the API's refusals, and OS errors as open() has them
                    code = 2
            else:
                code = _cli(command, out, results, body, capsys)
    finally:
        if situation == "read_only":
            out.chmod(0o755)
    after = _tree(base)
    allowed = _expected(command, situation, files)
    assert code == ((1 if command == "stopped" and not api else 0) if allowed else 2), (situation, files)
    for p in users:                               # no byte of a user's file or link changed
        assert after.get(p) == before[p], p
    if not allowed:
        assert after == before                    # refused: the whole tree as it was
        return
    leftovers = [p for p in after if ".partial-" in p or ".old-" in p or p.endswith((".lock", ".tmp"))]
    assert not leftovers, leftovers
    if command in FOLDER_COMMANDS:
        assert (out / MANIFEST).is_file()
    elif command == "elastodyn":
        assert out.read_text().startswith("! flexgear ")
    else:
        assert {"bar.npz", "bar.dmig"} <= set(os.listdir(out))
