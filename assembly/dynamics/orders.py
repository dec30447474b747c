"""Excitation orders of a drivetrain: gear-mesh frequencies and rotor orders against speed.

Every order is a straight line through the origin, f = ``hz_per_rpm`` x n, with n the speed
of the reference body (rpm) and f in Hz. Body speeds come from the kinematic chain (the
model's rigid-body mode, :func:`assembly.analysis.drivetrain.speed_ratios`: n_i = ratio_i n).

* A gear mesh of gear teeth z_1 and z_2 whose gears ride in the frame F (the housing, or a
  planet carrier) engages teeth at f = z_1 |n_1 - n_F| / 60 = z_2 |n_2 - n_F| / 60 (Hz,
  speeds in rpm); harmonic h at h times that.
* A planetary stage: one order per harmonic for all its meshes, f = z_sun |n_sun - n_c| / 60
  (Willis: teeth times the speed relative to the carrier); with the ring fixed this is
  z_ring |n_c| / 60, and the planet-ring meshes have the same frequency.
* Rotor orders 1P, 3P, 6P: f = k n / 60 of the reference body (k = 1, 3, 6).
* Shaft orders: each turning body's 1x, f = |n_i| / 60 (bodies at one speed share a line).
* Planet pass of a stage: its N planets pass a point of the ring N |n_c - n_ring| / 60 times
  a second (a point of the sun: N |n_s - n_c| / 60).
* Mesh sidebands: a mesh's first harmonic modulated by its carrier (a stage: f_mesh +- |n_c -
  n_ring| / 60, a planet's once-round against the ring) or by the slower gear of a pair
  (f_mesh +- min|n_g| / 60).

A mesh without tooth counts on its gears (base radii only) counts the teeth of its stiffness
variation (``variation.teeth`` of its counting gear; a stage's sun: ``variation_sun.teeth``)
when it has one; else it has no mesh frequency: it is left out and named in the notes.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

from ..scene.gears import body_teeth
from ..scene.tables import HOUSING
from .phasing import equally_spaced

log = logging.getLogger(__name__)

#: Rotor orders drawn by default (blade passing of a three-bladed rotor: 3P, 6P).
ROTOR_ORDERS = (1, 3, 6)


@dataclass(frozen=True)
class Order:
    """One excitation line f = ``hz_per_rpm`` x n (Hz, n in rpm of the reference body).

    ``kind``: ``"mesh"`` or ``"rotor"``; ``source``: the mesh or stage name (mesh) or the
    reference body (rotor); ``harmonic``: h of a mesh order, k of a rotor order kP.
    ``teeth``: the tooth count the frequency counts; planetary stages also give
    ``sun_teeth``, ``n_planets`` and ``equally_spaced`` (Parker's phasing rule). ``bodies``:
    a gear pair's mesh order its two gears; a shaft order every body turning at its speed."""

    name: str
    kind: str
    source: str
    harmonic: int
    hz_per_rpm: float
    teeth: int | None = None
    stage: str | None = None
    sun_teeth: int | None = None
    n_planets: int | None = None
    equally_spaced: bool | None = None
    bodies: tuple = ()

    def frequency_hz(self, rpm):
        """Frequency (Hz) of the order at reference speed ``rpm``."""
        return self.hz_per_rpm * rpm


def _frame_ratio(ratios: dict, *bodies) -> float:
    """Speed ratio of the frame the gears ride in (0: the housing)."""
    frames = {b.frame for b in bodies if b.frame != HOUSING}
    return ratios[frames.pop()] if frames else 0.0


def mesh_orders(scene, ratios: dict, harmonics: int) -> tuple[list[Order], list[str]]:
    """Mesh orders (harmonics 1..``harmonics``) of every planetary stage and every
    ``[[meshes]]`` gear pair of ``scene`` with tooth counts, and notes on those without.
    ``ratios``: body name -> speed over the reference body's (signed)."""
    orders, notes = [], []
    for st in scene.stages:
        zs = st.sun.teeth
        if zs is None and st.variation_sun is not None:          # the sun-planet variation's count
            zs = st.variation_sun.teeth
        if zs is None:
            notes.append(f"stage {st.name}: no sun teeth, no mesh order")
            continue
        rel = abs(ratios[f"{st.name}.sun"] - ratios[f"{st.name}.carrier"])
        spaced = equally_spaced(st.planet_angles())
        for h in range(1, harmonics + 1):
            orders.append(Order(f"{st.name} mesh x{h}", "mesh", st.name, h, h * zs * rel / 60.0, zs, st.name,
                                zs, st.planets.count, spaced))
    index = {b.name: i for i, b in enumerate(scene.bodies)}
    for i, m in enumerate(scene.meshes):
        name = m.name or f"{m.gear1}-{m.gear2}"
        g1, g2 = scene.body(m.gear1), scene.body(m.gear2)
        teeth = [(g, t[1].n_teeth) for g in (g1, g2)
                 if (t := body_teeth(g, f"bodies[{index.get(g.name, '?')}]")) is not None]
        v = m.variation
        if not teeth and v is not None and v.teeth is not None:     # the stiffness variation's count
            teeth = [(g1 if v.counting_gear == "gear1" else g2, v.teeth)]
        if not teeth:
            notes.append(f"meshes[{i}] ({name}): no tooth counts, no mesh order")
            continue
        g, z = teeth[0]
        rel = abs(ratios[g.name] - _frame_ratio(ratios, g1, g2))
        stage = g1.stage if g1.stage == g2.stage else None
        for h in range(1, harmonics + 1):
            orders.append(Order(f"{name} mesh x{h}", "mesh", name, h, h * z * rel / 60.0, z, stage,
                                bodies=(m.gear1, m.gear2)))
    for o in orders:
        log.info("order %s: %.6g Hz/rpm", o.name, o.hz_per_rpm)
    return orders, notes


def rotor_orders(reference: str, multiples=ROTOR_ORDERS) -> list[Order]:
    """Rotor orders kP of the reference body: f = k n / 60 (Hz, n in rpm)."""
    return [Order(f"{k}P", "rotor", reference, k, k / 60.0) for k in multiples]


def shaft_orders(ratios: dict) -> list[Order]:
    """The 1x of every turning body (``ratios``: body -> speed over the reference's): f =
    |ratio| n / 60; bodies turning at the same speed (to 1e-9) share one line, named by the
    first, every one of them in its ``bodies`` (an unbalance on any of them drives it)."""
    lines: dict = {}
    for body, r in ratios.items():
        a = abs(r)
        if a == 0.0:
            continue
        key = next((b for b in lines if abs(a - b) <= 1e-9 * a), a)
        lines.setdefault(key, []).append(body)
    return [Order(f"{names[0]} 1x", "shaft", names[0], 1, a / 60.0, bodies=tuple(names))
            for a, names in lines.items()]


def planet_pass_orders(scene, ratios: dict) -> list[Order]:
    """Each planetary stage's planet pass: N |n_c - n_ring| / 60 (module notes)."""
    out = []
    for st in scene.stages:
        rel = abs(ratios[f"{st.name}.carrier"] - ratios[f"{st.name}.ring"])
        if rel > 0:
            out.append(Order(f"{st.name} planet pass", "planet-pass", st.name, 1, st.planets.count * rel / 60.0,
                             stage=st.name, n_planets=st.planets.count))
    return out


def sideband_orders(ratios: dict, mesh: list) -> list[Order]:
    """The first sidebands of each first mesh harmonic in ``mesh`` (:func:`mesh_orders`' orders):
    f_mesh -+ the modulation (module notes); a lower sideband at or below 0 is left out."""
    out = []
    for o in mesh:
        if o.harmonic != 1:
            continue
        if o.n_planets is not None:
            mod = abs(ratios[f"{o.stage}.carrier"] - ratios[f"{o.stage}.ring"]) / 60.0
        else:                                       # a pair: its slower gear
            mod = min(abs(ratios[g]) for g in o.bodies) / 60.0
        for sign, tag in ((-1, "-"), (1, "+")):
            f = o.hz_per_rpm + sign * mod
            if mod > 0 and f > 0:
                out.append(Order(f"{o.source} mesh x1 {tag}1", "sideband", o.source, 1, f, o.teeth, o.stage,
                                 o.sun_teeth, o.n_planets, o.equally_spaced))
    return out
