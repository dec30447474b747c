"""``flexgear simulate --out DIR`` streams its history into the staged folder: a process killed
mid-run (SIGKILL) leaves ``.DIR.partial-*/partial_simulation.h5`` readable, marked incomplete,
with the steps written so far, and DIR as it was (docs/output.md)."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np

from assembly.dynamics.history import RUNNING
from tests.app.test_simulate_cli import pair_file

ROOT = Path(__file__).parents[2]
# 50-step blocks, a run of 1e7 steps that cannot end within the test
CHILD = ("import sys\nimport assembly.dynamics.history as h\nh.CHUNK_STEPS = 50\n"
         "from assembly.app.cli import main\nsys.exit(main(sys.argv[1:]))\n")


def test_a_killed_simulate_leaves_its_streamed_history_marked_incomplete(tmp_path):
    out = tmp_path / "res"
    scene = pair_file(tmp_path, sim='loads = [{ body = "rotor", value = 100.0 }]\ngenerator = { torque = 285.0 }')
    child = subprocess.Popen([sys.executable, "-c", CHILD, "simulate", scene, "--t-end", "1000", "--dt", "1e-4",
                              "--output", "force:m", "--out", str(out), "-q"], cwd=ROOT)
    try:
        deadline, steps = time.monotonic() + 120, -1
        while steps < 200 and time.monotonic() < deadline and child.poll() is None:
            time.sleep(0.2)
            for f in tmp_path.glob(".res.partial-*/partial_simulation.h5"):
                try:
                    with h5py.File(f, "r", locking=False) as h:
                        steps = int(h.attrs["steps"])
                except (OSError, KeyError):           # caught between its creation and a flush
                    pass
    finally:
        os.kill(child.pid, signal.SIGKILL)
        child.wait()
    assert steps >= 200, "the run wrote no blocks in 120 s"
    assert not out.exists()                              # DIR as it was: there was none
    (work,) = tmp_path.glob(".res.partial-*")
    with h5py.File(work / "partial_simulation.h5", "r") as h:
        assert not h.attrs["complete"] and h.attrs["stopped"] == RUNNING
        n = int(h.attrs["steps"]) + 1
        assert n >= steps + 1 and len(h["time_s"]) == len(h["outputs/force:m"]) == n
        np.testing.assert_array_equal(h["time_s"][:], np.arange(n) * 1e-4)
        assert np.all(np.isfinite(h["outputs/force:m"][:])) and h["outputs/force:m"].attrs["unit"] == "N"
