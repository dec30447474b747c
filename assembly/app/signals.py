"""Signal handlers installed for the length of a block (kept apart from
:mod:`assembly.app.output` so that a command without ``--out`` does not load the output
folder's locking and swapping)."""
from __future__ import annotations

import signal
import threading
from contextlib import contextmanager


@contextmanager
def signal_handler(handler, signals):
    """Install ``handler(signum, frame)`` for ``signals`` while inside; the handlers from
    before are put back after. Python runs signal handlers in the main thread only:
    elsewhere nothing is installed."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before = {s: signal.signal(s, handler) for s in signals}
    try:
        yield
    finally:
        for s, h in before.items():
            signal.signal(s, h if h is not None else signal.SIG_DFL)
