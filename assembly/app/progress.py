"""Progress bars for long pipeline steps (tqdm on stderr).

Bars are shown only when stderr is a terminal and the user did not ask for quiet output;
otherwise every call is a silent no-op, so library code can always use them.
"""
from __future__ import annotations

import contextlib
import logging
import sys
import time

log = logging.getLogger(__name__)


class Progress:
    """Factory of tqdm bars, one per step. ``enabled=None``: on when stderr is a TTY."""

    def __init__(self, enabled: bool | None = None, stream=None):
        self.stream = stream if stream is not None else sys.stderr
        if enabled is None:
            isatty = getattr(self.stream, "isatty", None)
            enabled = bool(isatty and isatty())
        self.enabled = bool(enabled)
        self.timings: dict = {}

    def bar(self, desc: str, total: int | None = None, unit: str = "it"):
        """A tqdm bar (disabled when progress is off). Use as a context manager."""
        from tqdm.auto import tqdm

        return tqdm(total=total, desc=desc, unit=unit, file=self.stream, disable=not self.enabled,
                    leave=True, dynamic_ncols=True)

    @contextlib.contextmanager
    def step(self, desc: str, total: int = 1, unit: str = "step"):
        """Context manager for one step: yields its bar; records the step's wall time (s)."""
        t0 = time.perf_counter()
        with self.bar(desc, total=total, unit=unit) as b:
            yield b
            if total == 1 and b.n == 0:
                b.update(1)
        dt = time.perf_counter() - t0
        self.timings[desc] = self.timings.get(desc, 0.0) + dt
        log.info("%s: %.2f s", desc, dt)
