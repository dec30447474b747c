"""A turbine read from its OpenFAST deck: the rotor, drivetrain, air and controller numbers a
turbine run takes, in SI, each with the file and key it came from.

The deck is the main input file (``.fst``) and the files it names: ElastoDyn's (and the blade
files that one names), ServoDyn's, the controller's input file (ROSCO's ``DISCON.IN``) and, for
an older deck's air density, AeroDyn's. A file named by another is found relative to the folder
of the file naming it (OpenFAST's rule), ``\\`` read as ``/``.

Every file is read by key. OpenFAST's input lines are ``value  Key  - description`` and
DISCON.IN's ``value  ! Key  - description``; a key's value is taken from the first line that
names it (in any letter case), wherever that line stands. OpenFAST versions add and move lines between the keys read
here, so a reader by line position reads one version's layout only: openfast_io 5.0.0 (NREL's
reader) stops on the OpenFAST 3.5 deck ROSCO 2.9 ships for the NREL 5 MW, and its ElastoDyn
reader, given that deck's ElastoDyn file, returns TipRad = 1.5 and NumBl = 63 before it stops.

What is taken, and how (ElastoDyn's keys and units):

- ``radius`` = TipRad, ``hub_radius`` = HubRad (m, along the coned blade from the rotor apex);
- ``hub_height`` = TowerHt + Twr2Shft + OverHang sin(ShftTilt) (m above the ground, or the mean
  sea level offshore: ElastoDyn's hub height, the apex OverHang along the tilted shaft from the
  point Twr2Shft above the tower top);
- ``tilt``: the shaft's angle to the horizontal (rad), positive with the rotor's end raised.
  ElastoDyn's ShftTilt (deg) is positive with the shaft's downwind end raised, and OverHang < 0
  places the rotor upwind, so ``tilt = -ShftTilt`` for an upwind rotor (OverHang <= 0) and
  ``+ShftTilt`` for a downwind one: the NREL 5 MW's ShftTilt = -5 deg is a 5 deg tilt;
- ``density`` (kg/m^3) = AirDens of the .fst, else of the AeroDyn file (older decks); WtrDens
  for a marine turbine (the .fst's MHK not 0; its hub height may be negative, below the sea);
- ``rotor_inertia`` (kg m^2, about the shaft axis): HubIner and the blades' distributed mass
  (BlFract, BMassDen x AdjBlMs of each blade file; TipMass, PreCone, BldNodes) summed as
  ElastoDyn sums them (:mod:`assembly.dynamics.blade_mass`);
- ``hub_inertia`` = HubIner, ``generator_inertia`` = GenIner (kg m^2, high-speed shaft),
  ``gear_ratio`` = GBRatio, ``gearbox_efficiency`` = GBoxEff / 100 (ElastoDyn gives %; the
  generator's efficiency is ServoDyn's, not read here), ``drivetrain_stiffness`` = DTTorSpr
  (N m/rad), ``drivetrain_damping`` = DTTorDmp (N m s/rad), both on the low-speed shaft;
- the controller, when ServoDyn runs a Bladed-style library (CompServo = 1 and PCMode or
  VSContrl = 5; else None): ``controller_library`` = DLL_FileName, ``controller_input`` =
  DLL_InFile, ``controller_period`` = DLL_DT (s; "default" is the .fst's DT). The library need
  not exist (a deck names the one built where it was written): the caller decides;
- ``surface``: the Cp/Ct/Cq file DISCON.IN's PerfFileName names (``with_surface=False``: None,
  DISCON.IN not read);
- ``dt`` = the .fst's DT (s); ``sources``: field -> "file name: key(s)".

Refused (:class:`assembly.errors.SceneError` at ``field``, one line naming the file): a missing
file, one without the keys of its kind, a value that is not a number or out of range (radius,
density, inertias, gear ratio not positive; the hub radius not below the tip radius; an
efficiency outside (0, 100] %), a deck with blades other than ElastoDyn's (CompElast != 1) or
other than three (ElastoDyn's HubIner is about the teeter axis for two), a blade table that is
not one (BlFract from 0 to 1 increasing, BMassDen positive), and, when the surface is asked for,
a deck without a DISCON.IN, a DISCON.IN without PerfFileName or the file it names missing.
Nothing is written and nothing printed.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import SceneError
from .blade_mass import blade_mass, rotor_inertia, uniform_elements

#: ServoDyn's PCMode / VSContrl for a Bladed-style controller library
BLADED_DLL = 5
#: The blades ElastoDyn's rotor inertia is read for (HubIner is about the teeter axis for two)
BLADES = 3


@dataclass(frozen=True)
class TurbineDeck:
    """A turbine as its OpenFAST deck describes it, in SI (module notes: each field's source,
    units and conventions). ``deck`` is the .fst read."""

    deck: Path
    radius: float
    hub_radius: float
    hub_height: float
    tilt: float
    density: float
    rotor_inertia: float
    hub_inertia: float
    generator_inertia: float
    gear_ratio: float
    gearbox_efficiency: float
    drivetrain_stiffness: float
    drivetrain_damping: float
    controller_library: Path | None
    controller_input: Path | None
    controller_period: float | None
    surface: Path | None
    dt: float
    sources: dict


def input_entry(line: str, discon: bool) -> tuple[str, str] | None:
    """(key, value text) of one input line -- OpenFAST's ``value Key``, or with ``discon``
    ROSCO's ``value ! Key`` -- or None for a rule or a comment (a table row gives a number as its
    key, which is never asked for)."""
    s = line.strip()
    if discon:
        value, bang, rest = s.partition("!")
        if not bang or not value.strip() or not rest.split():
            return None
        value = value.strip()
        if value[0] in "\"'" and value.find(value[0], 1) > 0:
            value = value[1:value.find(value[0], 1)]
        return rest.split()[0], value
    if not s or s.startswith(("---", "===", "!", "#")):
        return None
    if s[0] in "\"'":
        end = s.find(s[0], 1)
        if end < 0:
            return None
        value, rest = s[1:end], s[end + 1:]
    else:
        value, rest = (s.split(None, 1) + [""])[:2]
    words = rest.split()
    return (words[0], value) if words else None


class _Input:
    """One input file of the deck by key (module notes); refusals name the file."""

    def __init__(self, path: Path, field: str, named: str, discon: bool = False):
        self.path, self.field, self.name = path, field, path.name
        if not path.is_file():
            raise SceneError(field, str(path), f"is missing ({named})")
        try:
            self.lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
        except OSError as exc:
            raise SceneError(field, str(path), f"cannot be read ({type(exc).__name__})") from None
        self.entries = {}
        for i, line in enumerate(self.lines):
            e = input_entry(line, discon)
            if e is not None and e[0].lower() not in self.entries:
                self.entries[e[0].lower()] = (e[1], i + 1)

    def refuse(self, reason: str):
        raise SceneError(self.field, str(self.path), reason)

    def has(self, key: str) -> bool:
        return key.lower() in self.entries

    def line(self, key: str) -> int:
        return self.entries[key.lower()][1]

    def text(self, key: str) -> str:
        if not self.has(key):
            self.refuse(f"has no {key} line")
        return self.entries[key.lower()][0]

    def number(self, key: str) -> float:
        text = self.text(key)
        try:
            value = float(text.replace("D", "E").replace("d", "e"))
        except ValueError:
            value = math.nan
        if not math.isfinite(value):
            self.refuse(f"line {self.line(key)}: {key} = {text!r} is not a number")
        return value

    def whole(self, key: str, low: int = 1) -> int:
        value = self.number(key)
        if value != int(value) or value < low:
            self.refuse(f"line {self.line(key)}: {key} = {self.text(key)!r} is not a whole number >= {low}")
        return int(value)

    def check(self, key: str, ok: bool, what: str) -> None:
        if not ok:
            self.refuse(f"line {self.line(key)}: {key} = {self.text(key)!r} {what}")

    def named(self, key: str) -> Path:
        """The file this one names in ``key``, relative to this file's folder."""
        p = Path(self.text(key).replace("\\", "/"))
        return (p if p.is_absolute() else self.path.parent / p).resolve()


def _blade_table(b: _Input) -> tuple[np.ndarray, np.ndarray]:
    """(BlFract, BMassDen x AdjBlMs) of an ElastoDyn blade file."""
    n, adjust = b.whole("NBlInpSt", low=2), b.number("AdjBlMs")
    b.check("AdjBlMs", adjust > 0, "is not positive")
    head = next((i for i, s in enumerate(b.lines) if {"BlFract", "BMassDen"} <= set(s.split())), None)
    if head is None:
        b.refuse("has no distributed-properties header naming BlFract and BMassDen")
    names = b.lines[head].split()
    rows, lines, i = [], [], head + 1
    while len(rows) < n:
        if i >= len(b.lines):
            b.refuse(f"the blade table ends after {len(rows)} of NBlInpSt = {n} rows")
        words = b.lines[i].split()
        i += 1
        if not words or words[0].startswith("("):          # a blank line or the units line
            continue
        try:
            row = [float(w) for w in words]
        except ValueError:
            row = []
        if len(row) < len(names) or not all(map(math.isfinite, row)):
            b.refuse(f"line {i}: not a row of {len(names)} numbers ({' '.join(names)})")
        rows.append(row)
        lines.append(i)
    table = np.array(rows)
    fraction, density = table[:, names.index("BlFract")], table[:, names.index("BMassDen")]
    if fraction[0] != 0.0 or fraction[-1] != 1.0 or np.any(np.diff(fraction) <= 0):
        b.refuse("BlFract must run from 0 to 1, increasing")
    if np.any(density <= 0):
        b.refuse(f"line {lines[int(np.argmax(density <= 0))]}: BMassDen is not positive")
    return fraction, density * adjust


def _rotor_inertia(ed: _Input, field: str, radius: float, hub_radius: float, hub_inertia: float):
    """(rotor inertia, its source) from the ElastoDyn file ``ed`` and the blade files it names."""
    blades = ed.whole("NumBl")
    ed.check("NumBl", blades == BLADES, f"is not {BLADES}: ElastoDyn's HubIner is about the teeter axis for two")
    centres, widths = uniform_elements(ed.whole("BldNodes"), radius - hub_radius)
    tables, moments = {}, []
    for k in range(1, blades + 1):
        key = f"BldFile({k})" if ed.has(f"BldFile({k})") else f"BldFile{k}"
        p = ed.named(key)
        if p not in tables:
            tables[p] = _blade_table(_Input(p, field, f"the blade file {ed.name} names in {key}"))
        tip = ed.number(f"TipMass({k})")
        ed.check(f"TipMass({k})", tip >= 0, "is negative")
        moments.append((blade_mass(*tables[p], radius - hub_radius, centres, widths, tip),
                        math.radians(ed.number(f"PreCone({k})"))))
    return rotor_inertia(hub_inertia, hub_radius, moments), (
        f"{ed.name}: HubIner, HubRad, TipRad, NumBl, PreCone, TipMass, BldNodes; "
        f"{', '.join(p.name for p in tables)}: BlFract, BMassDen, AdjBlMs")


def _controller(fst: _Input, field: str, dt: float, with_surface: bool, sources: dict):
    """(library, input file, period, surface) of the deck's controller (module notes), their
    sources added to ``sources``."""
    library = infile = period = surface = None
    if fst.has("CompServo") and fst.number("CompServo") == 1:
        sd = _Input(fst.named("ServoFile"), field, f"the ServoDyn file {fst.name} names in ServoFile")
        if BLADED_DLL in (sd.number("PCMode"), sd.number("VSContrl")):
            library, infile = sd.named("DLL_FileName"), sd.named("DLL_InFile")
            sources["controller_library"] = f"{sd.name}: DLL_FileName"
            sources["controller_input"] = f"{sd.name}: DLL_InFile"
            if sd.text("DLL_DT").strip().lower() == "default":
                period = dt
                sources["controller_period"] = f"{fst.name}: DT ({sd.name}: DLL_DT = default)"
            else:
                period = sd.number("DLL_DT")
                sd.check("DLL_DT", period > 0, "is not positive")
                sources["controller_period"] = f"{sd.name}: DLL_DT"
    if with_surface:
        if infile is None:
            fst.refuse("runs no Bladed-style controller (that takes CompServo = 1 and ServoDyn's PCMode or "
                       "VSContrl = 5): no DISCON.IN names a performance table")
        discon = _Input(infile, field, "the controller input file the ServoDyn file names in DLL_InFile",
                        discon=True)
        if not discon.has("PerfFileName"):
            discon.refuse("has no PerfFileName line: no performance table (Cp, Ct, Cq) is named")
        surface = discon.named("PerfFileName")
        if not surface.is_file():
            discon.refuse(f"names in PerfFileName a performance table that is missing: {surface}")
        sources["surface"] = f"{discon.name}: PerfFileName"
    return library, infile, period, surface


def read_deck(path, field: str = "turbine.openfast", *, with_surface: bool = True) -> TurbineDeck:
    """The :class:`TurbineDeck` of the OpenFAST deck whose main input file is ``path``
    (module notes); SceneError at ``field`` for a deck that cannot give it."""
    fst_path = Path(path)
    if not fst_path.is_file():
        raise SceneError(field, str(path), "no such file (an OpenFAST main input file, .fst)")
    fst = _Input(fst_path.resolve(), field, "")
    if not all(fst.has(k) for k in ("EDFile", "CompElast", "DT")):
        fst.refuse("is not an OpenFAST main input file (.fst): it has no EDFile, CompElast or DT line")
    fst.check("CompElast", fst.number("CompElast") == 1, "is not 1: only ElastoDyn's blades are read")
    dt = fst.number("DT")
    fst.check("DT", dt > 0, "is not positive")
    ed = _Input(fst.named("EDFile"), field, f"the ElastoDyn file {fst.name} names in EDFile")
    sources = {}

    def take(name: str, f: _Input, key: str, ok=lambda v: v > 0, what: str = "is not positive") -> float:
        value = f.number(key)
        f.check(key, ok(value), what)
        sources[name] = f"{f.name}: {key}"
        return value

    radius = take("radius", ed, "TipRad")
    hub_radius = take("hub_radius", ed, "HubRad", lambda v: 0 <= v < radius, "is not in [0, TipRad)")
    shaft_tilt, overhang = math.radians(ed.number("ShftTilt")), ed.number("OverHang")
    hub_height = ed.number("TowerHt") + ed.number("Twr2Shft") + overhang * math.sin(shaft_tilt)
    sources["hub_height"] = f"{ed.name}: TowerHt + Twr2Shft + OverHang sin(ShftTilt)"
    tilt = -shaft_tilt if overhang <= 0 else shaft_tilt
    sources["tilt"] = f"{ed.name}: ShftTilt ({'upwind' if overhang <= 0 else 'downwind'} rotor, OverHang)"
    hub_inertia = take("hub_inertia", ed, "HubIner")
    generator_inertia = take("generator_inertia", ed, "GenIner")
    gear_ratio = take("gear_ratio", ed, "GBRatio")
    efficiency = take("gearbox_efficiency", ed, "GBoxEff", lambda v: 0 < v <= 100, "is not in (0, 100] %") / 100
    stiffness = take("drivetrain_stiffness", ed, "DTTorSpr", lambda v: v >= 0, "is negative")
    damping = take("drivetrain_damping", ed, "DTTorDmp", lambda v: v >= 0, "is negative")

    inertia, sources["rotor_inertia"] = _rotor_inertia(ed, field, radius, hub_radius, hub_inertia)

    if fst.has("MHK") and fst.number("MHK") != 0:
        density = take("density", fst, "WtrDens")
    elif fst.has("AirDens"):
        density = take("density", fst, "AirDens")
    elif fst.has("CompAero") and fst.number("CompAero") != 0 and fst.has("AeroFile"):
        aero = _Input(fst.named("AeroFile"), field, f"the AeroDyn file {fst.name} names in AeroFile")
        density = take("density", aero, "AirDens")
    else:
        fst.refuse("has no AirDens line and names no AeroDyn file that would have one")

    library, infile, period, surface = _controller(fst, field, dt, with_surface, sources)
    sources["dt"] = f"{fst.name}: DT"
    return TurbineDeck(deck=fst.path, radius=radius, hub_radius=hub_radius, hub_height=hub_height, tilt=tilt,
                       density=density, rotor_inertia=inertia, hub_inertia=hub_inertia,
                       generator_inertia=generator_inertia, gear_ratio=gear_ratio, gearbox_efficiency=efficiency,
                       drivetrain_stiffness=stiffness, drivetrain_damping=damping, controller_library=library,
                       controller_input=infile, controller_period=period, surface=surface, dt=dt,
                       sources=sources)
