"""On-disk cache of superelements keyed by the inputs that define them.

The key is a SHA-256 over a canonical JSON of the inputs (mesh content hash,
material, interfaces, mode selection, ...) plus the file-format version, so an
unchanged component is reduced once and later runs load it. Use
:func:`array_hash` for the mesh (node coordinates, connectivity), the hash of the
mesh file's content, or directly K and M: never a file name.

Integrity rules: each entry is one sealed file (``cms.superelement``: SHA-256 in the
zip comment, checked on every load). *Any* failure to use an entry (unreadable,
truncated, wrong hash, older format, or rejected by the caller's ``check``) is a
cache miss: the file is renamed to ``<name>.corrupt-<UTC time>-<pid>`` in the same
folder (delete those at will), a WARNING names it and the reason, and the
superelement is reduced again. Writes are atomic (unique temporary file, fsync,
``os.replace``), and a miss is reduced under an exclusive lock on ``.<key>.npz.lock``
(``fcntl.flock``): of two processes missing the same entry at once, one reduces and the
other waits and loads its entry; no reader ever sees a half-written file.
"""
from __future__ import annotations

import contextlib
import hashlib
import json
import logging
import os
import time
from typing import Callable

import numpy as np

from .superelement import VERSION, Superelement, json_default

log = logging.getLogger(__name__)

#: This process's superelement cache use, over every cache: {"hits": n, "misses": n} (a
#: design study reports per variant how many reductions it reused and how many it built).
STATS = {"hits": 0, "misses": 0}


def array_hash(*arrays) -> str:
    """SHA-256 of arrays' dtype, shape and bytes (sparse matrices: their CSR parts)."""
    h = hashlib.sha256()
    for a in arrays:
        if hasattr(a, "tocsr"):
            a = a.tocsr()
            a.sort_indices()
            parts = (a.indptr, a.indices, a.data, np.asarray(a.shape))
        else:
            parts = (np.ascontiguousarray(a),)
        for p in parts:
            p = np.ascontiguousarray(p)
            h.update(str((p.dtype.str, p.shape)).encode())
            h.update(p.tobytes())
    return h.hexdigest()


def cache_key(**inputs) -> str:
    """Hex key for the JSON-serialisable ``inputs`` (order-independent)."""
    payload = json.dumps({"format_version": VERSION, **inputs}, sort_keys=True,
                         default=json_default, separators=(",", ":"))
    return hashlib.sha256(payload.encode()).hexdigest()


class SuperelementCache:
    """Directory of ``<key>.npz`` superelement files (see the module's integrity rules)."""

    def __init__(self, directory: str | os.PathLike):
        self.directory = os.fspath(directory)
        self.hits = 0
        self.misses = 0
        self.discarded = 0

    def path(self, key: str) -> str:
        return os.path.join(self.directory, f"{key}.npz")

    def get(self, key: str, check: Callable[[Superelement], None] | None = None) -> Superelement | None:
        """The stored superelement, or None if absent or unusable (then moved aside).
        ``check(se)`` may raise to reject an entry that loads but does not fit its inputs."""
        p = self.path(key)
        if not os.path.exists(p):
            return None
        try:
            se = Superelement.load(p)
            if check is not None:
                check(se)
            return se
        except Exception as exc:  # any failure to use an entry is a miss, whatever raised it
            self._discard(p, exc)
            return None

    def _discard(self, p: str, exc: Exception) -> None:
        """Rename an unusable entry to ``<name>.corrupt-<UTC time>-<pid>`` and warn. The mesh
        cache (fe_components.meshing) moves bad files aside by the same rule, in its own
        copy: the two packages import nothing of each other."""
        self.discarded += 1
        dest = f"{p}.corrupt-{time.strftime('%Y%m%dT%H%M%SZ', time.gmtime())}-{os.getpid()}"
        try:
            os.replace(p, dest)
            where = f"moved to {os.path.basename(dest)}"
        except FileNotFoundError:  # another process moved or replaced it first
            where = "already gone"
        except OSError as err:
            where = f"could not be moved aside ({err})"
        log.warning("unusable superelement cache entry %s (%s): %s; reducing again", p, exc, where)

    def put(self, key: str, se: Superelement) -> str | None:
        """Store ``se`` under ``key``; a folder that cannot take it (read-only, full) costs
        only the reuse: warn and return None."""
        p = self.path(key)
        se.metadata.setdefault("cache_key", key)
        try:
            se.save(p)                      # creates the folder if needed
        except OSError as exc:
            log.warning("cannot store superelement in %s: %s; continuing without caching it",
                        self.directory, exc.strerror or exc)
            return None
        return p

    def get_or_reduce(self, inputs: dict, reduce: Callable[[], Superelement],
                      check: Callable[[Superelement], None] | None = None) -> Superelement:
        """Load the superelement for ``inputs`` or call ``reduce()`` once and store it.
        ``check(se)`` is applied to a loaded entry (raising = miss) and to a fresh
        reduction (raising = error, nothing stored)."""
        key = cache_key(**inputs)
        se = self.get(key, check)
        if se is None:
            with self._build_lock(key):  # another process may have stored it while we waited
                se = self.get(key, check)
                if se is None:
                    self.misses += 1
                    STATS["misses"] += 1
                    se = reduce()
                    if check is not None:
                        check(se)
                    se.metadata.setdefault("inputs", inputs)
                    self.put(key, se)
                    log.info("superelement cache miss %s: reduced and stored", key[:12])
                    return se
        self.hits += 1
        STATS["hits"] += 1
        log.info("superelement cache hit %s", key[:12])
        return se

    @contextlib.contextmanager
    def _build_lock(self, key: str):
        """Exclusive ``fcntl.flock`` on ``.<key>.npz.lock`` while an entry is reduced (the mesh
        cache, fe_components.meshing.build_lock, locks by the same rule in its own copy); a
        folder that cannot take the lock file reduces without it."""
        import fcntl
        try:
            os.makedirs(self.directory, exist_ok=True)
            lock = os.path.join(self.directory, f".{key}.npz.lock")
            fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError:
            yield
            return
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
            yield
        finally:
            # removed while held: whoever locks after this sees the published entry
            with contextlib.suppress(FileNotFoundError):
                os.unlink(lock)
            os.close(fd)
