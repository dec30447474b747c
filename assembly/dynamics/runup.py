"""A run-up (``flexgear runup``): the drivetrain driven through a speed range at a given rate by
the speed-controlled drive of :mod:`assembly.dynamics.speed_drive`, every other setting of the
scene's ``[simulation]`` kept.

The reference body (or ``body``) starts at the range's first speed, is held there for ``settle``
seconds (the start's transients die out), ramps at ``rate`` to the last speed and is held there
``settle`` seconds more: the run lasts ``2 settle + |n_1 - n_0| / rate``. Its life tables
(:mod:`assembly.dynamics.life_tables`) count the ramp alone.
"""
from __future__ import annotations

import dataclasses
import math

from .. import arguments as check
from ..scene.time_domain import LifeTables, Simulation, SpeedDrive

RPM = math.pi / 30.0


def runup_length(speed_range_rpm, rate_rpm_s: float, settle_s: float) -> float:
    """The run's length (s) of the module notes; the range, rate and settling time checked."""
    if not (isinstance(speed_range_rpm, (list, tuple)) and len(speed_range_rpm) == 2):
        raise check.refuse("speed_range", speed_range_rpm, "must be two speeds (rpm): from, to")
    n0 = check.number("speed_range", speed_range_rpm[0], "rpm", ge=0.0)
    n1 = check.number("speed_range", speed_range_rpm[1], "rpm", ge=0.0)
    if n0 == n1:
        raise check.refuse("speed_range", list(speed_range_rpm), "from and to must differ")
    rate = check.number("rate", rate_rpm_s, "rpm/s", gt=0.0)
    settle = check.number("settle", settle_s, "s", ge=0.0)
    return 2.0 * settle + abs(n1 - n0) / rate


def runup_simulation(scene, speed_range_rpm, rate_rpm_s: float, body: str | None = None, bandwidth: float = 10.0,
                     settle_s: float = 1.0, shaft: str | None = None) -> Simulation:
    """The scene's ``[simulation]`` table (or the defaults) with the run-up's starting speed and
    drive (module notes); ``body`` the driven body (default the reference). Its life tables
    (``[simulation.life]`` or the defaults) count the ramp, the load revolutions of ``shaft``
    (default the table's, else the reference)."""
    runup_length(speed_range_rpm, rate_rpm_s, settle_s)
    n0, n1 = (float(x) for x in speed_range_rpm)
    bandwidth = check.number("bandwidth", bandwidth, "Hz", gt=0.0)
    if body is not None:
        check.one_of("body", body, [b.name for b in scene.expanded().bodies])
    sim = scene.simulation or Simulation()
    ramp = abs(n1 - n0) / float(rate_rpm_s)
    drive = SpeedDrive(end_speed=n1 * RPM, t_start=float(settle_s), t_end=float(settle_s) + ramp, body=body,
                       bandwidth=bandwidth)
    life = sim.life or LifeTables()
    life = dataclasses.replace(life, window=(drive.t_start, drive.t_end), shaft=shaft or life.shaft)
    return dataclasses.replace(sim, speed=n0 * RPM, reference=body if body is not None else sim.reference,
                               drive=drive, life=life)
