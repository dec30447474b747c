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
from .history import span
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
    order label, order, excitation ("parametric" for a mesh order, else "additive"), mode
    class, Hz, passage speed and peak speed (rpm), peak, quasi-static level, amplification),
    ordered by output then passage speed; ``skipped`` {label: why}."""

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


def runup_orders(time_s, reference_speed, outputs: dict, orders: dict, modes, parametric=()) -> RunupOrders:
    """The :class:`RunupOrders` of ``outputs`` {name: history} over ``time_s`` with the
    reference's speed (rad/s) ``reference_speed``; ``modes``: (Hz, class) of the model's elastic
    modes. Each map reaches the highest order asked (x 1.1); an order the record cannot resolve
    (too few samples a revolution at the lowest speed) is skipped and said why. ``parametric``:
    the labels of mesh orders, whose quasi-static level is the parametric one
    (:func:`~assembly.dynamics.order_tracking.resonance_passages`: a varying mesh stiffness loads
    the drivetrain from inside, and at low speed its order vanishes as r^2 from every load)."""
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
            kind = "parametric" if label in parametric else "additive"
            for p in resonance_passages(cut, inside, parametric=kind == "parametric") if inside else []:
                passages.append({"output": name, "order_label": label, "order": o, "excitation": kind,
                                 "mode_class": p.mode_class,
                                 "frequency_hz": p.frequency_hz, "speed_rpm": p.speed * 30 / math.pi,
                                 "peak_speed_rpm": None if p.peak_speed is None else p.peak_speed * 30 / math.pi,
                                 "peak": p.peak, "quasi_static": p.quasi_static, "level_r": p.static_r,
                                 "amplification": p.amplification, "note": p.note})
    passages.sort(key=lambda d: (d["output"], d["speed_rpm"]))
    return RunupOrders(orders, maps, passages, skipped)


def run_orders(r, scene, track: str | None = None):
    """(reference, the ramp's slice of the record, :class:`RunupOrders`, the modes' (Hz, class)) of a
    run-up's result ``r`` (a
    :class:`~assembly.dynamics.simulate.SimulationResult` of ``scene`` with a
    ``[simulation.drive]``, its histories kept): every load asked for (not the speeds, nor the
    channels recorded for the life tables alone) tracked
    against the recorded speed of ``track`` (default the run's reference) over the ramp, the
    passages with the model's elastic modes; None when that speed was not recorded. A record too
    short for it raises SceneError (:func:`runup_orders`)."""
    from ..analysis.classify import classify_modes
    from ..analysis.modal import solve_modes
    from ..model.assemble import assemble

    ref = track or r.info.get("reference")
    key = f"speed:{ref}"
    if ref is None or key not in r.outputs:
        return None
    drive = scene.simulation.drive
    ramp = span(r.time_s, drive.t_start, drive.t_end)               # the sweep, not the settling
    skip = set(r.info.get("life_channels", ()))                      # read by the life tables alone
    outputs = {k: v[ramp] for k, v in r.outputs.items() if not k.startswith("speed:") and k not in skip}
    res = solve_modes(assemble(scene))
    info = classify_modes(res, nodal_diameters=False)
    modes = [(float(res.frequencies_hz[k]), info[k].label) for k in range(res.n_rigid, len(res.frequencies_hz))]
    orders = excitation_orders(r.mesh_frequencies_hz, r.shaft_speeds_hz, ref,
                               rotor=any(b.role == "rotor" and b.name == ref for b in scene.bodies))
    mesh = {f"{src} x{h}" for src in r.mesh_frequencies_hz for h in range(1, MESH_HARMONICS + 1)}
    return ref, ramp, runup_orders(r.time_s[ramp], r.outputs[key][ramp], outputs, orders, modes, mesh), modes


def largest_amplifications(ro: RunupOrders) -> dict:
    """{output: the passage of the largest amplification} (a passage dict of :class:`RunupOrders`;
    passages without a peak left out)."""
    out = {}
    for d in ro.passages:
        a = d["amplification"]
        if a is not None and math.isfinite(a) and (d["output"] not in out or a > out[d["output"]]["amplification"]):
            out[d["output"]] = d
    return out
