"""Where a time-domain run's history goes, as the run goes: the integrator hands over blocks of
consecutive steps, in order (``append(t, y, iterations)``: times (k,) in s, recorded rows
(k, n_obs), Newton iterations (k,)) and ends with ``close(complete, info)`` (``complete``
False for a run that stopped; ``info['stopped']`` the reason). A block is the integrator's own
buffer, reused for the next one: a history copies what it keeps.

* :class:`MemoryHistory`: the rows in memory (what the Python API returns as arrays);
* :class:`H5History`: the outputs in an HDF5 file, written and flushed block by block, so
  that memory stays flat in the run's length and a run that is killed or stops leaves a
  readable file with every step flushed so far, marked incomplete (layout in docs/output.md);
* :class:`Statistics`: per output its mean, RMS, min, max and peak |value| with its time,
  accumulated block by block (never the whole history);
* :class:`Tee`: several of them at once;
* :class:`Gathered`: any of them fed through a buffer that gathers the blocks of consecutive
  stretches into one (a stretch of one step -- a controller sampled every step -- would
  otherwise cost a file write and flush a step).

``split(y) -> ({name: (k,) history}, {name: unit})`` turns recorded rows into outputs
(:meth:`assembly.dynamics.run_outputs.Recorder.histories`, row by row, so it applies to a
block as to the whole).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

#: The HDF5 chunk length of a streamed history (fewer steps when the rows are many:
#: :data:`BUFFER_BYTES`), and the block :func:`read_blocks` reads back.
CHUNK_STEPS = 8192
#: Bytes a chunk of a streamed history may take.
BUFFER_BYTES = 16 * 2 ** 20
#: Bytes a recorded step takes besides its values: its time (float64) and Newton count (int32).
STEP_BYTES = 12
#: HDF5 file format of a streamed history: the earliest, whose file a run killed mid-run leaves
#: readable by any HDF5 reader ("latest" marks the file open for writing until it is closed, and
#: such a file opens only after ``h5clear``); it keeps some 360 B of memory per chunk written.
LIBVER = "earliest"
#: The file attribute a streamed history carries until it is closed.
RUNNING = "the run did not finish: it was killed, or is still running"


def put_rows(into: tuple, n: int, t: np.ndarray, y: np.ndarray, iterations: np.ndarray) -> None:
    """Times, rows and Newton counts into the arrays ``into`` (times, rows, counts) from row
    ``n`` on; rows or counts already written there in place (a ``reserve``'s views) are not
    copied onto themselves."""
    t_in, y_in, its_in = into
    k = len(t)
    t_in[n:n + k] = t
    if not np.may_share_memory(y, y_in):
        y_in[n:n + k] = y
    if not np.may_share_memory(iterations, its_in):
        its_in[n:n + k] = iterations


def chunk_steps(rows: int) -> int:
    """Steps of ``rows`` recorded values in a chunk of a streamed history."""
    return max(1, min(CHUNK_STEPS, BUFFER_BYTES // (8 * rows + STEP_BYTES)))


class MemoryHistory:
    """The rows in memory: ``time_s`` (n_t,), ``y`` (n_t, n_obs), ``iterations`` (n_t,)
    after :meth:`close`. ``capacity``: the number of steps to expect (the arrays are allocated
    once at the first block; more steps than that raise ValueError), None: grown by blocks."""

    def __init__(self, capacity: int | None = None):
        self.capacity = capacity
        self.n = 0
        self._t = self._y = self._its = None
        self._blocks = []
        self.complete, self.info = False, {}

    def reserve(self, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(times, rows, Newton counts): views of this history's next ``k`` rows, for the
        integrator to write its steps into before it appends them (no second copy of a block;
        the rows' width is known once a first block has been appended)."""
        a, b = self.n, self.n + k
        return self._t[a:b], self._y[a:b], self._its[a:b]

    def _allocate(self, rows: int) -> None:
        if self._y is None:
            self._t = np.empty(self.capacity)
            self._y = np.empty((self.capacity, rows))
            self._its = np.zeros(self.capacity, np.int32)

    def append(self, t: np.ndarray, y: np.ndarray, iterations: np.ndarray) -> None:
        k = len(t)
        if self.capacity is None:
            self._blocks.append((np.array(t, float), np.array(y, float), np.array(iterations, np.int32)))
        else:
            self._allocate(y.shape[1])
            if self.n + k > self.capacity:
                raise ValueError(f"{self.n + k} steps appended to a history of capacity {self.capacity}")
            put_rows((self._t, self._y, self._its), self.n, t, y, iterations)
        self.n += k

    def close(self, complete: bool, info: dict) -> None:
        self.complete, self.info = bool(complete), dict(info)
        if self.capacity is None and self._blocks:
            self._t, self._y, self._its = (np.concatenate(b) for b in zip(*self._blocks))
            self._blocks = []

    @property
    def time_s(self) -> np.ndarray:
        return self._t[:self.n] if self._t is not None else np.zeros(0)

    @property
    def y(self) -> np.ndarray:
        return self._y[:self.n] if self._y is not None else np.zeros((0, 0))

    @property
    def iterations(self) -> np.ndarray:
        return self._its[:self.n] if self._its is not None else np.zeros(0, np.int32)


def neumaier(acc: tuple, x: float) -> tuple:
    """``(sum, compensation)`` with ``x`` added (Neumaier's improved Kahan summation; Higham,
    Accuracy and Stability of Numerical Algorithms, 2nd ed., sec. 4.3): ``sum + compensation``
    is the total to about eps of it, whatever the number of terms."""
    s, c = acc
    t = s + x
    c += (s - t) + x if abs(s) >= abs(x) else (x - t) + s
    return t, c


class Statistics:
    """Per output (``split``: module notes) ``mean``, ``rms``, ``min``, ``max``, ``peak``
    (largest |value|) and ``peak_time_s`` (its first time), accumulated block by block:
    min, max and peak exact, the sums of the mean and RMS by numpy's pairwise sums per block
    added across blocks with Neumaier's compensation (:func:`neumaier`), so they equal the
    whole history's to round-off in memory that does not grow with the run. :meth:`result`
    gives them, ``units`` the outputs' units."""

    def __init__(self, split):
        self.split = split
        self.n = 0
        self.units: dict = {}
        self._acc: dict = {}
        self.complete, self.info = False, {}

    def append(self, t: np.ndarray, y: np.ndarray, iterations=None) -> None:
        values, units = self.split(y)
        self.add(t, values, units)

    def add(self, t: np.ndarray, values: dict, units: dict | None = None) -> None:
        """Account one block of outputs ``values`` {name: (k,)} at times ``t`` (k,)."""
        if not len(t):
            return
        for name, v in values.items():
            v = np.asarray(v, float)
            a = self._acc.setdefault(name, {"sum": (0.0, 0.0), "sq": (0.0, 0.0), "min": math.inf,
                                            "max": -math.inf, "peak": -1.0, "peak_time_s": math.nan})
            a["sum"] = neumaier(a["sum"], float(np.sum(v)))
            a["sq"] = neumaier(a["sq"], float(np.sum(v * v)))
            a["min"], a["max"] = min(a["min"], float(np.min(v))), max(a["max"], float(np.max(v)))
            mag = np.abs(v)
            k = int(np.argmax(mag))
            if mag[k] > a["peak"] or math.isnan(mag[k]):
                a["peak"], a["peak_time_s"] = float(mag[k]), float(t[k])
        self.units.update(units or {})
        self.n += len(t)

    def close(self, complete: bool, info: dict) -> None:
        self.complete, self.info = bool(complete), dict(info)

    def result(self) -> dict:
        """{name: {"unit", "mean", "rms", "min", "max", "peak", "peak_time_s"}} so far ({}
        before the first block)."""
        out = {}
        if not self.n:
            return out
        for name, a in self._acc.items():
            out[name] = {"unit": self.units.get(name, ""), "mean": sum(a["sum"]) / self.n,
                         "rms": math.sqrt(sum(a["sq"]) / self.n), "min": a["min"], "max": a["max"],
                         "peak": a["peak"], "peak_time_s": a["peak_time_s"]}
        return out


class H5History:
    """The outputs streamed to the HDF5 file ``path`` (which must not exist): ``/time_s`` (s)
    and ``/outputs/NAME`` (attribute ``unit``; a ``/`` in NAME is written ``|``), chunked and
    resizable, grown and flushed at every block; file attributes ``complete`` (False until
    :meth:`close` says otherwise), ``stopped`` (why it is incomplete: :data:`RUNNING` while
    the run goes) and ``steps`` (steps flushed, the first row being the start, step 0),
    plus ``attrs``. ``split``: module notes."""

    def __init__(self, path, split, attrs: dict | None = None, chunk: int = CHUNK_STEPS):
        import h5py
        self.path = Path(path)
        self.split, self.chunk = split, max(1, int(chunk))
        # never over a file that is there; no chunk cache (it kept up to 1 MB of written chunks per
        # dataset): every block is written whole, once
        self._f = h5py.File(self.path, "w-", rdcc_nbytes=0, libver=LIBVER)
        self._f.attrs["complete"] = False
        self._f.attrs["stopped"] = RUNNING
        self._f.attrs["steps"] = -1
        for k, v in (attrs or {}).items():
            self._f.attrs[k] = v
        self._time = self._grown("time_s", "s")
        self._f.create_group("outputs")
        self._out: dict = {}
        self.n = 0
        self.complete, self.info = False, {}
        self._f.flush()

    def _grown(self, name: str, unit: str):
        d = self._f.create_dataset(name, shape=(0,), maxshape=(None,), chunks=(self.chunk,), dtype="f8")
        d.attrs["unit"] = unit
        return d

    def append(self, t: np.ndarray, y: np.ndarray, iterations=None) -> None:
        k = len(t)
        if not k:
            return
        values, units = self.split(y)
        if not self._out:
            self._out = {name: self._grown(f"outputs/{name.replace('/', '|')}", units[name]) for name in values}
        for d, v in ((self._time, t), *((self._out[name], values[name]) for name in self._out)):
            d.resize((self.n + k,))
            d[self.n:] = v
        self.n += k
        self._f.attrs["steps"] = self.n - 1
        self._f.flush()

    def close(self, complete: bool, info: dict) -> None:
        self.complete, self.info = bool(complete), dict(info)
        if not self._f:
            return
        self._f.attrs["complete"] = bool(complete)
        if complete:
            del self._f.attrs["stopped"]
        else:
            self._f.attrs["stopped"] = str(info.get("stopped", RUNNING))
        self._f.close()


class Tee:
    """Several histories fed the same blocks, closed together."""

    def __init__(self, *histories):
        self.histories = histories

    def append(self, t, y, iterations) -> None:
        for h in self.histories:
            h.append(t, y, iterations)

    def close(self, complete: bool, info: dict) -> None:
        for h in self.histories:
            h.close(complete, info)


class Gathered:
    """``history`` fed through a buffer of ``steps`` rows of ``rows`` values: the integrator
    writes its steps into :meth:`reserve`'s views and appends them (:meth:`append`, as to
    :meth:`MemoryHistory.reserve`'s); the buffer goes to
    ``history`` as one block when the next reservation would not fit, at :meth:`flush` and at
    :meth:`close`."""

    def __init__(self, history, steps: int, rows: int):
        self.history = history
        self.t, self.y, self.its = np.empty(steps), np.empty((steps, rows)), np.zeros(steps, np.int32)
        self.n = 0

    def reserve(self, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(times, rows, Newton counts): views of the buffer's next ``k`` rows (at most its
        length; the buffer handed over first if they do not fit)."""
        if self.n + k > len(self.t):
            self.flush()
        a, b = self.n, self.n + k
        return self.t[a:b], self.y[a:b], self.its[a:b]

    def append(self, t: np.ndarray, y: np.ndarray, iterations: np.ndarray) -> None:
        """The first ``len(t)`` rows of the last reservation, at times ``t``, done."""
        put_rows((self.t, self.y, self.its), self.n, t, y, iterations)
        self.n += len(t)

    def flush(self) -> None:
        """Hand the gathered rows to the history as one block."""
        if self.n:
            self.history.append(self.t[:self.n], self.y[:self.n], self.its[:self.n])
            self.n = 0

    def close(self, complete: bool, info: dict) -> None:
        self.flush()
        self.history.close(complete, info)


def span(time_s, t0: float, t1: float) -> slice:
    """The rows of a record (``time_s`` increasing) from ``t0`` to ``t1`` inclusive, as a slice:
    its histories cut to it are views, not copies."""
    t = np.asarray(time_s)
    return slice(int(np.searchsorted(t, t0, "left")), int(np.searchsorted(t, t1, "right")))


def read_blocks(path, name: str, block: int = CHUNK_STEPS):
    """(t, y) blocks of output ``name`` of an HDF5 history (:class:`H5History`'s layout), in
    order, ``block`` steps at a time: the whole history never in memory."""
    import h5py
    with h5py.File(path, "r") as f:
        t, d = f["time_s"], f[f"outputs/{name.replace('/', '|')}"]
        n = min(len(t), len(d))
        for a in range(0, n, block):
            yield t[a:a + block], d[a:a + block]
