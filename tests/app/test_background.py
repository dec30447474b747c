"""assembly.app.report.background: a later step's work run early in a thread, collected in
order, its error raised in the collector, stopped between items when the run is interrupted."""
import threading

import pytest

from assembly.app.report.background import Background


def test_results_hold_every_item_by_key_with_its_time():
    import time

    def work(k):      # item k takes at least 5 k ms: its time says so
        time.sleep(0.005 * k)
        return k * k

    job = Background([(k, (k,)) for k in range(5)], work, "squares")
    done = job.results()
    assert {k: v for k, (v, _) in done.items()} == {k: k * k for k in range(5)}
    assert all(dt >= 0.005 * k for k, (_, dt) in done.items())


def test_the_threads_error_is_raised_in_the_caller_and_later_items_do_not_run():
    ran = []

    def work(k):
        ran.append(k)
        if k == 1:
            raise OSError(28, "No space left on device")
        return k

    job = Background([(k, (k,)) for k in range(4)], work, "failing")
    with pytest.raises(OSError, match="No space left"):
        job.results()
    assert ran == [0, 1]


def test_stop_ends_the_thread_after_the_item_it_is_on():
    started, release = threading.Event(), threading.Event()
    ran = []

    def work(k):
        ran.append(k)
        if k == 0:
            started.set()
            assert release.wait(10)
        return k

    job = Background([(k, (k,)) for k in range(3)], work, "stopped")
    assert started.wait(10)
    threading.Timer(0.05, release.set).start()
    job.stop()           # waits for item 0, then no more
    assert ran == [0]
