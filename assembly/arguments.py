"""Arguments of the public functions, checked at their entry.

A Python caller gets the same one-line :class:`SceneError` as the command line prints
(``t_end = '1e-3': must be a finite number > 0 s``), naming the argument as the function's
signature does, never a TypeError or AttributeError from deep inside. Numbers obey the rules
of scene numbers (:class:`fe_components.fields.Quantity`: a real number, not a bool or a
string, finite unless ``inf_ok``, zero or of magnitude in [1e-100, 1e100], then the range),
so a value gets one message whether it comes from a scene, a flag or an argument. An unknown
name is listed with the names there are and the nearest one (difflib). The command line maps
these argument names to its flags (:data:`assembly.app.cli.FLAGS`).

Each helper returns the value in the form the function uses.
"""
from __future__ import annotations

import difflib
import math
import numbers
import os

import numpy as np

from fe_components.fields import MAX_MAGNITUDE, MIN_MAGNITUDE, Quantity

from .errors import SceneError


class _Shown:
    """How a value of no plain kind appears in a message: ``<AssembledModel>``."""

    def __init__(self, text: str):
        self.text = text

    def __repr__(self):
        return self.text


def shown(value):
    """``value`` as a message shows it: itself when short and plain, else its kind."""
    if isinstance(value, np.generic):
        value = value.item()
    if value is None or isinstance(value, (bool, numbers.Number, str)):
        return value if not isinstance(value, str) or len(value) <= 200 else _Shown(f"<a text of {len(value)} chars>")
    if isinstance(value, (list, tuple)) and len(value) <= 8 and all(
            v is None or isinstance(v, (bool, numbers.Number, str)) for v in value):
        return value
    if isinstance(value, np.ndarray):
        return value.tolist() if value.size <= 8 and value.ndim <= 1 else _Shown(f"<array of shape {value.shape}>")
    return _Shown(f"<{type(value).__name__}>")


def refuse(name: str, value, reason: str) -> SceneError:
    """The SceneError naming argument ``name`` and its value (shown briefly)."""
    return SceneError(name, shown(value), reason)


def number(name: str, value, unit: str = "", infinite: str = "", **rule) -> float:
    """``value`` as a float obeying the number rules and ``rule`` (``gt``, ``ge``, ``lt``,
    ``le``, ... of :class:`Quantity`), in ``unit``; ``infinite``: what +inf means where it
    is admitted (e.g. "every mode")."""
    if infinite and isinstance(value, numbers.Real) and not isinstance(value, bool) and value == math.inf:
        return math.inf
    why = Quantity(unit, **rule).problem(value)
    if why:
        raise refuse(name, value, why + (f" (or inf: {infinite})" if infinite else ""))
    return float(value)


def integer(name: str, value, low: int, high: int | None = None) -> int:
    """``value`` as an int in [``low``, ``high``] (numpy integers too; not a bool, not a float)."""
    why = Quantity(integer=True, ge=low, le=high).problem(value)
    if why:
        raise refuse(name, value, why)
    return int(value)


def flag(name: str, value) -> bool:
    """``value`` as a bool: True or False (numpy's too), not a number or a string."""
    if not isinstance(value, (bool, np.bool_)):
        raise refuse(name, value, "must be True or False")
    return bool(value)


def text(name: str, value) -> str:
    """``value``, a non-empty string."""
    if not isinstance(value, str):
        raise refuse(name, value, "must be a string")
    if not value.strip():
        raise refuse(name, value, "must not be empty")
    return value


def nearest(value, have) -> str:
    """``"; nearest: 'x'"`` for the name of ``have`` closest to ``value`` (difflib), or ""."""
    close = difflib.get_close_matches(str(value), [str(h) for h in have], n=1, cutoff=0.5)
    return f"; nearest: {close[0]!r}" if close else ""


def unknown(name: str, value, have, what: str = "body") -> SceneError:
    """The SceneError for a ``what`` called ``value`` that is not among ``have``."""
    have = list(have)
    return refuse(name, value, f"no {what} of that name; have {have}{nearest(value, have)}")


def one_of(name: str, value, have, what: str = "body") -> str:
    """``value``, a string among ``have`` (the ``what`` names there are)."""
    text(name, value)
    if value not in have:
        raise unknown(name, value, have, what)
    return value


def names(name: str, value, empty: bool = False) -> list:
    """``value`` as a list of non-empty strings: one string, or a list or tuple of them
    (entry i named ``name[i]``); an empty list only if ``empty``."""
    if isinstance(value, str):
        return [text(name, value)]
    if not isinstance(value, (list, tuple)):
        raise refuse(name, value, "must be a name or a list of names")
    if not value and not empty:
        raise refuse(name, value, "must name at least one")
    return [text(f"{name}[{i}]", v) for i, v in enumerate(value)]


def frequencies(name: str, value) -> np.ndarray:
    """``value`` as a 1-D float array of frequencies (Hz): a number, or a non-empty list,
    tuple or 1-D array of numbers, each >= 0 and obeying the number rules (entry i named
    ``name[i]``)."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value.item()
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return np.array([number(name, value, "Hz", ge=0.0)])
    if not isinstance(value, (list, tuple, np.ndarray)):
        raise refuse(name, value, "must be a frequency or a list of frequencies (Hz)")
    if not len(value):
        raise refuse(name, value, "must hold at least one frequency (Hz)")
    if isinstance(value, np.ndarray) and value.ndim == 1 and value.dtype.kind in "iuf":   # checked at once
        f = value.astype(float)
        ok = np.isfinite(f) & (f >= 0) & ((f == 0) | ((f >= MIN_MAGNITUDE) & (f <= MAX_MAGNITUDE)))
        entries = [] if ok.all() else [int(np.argmin(ok))]
    else:
        f, entries = None, range(len(value))
    for i in entries:
        number(f"{name}[{i}]", value[i], "Hz", ge=0.0)
    return f if f is not None else np.array(value, float)


def file_path(name: str, value) -> str | os.PathLike:
    """``value``, a file or folder name: a non-empty string or a path object."""
    if isinstance(value, os.PathLike):
        return value
    if not isinstance(value, str):
        raise refuse(name, value, "must be a file or folder name (a string or a pathlib.Path)")
    return text(name, value)


def function(name: str, value):
    """``value``, a callable or None."""
    if value is not None and not callable(value):
        raise refuse(name, value, "must be a function (or None)")
    return value


def table(name: str, value) -> dict:
    """``value``, a dict."""
    if not isinstance(value, dict):
        raise refuse(name, value, "must be a dict")
    return value


def instance(name: str, value, cls, what: str):
    """``value``, an instance of ``cls`` (``what``: the thing in words, with how to make one)."""
    if not isinstance(value, cls):
        raise refuse(name, value, f"must be {what}")
    return value


def optional(check, name: str, value, *args, **kwargs):
    """``check(name, value, ...)`` unless ``value`` is None (then None)."""
    return None if value is None else check(name, value, *args, **kwargs)
