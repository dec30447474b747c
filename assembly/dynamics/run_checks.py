"""What a time-domain run warns about before it starts: a step too long for the highest
mesh harmonic or the band, elastic modes in the band that nothing damps, a brake that will
chatter once stopped, and the mesh frequencies, shaft speeds and sidebands at the start
(which the result reports and the spectra mark).
"""
from __future__ import annotations

import math

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ..mechanics.nullity import rigid_body_count
from ..model.probes import spin_row
from .frf import UNDAMPED_ZETA
from .run_loads import brake_body, polar_inertia

#: Fewer steps than this per period of the highest mesh harmonic or of the band draw a
#: warning (average acceleration's period error W^2/12 is 3.3 % at 10 steps a period).
STEPS_PER_PERIOD = 10


def brake_warnings(model, scene, sim, dt: float, torques) -> list:
    """A warning when the trapezoidal rule will make a stopped brake's creep alternate: below
    the stick speed the brake is a damper T/stick on the braked body, whose decay stays
    positive only for dt < 2 J stick / T (J: the body's own inertia)."""
    if sim.brake is None or torques is None or torques.i_brake is None:
        return []
    J_b = polar_inertia(model, brake_body(model, scene, sim))
    if J_b > 0 and dt > 2 * J_b * sim.brake.stick_speed / sim.brake.torque:
        return [f"dt = {dt:g} s > 2 J stick_speed / torque = "
                f"{2 * J_b * sim.brake.stick_speed / sim.brake.torque:.3g} s: once stopped, the "
                "braked shaft's speed alternates in sign inside the stick band (raise "
                "simulation.brake.stick_speed or lower dt)"]
    return []


def mesh_frequencies(model, scene, v0: np.ndarray):
    """{mesh or stage: mesh frequency Hz} and {body: shaft speed Hz} at the starting speeds."""
    from .orders import mesh_orders
    speeds = {b: float(spin_row(model, b) @ v0) for b in model.bodies}
    ref = max(speeds, key=lambda b: abs(speeds[b])) if speeds else None
    if ref is None or speeds[ref] == 0.0:
        return {}, {}, {}
    ratios = {b: w / speeds[ref] for b, w in speeds.items()}
    rpm = speeds[ref] * 60 / (2 * math.pi)
    orders, _ = mesh_orders(scene, ratios, 1)
    shaft = {b: abs(w) / (2 * math.pi) for b, w in speeds.items()}
    side = {}
    for o in orders:                       # modulation: a stage's carrier, a pair's slower gear
        if o.stage is not None and f"{o.stage}.carrier" in shaft:
            side[o.source] = shaft[f"{o.stage}.carrier"]
        else:
            m = next((m for m in scene.meshes if (m.name or f"{m.gear1}-{m.gear2}") == o.source), None)
            side[o.source] = min(shaft[m.gear1], shaft[m.gear2]) if m is not None else 0.0
    return {o.source: abs(o.frequency_hz(rpm)) for o in orders}, shaft, side


def _steps(n: float) -> str:
    """Steps a period, rounded down to 0.1 (9.96 reads 9.9, never "10.0 ... below 10")."""
    return f"{math.floor(10 * n) / 10:.1f}"


def step_warnings(dt: float, freqs: dict, meshes, band_hz: float) -> list:
    """Warnings when ``dt`` gives fewer than :data:`STEPS_PER_PERIOD` steps per period of a
    nonlinear mesh's highest harmonic kept or of the band (Hz); a linear mesh (constant
    stiffness, no backlash) excites nothing at its mesh frequency."""
    out = []
    harmonics = {}
    for mi in meshes.info:
        key = mi.name.split(".")[0] if mi.name.split(".")[0] in freqs else mi.name
        harmonics[key] = max(harmonics.get(key, 1), mi.harmonics or 1)
    for src, f in freqs.items():
        if src not in harmonics:
            continue
        top = f * harmonics[src]
        if top > 0 and 1.0 / (dt * top) < STEPS_PER_PERIOD:
            out.append(f"dt = {dt:g} s gives {_steps(1 / (dt * top))} steps per period of {src}'s mesh harmonic "
                       f"{harmonics[src]} ({top:.4g} Hz): below {STEPS_PER_PERIOD}, the period error "
                       f"exceeds {100 * (2 * math.pi / STEPS_PER_PERIOD) ** 2 / 12:.1f} %")
    if 1.0 / (dt * band_hz) < STEPS_PER_PERIOD:
        out.append(f"dt = {dt:g} s gives {_steps(1 / (dt * band_hz))} steps per period at the band's top "
                   f"({band_hz:g} Hz): modes there are not resolved")
    return out


def undamped_band(model, M, K, C, band_hz: float) -> list:
    """A warning naming the elastic modes up to ``band_hz`` (of a reduced, dense model) that
    no damper or ratio damps: a run started or driven at them rings without decay. Only the
    modes below the band are solved (a dense subset solve)."""
    if sp.issparse(K) or K.shape[0] == 0 or not band_hz > 0:
        return []
    r = rigid_body_count(model)
    lam, Phi = sla.eigh(K, M, subset_by_value=(-np.inf, (2 * np.pi * band_hz) ** 2))
    if lam.size <= r:
        return []
    lam, Phi = lam[r:], Phi[:, r:]
    fr = np.sqrt(np.maximum(lam, 0.0)) / (2 * np.pi)
    c = np.einsum("ij,ij->j", Phi, C @ Phi)                            # phi' C phi (C >= 0; phi' M phi = 1)
    zeta = c / (2 * 2 * np.pi * np.maximum(fr, 1e-300))
    bad = np.flatnonzero(zeta < UNDAMPED_ZETA)
    if not bad.size:
        return []
    names = ", ".join(f"{r + i + 1} ({fr[i]:.6g} Hz)" for i in bad[:8]) + (" ..." if bad.size > 8 else "")
    return [f"{bad.size} mode(s) in the band (to {band_hz:g} Hz) have no damping: {names}; they ring without "
            "decay (add element dampers or a [damping] table)"]
