"""Generator-torque laws of a variable-speed wind turbine without a controller library: the
torque a function of the (filtered) generator speed, in the regions of Jonkman et al.,
NREL/TP-500-38060 (2009), section 7.4, and of ServoDyn's simple variable-speed control.

Speeds here are the generator's (high-speed side), rad/s; torques N m.

* :func:`simple_torque` -- ServoDyn's simple law (its ``VSContrl = 1``: ``VS_RtGnSp``,
  ``VS_RtTq``, ``VS_Rgn2K``, ``VS_SlPc``): region 2, ``k w^2``, below the transition speed;
  region 2 1/2, the line of an induction generator with ``slip`` through its synchronous speed
  ``w_sync = w_rated / (1 + slip)`` and through the rated torque at rated speed; region 3, the
  rated torque at and above rated speed. The transition speed is where the parabola meets the
  line (the smaller root of ``k w^2 = m (w - w_sync)``), so the law is continuous.
* :func:`baseline_torque` -- the NREL 5 MW baseline controller's law: region 1 (no torque up to
  cut-in), region 1 1/2 (a line from cut-in to the start of region 2, continuous with it),
  region 2, region 2 1/2 (the slip line to rated *power* at rated speed), region 3 (rated power
  over speed, also once the blades pitch past ``rgn3_pitch``), capped at ``max_torque``. The
  controller's rate limit and speed filter are its own state; they are not part of the law.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import SceneError
from .discon import DisconOutput

#: rpm -> rad/s
RPM = math.pi / 30.0


def meeting_speed(k: float, slope: float, sync: float) -> float:
    """The speed where region 2's ``k w^2`` meets the slip line ``slope (w - sync)``: the lower
    root of ``k w^2 - slope w + slope sync = 0`` (``sync`` when k = 0)."""
    if k == 0.0:
        return sync
    return (slope - math.sqrt(slope * (slope - 4.0 * k * sync))) / (2.0 * k)


@dataclass(frozen=True)
class SimpleVariableSpeed:
    """ServoDyn's simple law (module notes): ``rated_speed`` (rad/s), ``rated_torque`` (N m),
    ``k`` (N m s^2/rad^2), ``slip`` (fraction, 0.1 = 10 %)."""

    rated_speed: float
    rated_torque: float
    k: float
    slip: float

    def __post_init__(self):
        # ServoDyn's rule: region 2's k omega^2 meets the slip line below rated, so the torque
        # rises to the rated torque without a jump (VS_Rgn2K VS_RtGnSp^2 < VS_RtTq, and the
        # crossing exists: its discriminant m (m - 4 k w_sync) >= 0)
        m, ws = self.slope, self.sync_speed
        if not (self.k * self.rated_speed ** 2 < self.rated_torque and m * (m - 4.0 * self.k * ws) >= 0.0):
            raise SceneError("turbine.controller.region2_k", self.k,
                             f"k x rated_speed^2 = {self.k * self.rated_speed ** 2:.6g} N m must stay below the rated "
                             f"torque {self.rated_torque:.6g} N m and meet the slip line (ServoDyn's simple law)")

    @property
    def sync_speed(self) -> float:
        return self.rated_speed / (1.0 + self.slip)

    @property
    def slope(self) -> float:
        return self.rated_torque / (self.rated_speed - self.sync_speed)

    @property
    def transition_speed(self) -> float:
        """Where ``k w^2`` meets the slip line (ServoDyn's ``VS_TrGnSp``)."""
        return meeting_speed(self.k, self.slope, self.sync_speed)


def simple_torque(law: SimpleVariableSpeed, speed: float) -> float:
    """The generator torque at generator ``speed`` (rad/s) by :class:`SimpleVariableSpeed`."""
    if speed >= law.rated_speed:
        return law.rated_torque
    if speed < law.transition_speed:
        return law.k * speed * speed
    return law.slope * (speed - law.sync_speed)


@dataclass(frozen=True)
class BaselineVariableSpeed:
    """The baseline law (module notes): speeds rad/s (``cut_in``, ``region2_start``,
    ``rated_speed``), ``rated_power`` W, ``k`` N m s^2/rad^2, ``slip`` fraction, ``max_torque``
    N m, ``rgn3_pitch`` rad (the pitch beyond which region 3 holds whatever the speed)."""

    cut_in: float
    region2_start: float
    rated_speed: float
    rated_power: float
    k: float
    slip: float
    max_torque: float
    rgn3_pitch: float

    @property
    def sync_speed(self) -> float:
        return self.rated_speed / (1.0 + self.slip)

    @property
    def slope15(self) -> float:
        return self.k * self.region2_start ** 2 / (self.region2_start - self.cut_in)

    @property
    def slope25(self) -> float:
        return (self.rated_power / self.rated_speed) / (self.rated_speed - self.sync_speed)

    @property
    def transition_speed(self) -> float:
        return meeting_speed(self.k, self.slope25, self.sync_speed)


def baseline_torque(law: BaselineVariableSpeed, speed: float, pitch: float = 0.0) -> float:
    """The generator torque at generator ``speed`` (rad/s) and blade ``pitch`` (rad) by
    :class:`BaselineVariableSpeed` (before the controller's rate limit)."""
    if speed >= law.rated_speed or pitch >= law.rgn3_pitch:
        torque = law.rated_power / speed
    elif speed <= law.cut_in:
        torque = 0.0
    elif speed < law.region2_start:
        torque = law.slope15 * (speed - law.cut_in)
    elif speed < law.transition_speed:
        torque = law.k * speed * speed
    else:
        torque = law.slope25 * (speed - law.sync_speed)
    return min(torque, law.max_torque)


#: The NREL 5 MW baseline law (Jonkman et al. 2009, section 7.4 and its DISCON source): cut-in
#: 670 rpm, region 2 from 871 rpm, rated 1161.963 rpm, 5.29661 MW, k = 2.332287 N m/(rad/s)^2
#: (0.0255764 N m/rpm^2), slip 10 %, torque cap 47 402.91 N m, region 3 from 1 deg of pitch.
NREL5MW_BASELINE = BaselineVariableSpeed(cut_in=670.0 * RPM, region2_start=871.0 * RPM,
                                         rated_speed=1161.963 * RPM, rated_power=5296610.0, k=2.332287,
                                         slip=0.10, max_torque=47402.91, rgn3_pitch=math.radians(1.0))


class TorqueLawController:
    """A controller without a library: the generator torque from ``law`` (a
    :class:`SimpleVariableSpeed` or :class:`BaselineVariableSpeed`) at the measured generator
    speed, the pitch held at ``pitch`` (rad; ServoDyn with its pitch control off). It has the
    :meth:`step` of :class:`assembly.dynamics.discon.Discon`, so
    :class:`assembly.dynamics.turbine_loop.ControllerLoop` calls it at its sample time alike."""

    def __init__(self, law, pitch: float = 0.0):
        self.law, self.pitch = law, float(pitch)
        self.calls, self.times = 0, []

    def step(self, t, dt, generator_speed, rotor_speed, pitch, generator_torque, wind, power=0.0) -> DisconOutput:
        if isinstance(self.law, SimpleVariableSpeed):
            torque = simple_torque(self.law, generator_speed)
        else:
            torque = baseline_torque(self.law, generator_speed, self.pitch)
        self.calls += 1
        self.times.append(t)
        return DisconOutput(torque, self.pitch, (self.pitch,) * 3)

    def close(self) -> None:
        pass
