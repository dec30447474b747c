"""Damage a cache file the ways disks, crashes and people do: the class of corruption the
cache-integrity tests sweep (hypothesis strategy and a fixed, named sweep)."""
from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

#: (kind, position or length, byte) for :func:`corrupt`: truncation, one byte XORed with a
#: non-zero mask, one byte inserted, foreign content of up to 4 kB (or empty).
CORRUPTIONS = st.tuples(st.sampled_from(["truncate", "flip", "insert", "garbage"]),
                        st.integers(0, 2 ** 31), st.integers(1, 255))


def corrupt(data: bytes, how: tuple) -> bytes:
    """``data`` damaged as ``how`` says (always different from ``data``)."""
    kind, a, b = how
    if kind == "truncate":
        return data[:a % len(data)]
    if kind == "flip":
        i = a % len(data)
        return data[:i] + bytes([data[i] ^ b]) + data[i + 1:]
    if kind == "insert":
        i = a % (len(data) + 1)
        return data[:i] + bytes([b]) + data[i:]
    return bytes((7 * k + b) % 256 for k in range(a % 4096))


def sweep() -> dict:
    """Named damages: empty, truncations from the first to the last byte, one flipped low bit
    at nine positions k/8 of the file from its first to its last byte, random garbage of the
    same length. The hash-specific cases (missing, wrong) depend on the format."""
    cases = {"zero-length": lambda d: b""}
    for frac in (0.01, 0.5, 0.99):
        cases[f"truncated-at-{frac:.0%}"] = lambda d, f=frac: d[:int(f * len(d))]
    cases["truncated-last-byte"] = lambda d: d[:-1]
    for k in range(9):
        cases[f"bit-flip-at-{k}/8"] = lambda d, k=k: corrupt(d, ("flip", round(k * (len(d) - 1) / 8), 1))
    cases["random-garbage"] = lambda d: np.random.default_rng(0).bytes(len(d))
    return cases
