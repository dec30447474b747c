"""Output folders under faults (rules: the docstring of assembly/app/output.py).

* Kills: `flexgear run` is killed (SIGKILL; SIGTERM at two points) while meshing, reducing,
  rendering, and at every step of the final swap, by a wrapper that replaces the function at
  that point with a kill of its own process (no hooks in the production code). Then (a) the
  earlier result -- its files, its manifest, the files a user added -- is intact at --out (or,
  after a kill between the two renames, once `recover_output` or the next run restored it),
  or the new result is complete there; (b) the next run succeeds and leaves nothing next to
  --out; (c) the caches it left give the frequencies of a clean run.
* OS errors: every file operation of the output folder (lock, work folder, result files,
  manifest, move aside, move into place, carrying a user's files over) x EACCES, ENOSPC, EROFS,
  injected in-process; real ones where they can be provoked (a file where a folder should be;
  permissions, as an unprivileged user). Each ends in one line naming --out and the reason,
  exit code 2, the earlier result intact, nothing left next to it.
* A second run into a folder a live run is writing is refused in one line.
"""
import errno
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

from assembly.app.cli import main
from assembly.app.output import MANIFEST, recover_output
from tests.support.unprivileged import run_unprivileged

ROOT = Path(__file__).resolve().parents[2]
RIGID = "kahraman_beta20.toml"  # shipped rigid helical pair: solved in 0.2 s
RIGID_ARGS = ["--no-images", "--no-compare", "-q", "--modes", "1"]
# The user's additions to an earlier result: a file at the top, a file in a flexgear folder,
# a folder of their own with a file and an empty folder (path -> bytes, None = folder).
USER_FILES = {"notes.txt": b"my notes", "plots/annotated.txt": b"see mode 3", "mine": None,
              "mine/sketch.txt": b"sketch", "mine/empty": None}

# Runs `flexgear run` (argv[1:]) with fresh caches (FI_CACHE) and the function at FI_POINT
# replaced by a kill (FI_SIGNAL) of this very process.
WRAPPER = r"""
import os, shutil, signal, sys
from pathlib import Path
cache = Path(os.environ["FI_CACHE"])
import assembly.model.components as components
import fe_components.meshing as meshing
components.CacheDirs.__init__.__defaults__ = (cache, cache / "cms")
meshing.DEFAULT_CACHE_DIR = cache
point, sig, out = os.environ["FI_POINT"], getattr(signal, os.environ["FI_SIGNAL"]), os.environ["FI_OUT"]

def die(*args, **kwargs):
    # SIGKILL ends the process here; SIGTERM raises in the CLI's handler (at once, or, inside
    # a swap where it is held back, when the swap ends).
    os.kill(os.getpid(), sig)

if point == "mesh":
    meshing.generate_mesh = die
elif point == "reduce":
    import cms.craig_bampton
    cms.craig_bampton.CraigBamptonReductor.reduce = die
elif point == "render":
    import assembly.app.render.renderer
    assembly.app.render.renderer.AssemblyRenderer.render_mode = die  # after the overview image
elif point in ("aside", "between", "placed"):
    rename = os.rename
    def killing_rename(src, dst):
        if point == "aside" and os.fspath(src) == out:
            die()
        rename(src, dst)
        if (point == "between" and os.fspath(src) == out) or (point == "placed" and os.fspath(dst) == out):
            die()
    os.rename = killing_rename
elif point == "carry":
    os.link = die
elif point == "trash":
    shutil.rmtree = die
elif point == "hold":  # wait (for a second run to try) before writing index.html
    import time, assembly.app.report.pipeline as pipeline
    render_index = pipeline.render_index
    def held(report):
        Path(os.environ["FI_READY"]).touch()
        while not Path(os.environ["FI_GO"]).exists():
            time.sleep(0.05)
        return render_index(report)
    pipeline.render_index = held
from assembly.app.cli import main
sys.exit(main(sys.argv[1:]))
"""


def _env(cache: Path, out: Path, point="none", sig="SIGKILL", **extra) -> dict:
    return {**os.environ, "PYTHONPATH": str(ROOT), "FI_CACHE": str(cache), "FI_OUT": str(out),
            "FI_POINT": point, "FI_SIGNAL": sig, **extra}


def _run(args, env, **kw):
    return subprocess.run([sys.executable, "-c", WRAPPER, *args], env=env, cwd=ROOT, capture_output=True,
                          text=True, timeout=300, **kw)


def _snapshot(folder: Path) -> dict:
    """Relative path -> bytes (files) or None (folders)."""
    return {p.relative_to(folder).as_posix(): (None if p.is_dir() else p.read_bytes())
            for p in sorted(folder.rglob("*"))}


def _elastic_frequencies(modes_json: bytes) -> list:
    data = json.loads(modes_json)
    return data["frequencies_hz"][data["n_rigid_body_modes"]:]


@pytest.fixture(scope="module")
def earlier(tmp_path_factory):
    """A flexgear result of RIGID (written in-process) plus the user's additions."""
    out = tmp_path_factory.mktemp("earlier") / "r"
    assert main(["run", RIGID, "--out", str(out), *RIGID_ARGS]) == 0
    for rel, data in USER_FILES.items():
        if data is None:
            (out / rel).mkdir()
        else:
            (out / rel).write_bytes(data)
    return out


@pytest.fixture
def out(tmp_path, earlier):
    """``tmp_path/p/r``: a copy of the earlier result, alone in its parent folder."""
    target = tmp_path / "p" / "r"
    shutil.copytree(earlier, target)
    return target


def _assert_clean(out: Path):
    """Nothing next to --out: no work folder, no old result, no lock file."""
    assert sorted(p.name for p in out.parent.iterdir()) == [out.name]


def _assert_user_files(out: Path):
    snap = _snapshot(out)
    assert {k: snap.get(k) for k in USER_FILES} == USER_FILES


@pytest.fixture(scope="module")
def flex_scene(tmp_path_factory):
    """The shipped test shaft (a flexible cylinder) at element size 0.025 m instead of the
    committed reference mesh's 0.0125 m: the run meshes it (0.3 s) and reduces it (0.6 s)."""
    src = (ROOT / "tests/support/data/shaft_torsion.toml").read_text()
    assert "mesh_size = 0.0125" in src
    path = tmp_path_factory.mktemp("scene") / "coarse_shaft.toml"
    path.write_text(src.replace("mesh_size = 0.0125", "mesh_size = 0.025"))
    return path


@pytest.fixture(scope="module")
def clean_flex(tmp_path_factory, flex_scene):
    """Elastic frequencies of the flexible scene from a clean run (its own fresh caches)."""
    tmp = tmp_path_factory.mktemp("clean")
    r = _run(["run", str(flex_scene), "--out", str(tmp / "r"), *RIGID_ARGS], _env(tmp / "cache", tmp / "r"))
    assert r.returncode == 0, r.stderr
    return _elastic_frequencies((tmp / "r" / "modes.json").read_bytes())


# (kill point, signal, scene, what --out holds after the kill: the earlier or the new result)
KILLS = [
    ("mesh", "SIGKILL", "flex", "earlier"),
    ("reduce", "SIGKILL", "flex", "earlier"),
    ("render", "SIGKILL", "images", "earlier"),
    ("render", "SIGTERM", "images", "earlier"),
    ("aside", "SIGKILL", "rigid", "earlier"),     # just before the earlier result is moved aside
    ("between", "SIGKILL", "rigid", "earlier"),   # between the two renames: restored by recovery
    ("carry", "SIGKILL", "rigid", "earlier"),     # while linking the user's files into the new result
    ("between", "SIGTERM", "rigid", "new"),       # held back until the swap is complete
    ("placed", "SIGKILL", "rigid", "new"),        # the new result is in place, the old one not deleted
    ("trash", "SIGKILL", "rigid", "new"),         # while deleting the old one
]


@pytest.mark.slow
@pytest.mark.parametrize("point,sig,scene,holds", KILLS, ids=[f"{p}-{s}" for p, s, _, _ in KILLS])
def test_kill_leaves_a_whole_result(point, sig, scene, holds, out, tmp_path, flex_scene, clean_flex):
    before = _snapshot(out)
    cache = tmp_path / "cache"
    source = str(flex_scene) if scene == "flex" else RIGID
    args = ["run", source, "--out", str(out), *RIGID_ARGS[:-1], "2"]  # --modes 2 marks the new result
    if scene == "images":
        args.remove("--no-images")
    r = _run(args, _env(cache, out, point, sig))
    if sig == "SIGKILL":
        assert r.returncode == -signal.SIGKILL, r.stderr
    else:  # the CLI's handler unwound the run: cleaned up at once, one line, exit 128 + 15
        assert r.returncode == 128 + signal.SIGTERM, r.stderr
        assert r.stderr.splitlines() == ["flexgear: terminated (SIGTERM)"]
        _assert_clean(out)
    # (a) the earlier result, or the whole new one (with the user's files carried over)
    if point in ("between", "carry") and sig == "SIGKILL":
        assert not out.exists()  # the window between the renames ...
        assert recover_output(out)[0].startswith("restored .r.old-")  # ... which recovery closes
    if holds == "earlier":
        assert _snapshot(out) == before
    else:
        manifest = json.loads((out / MANIFEST).read_text())
        assert manifest["options"]["n_modes"] == 2
        assert all((out / f).is_file() for f in manifest["files"])
        _assert_user_files(out)
    # (b) the next run succeeds and leaves nothing next to --out
    again = ["run", source, "--out", str(out), *RIGID_ARGS]
    if scene == "flex":  # with the caches the killed run left
        r = _run(again, _env(cache, out))
        assert r.returncode == 0, r.stderr
    else:
        assert main(again) == 0
    _assert_clean(out)
    _assert_user_files(out)
    # (c) same frequencies as a clean run. Flexible: independent reductions of one mesh agree to
    # the round-off of the sparse eigen solve (3e-11 relative measured); 1e-9 allows for that,
    # while a wrong or truncated cache entry moves them by far more.
    expected = clean_flex if scene == "flex" else _elastic_frequencies(before["modes.json"])
    assert _elastic_frequencies((out / "modes.json").read_bytes()) == pytest.approx(expected, rel=1e-9)


# --------------------------------------------------------------------------------------
# OS errors of the output folder's file operations: one line, exit 2, earlier result kept
# --------------------------------------------------------------------------------------

def _fault_lock(monkeypatch, out, exc):
    real = os.open
    monkeypatch.setattr(os, "open", lambda p, *a, **k: _raise(exc) if Path(p).name == f".{out.name}.lock"
                        else real(p, *a, **k))


def _fault_work_folder(monkeypatch, out, exc):
    real = os.mkdir
    monkeypatch.setattr(os, "mkdir", lambda p, *a, **k: _raise(exc) if Path(p).name.startswith(f".{out.name}.partial-")
                        else real(p, *a, **k))


def _fault_result_file(monkeypatch, out, exc):
    def write_modes_csv(infos, path, band=None):  # part of the file, then a full disk reported on flush: no file name
        Path(path).write_text("mode,")
        raise exc
    monkeypatch.setattr("assembly.app.report.pipeline.write_modes_csv", write_modes_csv)


def _fault_manifest(monkeypatch, out, exc):
    def write_manifest(folder, manifest):
        (Path(folder) / MANIFEST).write_text("{")
        raise type(exc)(exc.errno, exc.strerror, str(Path(folder) / MANIFEST))
    monkeypatch.setattr("assembly.app.report.pipeline.write_manifest", write_manifest)


def _fault_rename(which):
    def inject(monkeypatch, out, exc):
        real = os.rename

        def rename(src, dst):
            aside = os.fspath(src) == str(out)
            into_place = os.fspath(dst) == str(out) and Path(src).name.startswith(f".{out.name}.partial-")
            if (which == "aside" and aside) or (which == "into place" and into_place):
                raise exc
            return real(src, dst)
        monkeypatch.setattr(os, "rename", rename)
    return inject


def _fault_carry_over(monkeypatch, out, exc):
    monkeypatch.setattr(os, "link", lambda *a, **k: _raise(exc))
    monkeypatch.setattr(shutil, "copy2", lambda *a, **k: _raise(exc))


def _raise(exc):
    raise exc


FAULTS = {"lock": _fault_lock, "work folder": _fault_work_folder, "result file": _fault_result_file,
          "manifest": _fault_manifest, "move aside": _fault_rename("aside"),
          "move into place": _fault_rename("into place"), "carry over": _fault_carry_over}


def _assert_one_line(err: str, out: Path, reason: str):
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"flexgear: error: --out {out}") and reason in lines[0], err


@pytest.mark.parametrize("code", [errno.EACCES, errno.ENOSPC, errno.EROFS], ids=errno.errorcode.get)
@pytest.mark.parametrize("where", FAULTS)
def test_os_error_is_one_line_and_keeps_earlier_result(where, code, out, monkeypatch, capsys):
    before = _snapshot(out)
    exc = OSError(code, os.strerror(code))
    FAULTS[where](monkeypatch, out, exc)
    assert main(["run", RIGID, "--out", str(out), *RIGID_ARGS]) == 2
    _assert_one_line(capsys.readouterr().err, out, os.strerror(code))
    monkeypatch.undo()
    assert _snapshot(out) == before
    _assert_clean(out)


@pytest.mark.parametrize("error", [TypeError("a bug"), FileNotFoundError(errno.ENOENT, "gone", "/elsewhere/cache.npz")],
                         ids=["programming error", "OSError of another file"])
def test_other_errors_pass_unchanged(error, out, monkeypatch):
    # Only OSErrors about the output folder become one-line errors; the run still leaves the
    # earlier result as it was.
    before = _snapshot(out)
    monkeypatch.setattr("assembly.app.report.pipeline.write_modes_csv", lambda infos, path, band=None: _raise(error))
    with pytest.raises(type(error)):
        main(["run", RIGID, "--out", str(out), *RIGID_ARGS])
    assert _snapshot(out) == before
    _assert_clean(out)


def test_study_full_disk_is_one_line(out, monkeypatch, capsys):
    before = _snapshot(out)
    full = OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))  # reported on flush: no file name
    monkeypatch.setattr("assembly.app.study.out.write_table", lambda rows, names, folder: _raise(full))
    assert main(["study", "helix_angle", "--serial", "--out", str(out), "-q"]) == 2
    _assert_one_line(capsys.readouterr().err, out, os.strerror(errno.ENOSPC))
    assert _snapshot(out) == before
    _assert_clean(out)


def test_failed_run_removes_the_folders_it_created(tmp_path, monkeypatch, capsys):
    out = tmp_path / "a" / "b" / "r"
    _fault_work_folder(monkeypatch, out, OSError(errno.EROFS, os.strerror(errno.EROFS)))
    assert main(["run", RIGID, "--out", str(out), *RIGID_ARGS]) == 2
    _assert_one_line(capsys.readouterr().err, out, os.strerror(errno.EROFS))
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("below", ["r", "x/y/r"])
def test_out_under_a_file(tmp_path, below, capsys):
    # A real regular file where a folder of --out should be: ENOTDIR, nothing created.
    (tmp_path / "afile").write_text("data")
    out = tmp_path / "afile" / below
    assert main(["run", RIGID, "--out", str(out), *RIGID_ARGS]) == 2
    _assert_one_line(capsys.readouterr().err, out, os.strerror(errno.ENOTDIR))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"] and (tmp_path / "afile").read_text() == "data"


@pytest.mark.parametrize("read_only", ["parent", "earlier result"])
def test_real_permission_denied(read_only, out):
    before = _snapshot(out)
    locked = out.parent if read_only == "parent" else out / "plots"  # a folder we may not write in
    locked.chmod(0o555)
    try:
        r = run_unprivileged(["run", RIGID, "--out", str(out), *RIGID_ARGS])
    except subprocess.SubprocessError as exc:  # e.g. a container without CAP_SETPCAP
        pytest.skip(f"cannot drop root's file-mode capabilities here: {exc}")
    finally:
        locked.chmod(0o755)
    assert r.returncode == 2, r.stderr
    _assert_one_line(r.stderr, out, os.strerror(errno.EACCES))
    assert str(locked) in r.stderr
    assert _snapshot(out) == before
    _assert_clean(out)


def test_concurrent_run_is_refused(out, tmp_path, capsys):
    """While a run writes --out, a second one is refused in one line naming the first's pid;
    the first then completes whole."""
    ready, go = tmp_path / "ready", tmp_path / "go"
    first = subprocess.Popen([sys.executable, "-c", WRAPPER, "run", RIGID, "--out", str(out), *RIGID_ARGS[:-1], "2"],
                             env=_env(tmp_path / "cache", out, "hold", FI_READY=str(ready), FI_GO=str(go)),
                             cwd=ROOT, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 120
        while not ready.exists():
            assert first.poll() is None and time.monotonic() < deadline, "first run ended early"
            time.sleep(0.05)
        assert main(["run", RIGID, "--out", str(out), *RIGID_ARGS]) == 2
        _assert_one_line(capsys.readouterr().err, out, f"another flexgear run (pid {first.pid} on ")
        go.touch()
        assert first.wait(timeout=120) == 0, first.stderr.read()
    finally:
        go.touch()
        first.wait(timeout=120)
    assert json.loads((out / MANIFEST).read_text())["options"]["n_modes"] == 2
    _assert_user_files(out)
    _assert_clean(out)


# --------------------------------------------------------------------------------------
# Files a user added; folder modes; folders that are not flexgear results
# --------------------------------------------------------------------------------------

@pytest.mark.parametrize("links", [True, False], ids=["hard links", "copies"])
def test_user_files_are_carried_over(links, out, monkeypatch):
    inode = (out / "notes.txt").stat().st_ino
    if not links:  # a file system without hard links: copied instead
        monkeypatch.setattr(os, "link", lambda *a, **k: _raise(OSError(errno.EPERM, os.strerror(errno.EPERM))))
    assert main(["run", RIGID, "--out", str(out), *RIGID_ARGS]) == 0
    _assert_user_files(out)
    assert ((out / "notes.txt").stat().st_ino == inode) == links
    _assert_clean(out)


@pytest.mark.parametrize("kind", ["file", "folder"])
def test_user_file_named_like_a_new_result_file_is_refused(kind, out, capsys):
    # The earlier result had no comparison (--no-compare); the user's entry of that name is
    # theirs, and the run that writes fidelity_comparison.csv must not replace it.
    user = out / "fidelity_comparison.csv"
    user.mkdir() if kind == "folder" else user.write_text("mine")
    before = _snapshot(out)
    assert main(["run", RIGID, "--out", str(out), "--no-images", "-q", "--modes", "1"]) == 2
    _assert_one_line(capsys.readouterr().err, out, "fidelity_comparison.csv")
    assert _snapshot(out) == before
    _assert_clean(out)


@pytest.mark.parametrize("mask", [0o022, 0o027, 0o002])
def test_folders_and_files_follow_the_umask(mask, tmp_path):
    out = tmp_path / "new" / "r"
    old = os.umask(mask)
    try:
        assert main(["run", RIGID, "--out", str(out), *RIGID_ARGS]) == 0
    finally:
        os.umask(old)
    for p in (out.parent, out, out / "plots"):
        assert p.stat().st_mode & 0o777 == 0o777 & ~mask, p
    for p in (out / MANIFEST, out / "modes.csv", out / "plots" / "frequencies_by_fidelity.png"):
        assert p.stat().st_mode & 0o777 == 0o666 & ~mask, p


def _not_a_result(out: Path):
    out.mkdir()
    (out / "thesis.tex").write_text("precious")


def _bad_manifest(text):
    def make(out: Path):
        out.mkdir()
        (out / MANIFEST).write_text(text)
    return make


def _symlink(out: Path):
    (out.parent / "elsewhere").mkdir()
    out.symlink_to(out.parent / "elsewhere")


FOREIGN = {"not a result": _not_a_result, "manifest not JSON": _bad_manifest("{"),
           "manifest without files": _bad_manifest('{"tool": "flexgear run"}'),
           "a file": lambda out: out.write_text("data"), "a symlink": _symlink}


@pytest.mark.parametrize("what", FOREIGN)
def test_foreign_out_is_refused(what, tmp_path, capsys):
    out = tmp_path / "r"
    FOREIGN[what](out)
    before = sorted(os.listdir(tmp_path))
    assert main(["run", RIGID, "--out", str(out), *RIGID_ARGS]) == 2
    _assert_one_line(capsys.readouterr().err, out, "")
    assert sorted(os.listdir(tmp_path)) == before


def test_recovery_restores_only_a_complete_earlier_result(out):
    # A kill between the renames leaves .r.old-*; a kill while deleting it leaves a work-folder
    # name (never restored, even half deleted). Both mimicked by renames.
    os.rename(out, out.parent / ".r.old-0123abcd")
    (out.parent / ".r.partial-89abcdef").mkdir()
    assert recover_output(out) == ["restored .r.old-0123abcd", "removed .r.partial-89abcdef"]
    _assert_user_files(out)
    _assert_clean(out)
