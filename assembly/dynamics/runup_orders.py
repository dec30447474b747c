"""The orders of a run-up (``flexgear runup``): every recorded output tracked by order against the
driven reference's integrated angle (:mod:`assembly.dynamics.order_tracking`), the excitation
orders of the drivetrain cut out of it, and the resonance passages of each order with the
model's natural frequencies in the swept range.

Orders are counted per revolution of the reference: a gear mesh of f_mesh Hz when the reference
turns at f_ref has order f_mesh / f_ref (the same at every speed: the kinematic chain is fixed),
its harmonics 1-3 (:data:`MESH_HARMONICS`); the rotor orders 1P and 3P; each distinct shaft
speed's 1x. The reference's angle is the trapezoidal integral of its recorded speed
(:func:`assembly.dynamics.order_tracking.shaft_angle`: its rotation coordinate itself under the
average-acceleration scheme).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SceneError
from .order_tracking import angle_grid, order_cut, order_map, resonance_passages, revolution_samples, shaft_angle

#: Mesh harmonics tracked.
MESH_HARMONICS = 3
#: Blocks of an order map: revolutions of the tracked shaft (fewer on a short record), and the
#: fewest blocks over the run.
REVOLUTIONS = 8
BLOCKS = 8


@dataclass(frozen=True)
class RunupOrders:
    """``orders`` {label: order}; ``maps`` {output: OrderMap}; ``passages``: dicts (output,
    order label, order, mode, class, Hz, passage speed and peak speed (rpm), peak, quasi-static
    level, amplification), ordered by output then passage speed; ``skipped`` {label: why}."""

    orders: dict
    maps: dict
    passages: list
    skipped: dict


def excitation_orders(mesh_hz: dict, shaft_hz: dict, reference: str, rotor: bool = True) -> dict:
    """{label: order per reference revolution} of the run's meshes (``mesh_hz`` {stage or mesh:
    Hz at the start}), shafts (``shaft_hz`` {body: rev/s}) and, with ``rotor``, 1P and 3P."""
    f_ref = abs(shaft_hz.get(reference, 0.0))
    if f_ref <= 0:
        return {}
    out = {}
    if rotor:
        out.update({"1P": 1.0, "3P": 3.0})
    seen = [1.0]
    for body, f in shaft_hz.items():
        o = abs(f) / f_ref
        if o > 0 and all(abs(o - s) > 1e-9 * o for s in seen):
            seen.append(o)
            out[f"{body} 1x"] = o
    for src, f in mesh_hz.items():
        for h in range(1, MESH_HARMONICS + 1):
            out[f"{src} x{h}"] = h * f / f_ref
    return out


def runup_orders(time_s, reference_speed, outputs: dict, orders: dict, modes) -> RunupOrders:
    """The :class:`RunupOrders` of ``outputs`` {name: history} over ``time_s`` with the
    reference's speed (rad/s) ``reference_speed``; ``modes``: (Hz, class) of the model's elastic
    modes. Each map reaches the highest order asked (x 1.1); an order the record cannot resolve
    (too few samples a revolution at the lowest speed) is skipped and said why."""
    t = np.asarray(time_s, float)
    w = np.abs(np.asarray(reference_speed, float))
    angle = shaft_angle(t, w)
    fs = 1.0 / float(t[1] - t[0])
    lowest = float(w.min()) / (2 * math.pi)                 # rev/s
    # an order of f_o = order x rev/s needs fs >= 4 f_o at the slowest speed for the spline (module
    # notes of order_tracking: 8 % at fs / f = 4)
    limit = fs / (4.0 * lowest) if lowest > 0 else 0.0
    keep = {k: o for k, o in orders.items() if o <= limit}
    skipped = {k: f"order {o:.4g} above the record's {limit:.4g} (dt too long at the slowest speed)"
               for k, o in orders.items() if o > limit}
    maps, passages = {}, []
    turns = float(angle[-1] - angle[0]) / (2 * math.pi)
    # blocks of REVOLUTIONS turns, fewer on a short record: at least BLOCKS of them over the run
    revs = min(REVOLUTIONS, int(turns // BLOCKS))
    if revs < 1:
        raise SceneError("track", f"{turns:.3g} revolutions", f"too few for order tracking ({BLOCKS} blocks of a "
                                                               f"revolution at least): track a faster shaft or run "
                                                               f"longer")
    for k, o in list(keep.items()):
        if o * revs < 2:
            skipped[k] = f"order {o:.4g}: fewer than 2 cycles in a block of {revs} revolutions"
            del keep[k]
    if not keep:
        return RunupOrders(orders, maps, passages, skipped)
    top = 1.1 * max(keep.values())
    pairs = [(float(f), str(c)) for f, c in modes if f > 0]
    grid = angle_grid(t, angle, revolution_samples(top))        # the instants of equal angle, once for every output
    for name, y in outputs.items():
        omap = order_map(t, angle, np.asarray(y, float), max_order=top, revolutions=revs,
                         lowest_order=min(keep.values()), grid=grid)
        maps[name] = omap
        for label, o in keep.items():
            cut = order_cut(omap, o)
            lo, hi = float(cut.speed.min()), float(cut.speed.max())
            inside = [(f, c) for f, c in pairs if lo <= 2 * math.pi * f / o <= hi]
            for p in resonance_passages(cut, inside) if inside else []:
                passages.append({"output": name, "order_label": label, "order": o, "mode_class": p.mode_class,
                                 "frequency_hz": p.frequency_hz, "speed_rpm": p.speed * 30 / math.pi,
                                 "peak_speed_rpm": None if p.peak_speed is None else p.peak_speed * 30 / math.pi,
                                 "peak": p.peak, "quasi_static": p.quasi_static, "amplification": p.amplification})
    passages.sort(key=lambda d: (d["output"], d["speed_rpm"]))
    return RunupOrders(orders, maps, passages, skipped)
