"""Run the command line in a child process that file modes bind, also when the tests run as
root: permission errors (a read-only folder) can then be provoked for real."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
# Linux capabilities that let root ignore file modes: CAP_DAC_OVERRIDE, CAP_DAC_READ_SEARCH,
# CAP_FOWNER (linux/capability.h); PR_CAPBSET_DROP (linux/prctl.h).
DAC_CAPABILITIES, PR_CAPBSET_DROP = (1, 2, 3), 24


def without_dac_capabilities():
    """preexec_fn: drop root's power to ignore file modes (for the program it runs), so that
    permission errors can be provoked as root too."""
    import ctypes
    libc = ctypes.CDLL(None, use_errno=True)
    for cap in DAC_CAPABILITIES:
        if libc.prctl(PR_CAPBSET_DROP, cap, 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), "prctl(PR_CAPBSET_DROP)")


def run_unprivileged(args, timeout: float = 120) -> subprocess.CompletedProcess:
    """``flexgear ARGS`` (``python -m assembly.app.cli``) in a child without those capabilities;
    SubprocessError (e.g. a container without CAP_SETPCAP) when they cannot be dropped."""
    return subprocess.run([sys.executable, "-m", "assembly.app.cli", *args], env={**os.environ, "PYTHONPATH": str(ROOT)},
                          cwd=ROOT, capture_output=True, text=True, timeout=timeout,
                          preexec_fn=without_dac_capabilities if os.geteuid() == 0 else None)
