"""Plausible sizes of drivetrain parts: a length outside them is a unit slip.

A length typed in millimetres where metres belong (a module of 5 makes a 100 m pinion, a
face width of 60 a 60 m gear) lies a factor 1000 beyond the sizes gears and shafts are built
in; one converted to metres twice lies 1000 below. Each range spans what is built, from watch
gears to the largest wind-turbine, mill and marine gears, with a margin of 2 to 5 on either
side, so a slip of 1000 falls outside it while no real part does; the message offers the
unit that brings the number into the range (as a STEP part's size check offers its units,
:func:`fe_components.part.geometry.check_size`). Declared on a field with
``quantity(..., plausible=RANGE)`` (:class:`fe_components.fields.Quantity`), so a TOML table,
a dataclass built in Python and the scene reference all see the same rule. SI metres.
"""
from __future__ import annotations

from dataclasses import dataclass

#: Units a length may have been typed in by mistake, and their size in metres.
SLIPS = (("mm", 1e-3), ("cm", 1e-2), ("in", 0.0254))


@dataclass(frozen=True)
class Plausible:
    """The sizes (m) a length of kind ``what`` is built in, ``lo`` to ``hi`` (its
    magnitude; 0 stands for "none" and is the field's range's business), and where the
    bounds come from (``basis``)."""

    what: str
    lo: float
    hi: float
    basis: str

    def problem(self, x: float) -> str | None:
        """Why the non-zero length ``x`` (m) is not plausible, or None."""
        a = abs(x)
        if a == 0 or self.lo <= a <= self.hi:
            return None
        return (f"{a:.6g} m is not a plausible {self.what}: {self.lo:g} to {self.hi:g} m ({self.basis})"
                f"{unit_hint(x, self.lo, self.hi)}")

    def text(self) -> str:
        """The range in words, for the scene reference."""
        return f"plausible {self.lo:g} to {self.hi:g} m ({self.basis})"


def unit_hint(x: float, lo: float, hi: float) -> str:
    """``"; did you mean 60 mm (0.06 m)?"``: the unit that brings a length ``x`` (m) typed
    in the wrong unit into ``[lo, hi]``, or a value converted to metres twice; "" if none."""
    a = abs(x)
    if a > hi:
        for unit, m in SLIPS:
            if lo <= a * m <= hi:
                return f"; did you mean {x:.6g} {unit} ({x * m:.6g} m)?"
    elif 0 < a < lo and lo <= a * 1e3 <= hi:
        return f"; did you mean {x * 1e3:.6g} m (a length in mm converted to metres twice?)"
    return ""


#: Normal module m_n. ISO 54:1996 gives the modules of general and heavy engineering, 1 to
#: 50 mm; fine-pitch gears of instruments and watches go down to 0.05 mm (DIN 780-1 lists
#: 0.05 to 60 mm); the NREL 5 MW gearbox's first stage has 45 mm. A factor 5 below, 2 above.
MODULE = Plausible("normal module", 1e-5, 0.1, "ISO 54 1 to 50 mm, fine pitch from 0.05 mm")
#: Face width b: watch wheels are 0.1 to 0.3 mm thick, the widest gears (marine double
#: helical, mill girth gears) about 1.5 m.
FACE_WIDTH = Plausible("face width", 5e-5, 3.0, "from watch wheels, 0.1 mm, to marine and mill gears, 1.5 m")
#: Gear radii (base, outer): watch pinions from 0.2 mm, the largest girth gears about 15 m
#: across.
GEAR_RADIUS = Plausible("gear radius", 1e-4, 10.0, "from watch pinions, 0.2 mm, to girth gears 15 m across")
#: Shaft diameters: watch pivots 0.05 to 0.1 mm, ship propeller and wind-turbine main shafts
#: about 1 m.
SHAFT_DIAMETER = Plausible("shaft diameter", 2e-5, 3.0, "from watch pivots, 0.05 mm, to main and propeller "
                                                        "shafts, 1.2 m")
#: Shaft and cylinder lengths (a modelled piece): watch arbors from 1 mm; a ship's
#: intermediate shaft, the longest piece of a shaft line, about 15 m.
SHAFT_LENGTH = Plausible("shaft length", 1e-4, 30.0, "from watch arbors, 1 mm, to a ship's intermediate "
                                                     "shaft, 15 m")
#: Longest shaft, in diameters: drive shafts run 1 to 50 diameters between their ends
#: (the NREL 5 MW main shaft 3.6, a ship's intermediate shaft about 30); beyond 500 the
#: diameter or the length is in the wrong unit (a 0.7 m shaft typed as 0.0007), or the
#: shaft is a wire.
SLENDERNESS = 500.0
#: Face width over normal module b / m_n: about 6 (narrow spur gears) to 40-60 (wide helical
#: gears) for power gears (ISO 6336-1 practice), down to about 1 for stamped and watch
#: wheels and up to about 150 for marine double-helical gears; 0.3 to 300 leaves a margin of
#: 2 to 3, and a face width or module typed 1000 x off falls outside.
FACE_PER_MODULE = (0.3, 300.0)
