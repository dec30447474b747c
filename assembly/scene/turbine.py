"""Scene data of the turbine around the drivetrain (``[turbine]``): the rotor's aerodynamics,
the wind, the controller in the loop, and the turbine's frame (gravity, shaft tilt). Data only;
the physics is in :mod:`assembly.dynamics.turbine_run` and the modules it names. SI units: m,
kg, s, rad, m/s, m/s^2.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Literal, Optional

from fe_components.fields import quantity


def _angle(default=dataclasses.MISSING, **rule):
    return quantity("rad", default, angle=True, **rule)


@dataclass(frozen=True)
class Wind:
    """``[turbine.wind]``: the rotor-effective wind speed V(t), one of

    * ``speed`` alone: constant;
    * ``speed`` -> ``end_speed`` ramped from ``t_start`` to ``t_end`` (s);
    * ``steps = [[t, V], ...]``: V from t on (the first from t = 0);
    * ``table`` (CSV, ``time_column``, ``column``) or ``openfast`` (an output file's channel,
      e.g. ``RtVAvgxh`` or ``Wind1VelX``, in m/s), ``scale``, ``time_offset``, ``time_window``;
    * ``turbulence`` = "A", "B" or "C": IEC 61400-1 turbulence of that class about the mean
      ``speed`` at the hub (pyconturb, the ``wind`` extra), ``seed``, on a ``grid`` x ``grid``
      square of points over the rotor whose points inside the disc are averaged, sampled every
      ``sample`` s."""

    speed: Optional[float] = quantity("m/s", None, gt=0.0)
    end_speed: Optional[float] = quantity("m/s", None, gt=0.0)
    t_start: float = quantity("s", 0.0, ge=0.0)
    t_end: Optional[float] = quantity("s", None, gt=0.0)
    steps: Optional[tuple[tuple[float, float], ...]] = None
    turbulence: Optional[Literal["A", "B", "C"]] = None
    seed: int = quantity("", 1, integer=True, ge=0)
    grid: int = quantity("", 7, integer=True, ge=2, le=31)
    sample: float = quantity("s", 0.05, gt=0.0)
    table: Optional[str] = None
    openfast: Optional[str] = None
    column: Optional[str] = None
    time_column: str = "time"
    scale: float = quantity("", 1.0, gt=0.0)
    time_offset: float = quantity("s", 0.0)
    time_window: Optional[tuple[float, float]] = quantity("s", None)


@dataclass(frozen=True)
class Controller:
    """``[turbine.controller]``: what sets the generator torque and the blade pitch, called
    every ``period`` s (a whole number of the run's steps; default the deck's DLL_DT, else 0.01), its torque held in between.

    ``kind``: "rosco" (the compiled ROSCO controller of the installed ``rosco`` wheel with its
    NREL 5 MW ``DISCON.IN``, or ``input``), "discon" (any DISCON library ``library`` with its
    ``input`` file), "simple" (ServoDyn's simple variable-speed law: ``rated_speed`` rad/s and
    ``rated_torque`` N m of the generator, ``region2_k`` N m s^2/rad^2, ``slip`` fraction;
    pitch held) or "baseline" (the NREL 5 MW baseline torque law, pitch held). The pitch demand
    drives a first-order actuator of time constant ``pitch_tau`` (s; 0: the demand itself), or,
    given ``pitch_omega`` (rad/s), a second-order one of that natural frequency and damping
    ratio ``pitch_zeta``.
    ``efficiency``: the generator's, for the electrical power reported and measured."""

    kind: Literal["rosco", "discon", "simple", "baseline"] = "rosco"
    library: Optional[str] = None
    input: Optional[str] = None
    period: Optional[float] = quantity("s", None, gt=0.0)
    pitch_tau: float = quantity("s", 0.0, ge=0.0)
    pitch_omega: Optional[float] = quantity("rad/s", None, gt=0.0)
    pitch_zeta: float = quantity("", 0.7, gt=0.0, le=10.0)
    efficiency: float = quantity("", 0.944, gt=0.0, le=1.0)
    rated_speed: Optional[float] = quantity("rad/s", None, gt=0.0)
    rated_torque: Optional[float] = quantity("N m", None, gt=0.0)
    region2_k: Optional[float] = quantity("N m s^2/rad^2", None, ge=0.0)
    slip: Optional[float] = quantity("", None, gt=0.0, lt=1.0)


@dataclass(frozen=True)
class Turbine:
    """``[turbine]``: the turbine around the drivetrain in ``flexgear simulate`` (and gravity in
    ``static``). ``openfast``: an OpenFAST deck (``.fst``) the rotor radius, hub height, tilt,
    air density, controller library, ``DISCON.IN`` and performance surface are read from when
    not given here ("rosco": the NREL 5 MW deck of the installed ``rosco`` wheel). ``surface``: a ROSCO ``Cp_Ct_Cq`` file ("rosco": the NREL 5 MW surface of
    the installed ``rosco`` wheel); ``radius`` (m), ``density`` (kg/m^3, default 1.225),
    ``hub_height`` (m, for turbulence); ``rotor`` and ``generator``: the bodies (default those of
    role "rotor" and "generator"); ``generator_ratio``: the generator's speed per unit speed of
    that body (1: the body is the generator; N: a two-mass model's generator on the low-speed
    side, as ElastoDyn's GBRatio, so the controller sees and sets the high-speed shaft's speed
    and torque). ``pitch``: the blade pitch at t = 0 (rad). ``thrust``: the
    thrust acts along the rotor's axis. ``gravity``: gravity (9.80665 m/s^2, along -y) as a body
    load, the shaft ``tilt`` (rad) turning it about x. ``wind`` and ``controller``: the tables
    above; without ``wind`` the table gives the turbine's frame only (gravity and tilt)."""

    openfast: Optional[str] = None
    surface: Optional[str] = None
    radius: Optional[float] = quantity("m", None, gt=0.0)
    density: Optional[float] = quantity("kg/m^3", None, gt=0.0)
    hub_height: Optional[float] = quantity("m", None, gt=0.0)
    tilt: Optional[float] = _angle(None, ge=-0.5, le=0.5)
    rotor: Optional[str] = None
    generator: Optional[str] = None
    generator_ratio: float = quantity("", 1.0, gt=0.0)
    pitch: float = _angle(0.0, ge=-0.2, le=1.6)
    thrust: bool = True
    gravity: bool = False
    wind: Optional[Wind] = None
    controller: Optional[Controller] = None
