"""Where a study's variants run: in this process, on a local Dask cluster, or on a cluster
the user already has (``dask.distributed``).

* ``serial``: one variant after the other in this process.
* ``local`` (the default): a :class:`distributed.LocalCluster` of worker *processes*, one
  per core (or ``workers``), one thread each: gmsh keeps process-global state, so each
  worker process initialises its own (``interruptible=False``: a worker's task thread is
  not the main thread), and the Dask nanny starts each worker with one BLAS thread
  (``OMP_NUM_THREADS=1`` ...; :func:`assembly.app.study.run.run_variant` also holds BLAS to
  one thread), so two workers on two cores do not oversubscribe. Workers keep glibc's own
  allocator settings (the nanny's ``MALLOC_TRIM_THRESHOLD_`` is left out: it made a flexible
  variant 2.4x slower).
* ``scheduler``: a running scheduler at ``address`` (``tcp://host:8786``); its workers must
  see the scene file and the cache folder at the same paths (a shared file system).

A worker that dies (killed, out of memory) loses its running variant; the scheduler
reschedules it on another worker (up to ``distributed.scheduler.allowed-failures`` times,
3 by default), so the study still completes; a variant that killed workers that often is an
error row. Rows come back in variant order whatever order they finish in.
"""
from __future__ import annotations

import logging
import os
import time
from typing import Callable

from ...errors import SceneError
from .run import run_variant

log = logging.getLogger(__name__)

MODES = ("serial", "local", "scheduler")
#: Seconds to reach a scheduler given by address before giving up.
CONNECT_TIMEOUT_S = 5


class SchedulerUnreachable(SceneError):
    """``--scheduler ADDRESS`` names no scheduler that answers."""


def default_workers() -> int:
    """One worker per core this process may use."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def run_study(study, mode: str = "local", address: str | None = None, workers: int | None = None,
              cache_dir: str | None = None, tick: Callable[[dict], None] | None = None) -> list[dict]:
    """Every variant's row of ``study`` (:class:`assembly.app.study.file.Study`), in variant
    order; ``tick(row)`` is called as each one arrives (a progress bar)."""
    if mode not in MODES:
        raise SceneError("mode", mode, f"must be one of {list(MODES)}")
    settings = study.settings
    if study.analysis == "modes" and study.keep.get("track"):   # the modes each variant follows
        from .file import first_reference
        settings = {**settings, "reference": first_reference(study, cache_dir)}
    args = (study.scene, study.analysis, study.keep, settings, cache_dir)
    tick = tick or (lambda row: None)
    if mode == "serial":
        rows = []
        for v in study.variants:
            rows.append(run_variant(args[0], v, *args[1:]))
            tick(rows[-1])
        return rows
    with _client(mode, address, workers) as client:
        return _gather(client, study.variants, args, tick)


def _client(mode: str, address: str | None, workers: int | None):
    """A :class:`distributed.Client` on a new LocalCluster or on the scheduler at ``address``."""
    from distributed import Client, LocalCluster
    # Dask configures its loggers at INFO; flexgear's -v decides what is shown
    logging.getLogger("distributed").setLevel(max(logging.getLogger().getEffectiveLevel(), logging.WARNING))
    if mode == "scheduler":
        if not address:
            raise SceneError("--scheduler", address, "needs the scheduler's address, e.g. tcp://host:8786")
        deadline = time.monotonic() + CONNECT_TIMEOUT_S
        try:
            handshake(address, CONNECT_TIMEOUT_S)
            return Client(address, timeout=f"{max(deadline - time.monotonic(), 0.5):.3f}s")
        except Exception as exc:  # noqa: BLE001 -- whatever the address gives back, it is no scheduler
            raise SchedulerUnreachable("--scheduler", address, f"no Dask scheduler answered within "
                                       f"{CONNECT_TIMEOUT_S} s ({type(exc).__name__}: "
                                       f"{str(exc).splitlines()[0] if str(exc) else 'no answer'})") from None
    import dask
    n = workers or default_workers()
    # Workers with glibc's own allocator settings: the nanny's default MALLOC_TRIM_THRESHOLD_ =
    # 65536 makes every large numpy temporary fresh pages from the kernel; a flexible variant
    # then took 2.4x the CPU time (system time 2.4 -> 23.1 s, minor page faults 0.13 -> 10.7
    # million over 3 variants, measured) and 2 workers were slower than serial. The nanny also
    # writes its settings into this process's environment: restored when the cluster closes.
    config = dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None})
    environ = dict(os.environ)
    os.environ.pop("MALLOC_TRIM_THRESHOLD_", None)
    try:
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                               scheduler_kwargs={"dashboard": False}, silence_logs=logging.ERROR)
    except BaseException:
        _restore(environ)
        config.__exit__(None, None, None)
        raise
    return _Closing(Client(cluster), cluster, config, environ)


def handshake(address: str, timeout: float) -> None:
    """Open a connection to ``address`` and complete Dask's handshake within ``timeout`` s,
    then close it. ``distributed.Client(address, timeout=...)`` bounds the TCP connect but
    waits for the handshake's reply without limit, so a port that accepts and never answers
    would hang it. Runs on an event loop of its own (in a thread), whatever loop the caller
    has; raises what the connection raised, TimeoutError when nothing answered in time."""
    import asyncio
    from concurrent.futures import ThreadPoolExecutor

    from distributed.comm import connect

    async def shake():
        comm = await asyncio.wait_for(connect(address, timeout=timeout), timeout)
        await comm.close()

    with ThreadPoolExecutor(1) as pool:
        pool.submit(asyncio.run, shake()).result()


def _restore(environ: dict) -> None:
    os.environ.clear()
    os.environ.update(environ)


class _Closing:
    """Context manager closing a client and the LocalCluster it owns, then restoring the Dask
    configuration and environment of this process."""

    def __init__(self, client, cluster, config, environ):
        self.client, self.cluster, self.config, self.environ = client, cluster, config, environ

    def __enter__(self):
        return self.client

    def __exit__(self, *exc):
        try:
            self.client.close()
            self.cluster.close()
        finally:
            _restore(self.environ)
            self.config.__exit__(None, None, None)
        return False


def _gather(client, variants, args: tuple, tick) -> list[dict]:
    """Submit every variant, collect rows as they finish; a variant whose workers kept dying
    is an error row."""
    from distributed import as_completed
    futures = {client.submit(run_variant, args[0], v, *args[1:], key=f"flexgear-variant-{v.index}-{os.getpid()}",
                             pure=False): v for v in variants}
    rows = {}
    for fut in as_completed(futures):
        v = futures[fut]
        try:
            row = fut.result()
        except Exception as exc:  # noqa: BLE001 -- KilledWorker and the like: the variant's row says so
            row = {"variant": v.index, **v.params, "status": "error",
                   "error": f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"}
        rows[v.index] = row
        tick(row)
    return [rows[v.index] for v in variants]
