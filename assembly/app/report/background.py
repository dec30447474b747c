"""Work of a later step started early in a thread of its own: the stresses and VTU files of
the drawn modes are computed while the mode-shape images are drawn (VTK lets go of the GIL
while it renders, numpy and the sparse solvers while they compute), and collected by the
step that reports them, in its own order.

A job runs its items one after the other; :meth:`Background.results` waits for all of them
and raises the first error of the thread in the caller; :meth:`Background.stop` makes the
thread stop after the item it is on and waits for it (an interrupted run must not leave a
thread writing into an output folder that is being removed).
"""
from __future__ import annotations

import threading
import time


class Background:
    """``work(*args)`` for each ``(key, args)`` of ``items``, in order, in one thread."""

    def __init__(self, items: list, work, name: str):
        self._stop = threading.Event()
        self._done: dict = {}
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._run, args=(list(items), work), name=name, daemon=True)
        self._thread.start()

    def _run(self, items: list, work) -> None:
        try:
            for key, args in items:
                if self._stop.is_set():
                    return
                t0 = time.perf_counter()
                value = work(*args)
                self._done[key] = (value, time.perf_counter() - t0)
        except BaseException as exc:   # handed to the caller of results()
            self._error = exc

    def results(self) -> dict:
        """{key: (value, seconds)} of every item, after the thread has finished; the
        thread's error, if it had one, raised here."""
        self._thread.join()
        if self._error is not None:
            raise self._error
        return dict(self._done)

    def stop(self) -> None:
        """Stop after the current item and wait for the thread."""
        self._stop.set()
        self._thread.join()
