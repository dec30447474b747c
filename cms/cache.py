"""On-disk cache of superelements keyed by the inputs that define them.

The key is a SHA-256 over a canonical JSON of the inputs (mesh hash, material,
interfaces, mode selection, ...) plus the file-format version, so an unchanged
component is reduced once and later runs load it. Use :func:`array_hash` for the
mesh (node coordinates, connectivity) or directly for K and M.
"""
from __future__ import annotations

import hashlib
import json
import logging
import os
from typing import Callable

import numpy as np

from .errors import CacheError
from .superelement import VERSION, Superelement, _json_default

log = logging.getLogger(__name__)


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
                         default=_json_default, separators=(",", ":"))
    return hashlib.sha256(payload.encode()).hexdigest()


class SuperelementCache:
    """Directory of ``<key>.npz`` superelement files."""

    def __init__(self, directory: str | os.PathLike):
        self.directory = os.fspath(directory)
        self.hits = 0
        self.misses = 0

    def path(self, key: str) -> str:
        return os.path.join(self.directory, f"{key}.npz")

    def get(self, key: str) -> Superelement | None:
        p = self.path(key)
        if not os.path.exists(p):
            return None
        try:
            return Superelement.load(p)
        except CacheError as exc:
            log.warning("ignoring unreadable cache entry %s: %s", p, exc)
            return None

    def put(self, key: str, se: Superelement) -> str:
        p = self.path(key)
        se.metadata.setdefault("cache_key", key)
        se.save(p)
        return p

    def get_or_reduce(self, inputs: dict, reduce: Callable[[], Superelement]) -> Superelement:
        """Load the superelement for ``inputs`` or call ``reduce()`` once and store it."""
        key = cache_key(**inputs)
        se = self.get(key)
        if se is not None:
            self.hits += 1
            log.info("superelement cache hit %s", key[:12])
            return se
        self.misses += 1
        se = reduce()
        se.metadata.setdefault("inputs", inputs)
        self.put(key, se)
        log.info("superelement cache miss %s: reduced and stored", key[:12])
        return se
