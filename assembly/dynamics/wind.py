"""The rotor-effective wind speed of a run: a series V(t) (m/s) that the rotor's aerodynamics
read (:mod:`assembly.dynamics.rotor_aero`) -- constant, steps, a ramp, a recorded series, or
turbulence generated to IEC 61400-1.

Turbulence comes from pyconturb (DTU's constrained-turbulence generator: the IEC Kaimal spectra
and exponential coherence, power-law shear; the ``wind`` extra, it needs pandas): the
longitudinal component on a square grid of points over the rotor disc, reproducible by seed.
The rotor-effective speed is the mean of the points inside the disc (equal weights: the grid's
points cover equal areas), so it keeps the disc's shear average and the part of the
turbulence coherent over the rotor; eddies smaller than the rotor average out, as they do on
the blades. A series is linear between its samples and refused outside them.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SceneError


@dataclass(frozen=True)
class WindSeries:
    """``time_s`` (k,) increasing and ``speed`` (k,) m/s; ``field`` names it in errors. Called
    as ``wind(t)``: linear between samples."""

    time_s: np.ndarray
    speed: np.ndarray
    field: str = "turbine.wind"

    def __post_init__(self):
        t, v = np.asarray(self.time_s, float), np.asarray(self.speed, float)
        if t.ndim != 1 or t.shape != v.shape or len(t) < 1:
            raise SceneError(self.field, f"{t.shape} times, {v.shape} speeds", "must be two series of one length")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))) or np.any(np.diff(t) <= 0):
            raise SceneError(self.field, "times", "must be finite and strictly increasing, the speeds finite")
        if np.any(v <= 0):
            raise SceneError(self.field, float(v.min()), "wind speeds must be positive (m/s)")
        object.__setattr__(self, "time_s", t)
        object.__setattr__(self, "speed", v)

    def __call__(self, t):
        t_arr = np.asarray(t, float)
        lo, hi = self.time_s[0], self.time_s[-1]
        if np.any(t_arr < lo - 1e-12 * max(1.0, abs(lo))) or np.any(t_arr > hi + 1e-12 * max(1.0, abs(hi))):
            raise SceneError(self.field, f"t = {float(np.max(t_arr)) if np.any(t_arr > hi) else float(np.min(t_arr)):g} s",
                             f"outside the wind series ({lo:g} .. {hi:g} s)")
        if len(self.time_s) == 1:
            return np.full(np.shape(t_arr), self.speed[0]) if np.ndim(t_arr) else float(self.speed[0])
        out = np.interp(t_arr, self.time_s, self.speed)
        return float(out) if np.ndim(t_arr) == 0 else out


def constant(speed: float, t_end: float, field: str = "turbine.wind") -> WindSeries:
    return WindSeries(np.array([0.0, t_end]), np.array([speed, speed]), field)


def steps(points, t_end: float, field: str = "turbine.wind") -> WindSeries:
    """Steps ``[(t_i, v_i), ...]``: v_i from t_i to the next (the first from t = 0)."""
    pts = sorted((float(a), float(b)) for a, b in points)
    if not pts:
        raise SceneError(field, points, "needs at least one (time, speed)")
    t, v = [0.0], [pts[0][1]]
    for (ti, vi) in pts[1:]:
        t += [ti, ti * (1 + 1e-12) + 1e-12]          # a jump within round-off of t_i
        v += [v[-1], vi]
    t.append(max(t_end, t[-1] + 1e-9))
    v.append(v[-1])
    return WindSeries(np.array(t), np.array(v), field)


def ramp(v0: float, v1: float, t0: float, t1: float, t_end: float, field: str = "turbine.wind") -> WindSeries:
    """``v0`` until ``t0``, linear to ``v1`` at ``t1``, then ``v1``."""
    if not (0.0 <= t0 < t1):
        raise SceneError(field, (t0, t1), "a ramp needs 0 <= t_start < t_end")
    t = [0.0, t0, t1, max(t_end, t1)]
    return WindSeries(np.array(sorted(set(t))), np.interp(sorted(set(t)), [t0, t1], [v0, v1]), field)


def iec_turbulence(mean: float, turb_class: str, radius: float, hub_height: float, t_end: float, dt: float,
                   seed: int, points: int = 7, field: str = "turbine.wind") -> WindSeries:
    """Rotor-effective IEC 61400-1 turbulence (module notes): ``mean`` wind speed at hub height
    (m/s), ``turb_class`` "A", "B" or "C", a ``points`` x ``points`` grid over the rotor's square,
    ``t_end`` s sampled every ``dt`` s, ``seed``."""
    try:
        from pyconturb import gen_spat_grid, gen_turb
    except ImportError:
        raise SceneError(field, "turbulence", "needs pyconturb (the wind extra: pip install pyconturb)") from None
    if turb_class not in ("A", "B", "C"):
        raise SceneError(f"{field}.class", turb_class, "must be A, B or C (IEC 61400-1)")
    c = np.linspace(-radius, radius, points)
    spat = gen_spat_grid(c, hub_height + c, comps=[0])
    nt = int(round(t_end / dt)) + 1
    turb = gen_turb(spat, T=nt * dt, nt=nt, u_ref=mean, z_ref=hub_height, turb_class=turb_class, seed=seed)
    yy, zz = np.meshgrid(c, c, indexing="ij")
    inside = (yy ** 2 + zz ** 2 <= radius ** 2).ravel()
    u = turb.values.reshape(nt, -1)
    return WindSeries(np.arange(nt) * dt, u[:, inside].mean(axis=1), field)
