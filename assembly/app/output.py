"""Output folders: staged (written next to the target, moved into place on success, removed
on any failure) and marked with a run manifest, so a results folder is either a complete
flexgear result or untouched, and a foreign folder is never replaced.
"""
from __future__ import annotations

import json
import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

#: Manifest file that marks a folder as a flexgear result (JSON: tool, scene, files, timings).
MANIFEST = "flexgear_run.json"


class OutputDirError(RuntimeError):
    """The output folder cannot be (re)placed."""


def check_output_dir(out_dir: Path) -> None:
    """Raise :class:`OutputDirError` if ``out_dir`` exists and may not be replaced."""
    if not out_dir.exists() and not out_dir.is_symlink():
        return
    if not out_dir.is_dir() or out_dir.is_symlink():
        raise OutputDirError(f"--out {out_dir}: exists and is not a folder")
    if any(out_dir.iterdir()) and not (out_dir / MANIFEST).is_file():
        raise OutputDirError(f"--out {out_dir}: folder exists, is not empty and holds no earlier flexgear "
                             f"run ({MANIFEST}); choose a new or empty folder")


def _new_work_dir(out_dir: Path) -> Path:
    parent = out_dir.parent
    parent.mkdir(parents=True, exist_ok=True)
    return Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.partial-", dir=parent))


def _move_into_place(work: Path, out_dir: Path) -> None:
    old = None
    if out_dir.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.old-", dir=out_dir.parent))
        os.rename(out_dir, old / "previous")
    try:
        os.rename(work, out_dir)
    except OSError:
        if old is not None:  # put the previous result back
            os.rename(old / "previous", out_dir)
            shutil.rmtree(old, ignore_errors=True)
        raise
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


@contextmanager
def staged_output(out_dir: Path):
    """Yield a fresh work folder next to ``out_dir``; on success it replaces ``out_dir``
    (checked again just before), on any failure it is deleted: nothing half-written."""
    check_output_dir(out_dir)
    work = _new_work_dir(out_dir)
    try:
        yield work
        check_output_dir(out_dir)
        _move_into_place(work, out_dir)
    except BaseException:
        shutil.rmtree(work, ignore_errors=True)
        raise


def write_manifest(folder: Path, manifest: dict) -> None:
    """Write the run manifest (JSON) that marks ``folder`` as a flexgear result."""
    (Path(folder) / MANIFEST).write_text(json.dumps(manifest, indent=1))
