"""Histories that stream (:mod:`assembly.dynamics.history`): the rows a run hands over block by
block, in memory, to an HDF5 file or to statistics only, give the same numbers as the whole
history; a run that stops, or a process killed mid-run, leaves a readable file marked
incomplete with every step flushed; memory does not grow with the run's length.

Models: the torsional gear pair of test_simulate.py (backlash, mesh stiffness variation: a
nonlinear run) and a unit oscillator x'' + (2 pi)^2 x = 0 (the integrator alone)."""
from __future__ import annotations

import gc
import math
import os
import signal
import subprocess
import sys
import textwrap
import tracemalloc
from pathlib import Path

import h5py
import numpy as np
import pytest

import assembly.dynamics.history as history
from assembly.dynamics.budget import memory_budget
from assembly.dynamics.history import RUNNING, H5History, MemoryHistory, Statistics, read_blocks
from assembly.dynamics.simulate import simulate
from assembly.dynamics.transient import Diverged, Nonlinear, check_history, integrate
from assembly.errors import SceneError
from assembly.scene.schema import scene_from_dict
from tests.dynamics.test_simulate import pair

EPS = float(np.finfo(float).eps)
OUTPUTS = ["force:m", "speed:rotor", "speed:generator"]
ROOT = Path(__file__).parents[2]


def rattling_pair():
    # rotor torque against a generator torque 5 % short of balance, backlash and a 20 % mesh
    # stiffness ripple: contact losses and Newton's iterations vary from step to step
    return scene_from_dict(pair({"speed": 10.0, "loads": [{"body": "rotor", "value": 100.0}],
                                 "generator": {"torque": 285.0}},
                                {"backlash": 1.0e-4, "variation": {"amplitudes": [0.2], "teeth": 20}}))


class Blowup(Nonlinear):
    """nu = -x^3 on a unit mass: x'' = x^3."""

    def __init__(self):
        self.U = np.ones((1, 1))

    def forces(self, t, x, xd):
        return -x ** 3, -3 * x ** 2, np.zeros(1)


@pytest.fixture
def small_chunks(monkeypatch):
    # HDF5 chunks of 7 steps: a 0.01 s run at 1e-4 s (101 rows) fills 15, the last one short
    monkeypatch.setattr(history, "CHUNK_STEPS", 7)


def test_streamed_history_is_bit_identical_to_the_one_in_memory(tmp_path, small_chunks):
    scene = rattling_pair()
    whole = simulate(scene, 0.01, 1e-4, OUTPUTS)
    streamed = simulate(scene, 0.01, 1e-4, OUTPUTS, history=tmp_path / "h.h5")
    assert streamed.outputs == {} and streamed.history_file == str(tmp_path / "h.h5")
    with h5py.File(tmp_path / "h.h5", "r") as f:
        assert f.attrs["complete"] and "stopped" not in f.attrs and f.attrs["steps"] == 100
        assert np.array_equal(f["time_s"][:], whole.time_s)
        for name in OUTPUTS:
            assert np.array_equal(f[f"outputs/{name}"][:], whole.outputs[name]), name
            assert f[f"outputs/{name}"].attrs["unit"] == whole.units[name]
    # read back in blocks of another length: the same rows in order
    t = np.concatenate([b[0] for b in read_blocks(tmp_path / "h.h5", "force:m", block=13)])
    assert np.array_equal(t, whole.time_s)


def test_integrate_buffers_give_the_preallocated_rows(small_chunks):
    # the buffer flushed every 7 steps into a history grown by blocks, and into one allocated
    # whole: the same bits, the same Newton counts
    scene_free = (np.eye(2), np.diag([0.1, 0.2]), np.array([[2.0, -1.0], [-1.0, 2.0]]))
    args = (*scene_free, lambda t: np.array([math.sin(3 * t), 0.0]), [0.1, 0.0], [0.0, 0.3], 1e-2, 1.0)
    a = integrate(*args)
    grown = MemoryHistory()
    b = integrate(*args, history=grown)
    assert b.history is grown and np.array_equal(b.y, a.y)
    assert np.array_equal(grown.time_s, a.time_s) and np.array_equal(grown.y, a.y)
    assert np.array_equal(grown.iterations, a.iterations)
    np.testing.assert_array_equal(a.time_s, np.arange(101) * 1e-2)   # the times: np.arange * dt


def test_statistics_on_the_fly_equal_those_of_the_whole_history(small_chunks):
    scene = rattling_pair()
    whole = simulate(scene, 0.01, 1e-4, OUTPUTS)
    flat = simulate(scene, 0.01, 1e-4, OUTPUTS, arrays=False)
    assert flat.outputs == {} and flat.history_file is None and flat.steps == 100
    for name, y in whole.outputs.items():
        s = flat.statistics[name]
        n = len(y)
        # min, max, peak and its (first) time are exact; a sum of n terms in any order is within
        # (n - 1) eps sum|y| of another (Higham, Accuracy and Stability, 2nd ed., eq. 4.4)
        assert (s["min"], s["max"]) == (float(y.min()), float(y.max()))
        k = int(np.argmax(np.abs(y)))
        assert (s["peak"], s["peak_time_s"]) == (float(abs(y[k])), float(whole.time_s[k]))
        assert abs(s["mean"] - np.mean(y)) <= n * EPS * np.mean(np.abs(y))
        assert abs(s["rms"] ** 2 - np.mean(y * y)) <= n * EPS * np.mean(y * y)
        assert s["unit"] == whole.units[name]


def test_a_run_that_stops_leaves_its_file_marked_incomplete_with_the_steps_so_far(tmp_path, small_chunks):
    # x'' = x^3 blows up at t = sqrt(2) s (test_simulate.py): the run stops there
    split = (lambda y: ({"x": y[:, 0]}, {"x": "m"}))
    args = (np.eye(1), None, np.zeros((1, 1)), lambda t: np.zeros(1), [1.0], [1 / math.sqrt(2)], 1e-3, 3.0)
    with pytest.raises(Diverged) as mem:
        integrate(*args, nonlinear=Blowup(), dof_names=["x"])
    with pytest.raises(Diverged) as streamed:
        integrate(*args, nonlinear=Blowup(), dof_names=["x"], history=H5History(tmp_path / "x.h5", split))
    p = mem.value.partial
    assert streamed.value.partial.info["steps"] == len(p.time_s) - 1 == p.info["steps"]
    with h5py.File(tmp_path / "x.h5", "r") as f:
        assert not f.attrs["complete"] and f.attrs["stopped"] == str(mem.value)
        assert f.attrs["steps"] == len(p.time_s) - 1
        assert np.array_equal(f["time_s"][:], p.time_s) and np.array_equal(f["outputs/x"][:], p.y[:, 0])


KILLED = """
import sys, time
import numpy as np
import assembly.dynamics.history as history
from assembly.dynamics.transient import integrate
history.CHUNK_STEPS = 500
h = history.H5History(sys.argv[1], lambda y: ({"x": y[:, 0]}, {"x": "m"}), chunk=500)
blocks = []
def append(t, y, its):
    h.append(t, y, its)
    blocks.append(len(t))
    if len(blocks) == 3:
        print(h.n, sum(blocks), flush=True)  # three blocks flushed: the parent may kill now
    if len(blocks) >= 3:
        time.sleep(0.001)
w = 2 * np.pi
integrate(np.eye(1), None, np.array([[w * w]]), lambda t: np.zeros(1), [1.0], [0.0], 1e-3, 1e6,
          history=type("H", (), {"append": staticmethod(append), "close": staticmethod(h.close)})())
"""


def test_a_killed_process_leaves_a_readable_file_marked_incomplete(tmp_path):
    # a run of 1e9 steps, killed (SIGKILL) once it has flushed three blocks: the file opens,
    # says it is incomplete, and holds at least those steps, the same rows an uninterrupted run
    # computes to there (the run is deterministic)
    path = tmp_path / "killed.h5"
    child = subprocess.Popen([sys.executable, "-c", textwrap.dedent(KILLED), str(path)], cwd=ROOT,
                             stdout=subprocess.PIPE, text=True)
    try:
        flushed, handed = map(int, child.stdout.readline().split())
        assert flushed == handed > 2           # the first row, then two stretches of steps
    finally:
        os.kill(child.pid, signal.SIGKILL)
        child.wait()
    assert child.returncode == -signal.SIGKILL
    with h5py.File(path, "r") as f:
        assert not f.attrs["complete"] and f.attrs["stopped"] == RUNNING
        t, x = f["time_s"][:], f["outputs/x"][:]
        assert len(t) == len(x) == f.attrs["steps"] + 1 >= flushed
    w = 2 * np.pi
    ref = integrate(np.eye(1), None, np.array([[w * w]]), lambda t: np.zeros(1), [1.0], [0.0], 1e-3,
                    (len(t) - 1) * 1e-3)
    assert np.array_equal(t, ref.time_s) and np.array_equal(x, ref.y[:, 0])


def _fill_tuple_free_lists() -> None:
    # CPython keeps up to 2000 freed tuples of each length 1-19 for reuse (PyTuple_MAXFREELIST,
    # Objects/tupleobject.c, 3.11), and tracemalloc counts a tuple from its allocation until its
    # memory goes back to the allocator: a tuple allocated while tracing, because the list was
    # empty, stays counted once freed into the list. A streamed file run frees some 1.3 small
    # tuples per block into the list (h5py's selection shapes: 20 kB over 4000 steps in
    # 8-step blocks), so with the lists empty the measure grew with t_end by list filling,
    # not by what the run keeps. In a process that has run for a while (the whole suite) the
    # lists are full; here they are filled the same way before each measure: 2000 tuples of
    # each short length made and freed (a full collection empties the lists: the test makes one
    # before it starts measuring, so that none is pending during the measured runs).
    held = [tuple(range(n)) for n in (1, 2, 3, 4) for _ in range(2000)]
    del held


def _peak_bytes(run) -> int:
    _fill_tuple_free_lists()
    tracemalloc.start()
    try:
        run()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_memory_is_flat_in_t_end_when_streaming(tmp_path, monkeypatch):
    # 8-step HDF5 chunks; 1000 and 4000 steps of a damped 2-DOF chain recording 3 values a step.
    # Kept in memory, the long run ends holding its 4001 rows of 3 values + time + count (8, 8,
    # 4 B); streamed (to a file, or to statistics alone) the integrator's buffer is its longest
    # stretch whatever t_end.
    # (h5py keeps a bounded cache of selections, full after about 80 blocks: both runs fill it)
    monkeypatch.setattr(history, "CHUNK_STEPS", 8)
    split = (lambda y: ({"a": y[:, 0], "b": y[:, 1], "c": y[:, 2]}, {"a": "m", "b": "m", "c": "m/s"}))
    chain = (np.eye(2), np.diag([0.1, 0.2]), np.array([[2.0, -1.0], [-1.0, 2.0]]),
             lambda t: np.array([math.sin(3 * t), 0.0]), [0.1, 0.0], [0.0, 0.3], 1e-3)

    def run(t_end, h=None):
        integrate(*chain, t_end, observe=lambda q, v, a, nu: np.concatenate([q, v[:1]]), history=h)

    gc.collect()                                                # see _fill_tuple_free_lists
    run(0.01, H5History(tmp_path / "warm.h5", split))          # warm imports and caches
    short, long_ = 1.0, 4.0
    rows = 4001 * (3 * 8 + 12)
    kept = _peak_bytes(lambda: run(long_))
    flat = [_peak_bytes(lambda t=t: run(t, Statistics(split))) for t in (short, long_)]
    files = [_peak_bytes(lambda t=t: run(t, H5History(tmp_path / f"{t}.h5", split))) for t in (short, long_)]
    assert kept - flat[1] >= 0.9 * rows, (kept, flat)           # the measure sees a kept history
    growth = 3000 * (3 * 8 + 12)                                # what 3000 more kept rows would take
    # not growing with t_end (the caches of h5py come and go by some 20 kB either way)
    assert flat[1] - flat[0] < growth / 10, flat
    assert files[1] - files[0] < growth / 10, files


def test_the_budget_counts_the_buffer_when_streaming():
    # a history of 10 values a step over the whole budget: refused kept in memory, accepted
    # streamed (its buffer is the longest stretch)
    rows, dt = 10, 1e-6
    steps = int(2 * memory_budget() / (8 * rows + history.STEP_BYTES))
    with pytest.raises(SceneError, match="t_end"):
        check_history(dt, steps * dt, rows)
    assert check_history(dt, steps * dt, rows, streaming=True) == pytest.approx(steps, abs=1)


def test_statistics_of_blocks_equal_those_of_the_whole():
    # a sampled sine plus an offset, its peak in the middle of a block: statistics of any cut
    t = np.arange(1000) * 1e-3
    y = 2.0 + 3.0 * np.sin(2 * np.pi * 7 * t) + np.where(np.arange(1000) == 517, 10.0, 0.0)
    whole = Statistics(None)
    whole.add(t, {"y": y})
    cut = Statistics(None)
    for a, b in ((0, 1), (1, 300), (300, 517), (517, 999), (999, 1000)):
        cut.add(t[a:b], {"y": y[a:b]})
    w, c = whole.result()["y"], cut.result()["y"]
    assert c["peak_time_s"] == t[517] == w["peak_time_s"] and c["peak"] == w["peak"] == float(np.max(np.abs(y)))
    assert (c["min"], c["max"]) == (float(y.min()), float(y.max()))
    assert abs(c["mean"] - np.mean(y)) <= 1000 * EPS * np.mean(np.abs(y))
    assert abs(c["rms"] - np.sqrt(np.mean(y * y))) <= 1000 * EPS * np.sqrt(np.mean(y * y))


RSS_CHILD = """
import numpy as np
import assembly.dynamics.history as history
from assembly.dynamics.transient import integrate
history.CHUNK_STEPS = 4000

def rss():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096

R = np.linspace(0.5, 1.5, 100)[:, None] * np.ones((1, 2))
h = history.H5History(__import__("sys").argv[1], lambda y: ({f"y{j}": y[:, j] for j in range(y.shape[1])},
                                                            {f"y{j}": "m" for j in range(y.shape[1])}), chunk=4000)
seen = []
def append(t, y, its):
    h.append(t, y, its)
    seen.append(rss())
w = 2 * np.pi
integrate(np.eye(2), None, np.diag([w * w, 4 * w * w]), lambda t: np.zeros(2), [1.0, 0.5], [0.0, 0.0], 1e-3, 120.0,
          observe=lambda q, v, a, nu: R @ q,
          history=type("H", (), {"append": staticmethod(append), "close": staticmethod(h.close)})())
print(seen[5], seen[-1])
"""


def test_resident_memory_is_flat_while_a_file_history_grows(tmp_path):
    # what tracemalloc cannot see (HDF5's own buffers, e.g. a chunk cache keeping what was
    # written): 100 outputs in 4000-step blocks, 30 blocks of 3.2 MB; the process's resident
    # memory after block 6 and after the last differ by less than a tenth of the 80 MB written
    # in between (HDF5 keeps some 360 B per chunk written: 1 % of these 32 kB chunks)
    r = subprocess.run([sys.executable, "-c", RSS_CHILD, str(tmp_path / "h.h5")], cwd=ROOT, capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    early, late = map(int, r.stdout.split())
    written = 25 * 100 * 4000 * 8
    assert late - early < written / 10, (early, late)
