"""A rotor's power, thrust and torque coefficients over tip-speed ratio and blade pitch, and
the quasi-steady aerodynamic torque and thrust they give.

Definitions (rotor radius R, air density rho, rotor-effective wind speed V, rotor speed Omega,
collective blade pitch beta; IEC 61400-1 and ROSCO's performance tables):

    lambda = Omega R / V,  q_dyn = 1/2 rho pi R^2 V^2,
    P = q_dyn V Cp,  T = q_dyn Ct,  Q = q_dyn R Cq,  Cq = Cp / lambda.

The tables are read from ROSCO's ``Cp_Ct_Cq.*.txt`` (the NREL/TU Delft controller distributes
the NREL 5 MW one with its package): a pitch vector in degrees (converted to rad here), a
tip-speed-ratio vector, then the three coefficient blocks, one row per tip-speed ratio. A
coefficient between the grid points is the bilinear interpolant of its cell, so its slopes are
the cell's own finite differences: the aerodynamic damping ``-dQ/dOmega = -q_dyn R dCq/dlambda
R / V`` follows from the surface and is never added by hand. The torque comes from the Cq
table and the power is ``Q Omega``: ROSCO's NREL 5 MW table has its Cq computed on its own, and
it differs from Cp / lambda by 0.1 % near rated (0.4 % at the table's corner), so taking the
power from Cp would not be the work the torque does on the rotor. A point outside the table is
refused (:class:`assembly.errors.SceneError` naming the quantity): the surface says nothing
there. The lookup and the loads are the plain functions of :mod:`assembly.dynamics.rotor_laws`,
the time step's (Python's and the compiled one's) too.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import SceneError
from .jit import pick
from .rotor_laws import (
    DQ_DOMEGA,
    DQ_DPITCH,
    DQ_DWIND,
    DT_DOMEGA,
    DT_DWIND,
    N_OUT,
    PITCH_OUTSIDE,
    THRUST,
    TORQUE,
    TSR,
    TSR_OUTSIDE,
    bilinear,
    cell,
    rotor_law,
)

#: The three blocks of a ROSCO performance file, in their order
BLOCKS = ("power", "thrust", "torque")


@dataclass(frozen=True)
class RotorSurface:
    """Coefficient tables on ``tsr`` (n,) x ``pitch`` (k,) rad: ``cp``, ``ct``, ``cq`` (n, k);
    ``source`` the file read."""

    tsr: np.ndarray
    pitch: np.ndarray
    cp: np.ndarray
    ct: np.ndarray
    cq: np.ndarray
    source: str = ""


def read_surface(path, field: str = "turbine.surface") -> RotorSurface:
    """The :class:`RotorSurface` of a ROSCO ``Cp_Ct_Cq`` file (module notes); SceneError at
    ``field`` for a file that is missing or not one."""
    p = Path(path)
    try:
        lines = p.read_text(encoding="utf-8", errors="strict").splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(field, str(path), f"cannot be read ({type(exc).__name__})") from None
    heads = [i for i, s in enumerate(lines) if s.lstrip().startswith("#")]

    def after(word: str) -> int:
        for i in heads:
            if word in lines[i].lower():
                return i
        raise SceneError(field, str(path), f"has no '# ... {word} ...' header line: not a ROSCO Cp_Ct_Cq file")

    def numbers(i: int, what: str) -> np.ndarray:
        row = lines[i].split() if i < len(lines) else []
        try:
            out = np.array([float(x) for x in row])
        except ValueError:
            raise SceneError(field, str(path), f"line {i + 1} ({what}) is not a row of numbers") from None
        if not len(out) or not np.all(np.isfinite(out)):
            raise SceneError(field, str(path), f"line {i + 1} ({what}) has no finite numbers")
        return out

    i_pitch = after("pitch angle")
    if "(deg)" not in lines[i_pitch]:
        raise SceneError(field, str(path), f"line {i_pitch + 1}: the pitch vector's unit is not (deg)")
    pitch = np.radians(numbers(i_pitch + 1, "pitch angles"))
    tsr = numbers(after("tsr vector") + 1, "tip-speed ratios")
    for name, grid in (("pitch angles", pitch), ("tip-speed ratios", tsr)):
        if len(grid) < 2 or np.any(np.diff(grid) <= 0):
            raise SceneError(field, str(path), f"the {name} must be at least two, strictly increasing")
    stated = re.search(r"(\d+)\s+entries", lines[i_pitch])
    if stated and int(stated.group(1)) != len(pitch):
        raise SceneError(field, str(path), f"the pitch vector has {len(pitch)} entries, its header says "
                                           f"{stated.group(1)}")
    blocks = []
    for word in BLOCKS:
        i = after(f"{word} coefficient") + 1
        rows = []
        while len(rows) < len(tsr):
            if i >= len(lines):
                raise SceneError(field, str(path), f"the {word} coefficient block ends after {len(rows)} of "
                                                   f"{len(tsr)} rows")
            if lines[i].strip():
                row = numbers(i, f"{word} coefficients")
                if len(row) != len(pitch):
                    raise SceneError(field, str(path), f"line {i + 1}: {len(row)} {word} coefficients, "
                                                       f"{len(pitch)} pitch angles")
                rows.append(row)
            i += 1
        blocks.append(np.array(rows))
    cp, ct, cq = blocks
    return RotorSurface(tsr, pitch, cp, ct, cq, str(p))


def _cell(grid: np.ndarray, x: float, what: str, source: str) -> tuple[int, float]:
    """(i, u): ``x`` lies in [grid[i], grid[i+1]] at fraction u; SceneError outside the grid."""
    i, u = pick(cell)(np.asarray(grid, float), float(x))
    if i < 0:
        raise SceneError(what, x, f"outside the rotor surface's {grid[0]:.6g} .. {grid[-1]:.6g} ({source})")
    return i, u


def coefficients(s: RotorSurface, tsr: float, pitch: float) -> dict:
    """Bilinear ``cp``, ``ct``, ``cq`` at (``tsr``, ``pitch`` rad) and their slopes ``d*_dtsr``,
    ``d*_dpitch`` (per rad) inside the cell (module notes; :func:`assembly.dynamics.rotor_laws.bilinear`)."""
    i, u = _cell(s.tsr, float(tsr), "tip-speed ratio", s.source)
    j, w = _cell(s.pitch, float(pitch), "blade pitch (rad)", s.source)
    h, k = s.tsr[i + 1] - s.tsr[i], s.pitch[j + 1] - s.pitch[j]
    out = {}
    for name, C in (("cp", s.cp), ("ct", s.ct), ("cq", s.cq)):
        out[name], out[f"d{name}_dtsr"], out[f"d{name}_dpitch"] = pick(bilinear)(np.asarray(C, float), i, j, u, w,
                                                                                 float(h), float(k))
    return out


@dataclass(frozen=True)
class RotorLoads:
    """Quasi-steady rotor loads: ``torque`` Q (N m), ``thrust`` T (N), ``power`` Q Omega (W), the
    tip-speed ratio, and the slopes ``dq_domega`` (N m s/rad; its negative is the aerodynamic
    damping), ``dq_dwind`` (N m s/m), ``dq_dpitch`` (N m/rad), ``dt_domega``, ``dt_dwind``."""

    torque: float
    thrust: float
    power: float
    tsr: float
    dq_domega: float
    dq_dwind: float
    dq_dpitch: float
    dt_domega: float
    dt_dwind: float


def rotor_loads(s: RotorSurface, radius: float, density: float, wind: float, omega: float,
                pitch: float) -> RotorLoads:
    """The :class:`RotorLoads` at wind speed ``wind`` (m/s), rotor speed ``omega`` (rad/s) and
    pitch (rad) of a rotor of ``radius`` (m) in air of ``density`` (kg/m^3) (module notes): the
    law the time step calls (:func:`assembly.dynamics.rotor_laws.rotor_law`), its refusals named."""
    for name, x in (("turbine.radius", radius), ("turbine.air_density", density), ("wind speed", wind)):
        if not (math.isfinite(x) and x > 0.0):
            raise SceneError(name, x, "must be a positive number")
    out = np.zeros(N_OUT)
    status = pick(rotor_law)(*surface_arrays(s), float(radius), float(density), float(wind), float(omega),
                             float(pitch), out)
    if status == TSR_OUTSIDE:
        _cell(s.tsr, out[TSR], "tip-speed ratio", s.source)
    if status == PITCH_OUTSIDE:
        _cell(s.pitch, float(pitch), "blade pitch (rad)", s.source)
    return RotorLoads(torque=out[TORQUE], thrust=out[THRUST], power=out[TORQUE] * omega, tsr=out[TSR],
                      dq_domega=out[DQ_DOMEGA], dq_dwind=out[DQ_DWIND], dq_dpitch=out[DQ_DPITCH],
                      dt_domega=out[DT_DOMEGA], dt_dwind=out[DT_DWIND])


def surface_arrays(s: RotorSurface) -> tuple:
    """(tsr, pitch, cq, ct): the arrays the law reads (:func:`assembly.dynamics.rotor_laws.rotor_law`),
    C-ordered floats (one compiled signature)."""
    return tuple(np.ascontiguousarray(x, float) for x in (s.tsr, s.pitch, s.cq, s.ct))
