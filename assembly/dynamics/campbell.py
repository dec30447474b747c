"""Campbell diagram: natural frequencies and excitation orders over a speed range, and
where they cross.

Speeds are those of a reference body (rpm; default the body of role ``"rotor"``), every
other body turning at its ratio from the kinematic chain (:func:`assembly.analysis.drivetrain.speed_ratios`).

* Natural frequencies: without gyroscopic coupling they do not depend on speed and are
  solved once (:func:`assembly.analysis.modal.solve_modes`); with it they are solved at every speed
  (:mod:`assembly.dynamics.gyroscopic`), line j being the j-th lowest elastic frequency.
* Orders (:mod:`assembly.dynamics.orders`): mesh harmonics, their first sidebands, each stage's
  planet pass, each turning body's 1x, and the rotor orders 1P/3P/6P when the reference is a
  rotor.
* Crossings: where an order line f = a n meets natural-frequency line j: f_j(n) = a n.
  A speed-independent line f_0 crosses at n = f_0 / a exactly; a gyroscopic line is
  interpolated linearly between neighbouring speeds.
* Each crossing gets the crossed mode's class, scope and energy shares (:func:`classify_modes`
  of the non-spinning model, mode numbers as in ``flexgear modes``) and whether the order
  can excite that class: mesh orders of a planetary stage by Parker's phasing rule
  (:mod:`assembly.dynamics.phasing`) for modes of that stage (scope the stage, or global)
  in the classes the rule names; ``None`` where the rule says nothing (other classes,
  modes local to another part); parallel meshes and rotor orders: every class -- but never a
  mode its exciter holds no energy in (a mesh without strain in it, a rotor that does not turn
  in it: :mod:`assembly.dynamics.participation`), and crossings are ranked by that share.
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from .. import arguments
from ..analysis.classify import classify_modes
from ..analysis.drivetrain import speed_ratios
from ..analysis.modal import solve_modes
from ..errors import MechanismError, SceneError
from ..model.assemble import model_of, source_scene
from .budget import check_memory
from .gyroscopic import gyroscopic_matrix, whirl_frequencies
from .orders import ROTOR_ORDERS, Order, mesh_orders, planet_pass_orders, rotor_orders, shaft_orders, sideband_orders
from .participation import body_kinetic_shares, mesh_strain_shares, order_meshes, spin_kinetic_shares
from .phasing import RULE_CLASSES, excited_class

log = logging.getLogger(__name__)

RPM = 2 * math.pi / 60.0   # rad/s per rpm
#: Bytes an order line takes (its Order and label) and a pair of order and natural-frequency
#: line (the Crossing they may make, with its energy shares); measured: 360-440 B a crossing,
#: nrel5mw with 100-300 harmonics.
ORDER_BYTES, CROSSING_BYTES = 1024, 512
#: An exciter holding less than this share of a mode's energy takes no part in it: round-off of
#: mass-normalised shapes is some 1e-12, a mesh the mode does strain some 1e-3 and up.
NEGLIGIBLE = 1e-6


def check_size(points: int, harmonics: int, n_sources: int, n_lines: int) -> None:
    """SceneError at ``harmonics`` or ``points`` (the larger share) when a diagram of
    ``points`` speeds, ``n_lines`` natural-frequency lines and ``harmonics`` mesh harmonics of
    ``n_sources`` meshes and stages (each order may cross each line) exceeds the memory budget
    (:func:`assembly.dynamics.budget.check_memory`)."""
    n_orders = float(harmonics) * n_sources + len(ROTOR_ORDERS)
    by_orders = n_orders * (ORDER_BYTES + CROSSING_BYTES * n_lines)
    by_speeds = 8.0 * float(points) * (n_lines + 1)
    path, value = ("harmonics", harmonics) if by_orders >= by_speeds else ("points", points)
    check_memory(path, value, by_orders + by_speeds, f"{n_orders:.3g} order lines ({harmonics} harmonics x "
                 f"{n_sources} meshes and stages, {len(ROTOR_ORDERS)} rotor orders)"
                 + (f" crossing {n_lines} natural-frequency lines" if n_lines else "") + f" at {points} speeds",
                 "fewer harmonics or speeds")


@dataclass(frozen=True)
class Crossing:
    """An order line meeting a natural-frequency line: ``speed_rpm`` (reference body),
    ``frequency_hz``, ``mode`` (1-based, as in the mode table), its ``mode_class``,
    ``scope`` and ``energy`` ((group, kinetic share, strain share), largest first);
    ``excitable``: True / False by the phasing rule, None where the rule does not decide, and
    False where the exciter holds none of the mode's energy (``share`` below
    :data:`NEGLIGIBLE`); ``rule``: why. ``share``: how strongly the exciter takes part in the
    mode (:mod:`assembly.dynamics.participation`: a mesh order's meshes' share of its strain
    energy, a rotor order's spin share of its kinetic energy), by which crossings are ranked
    (:meth:`Campbell.ranked`)."""

    order: str
    harmonic: int
    speed_rpm: float
    frequency_hz: float
    mode: int
    mode_class: str
    scope: str | None
    energy: tuple
    excitable: bool | None
    rule: str
    share: float = 0.0


@dataclass(frozen=True)
class Campbell:
    """A Campbell diagram. ``frequencies_hz``: (len(speeds_rpm), n_lines) elastic natural
    frequencies (Hz) per speed, line j = mode ``modes[j].index + 1``; ``ratios``: body ->
    speed over the reference's; ``notes``: what was left out or assumed."""

    scene: str
    reference: str
    speeds_rpm: np.ndarray
    frequencies_hz: np.ndarray
    modes: tuple
    orders: tuple
    crossings: tuple
    ratios: dict
    gyroscopic: bool
    notes: tuple

    def ranked(self) -> list:
        """The crossings most likely to matter first: those the exciter can drive (excitable
        not False) by decreasing ``share``, then the rest; ties by speed."""
        return sorted(self.crossings, key=lambda x: (x.excitable is False, -x.share, x.speed_rpm))


def reference_body(scene, reference: str | None) -> str:
    """The reference body: ``reference`` if given (SceneError ``reference`` naming it when
    no body has that name), else the one body of role ``"rotor"``."""
    names = [b.name for b in scene.expanded().bodies]
    if reference is not None:
        return arguments.one_of("reference", reference, names)
    rotors = [b.name for b in scene.bodies if b.role == "rotor"]
    if len(rotors) != 1:
        raise SceneError("reference", None, f"{len(rotors)} bodies have role = 'rotor': name the reference "
                                              f"body (one of {names})")
    return rotors[0]


def check_speed_range(speed_range) -> tuple[float, float]:
    """(min, max) reference speeds (rpm): two numbers, >= 0, min < max; SceneError
    ``speed_range`` else."""
    if isinstance(speed_range, np.ndarray):
        speed_range = speed_range.tolist()
    if not isinstance(speed_range, (list, tuple)) or len(speed_range) != 2:
        raise arguments.refuse("speed_range", speed_range, "must be two speeds (min, max), rpm")
    lo, hi = (arguments.number(f"speed_range[{i}]", v, "rpm", ge=0.0, hint="the reference body's speed; the "
                               "sense of rotation does not change the diagram") for i, v in enumerate(speed_range))
    if lo >= hi:
        raise SceneError("speed_range", [lo, hi], "the minimum must be below the maximum")
    return lo, hi


def chain_ratios(model, reference: str) -> dict:
    """Speed ratios of the model's bodies to ``reference`` (SceneError naming ``SCENE`` when the
    model has no single rigid-body mode, ``--reference`` when that body stands still in it)."""
    try:
        return speed_ratios(model, reference)
    except MechanismError as exc:
        if "stands still" in str(exc):
            raise SceneError("reference", reference, f"{exc}: pick a body that turns with the chain") from None
        raise SceneError("SCENE", model.scene.name, f"no free chain to spin: {exc}") from None


def line_crossings(speeds, f_line, slope: float) -> list[tuple[float, float]]:
    """(speed, frequency) where the line ``f_line`` (Hz at ``speeds``, ascending rpm) meets the
    order line f = ``slope`` n. A speed-independent line f_0 crosses at n = f_0 / slope
    exactly (when in range); otherwise g = f_line - slope n is interpolated linearly between
    neighbouring speeds where it changes sign (a zero at a sample counts once)."""
    n = np.asarray(speeds, float)
    f = np.asarray(f_line, float)
    if slope <= 0:
        return []
    if np.all(f == f[0]):
        x = f[0] / slope
        return [(x, f[0])] if n[0] <= x <= n[-1] else []
    g = f - slope * n
    out = []
    for k in range(len(n)):
        if g[k] == 0:
            out.append((n[k], f[k]))
        elif k + 1 < len(n) and g[k] * g[k + 1] < 0:
            x = n[k] - g[k] * (n[k + 1] - n[k]) / (g[k + 1] - g[k])
            out.append((x, slope * x))
    return out


def phasing_verdict(order: Order, mode) -> tuple[bool | None, str]:
    """Whether ``order`` can excite ``mode`` (a :class:`assembly.analysis.classify.ModeInfo`) and why."""
    if order.kind != "mesh" or order.n_planets is None:
        return True, {"mesh": "every class", "rotor": "rotor order"}.get(order.kind, f"{order.kind} order")
    cls = excited_class(order.harmonic, order.sun_teeth, order.n_planets)
    rule = (f"Parker: h Z_s / N = {order.harmonic} x {order.sun_teeth} / {order.n_planets} -> {cls} only")
    if not order.equally_spaced:
        rule += " (planets not equally spaced: the rule does not hold)"
        return None, rule
    if mode.scope not in (order.stage, "global"):
        return None, rule + f"; mode local to {mode.scope}"
    if mode.mode_class not in RULE_CLASSES:
        return None, rule + f"; rule silent on {mode.mode_class} modes"
    return mode.mode_class == cls, rule


def campbell(model, speed_range, reference: str | None = None, points: int = 41, gyroscopic: bool = False,
             harmonics: int = 3) -> Campbell:
    """The Campbell diagram of ``model`` (an :class:`AssembledModel`, or a Scene assembled
    here) over ``speed_range`` (rpm of the reference body). ``points``: speeds sampled
    (>= 2); ``harmonics``: mesh harmonics 1..H (>= 1). Sizes over the memory budget are
    refused (:func:`check_size`) before a scene is assembled and again once the model's
    natural-frequency lines are known."""
    scene = source_scene("model", model)
    lo, hi = check_speed_range(speed_range)
    points, harmonics = arguments.integer("points", points, 2), arguments.integer("harmonics", harmonics, 1)
    arguments.flag("gyroscopic", gyroscopic)
    sources = len(scene.stages) + len(scene.meshes)
    check_size(points, harmonics, sources, 0)                  # before assembling: the orders alone
    ref = reference_body(scene, reference)
    model = model_of("model", model)
    ratios = chain_ratios(model, ref)
    res = solve_modes(model)
    info = classify_modes(res)[res.n_rigid:]
    check_size(points, harmonics, sources, len(info))
    speeds = np.linspace(lo, hi, int(points))
    notes = []
    if gyroscopic:
        F = np.array([whirl_frequencies(model.K, model.M, gyroscopic_matrix(
            model, {b: r * n * RPM for b, r in ratios.items()}), res.n_rigid) for n in speeds])
        notes.append("gyroscopic: each body's own spin (rigid-equivalent for flexible bodies: no gyroscopic or "
                     "spin-softening terms of their elastic motion); carrier-frame Coriolis terms neglected")
    else:
        F = np.tile(res.frequencies_hz[res.n_rigid:], (len(speeds), 1))
        notes.append("no gyroscopic coupling: natural frequencies do not depend on speed (solved once)")
    orders, skipped = mesh_orders(scene, ratios, int(harmonics))
    orders += sideband_orders(ratios, orders) + planet_pass_orders(scene, ratios) + shaft_orders(ratios)
    if any(b.role == "rotor" and b.name == ref for b in scene.bodies):        # rotor orders of a rotor only
        orders += rotor_orders(ref)
    notes += skipped
    notes += [f"{o.stage}: planets not equally spaced, Parker's phasing rule does not hold"
              for o in orders if o.equally_spaced is False and o.harmonic == 1]
    meshes = mesh_strain_shares(model, res)
    spin = spin_kinetic_shares(model, res, ref)
    rows = []
    for o in orders:
        names = order_meshes(o, meshes) if o.kind in ("mesh", "sideband", "planet-pass") else []
        if names:
            share, what = sum((meshes[m] for m in names), np.zeros(len(res.eigenvalues))), "its meshes hold"
        elif o.kind == "shaft":     # an unbalance on any body at this speed: their kinetic shares
            share = sum(body_kinetic_shares(model, res, b) for b in o.bodies)
            what = f"{', '.join(o.bodies)} hold"
        else:
            share, what = spin, f"{ref}'s spin holds"
        for j, mi in enumerate(info):
            for n, f in line_crossings(speeds, F[:, j], o.hz_per_rpm):
                ok, why = phasing_verdict(o, mi)
                x = float(share[mi.index])
                if ok is not False and x < NEGLIGIBLE:
                    ok, why = False, (f"{what} {x:.1e} of the mode's {'strain' if names else 'kinetic'} energy: "
                                      f"no modal force")
                energy = tuple(sorted(mi.energy, key=lambda e: -(e[1] + e[2]))[:3])
                rows.append(Crossing(o.name, o.harmonic, float(n), float(f), mi.index + 1, mi.mode_class,
                                     mi.scope, energy, ok, why, x))
    rows.sort(key=lambda c: (c.speed_rpm, c.frequency_hz))
    log.info("campbell %s: %d orders, %d lines, %d crossings", scene.name, len(orders), F.shape[1], len(rows))
    return Campbell(scene.name, ref, speeds, F, tuple(info), tuple(orders), tuple(rows), ratios, gyroscopic,
                    tuple(notes))
