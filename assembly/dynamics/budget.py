"""Memory budget of an analysis: the arrays whose size the caller chooses (time steps and
recorded outputs, frequencies, speeds, harmonics) are estimated before they are allocated and
a size over the budget is refused in one line (:class:`~assembly.errors.SceneError` naming
the argument, its value and the estimate), instead of a MemoryError, swapping or the kernel's
out-of-memory kill after the work.

Budget: :data:`BUDGET_FRACTION` of the memory this process may use, which is the physical
memory (``os.sysconf``: ``SC_PHYS_PAGES`` x ``SC_PAGE_SIZE``) or, when lower, the limit of its
control group (cgroup v2 ``memory.max``); :data:`FALLBACK_BYTES` where neither is known. The
other half is left for the model, its factorisations and writing the result (plots, JSON).
"""
from __future__ import annotations

import os
from pathlib import Path

from ..errors import SceneError

#: Share of the usable memory an analysis's caller-sized arrays may take.
BUDGET_FRACTION = 0.5
#: Usable memory assumed where the platform does not say (bytes).
FALLBACK_BYTES = 8 * 2 ** 30
#: The control group's memory limit (cgroup v2): "max" or bytes.
CGROUP_LIMIT = Path("/sys/fs/cgroup/memory.max")


def usable_memory() -> int | None:
    """Bytes of memory this process may use: the physical memory, or the cgroup's limit when
    lower; None when the platform says neither."""
    found = []
    try:
        found.append(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):      # no sysconf (Windows) or no such name
        pass
    try:
        text = CGROUP_LIMIT.read_text().strip()
        if text.isdigit():
            found.append(int(text))
    except OSError:
        pass
    found = [v for v in found if v > 0]
    return min(found) if found else None


def memory_budget() -> int:
    """Bytes an analysis's caller-sized arrays may take (module notes)."""
    return int(BUDGET_FRACTION * (usable_memory() or FALLBACK_BYTES))


def size_text(n_bytes: float) -> str:
    """``n_bytes`` in binary units, three significant digits: ``"7.28 TiB"``."""
    value, unit = float(n_bytes), "B"
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"):
        if value < 1024 or unit == "EiB":
            break
        value /= 1024
    return f"{value:.3g} {unit}"


def check_memory(path: str, value, need: float, what: str, remedy: str) -> None:
    """SceneError at ``path`` (= ``value``) when ``need`` bytes (``what`` takes them, in
    words) exceed :func:`memory_budget`; ``remedy``: what to change."""
    budget = memory_budget()
    if need > budget:
        raise SceneError(path, value, f"{what}: {size_text(need)} of memory, over the budget of {size_text(budget)} "
                                      f"({BUDGET_FRACTION:.0%} of {size_text(budget / BUDGET_FRACTION)}): {remedy}")
