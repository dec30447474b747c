"""Where a time-domain run puts its rows as it goes: a history takes blocks of steps,
``append(t_block, y_block, iterations_block)``, and is told the end, ``close(complete,
info)``, which gives back ``(time_s, y, iterations)`` arrays (what the run returns).
:class:`MemoryHistory` keeps every row in memory (a streaming history writes the blocks to a
file instead, with the same two calls).
"""
from __future__ import annotations

import numpy as np


class MemoryHistory:
    """Every row in memory, in arrays of ``rows_max`` rows of ``width`` values allocated once
    (the rows a run can record: its steps + 1); :meth:`close` gives the filled part."""

    def __init__(self, rows_max: int, width: int):
        self.t = np.empty(rows_max)
        self.y = np.empty((rows_max, width))
        self.iterations = np.zeros(rows_max, np.int32)
        self.rows = 0
        self.complete, self.info = None, {}

    def reserve(self, k: int):
        """(times, rows, Newton counts): views of the next ``k`` rows, for a run to write its
        steps into before it appends them (no second copy of a block)."""
        a, b = self.rows, self.rows + k
        return self.t[a:b], self.y[a:b], self.iterations[a:b]

    def append(self, t_block: np.ndarray, y_block: np.ndarray, iterations_block: np.ndarray) -> None:
        """A block of consecutive steps: times (k,), rows (k, width), Newton counts (k,)."""
        a, b = self.rows, self.rows + len(t_block)
        if np.asarray(y_block).ctypes.data != self.y[a:b].ctypes.data:   # not the reserved rows
            self.y[a:b] = y_block
        self.t[a:b], self.iterations[a:b] = t_block, iterations_block
        self.rows = b

    def close(self, complete: bool, info: dict):
        """(time_s, y, iterations) of the rows appended, in order; ``complete`` False: a run
        that stopped (``info['stopped']`` says why)."""
        self.complete, self.info = complete, dict(info)
        k = self.rows
        return self.t[:k], self.y[:k], self.iterations[:k]
