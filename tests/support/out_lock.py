"""The lock of an output folder ``P/X`` (``P/.X.lock``, assembly/app/output.py) seen from a test:
held as another flexgear process holds it (``flock`` on its own open file: the kernel treats
it as another holder even within this process), and whether someone holds it."""
from __future__ import annotations

import contextlib
import fcntl
import os
from pathlib import Path

HOLDER = b"pid 4242 on elsewhere"       # what a holder writes into the lock file


def lock_path(out) -> Path:
    out = Path(out)
    return out.parent / f".{out.name}.lock"


@contextlib.contextmanager
def held_elsewhere(out):
    """Hold the lock of ``out`` for the block, as another run would; the file is removed after."""
    fd = os.open(lock_path(out), os.O_RDWR | os.O_CREAT, 0o666)
    os.write(fd, HOLDER)
    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    try:
        yield
    finally:
        os.close(fd)
        os.unlink(lock_path(out))


def is_locked(out) -> bool:
    """Whether someone holds the lock of ``out`` (its file must exist)."""
    fd = os.open(lock_path(out), os.O_RDWR)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        return False
    except BlockingIOError:
        return True
    finally:
        os.close(fd)
