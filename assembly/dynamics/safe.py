"""Interference (SAFE) diagram of a planetary stage: mesh harmonics and modes by phase index.

Singh's SAFE diagram (after the turbomachinery "Singh's Advanced Frequency Evaluation"), with
the planetary phasing of Parker (2000, J. Sound Vib. 236(4), 561-573) and Parker & Lin (2004,
J. Mech. Des. 126, 365-370): for N equally spaced planets (psi_n = 2 pi n / N) and a sun of
Z_s teeth, harmonic l of the mesh force of planet n lags planet 0's by l Z_s psi_n, so the N
mesh forces of harmonic l form a travelling wave of **phase index** (nodal diameter over the
planets) k_l = (l Z_s) mod N, in 0..N-1; k and N - k (the symmetric -k) are the same standing
pattern, drawn at |k| = min(k, N - k). The planet-ring meshes give the same index: equally
spaced planets assemble only when Z_s + Z_r is a multiple of N (Z_r = -Z_s mod N), whichever
member is held.

A mode of the stage sits at the indices its motion over the planets has (Lin & Parker 1999,
J. Vib. Acoust. 121, 316-321; :mod:`assembly.analysis.classify` for the classes):

* rotational modes at k = 0, translational at k = +-1, planet modes at every other index
  (2..N-2: the class does not tell which; none for N = 3);
* an elastic mode of a flexible sun, ring or carrier of the stage with n nodal diameters at
  k = +-(n mod N) (N equally spaced point loads of index k load the circumferential waves
  n = k (mod N));
* other modes (out-of-plane, mixed, modes local to another part) get no index and are not
  placed; neither is any mode of a stage whose planets are not equally spaced.

An **interference** is a crossing of a stage mesh harmonic with a mode (the Campbell
diagram's, :mod:`assembly.dynamics.campbell`, at the crossing's speed and frequency) whose
index set holds the harmonic's index and whose stage meshes hold a share of the mode's strain
energy (:data:`assembly.dynamics.campbell.NEGLIGIBLE` and up): the crossings the Campbell
ranks as drivable with a share, Parker's rule read as an index match. A placed mode at another
index is ruled out (Parker). As a band: over the speed range harmonic l spans
l f_m(n_min)..l f_m(n_max) at its index; Singh's zig-zag line is the order line f = nu f_m / Z_s
of the carrier-relative order nu (nu = l Z_s at harmonic l) drawn at its folded index
(:func:`zigzag`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import arguments
from .campbell import NEGLIGIBLE, Campbell
from .phasing import excited_class

#: Central members (body ``STAGE.member``) whose elastic nodal-diameter modes are placed.
CENTRAL = ("sun", "ring", "carrier")
INTERFERENCE = "interference"


def phase_index(harmonic: int, sun_teeth: int, n_planets: int) -> int:
    """k = (``harmonic`` Z_s) mod N, in 0..N-1 (module notes)."""
    return harmonic * sun_teeth % n_planets


def folded(k, n_planets: int):
    """|k| of the symmetric form: min(k mod N, N - k mod N), for ints or arrays of reals."""
    r = np.mod(k, n_planets)
    return np.minimum(r, n_planets - r)


def class_indices(mode_class: str, n_planets: int) -> tuple[int, ...]:
    """Phase indices (0..N-1) of a rigid-member class: rotational 0, translational +-1,
    planet the others (Lin & Parker 1999); () for any other class. Consistent with
    :func:`assembly.dynamics.phasing.excited_class`: r = (h Z_s) mod N excites class c exactly when r
    is in ``class_indices(c, N)``."""
    n = n_planets
    if mode_class == "rotational":
        return (0,)
    if mode_class == "translational":
        return tuple(sorted({k for k in (1, n - 1) if 0 < k < n}))
    if mode_class == "planet":
        return tuple(k for k in range(n) if k not in (0, 1, n - 1))
    return ()


def mode_indices(mode, stage: str, n_planets: int) -> tuple[int, ...]:
    """Phase indices of ``mode`` (a :class:`assembly.analysis.classify.ModeInfo`) on the diagram
    of ``stage`` (module notes): its class's, for a mode of that stage or a global one; +-(n
    mod N) for an elastic n-nodal-diameter mode of one of the stage's central members."""
    if mode.mode_class == "elastic":
        nd = mode.nodal_diameters
        if nd is None or mode.body not in {f"{stage}.{m}" for m in CENTRAL}:
            return ()
        r = nd % n_planets
        return tuple(sorted({r, (-r) % n_planets}))
    if mode.scope not in (stage, "global"):
        return ()
    return class_indices(mode.mode_class, n_planets)


def zigzag(nu_max: float, n_planets: int) -> tuple[np.ndarray, np.ndarray]:
    """Singh's zig-zag: (nu, |k|) at the vertices of the folded order line, carrier-relative
    order nu from 0 to ``nu_max`` (a vertex every N / 2 orders, where the fold turns);
    frequency f = nu f_m / Z_s at mesh frequency f_m."""
    half = n_planets / 2.0
    nu = np.append(np.arange(0.0, nu_max, half), nu_max)
    return nu, folded(nu, n_planets)


@dataclass(frozen=True)
class SafeExcitation:
    """Mesh harmonic ``harmonic`` (Campbell order ``order``, f = ``hz_per_rpm`` n) at phase
    index ``index`` (0..N-1); ``excites``: the class Parker's rule names."""

    order: str
    harmonic: int
    index: int
    hz_per_rpm: float
    excites: str


@dataclass(frozen=True)
class SafeMode:
    """Mode ``mode`` (1-based, as in the mode table) at ``frequency_hz`` (not spinning), its
    class ``label`` and phase ``indices`` (0..N-1; empty: not placed)."""

    mode: int
    frequency_hz: float
    label: str
    indices: tuple


@dataclass(frozen=True)
class SafeRow:
    """A crossing of a stage mesh harmonic with a mode, judged on the diagram: ``verdict`` is
    :data:`INTERFERENCE`, ``"ruled out"`` (index mismatch, or no modal force) or
    ``"no index"`` (the mode is not placed); ``why`` says so. ``excitable``: the Campbell
    verdict of the same crossing (True / False / None)."""

    order: str
    harmonic: int
    index: int
    mode: int
    mode_class: str
    mode_indices: tuple
    frequency_hz: float
    speed_rpm: float
    share: float
    verdict: str
    why: str
    excitable: bool | None


@dataclass(frozen=True)
class SafeDiagram:
    """The SAFE diagram of planetary stage ``stage``: N planets of a sun of ``sun_teeth``
    teeth, mesh order f_m = ``mesh_hz_per_rpm`` n, over ``speed_range_rpm``; its
    ``excitations`` (mesh harmonics), ``modes`` (every elastic mode, placed or not) and
    ``rows`` (every crossing of its mesh harmonics, judged); ``notes``."""

    stage: str
    n_planets: int
    sun_teeth: int
    equally_spaced: bool
    mesh_hz_per_rpm: float
    speed_range_rpm: tuple
    excitations: tuple
    modes: tuple
    rows: tuple
    notes: tuple

    @property
    def interferences(self) -> tuple:
        """The rows that are interferences, by speed."""
        return tuple(r for r in self.rows if r.verdict == INTERFERENCE)


def judge(index: int, indices: tuple, share: float, equal: bool, stage_planet_mode: bool = False) -> tuple[str, str]:
    """(verdict, why) of a harmonic at ``index`` meeting a mode at ``indices`` whose stage
    meshes hold ``share`` of its strain energy (module notes); ``stage_planet_mode``: the mode
    is a planet mode of the stage (left without an index only when N <= 3)."""
    if not equal:
        return "no index", "planets not equally spaced: no phase index"
    if not indices and stage_planet_mode:
        return "ruled out", "Parker: N <= 3 leaves planet modes no phase index (k = 0, +-1 only)"
    if not indices:
        return "no index", "mode not placed (its class or scope has no phase index here)"
    at = ", ".join(str(k) for k in indices)
    if index not in indices:
        return "ruled out", f"Parker: harmonic at k = {index}, mode at k = {at}"
    if share < NEGLIGIBLE:
        return "ruled out", f"index matches (k = {index}) but the stage meshes hold {share:.1e} of its strain energy"
    return INTERFERENCE, f"k = {index} on the mode's index; meshes hold {share:.3g} of its strain energy"


def _campbell(c) -> Campbell:
    return arguments.instance("campbell", c, Campbell, "a Campbell diagram (assembly.dynamics.campbell.campbell)")


def stage_diagram(c: Campbell, stage: str) -> SafeDiagram:
    """The SAFE diagram of ``stage`` from the Campbell diagram ``c`` (its mesh orders, modes and
    crossings). SceneError naming ``stage`` when ``c`` has no mesh order of that stage (not a
    planetary stage, or no sun teeth)."""
    have = _stages(_campbell(c))
    arguments.one_of("stage", stage, have, "planetary stage with a mesh order")
    mesh = [o for o in c.orders if o.kind == "mesh" and o.stage == stage and o.n_planets is not None]
    n, zs, equal = mesh[0].n_planets, mesh[0].sun_teeth, bool(mesh[0].equally_spaced)
    exc = tuple(SafeExcitation(o.name, o.harmonic, phase_index(o.harmonic, zs, n), o.hz_per_rpm,
                               excited_class(o.harmonic, zs, n)) for o in mesh)
    by_order = {e.order: e for e in exc}
    modes = tuple(SafeMode(m.index + 1, m.frequency_hz, m.label, mode_indices(m, stage, n) if equal else ())
                  for m in c.modes)
    placed = {m.mode: m for m in modes}
    own_planet = {m.index + 1 for m in c.modes if m.mode_class == "planet" and m.scope in (stage, "global")}
    rows = []
    for x in c.crossings:
        e = by_order.get(x.order)
        if e is None:
            continue
        ind = placed[x.mode].indices
        verdict, why = judge(e.index, ind, x.share, equal, x.mode in own_planet)
        rows.append(SafeRow(x.order, x.harmonic, e.index, x.mode, x.mode_class, ind, x.frequency_hz, x.speed_rpm,
                            x.share, verdict, why, x.excitable))
    notes = []
    if not equal:
        notes.append(f"{stage}: planets not equally spaced: the phase index and Parker's rule do not hold")
    if n <= 3:
        notes.append(f"{stage}: N = {n} leaves no index for planet modes (k = 0, +-1 only): no harmonic excites them")
    unplaced = sum(1 for m in modes if not m.indices)
    if equal and unplaced:
        notes.append(f"{stage}: {unplaced} of {len(modes)} modes not placed (out-of-plane, mixed, local to another "
                     f"part, or elastic without a nodal-diameter count)")
    if c.gyroscopic:
        notes.append("modes drawn at their non-spinning frequency; crossings at the gyroscopic lines'")
    return SafeDiagram(stage, n, zs, equal, mesh[0].hz_per_rpm / mesh[0].harmonic,
                       (float(c.speeds_rpm[0]), float(c.speeds_rpm[-1])), exc, modes,
                       tuple(sorted(rows, key=lambda r: (r.verdict != INTERFERENCE, r.speed_rpm, r.mode))),
                       tuple(notes))


def _stages(c: Campbell) -> list:
    """The planetary stages with a mesh order in ``c``, in scene order."""
    return list(dict.fromkeys(o.stage for o in c.orders if o.kind == "mesh" and o.n_planets is not None))


def safe_diagrams(c: Campbell) -> tuple:
    """One :class:`SafeDiagram` per planetary stage of ``c`` (a :class:`Campbell`) that has a
    mesh order, in scene order."""
    return tuple(stage_diagram(c, s) for s in _stages(_campbell(c)))
