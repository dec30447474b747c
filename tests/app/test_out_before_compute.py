"""``simulate``, ``frf`` and ``campbell`` check ``--out`` and take its lock before they compute,
hold the lock through the computation and release it however the command ends (rules:
assembly/app/output.py, ``hold_output``).

* Refused before the solve: a foreign folder, a folder whose lock another run holds, a file
  at ``--out``; and, as an unprivileged user, a folder this user cannot write. Exit 2, one line
  naming --out, the computation never called. Measured with the real solver too: a
  simulation of 1e7 steps (minutes) is refused in about the time the program takes to start.
* Held and released: while the computation runs, ``.X.lock`` is locked (a second flock on it
  fails); after success, a user error, Ctrl-C, SIGTERM and a stopped run the lock file is
  gone and the folder can be locked again.

Scene: the two-gear torsional pair of tests/app/test_simulate_cli.py."""
from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import time

import pytest

import assembly.dynamics.campbell as campbell_mod
import assembly.dynamics.frf as frf_mod
import assembly.dynamics.simulate as sim_mod
from assembly.app.cli import main
from assembly.errors import SceneError
from tests.app.test_simulate_cli import pair_file
from tests.support.out_lock import HOLDER, held_elsewhere, is_locked, lock_path
from tests.support.tiny_runs import stop_after
from tests.support.unprivileged import run_unprivileged

# command -> (arguments after the scene, the module and name of the computation it calls)
COMMANDS = {
    "simulate": (["--t-end", "0.002", "--dt", "1e-4", "--output", "force:m"], sim_mod, "simulate"),
    "frf": (["--input", "torque:generator", "--output", "force:m", "--points", "5"], frf_mod, "frequency_response"),
    "campbell": (["--speed-range", "0", "100"], campbell_mod, "campbell"),
}
# 1e7 steps of the pair: ~12 000 steps/s here, so about 14 minutes; the history, 1e7 x 20 B,
# is well inside the memory budget, so only the output rules can refuse it early
LONG = ["--t-end", "100", "--dt", "1e-5", "--output", "force:m"]
STARTUP_S = 10.0           # an in-process refusal, scene loaded: well under a second here


def _argv(command: str, scene: str, out, args=None) -> list:
    return [command, scene, *(COMMANDS[command][0] if args is None else args), "--out", str(out), "-q"]


def _one_error_line(err: str, *words) -> None:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("flexgear: error: --out ") and all(w in lines[0] for w in words), err


@pytest.mark.parametrize("situation", ["foreign folder", "held lock", "a file"])
@pytest.mark.parametrize("command", list(COMMANDS))
def test_out_is_refused_before_the_computation(command, situation, tmp_path, capsys, monkeypatch):
    scene, out = pair_file(tmp_path), tmp_path / "out"
    called = []
    _, module, name = COMMANDS[command]
    monkeypatch.setattr(module, name, lambda *a, **k: called.append(name))
    if situation == "a file":
        out.write_bytes(b"the user's")
    elif situation == "foreign folder":
        out.mkdir()
        (out / "notes.txt").write_bytes(b"the user's")
    with held_elsewhere(out) if situation == "held lock" else contextlib.nullcontext():
        t0 = time.perf_counter()
        rc = main(_argv(command, scene, out))
        wall = time.perf_counter() - t0
    assert rc == 2 and not called and wall < STARTUP_S, (rc, called, wall)
    _one_error_line(capsys.readouterr().err, str(out), {"foreign folder": "holds no earlier flexgear run",
                                                        "held lock": f"another flexgear run ({HOLDER.decode()})",
                                                        "a file": "is not a folder"}[situation])
    if situation == "a file":
        assert out.read_bytes() == b"the user's"
    elif situation == "foreign folder":
        assert os.listdir(out) == ["notes.txt"] and (out / "notes.txt").read_bytes() == b"the user's"
    else:
        assert not os.path.lexists(out)


@pytest.mark.parametrize("situation", ["foreign folder", "held lock"])
def test_a_long_simulation_is_refused_in_startup_time(situation, tmp_path, capsys):
    # the real solver: today's refusal came after the whole integration (1e7 steps)
    scene, out = pair_file(tmp_path), tmp_path / "out"
    if situation == "foreign folder":
        out.mkdir()
        (out / "notes.txt").write_text("mine")
    with held_elsewhere(out) if situation == "held lock" else contextlib.nullcontext(), _alarm(60):
        t0 = time.perf_counter()
        assert main(_argv("simulate", scene, out, LONG)) == 2
        wall = time.perf_counter() - t0
    assert wall < STARTUP_S, wall
    _one_error_line(capsys.readouterr().err, str(out))


@contextlib.contextmanager
def _alarm(seconds: float):
    """Fail (TimeoutError) instead of waiting when the block runs longer than ``seconds``."""
    def expired(signum, frame):
        raise TimeoutError(f"still running after {seconds} s: the refusal did not come before the computation")
    before = signal.signal(signal.SIGALRM, expired)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, before)


def test_a_folder_this_user_cannot_write_is_refused_before_the_simulation(tmp_path):
    # a real permission error (file modes bind the child, also as root): the parent is read-only
    scene, parent = pair_file(tmp_path), tmp_path / "ro"
    parent.mkdir()
    out = parent / "out"
    parent.chmod(0o555)
    try:
        t0 = time.perf_counter()
        r = run_unprivileged(["simulate", scene, *LONG, "--out", str(out), "-q"], timeout=120)
        wall = time.perf_counter() - t0
    except subprocess.TimeoutExpired:
        pytest.fail("the simulation ran: --out was not checked before it")
    except subprocess.SubprocessError as exc:  # e.g. a container without CAP_SETPCAP
        pytest.skip(f"cannot drop root's file-mode capabilities here: {exc}")
    finally:
        parent.chmod(0o755)
    assert r.returncode == 2, r.stderr
    _one_error_line(r.stderr, str(out), os.strerror(13))
    assert wall < 6 * STARTUP_S and os.listdir(parent) == []


def _ends(how: str, command: str, real, out):
    """A computation that checks the lock is held, then ends ``how``."""
    def computation(*args, **kwargs):
        assert is_locked(out), "--out is not locked while the computation runs"
        if how == "success":
            return real(*args, **kwargs)
        if how == "user error":
            raise SceneError("simulation.speed", -1.0, "a user error found while computing")
        if how == "Ctrl-C":
            raise KeyboardInterrupt
        if how == "SIGTERM":
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(5)                         # the CLI's handler raises at once
            raise AssertionError("SIGTERM did not end the command")
        with pytest.MonkeyPatch.context() as mp:  # a run that stops: the real one, after 5 steps
            mp.setattr(sim_mod, "integrate", stop_after(5))
            return real(*args, **kwargs)
    return computation


ENDINGS = {"success": 0, "user error": 2, "Ctrl-C": 130, "SIGTERM": 143, "stopped": 1}


@pytest.mark.parametrize("how", list(ENDINGS))
@pytest.mark.parametrize("command", list(COMMANDS))
def test_the_lock_is_held_through_the_computation_and_released_however_it_ends(command, how, tmp_path, capsys,
                                                                              monkeypatch):
    if how == "stopped" and command != "simulate":
        pytest.skip("only a simulation stops")
    scene, out = pair_file(tmp_path), tmp_path / "a" / "out"           # parents made for the lock
    _, module, name = COMMANDS[command]
    monkeypatch.setattr(module, name, _ends(how, command, getattr(module, name), out))
    assert main(_argv(command, scene, out)) == ENDINGS[how]
    written = how in ("success", "stopped")
    assert out.is_dir() == written
    assert os.path.isdir(tmp_path / "a") == written   # a parent made for a failed run is removed again
    assert not os.path.lexists(lock_path(out))
    if written:                                   # free again: another run may lock the folder
        with held_elsewhere(out):
            pass
    capsys.readouterr()
