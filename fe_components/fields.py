"""Numeric field rules declared once, as dataclass field metadata, and checked before use.

A field made with :func:`quantity` carries its SI unit and admissible range; a parameter
class calls :func:`first_problem` (or :func:`check_fields`) at the top of its
``__post_init__``, before any comparison or derived quantity, and a table reader (the
scene schema) applies the same rule to the same field, so a value gets one message
wherever it comes from. Every number obeys, whatever its range:

* a real number: not a bool, not a string, not NaN;
* finite, unless the field admits ``+inf`` (a rigid bearing direction);
* zero, or of magnitude in ``[MIN_MAGNITUDE, MAX_MAGNITUDE]`` = [1e-100, 1e100]. Derived
  quantities are products and quotients of a few inputs (``m r^2``, ``k r^2``, ``k / m``,
  a vector norm): within these bounds a product of three inputs or a quotient of two stays
  finite and non-zero in double precision (range 2.2e-308 .. 1.8e308), so no check further
  on can be defeated by an overflow to inf or an underflow to 0. Physical inputs lie far
  inside (E = 2.1e11 Pa, a rotor of 4e7 kg m^2, a module of 1e-3 m).

Angle fields (unit ``"rad"``) state their bounds in degrees in the message.
"""
from __future__ import annotations

import dataclasses
import functools
import math
import numbers
import types
import typing
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .errors import GeometryError

#: Largest magnitude of any number (see the module docstring).
MAX_MAGNITUDE = 1e100
#: Smallest non-zero magnitude of any number.
MIN_MAGNITUDE = 1e-100


@dataclass(frozen=True)
class Quantity:
    """Unit and admissible range of a numeric field (bounds in SI units, rad for angles).

    ``gt``/``ge``/``lt``/``le``: strict and non-strict bounds; ``abs_lt``: ``|x| < abs_lt``;
    ``nonzero``: 0 is refused; ``inf_ok``: ``+inf`` is admitted (rigid); ``integer``: an
    int is required; ``hint``: appended to every message about this field; ``plausible``:
    a :class:`fe_components.sizes.Plausible`, the sizes a length is built in (a non-zero
    value outside them is a unit slip, refused with the unit that fits).
    """

    unit: str = ""
    gt: float | None = None
    ge: float | None = None
    lt: float | None = None
    le: float | None = None
    abs_lt: float | None = None
    nonzero: bool = False
    inf_ok: bool = False
    integer: bool = False
    hint: str = ""
    plausible: Any = None   # a fe_components.sizes.Plausible: the sizes a length is built in

    def _unit(self, x: float) -> str:
        """``x`` and the unit as shown to a user (degrees for an angle)."""
        if self.unit == "rad":
            return f"{math.degrees(x):.6g} deg"
        return f"{x:.6g} {self.unit}".rstrip()

    def range_text(self) -> str:
        """The admissible range in words, e.g. ``> 0 kg`` or ``in (0, 90) deg``."""
        lo = ("(", self.gt) if self.gt is not None else ("[", self.ge) if self.ge is not None else None
        hi = (")", self.lt) if self.lt is not None else ("]", self.le) if self.le is not None else None
        unit = "deg" if self.unit == "rad" else self.unit
        conv = math.degrees if self.unit == "rad" else float
        if lo and hi:
            text = f"in {lo[0]}{conv(lo[1]):.6g}, {conv(hi[1]):.6g}{hi[0]} {unit}"
        elif lo:
            text = f"{'>' if lo[0] == '(' else '>='} {self._unit(lo[1])}"
        elif hi:
            text = f"{'<' if hi[0] == ')' else '<='} {self._unit(hi[1])}"
        elif self.abs_lt is not None:
            text = f"of magnitude < {self._unit(self.abs_lt)}"
        else:
            text = f"in {unit}" if unit else ""
        if self.nonzero:
            text = f"non-zero {text}".strip()
        return text.rstrip()

    def reason(self) -> str:
        kind = "an integer" if self.integer else "a number" if self.inf_ok else "a finite number"
        text = f"must be {kind} {self.range_text()}".rstrip()
        if self.inf_ok:
            text += " (inf = rigid)"
        return f"{text}; {self.hint}" if self.hint else text

    def problem(self, value) -> str | None:
        """Why the scalar ``value`` breaks this rule, or None."""
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            return self.reason()
        if self.integer and not isinstance(value, numbers.Integral):
            return self.reason()
        x = float(value)
        if math.isnan(x) or (math.isinf(x) and not (self.inf_ok and x > 0)):
            return self.reason()
        if math.isfinite(x) and x != 0 and not MIN_MAGNITUDE <= abs(x) <= MAX_MAGNITUDE:
            return (f"{self.reason()}; a non-zero magnitude outside [{MIN_MAGNITUDE:g}, {MAX_MAGNITUDE:g}] "
                    "is not physical")
        ok = ((self.gt is None or x > self.gt) and (self.ge is None or x >= self.ge)
              and (self.lt is None or x < self.lt) and (self.le is None or x <= self.le)
              and (self.abs_lt is None or abs(x) < self.abs_lt) and not (self.nonzero and x == 0))
        if not ok:
            return self.reason()
        return self.plausible.problem(x) if self.plausible is not None and math.isfinite(x) else None


def quantity(unit: str = "", default=dataclasses.MISSING, *, angle: bool = False, **rule):
    """A dataclass field with a :class:`Quantity` rule (``angle=True``: radians that a
    table reader may accept in degrees under ``<name>_deg``)."""
    meta = {"quantity": Quantity(unit, **rule)}
    if angle:
        meta["angle"] = True
    return field(default=default, metadata=meta)


def value_problem(rule: Quantity, value, sequence: bool, optional: bool = True):
    """``(index suffix, bad value, reason)`` of the first entry of ``value`` breaking
    ``rule`` (``sequence``: the field holds an array, checked entry by entry; ``optional``:
    None is admitted), or None."""
    if value is None:
        return None if optional else ("", value, rule.reason())
    if sequence:
        if not isinstance(value, (list, tuple, np.ndarray)) or getattr(value, "ndim", 1) == 0:
            return "", value, "must be an array"
        for i, v in enumerate(value):
            if isinstance(v, (list, tuple, np.ndarray)):
                p = value_problem(rule, v, True)
            else:
                why = rule.problem(v)
                p = ("", v, why) if why else None
            if p is not None:
                return f"[{i}]{p[0]}", p[1], p[2]
        return None
    why = rule.problem(value)
    return ("", value, why) if why else None


@functools.cache
def field_rules(cls) -> tuple:
    """``(name, Quantity, is_sequence, is_optional)`` of every field of ``cls`` that has a rule."""
    hints = typing.get_type_hints(cls)
    out = []
    for f in dataclasses.fields(cls):
        rule = f.metadata.get("quantity")
        if rule is not None:
            tp = hints[f.name]
            out.append((f.name, rule, _is_sequence(tp), type(None) in typing.get_args(tp)))
    return tuple(out)


def _is_sequence(tp) -> bool:
    """A tuple annotation, or an optional one."""
    if typing.get_origin(tp) in (typing.Union, types.UnionType):
        args = [a for a in typing.get_args(tp) if a is not type(None)]
        tp = args[0] if len(args) == 1 else tp
    return typing.get_origin(tp) is tuple


def first_problem(obj) -> tuple[str, Any, str] | None:
    """``(field path, value, reason)`` of the first field of dataclass ``obj`` breaking its
    rule, in field order, or None."""
    for name, rule, seq, optional in field_rules(type(obj)):
        p = value_problem(rule, getattr(obj, name), seq, optional)
        if p is not None:
            return name + p[0], p[1], p[2]
    return None


def check_fields(obj, error=GeometryError) -> None:
    """Raise ``error(path, value, reason)`` for the first field of ``obj`` breaking its rule."""
    p = first_problem(obj)
    if p is not None:
        raise error(*p)
