"""Lazy public names of a package: ``from pkg import Name`` imports Name's submodule on first
use, so importing the package (or one light submodule of it) loads nothing heavy."""
from __future__ import annotations

import importlib


def lazy_exports(package: str, exports: dict, namespace: dict):
    """``(__getattr__, __dir__)`` for the package ``package`` whose public names map to
    submodules in ``exports`` (name -> submodule); a name, once imported, is stored in the
    package ``namespace`` (its ``globals()``)."""

    def __getattr__(name: str):
        if name not in exports:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{package}.{exports[name]}"), name)
        namespace[name] = value
        return value

    def __dir__():
        return sorted(set(namespace) | set(exports))

    return __getattr__, __dir__
