"""A model's matrices as plain arrays, whichever way they are stored.

A small rigid model is assembled as dense numpy arrays (no SciPy import on the path of
``flexgear modes``), a larger one as SciPy sparse matrices: code that needs the entries
asks :func:`dense` and works on either.
"""
from __future__ import annotations

import numpy as np


def dense(A) -> np.ndarray:
    """``A`` as a dense float array: a sparse matrix's ``toarray()``, an array itself."""
    return A.toarray() if hasattr(A, "toarray") else np.asarray(A, float)


def entries(A) -> np.ndarray:
    """The stored entries of ``A`` (a sparse matrix's ``data``, every entry of an array):
    what a finiteness check looks at."""
    return np.asarray(A.data) if hasattr(A, "toarray") else np.asarray(A)
