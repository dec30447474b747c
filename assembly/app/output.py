"""Output folders of ``flexgear run``, ``flexgear study`` and the other commands with ``--out``: ``--out P/X`` always holds either a
complete flexgear result or what it held before, also when the program is killed, the disk fills
or a second run writes into the same folder.

Rules:

* **Staging.** A run writes into a work folder ``P/.X.partial-<8 hex digits>`` next to the
  target; on any failure (exception, Ctrl-C, SIGTERM through the CLI) it is deleted.
* **Swap.** On success an earlier result is renamed to ``P/.X.old-<8 hex>`` (same parent, so the
  rename is atomic), then the work folder to ``P/X``; SIGINT and SIGTERM are held back during
  these renames. The old folder is then renamed to a work-folder name and deleted. A SIGKILL
  between the two renames leaves no ``P/X``, but ``.X.old-*`` holds the complete earlier result:
  the next run (or :func:`recover_output`) renames it back before doing anything else.
* **One run per folder.** A run holds an exclusive ``flock`` on ``P/.X.lock`` (which names its
  pid and host) from start to end; a second run into the same folder is refused in one line.
  The kernel drops the lock when its holder dies, however it dies; the file is removed at the end.
  A command whose computation is long (simulate, frf, campbell) checks the folder and takes the
  lock before it computes (:func:`hold_output`) and holds it until the result is in place or the
  command ends, however it ends.
* **Healing.** Holding the lock, leftovers of earlier runs are known to belong to dead
  processes: after restoring an interrupted swap, ``.X.partial-*`` and ``.X.old-*`` are deleted
  (an ``.X.old-*`` holding a complete result is kept while ``P/X`` is not a flexgear result).
* **Never a foreign folder.** ``P/X`` is replaced only if it is empty or holds a run manifest
  (:data:`MANIFEST`, listing the files the run wrote), and only if every folder in it may be
  emptied by this user (checked before the run starts).
* **Files a user added are carried over.** Every file or folder in an earlier result that its
  manifest does not list (notes, a sketch) is carried into the new result at the same relative
  path (hard link, or a copy where the file system refuses links) and never deleted; if the new
  run wrote a file of that name, it is refused in one line and the earlier result is kept.
  Files the manifest lists belong to flexgear and are replaced, edited or not.
* **Single files.** Commands that write files rather than a folder (``export elastodyn``,
  ``export superelement``, ``reference``) replace a file only if flexgear wrote it -- each recognises its own
  earlier output by its format's marker (:func:`check_own_file`) -- and never write through a
  symbolic link; anything else at that name is refused in one line and left as it is.
* **One-line errors.** Every OSError of these operations -- creating folders, the lock, the work
  folder, writing results into it (:func:`writing`), the swap -- becomes an
  :class:`OutputDirError` ``--out P/X: <what failed>: <strerror>``; errors about other files
  (scene, caches) and programming errors pass unchanged.
* **Modes.** Folders are made with ``os.mkdir(path, 0o777)`` and files with ``open()``, so the
  user's umask applies (no 0700 temporary folders).
"""
from __future__ import annotations

import errno
import json
import logging
import os
import re
import secrets
import shutil
import signal
import socket
import threading
from contextlib import contextmanager, suppress
from pathlib import Path

from .signals import signal_handler

log = logging.getLogger(__name__)

#: Manifest file that marks a folder as a flexgear result (JSON: tool, scene, files, timings).
MANIFEST = "flexgear_run.json"


class OutputDirError(RuntimeError):
    """The output folder cannot be (re)placed."""


def _fail(out_dir: Path, what: str, exc: OSError) -> OutputDirError:
    return OutputDirError(f"--out {out_dir}: {what}: {exc.strerror or exc}")


@contextmanager
def _os_errors(out_dir: Path, what: str):
    """OSError -> :class:`OutputDirError` ``--out DIR: what: strerror``."""
    try:
        yield
    except OSError as exc:
        raise _fail(out_dir, what, exc) from exc


# --------------------------------------------------------------------------------------
# Names next to the target
# --------------------------------------------------------------------------------------

def _sibling(out_dir: Path, kind: str, tag: str) -> Path:
    return out_dir.parent / f".{out_dir.name}.{kind}-{tag}"


def _leftovers(out_dir: Path) -> list[tuple[str, Path]]:
    """(kind, path) of the ``.X.partial-*`` and ``.X.old-*`` folders next to ``out_dir``."""
    pattern = re.compile(rf"\.{re.escape(out_dir.name)}\.(partial|old)-[0-9a-f]{{8}}")
    with os.scandir(out_dir.parent) as it:
        return sorted((m.group(1), Path(e.path)) for e in it
                      if (m := pattern.fullmatch(e.name)) and e.is_dir(follow_symlinks=False))


def _free_name(out_dir: Path, kind: str) -> Path:
    while True:
        p = _sibling(out_dir, kind, secrets.token_hex(4))
        if not os.path.lexists(p):
            return p


def _new_dir(out_dir: Path, kind: str) -> Path:
    """A new empty folder ``.X.<kind>-<8 hex>`` (mode 0o777 less the umask)."""
    while True:
        p = _free_name(out_dir, kind)
        try:
            os.mkdir(p, 0o777)
            return p
        except FileExistsError:  # taken meanwhile
            continue


def _vacant(out_dir: Path) -> bool:
    """Missing, or an empty real folder (which a rename replaces atomically)."""
    if not os.path.lexists(out_dir):
        return True
    return out_dir.is_dir() and not out_dir.is_symlink() and not any(out_dir.iterdir())


def _is_inside(name, folder: Path) -> bool:
    try:
        return Path(os.fsdecode(name)).absolute().is_relative_to(folder)
    except TypeError:  # a file descriptor
        return False


def _remove(path: Path) -> None:
    """Delete a folder of ours; failures are logged (the next run tries again)."""
    def warn(func, p, exc_info):
        log.warning("cannot remove %s: %s", p, exc_info[1])
    if os.path.lexists(path):
        shutil.rmtree(path, onerror=warn)


# --------------------------------------------------------------------------------------
# Parent folders and the lock
# --------------------------------------------------------------------------------------

def _make_parents(out_dir: Path) -> list[Path]:
    """Create the missing parent folders of ``out_dir``; returns them, outermost first."""
    missing, p = [], out_dir.parent
    while not os.path.lexists(p):
        missing.append(p)
        p = p.parent
    with _os_errors(out_dir, f"cannot inspect {p}"):
        is_dir = p.is_dir()
    if not is_dir:
        raise OutputDirError(f"--out {out_dir}: cannot create a folder under {p}, which is a file: "
                             f"{os.strerror(errno.ENOTDIR)}")
    created = []
    try:
        for d in reversed(missing):
            with _os_errors(out_dir, f"cannot create folder {d}"):
                os.mkdir(d, 0o777)
            created.append(d)
    except BaseException:
        _remove_empty(created)
        raise
    return created


def _remove_empty(folders: list[Path]) -> None:
    for d in reversed(folders):
        try:
            os.rmdir(d)
        except OSError:
            return


@contextmanager
def _locked(out_dir: Path):
    """Hold an exclusive lock on ``P/.X.lock``; yields False (no lock) where the file system
    or the platform has no ``flock``."""
    path = out_dir.parent / f".{out_dir.name}.lock"
    fd = _lock(out_dir, path)
    if fd is None:
        yield False
        return
    try:
        yield True
    finally:
        with suppress(OSError):
            os.unlink(path)  # while still holding the lock
        os.close(fd)


def _lock(out_dir: Path, path: Path) -> int | None:
    """Open and lock ``path`` (writing our pid and host into it); None if locks are unavailable."""
    try:
        import fcntl
    except ImportError:  # Windows
        return None
    while True:
        with _os_errors(out_dir, f"cannot create {path}"):
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.read(fd, 200).decode(errors="replace").strip() or "pid unknown"
            os.close(fd)
            raise OutputDirError(f"--out {out_dir}: another flexgear run ({holder}) is writing this folder; "
                                 "wait for it to end or choose another folder") from None
        except OSError as exc:
            os.close(fd)
            log.warning("cannot lock %s (%s): running without lock; leftovers of interrupted runs "
                        "are not cleaned", path, exc.strerror)
            return None
        try:  # the holder we raced with may have removed the file meanwhile: lock the new one
            same = os.path.samestat(os.fstat(fd), os.stat(path))
        except FileNotFoundError:
            same = False
        if same:
            try:
                with _os_errors(out_dir, f"cannot write {path}"):
                    os.ftruncate(fd, 0)
                    os.write(fd, f"pid {os.getpid()} on {socket.gethostname()}".encode())
            except BaseException:
                with suppress(OSError):
                    os.unlink(path)
                os.close(fd)
                raise
            return fd
        os.close(fd)


# --------------------------------------------------------------------------------------
# Checks and healing
# --------------------------------------------------------------------------------------

def _manifest_files(out_dir: Path) -> set[str]:
    """Relative paths (POSIX) the earlier run wrote, the manifest included."""
    path = out_dir / MANIFEST
    if not path.is_file():
        raise OutputDirError(f"--out {out_dir}: folder exists, is not empty and holds no earlier flexgear "
                             f"run ({MANIFEST}); choose a new or empty folder")
    try:
        files = json.loads(path.read_text(encoding="utf-8"))["files"]
        if not isinstance(files, list) or not all(isinstance(f, str) for f in files):
            raise TypeError
    except (ValueError, KeyError, TypeError):
        raise OutputDirError(f"--out {out_dir}: {MANIFEST} is not a flexgear run manifest (no list of "
                             "files); choose a new or empty folder") from None
    return {MANIFEST, *files}


def check_output_dir(out_dir: Path) -> None:
    """Raise :class:`OutputDirError` if ``out_dir`` exists and may not be replaced: not a
    folder, a foreign folder (not empty, no manifest), or a folder this user cannot empty."""
    out_dir = Path(out_dir).absolute()
    with _os_errors(out_dir, "cannot inspect the folder"):
        if not os.path.lexists(out_dir):
            return
        if out_dir.is_symlink() or not out_dir.is_dir():
            raise OutputDirError(f"--out {out_dir}: exists and is not a folder")
        if not any(out_dir.iterdir()):
            return
        _manifest_files(out_dir)
        for d, _, _ in os.walk(out_dir, onerror=_raise):
            if not os.access(d, os.R_OK | os.W_OK | os.X_OK):
                raise OutputDirError(f"--out {out_dir}: cannot replace the earlier result: {d}: "
                                     f"{os.strerror(errno.EACCES)}")


def _raise(exc: OSError):
    raise exc


def _heal(out_dir: Path) -> list[str]:
    """With the lock held: restore an earlier result a killed swap left aside, then delete
    the leftovers of dead runs. Returns what was done (one line each)."""
    with _os_errors(out_dir, "cannot clean up after earlier runs"):
        return _heal_leftovers(out_dir)


def _heal_leftovers(out_dir: Path) -> list[str]:
    done = []
    left = _leftovers(out_dir)
    complete = [p for kind, p in left if kind == "old" and (p / MANIFEST).is_file()]
    if complete and _vacant(out_dir):
        best = max(complete, key=lambda p: (p / MANIFEST).stat().st_mtime)
        with _os_errors(out_dir, f"cannot restore the earlier result from {best.name}"):
            if os.path.lexists(out_dir):
                os.rmdir(out_dir)
            os.rename(best, out_dir)
        log.warning("--out %s: restored the earlier result from %s (a run was killed while replacing it)",
                    out_dir, best.name)
        done.append(f"restored {best.name}")
        complete.remove(best)
    keep = set(complete) if not (out_dir / MANIFEST).is_file() else set()
    for p in keep:
        log.warning("--out %s: keeping %s, an earlier result, as %s is not a flexgear result", out_dir, p, out_dir)
    for _, p in left:
        if p not in keep and os.path.lexists(p):
            _remove(p)
            done.append(f"removed {p.name}")
    return done


def recover_output(out_dir) -> list[str]:
    """Repair ``out_dir`` after a killed run (what every run does first): restore an earlier
    result left aside, delete leftover work folders. Returns what was done."""
    out_dir = Path(out_dir).absolute()
    if not out_dir.parent.is_dir():
        return []
    with _locked(out_dir) as locked:
        return _heal(out_dir) if locked else []


# --------------------------------------------------------------------------------------
# Swap
# --------------------------------------------------------------------------------------

@contextmanager
def _signals_held():
    """Hold back SIGINT and SIGTERM until the block ends (then they reach the handlers from
    before), so that handlers which turn them into exceptions cannot stop a swap between its
    renames."""
    caught = []
    try:
        with signal_handler(lambda signum, frame: caught.append(signum), (signal.SIGINT, signal.SIGTERM)):
            yield
    finally:
        for s in caught:
            signal.raise_signal(s)


def _carry_over(src: Path, dst: Path, ours: set[str], out_dir: Path, rel: str = "", foreign: bool = False) -> None:
    """Link every entry of the earlier result ``src`` that ``ours`` does not list into ``dst``."""
    with os.scandir(src) as it:
        entries = sorted(it, key=lambda e: e.name)
    for e in entries:
        r, target = f"{rel}{e.name}", dst / e.name
        if e.is_dir(follow_symlinks=False):
            inner = foreign or not any(f.startswith(r + "/") for f in ours)
            if inner:  # a user's folder: kept even when empty
                _user_dir(target, r, out_dir)
            _carry_over(Path(e.path), target, ours, out_dir, r + "/", inner)
        elif foreign or r not in ours:
            if os.path.lexists(target):
                raise OutputDirError(f"--out {out_dir}: {r} is not a flexgear file (not in {MANIFEST} of the earlier "
                                     "result) and this run writes a file of that name; move it away and run again")
            _user_dir(target.parent, rel.rstrip("/"), out_dir)
            with _os_errors(out_dir, f"cannot carry {r} over from the earlier result"):
                _link_or_copy(Path(e.path), target)


def _user_dir(target: Path, rel: str, out_dir: Path) -> None:
    if target.is_dir() and not target.is_symlink():
        return
    if os.path.lexists(target):
        raise OutputDirError(f"--out {out_dir}: folder {rel} of the earlier result is not a flexgear folder and "
                             "this run writes a file of that name; move it away and run again")
    with _os_errors(out_dir, f"cannot carry folder {rel} over from the earlier result"):
        target.mkdir(mode=0o777, parents=True)


def _link_or_copy(src: Path, dst: Path) -> None:
    try:
        os.link(src, dst, follow_symlinks=False)
    except OSError:  # no hard links here (file system, quota of links): copy
        if src.is_symlink():
            os.symlink(os.readlink(src), dst)
        else:
            shutil.copy2(src, dst)


def _move_into_place(work: Path, out_dir: Path) -> None:
    """``work`` becomes ``out_dir``; an earlier result goes aside (its user files carried over)
    and is deleted once the new result is in place."""
    with _signals_held():
        if _vacant(out_dir):  # a rename replaces a missing or empty folder atomically
            with _os_errors(out_dir, "cannot move the new result into place"):
                os.rename(work, out_dir)
            return
        ours = _manifest_files(out_dir)
        old = _free_name(out_dir, "old")
        with _os_errors(out_dir, f"cannot move the earlier result aside to {old.name}"):
            os.rename(out_dir, old)
        try:
            _carry_over(old, work, ours, out_dir)
            with _os_errors(out_dir, "cannot move the new result into place"):
                os.rename(work, out_dir)
        except BaseException:
            try:
                os.rename(old, out_dir)
            except OSError as exc:  # the next run restores it
                log.warning("cannot put the earlier result back from %s: %s", old, exc.strerror)
            raise
        try:  # a work-folder name: never mistaken for a restorable result, even half deleted
            os.rename(old, work)
            old = work
        except OSError:
            pass
    _remove(old)


# --------------------------------------------------------------------------------------
# Public entry points
# --------------------------------------------------------------------------------------

def _names(exc: OSError) -> list:
    return [n for n in (exc.filename, exc.filename2) if n is not None]


def _write_error(out_dir: Path, work: Path, exc: OSError, what: str) -> OutputDirError:
    """``--out DIR: writing <file in work, else what>: <strerror>``."""
    inside = [n for n in _names(exc) if _is_inside(n, work)]
    if inside:
        what = Path(os.fsdecode(inside[0])).absolute().relative_to(work).as_posix()
    return _fail(out_dir, f"writing {what}", exc)


@contextmanager
def writing(out_dir: Path, work: Path, what: str):
    """Around code that writes result files into ``work``: an OSError naming a file in
    ``work``, or no file (a full disk reported on flush), becomes an :class:`OutputDirError`
    ``--out DIR: writing <file or what>: <strerror>``; errors about other files pass."""
    try:
        yield
    except OSError as exc:
        names = _names(exc)
        if names and not any(_is_inside(n, Path(work)) for n in names):
            raise
        raise _write_error(Path(out_dir), Path(work), exc, what) from exc


@contextmanager
def hold_output(out_dir):
    """Check ``out_dir`` and hold its lock for the whole block -- the computation whose result
    will go there -- so that a foreign folder, a folder another run is writing or one this
    user cannot write is refused before anything is computed, not after. Inside the block,
    :func:`staged_output` of the same folder (in the same thread) works under this lock.
    Parent folders made for the lock are removed again when the block fails. Yields the
    absolute folder."""
    out_dir = Path(out_dir).absolute()
    held = _held_here()
    if out_dir in held:
        yield out_dir
        return
    check_output_dir(out_dir)  # before creating anything
    created = _make_parents(out_dir)
    try:
        with _locked(out_dir) as locked:
            if locked:
                _heal(out_dir)
            check_output_dir(out_dir)
            held.add(out_dir)
            try:
                yield out_dir
            finally:
                held.discard(out_dir)
    except BaseException:
        _remove_empty(created)
        raise


_HELD = threading.local()


def _held_here() -> set:
    """Output folders this thread holds (:func:`hold_output`)."""
    if not hasattr(_HELD, "folders"):
        _HELD.folders = set()
    return _HELD.folders


@contextmanager
def staged_output(out_dir: Path):
    """Yield a fresh work folder next to ``out_dir``; on success it replaces ``out_dir``
    (checked again just before), on any failure it is deleted: nothing half-written.
    Holds the folder's lock (:func:`hold_output`) unless the caller already does.
    See the module docstring for the rules."""
    with hold_output(out_dir) as out_dir:
        check_output_dir(out_dir)  # again: a user may have put files there during a long computation
        with _os_errors(out_dir, f"cannot create a work folder in {out_dir.parent}"):
            work = _new_dir(out_dir, "partial")
        try:
            yield work
            check_output_dir(out_dir)
            _move_into_place(work, out_dir)
        except BaseException as exc:
            _remove(work)
            if isinstance(exc, OSError) and any(_is_inside(n, work) for n in _names(exc)):
                raise _write_error(out_dir, work, exc, "results") from exc
            raise


def check_own_file(path, ours, what: str, out=None) -> None:
    """Raise :class:`OutputDirError` ``--out OUT: ...`` unless ``path`` may be (re)written:
    missing, or a regular file -- not a symbolic link -- that ``ours(path)`` recognises as
    flexgear's own earlier output (``what``: that kind of file, in words). ``out``: the
    ``--out`` value to name (default ``path``)."""
    path = Path(path)
    flag = f"--out {out if out is not None else path}"
    where = "" if out is None else f"{path}: "
    try:
        if path.is_symlink():
            raise OutputDirError(f"{flag}: {where}is a symbolic link (to {os.readlink(path)}); flexgear does not "
                                 "write through links: give the file itself")
        if not os.path.lexists(path):
            return
        if not path.is_file():
            raise OutputDirError(f"{flag}: {where}exists and is not a regular file")
        mine = ours(path)
    except OSError as exc:
        raise OutputDirError(f"{flag}: {where}cannot read it to check that flexgear wrote it: "
                             f"{exc.strerror or exc}") from exc
    if not mine:
        raise OutputDirError(f"{flag}: {where}exists and is not {what}; flexgear replaces only files it wrote: "
                             "choose another name or move the file away")


def write_manifest(folder: Path, manifest: dict) -> None:
    """Write the run manifest (JSON) that marks ``folder`` as a flexgear result."""
    (Path(folder) / MANIFEST).write_text(json.dumps(manifest, indent=1), encoding="utf-8")
