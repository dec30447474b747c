"""Files that the ``rosco`` package installs (ROSCO, the NREL/TU Delft reference controller):
its example turbines' performance tables and controller inputs, beside its compiled library.

flexgear's Makefile installs ``rosco`` without its Python toolbox's dependencies (the toolbox
pulls in WISDEM and Jupyter, about 1.4 GB): only the package's files are used, and nothing here
imports it.
"""
from __future__ import annotations

import importlib.util
from pathlib import Path

from ..errors import SceneError

#: The NREL 5 MW reference turbine's performance table in ROSCO's examples
NREL5MW_SURFACE = "Examples/Test_Cases/NREL-5MW/Cp_Ct_Cq.NREL5MW.txt"


def rosco_root() -> Path:
    """The folder the ``rosco`` package was installed into (its ``Examples`` beside it)."""
    spec = importlib.util.find_spec("rosco")
    if spec is None or spec.origin is None:
        raise SceneError("turbine", "rosco", "is not installed (make installs it without its toolbox's "
                                             "dependencies; README)")
    return Path(spec.origin).resolve().parent.parent


def rosco_file(relative: str) -> Path:
    """A file of the installed ``rosco`` package, by its path in the package's wheel."""
    p = rosco_root() / relative
    if not p.is_file():
        raise SceneError("turbine", relative, f"is not in the installed rosco package ({rosco_root()})")
    return p
