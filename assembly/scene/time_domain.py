"""Scene data of time-domain runs (``flexgear simulate``): mesh stiffness that varies with
the gear angle, backlash's partner table, and the ``[simulation]`` table (initial speed,
loads, generator law, brake, gearbox efficiency, integration scheme). Data only; the
physics is in :mod:`assembly.dynamics.mesh_variation` and :mod:`assembly.dynamics.simulate`.
SI units: m, N, N m, s, rad, rad/s.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Literal, Optional

from fe_components.fields import quantity

#: Harmonics kept of a rectangular-wave mesh stiffness by default (Park et al.'s Fourier
#: series to 8th order).
DEFAULT_HARMONICS = 8


def _angle(default=dataclasses.MISSING, **rule):
    return quantity("rad", default, angle=True, **rule)


@dataclass(frozen=True)
class MeshVariation:
    """Mesh stiffness as a function of the gear angle (time-domain runs only; modal, FRF
    and static analyses use the mean ``stiffness`` k0)::

        k(phi) = k0 (1 + sum_h a_h cos(h phi + phi_h)),  phi = z (theta - theta_frame) - phase

    with theta the counting gear's rotation (rad, integrated, so start-up and stops are
    right), theta_frame its carrier's (0 for gears in the housing) and z its teeth
    (``teeth``, default the counting gear's).

    Either ``amplitudes`` (a_h, relative to k0, h = 1, 2, ...) with ``phases`` (phi_h, rad,
    default 0), or the rectangular wave of tooth-pair alternation: ``step`` (dk / k0, the
    relative stiffness step between double and single tooth contact) with the profile
    contact ratio ``contact_ratio`` in (1, 2) (default from the teeth) and the overlap
    ratio ``face_contact_ratio`` (default from the teeth, 0 for spur gears): harmonic h of
    ``harmonics`` has a_h = 2 step sin(h pi (c - 1)) / (h pi) x sinc(h eps_beta), the
    rectangular wave's series (double contact centred on phi = 0) averaged over the
    helical contact line's sweep of eps_beta mesh periods. ``counting_gear``: the gear whose
    teeth and angle count ("gear1" or "gear2"). Planet meshes of a stage are phased by
    their planet angle psi_n: ``phase`` += z psi_n (Parker 2000)."""

    amplitudes: Optional[tuple[float, ...]] = quantity("", None, abs_lt=10.0)
    phases: Optional[tuple[float, ...]] = _angle(None)
    step: Optional[float] = quantity("", None, ge=0.0, lt=10.0)
    contact_ratio: Optional[float] = quantity("", None, gt=1.0, lt=2.0)
    face_contact_ratio: Optional[float] = quantity("", None, ge=0.0, lt=20.0)
    harmonics: int = quantity("", DEFAULT_HARMONICS, integer=True, ge=1, le=64)
    phase: float = _angle(0.0)
    teeth: Optional[int] = quantity("", None, integer=True, ge=3)
    counting_gear: Literal["gear1", "gear2"] = "gear1"


@dataclass(frozen=True)
class TimeLoad:
    """A load of a time-domain run on ``body`` (at ``interface`` of a flexible body).

    ``kind``: "torque" (about the body's own axis, N m), "force" (N) or "moment" (N m)
    along the global ``direction``. Its history, one of:

    * ``value`` alone: constant;
    * ``value`` -> ``end_value`` ramped linearly from ``t_start`` to ``t_end`` (s; a step is
      a ramp of one time step);
    * ``table``: a CSV file (path relative to the scene file) with a header row, the time
      column ``time_column`` (s) and the value column ``column``;
    * ``openfast``: an OpenFAST output file, text (``.out``, FAST v7/v8 too) or binary
      (``.outb``), channel ``column`` (e.g. ``RtAeroMxh``), converted to SI by its unit
      (kN-m -> N m); a torque or moment needs a torque channel, a force a force channel.

    ``scale`` multiplies a table's or file's values after the conversion to SI (e.g. -1 for
    the other sense). ``time_window = [t0, t1]`` (s, the file's time) keeps that part of a
    file; ``time_offset`` (s) moves it: run time = file time - time_offset. Outside the
    file's rows the first / last value is held, and the run warns."""

    body: str
    kind: Literal["torque", "force", "moment"] = "torque"
    direction: tuple[float, float, float] = quantity("", (0.0, 0.0, 1.0))
    interface: Optional[str] = None
    value: float = quantity("N or N m", 0.0)
    end_value: Optional[float] = quantity("N or N m", None)
    t_start: float = quantity("s", 0.0, ge=0.0)
    t_end: Optional[float] = quantity("s", None, ge=0.0)
    table: Optional[str] = None
    openfast: Optional[str] = None
    column: Optional[str] = None
    time_column: str = "time"
    scale: float = quantity("", 1.0)
    time_offset: float = quantity("s", 0.0)
    time_window: Optional[tuple[float, float]] = quantity("s", None)


@dataclass(frozen=True)
class Generator:
    """The generator's electromagnetic torque on ``body`` (default the body of role
    "generator"), a positive torque opposing its rotation sense at the start. ``law``
    "constant": ``torque`` (N m); "pi": ``torque`` + ``kp`` (omega - ``rated_speed``) +
    ``ki`` x the integral of (omega - ``rated_speed``) dt, clipped to [0, ``max_torque``]
    (omega: the body's speed, rad/s, in its starting sense; default max: 1.1 x ``torque``);
    "table": a recorded torque history read as a load's (``table`` or ``openfast``,
    ``column``, ``time_column``, ``scale``, ``time_offset``, ``time_window``; e.g.
    OpenFAST's ``GenTq``, whose positive value brakes the generator as here, and a negative
    value drives it). From standstill (``speed = 0``) the sense is the one the generator
    turns in when the reference rotor turns positively about its own axis."""

    body: Optional[str] = None
    law: Literal["constant", "pi", "table"] = "constant"
    torque: float = quantity("N m", 0.0, ge=0.0)
    rated_speed: Optional[float] = quantity("rad/s", None, gt=0.0)
    kp: float = quantity("N m s/rad", 0.0, ge=0.0)
    ki: float = quantity("N m/rad", 0.0, ge=0.0)
    max_torque: Optional[float] = quantity("N m", None, gt=0.0)
    table: Optional[str] = None
    openfast: Optional[str] = None
    column: Optional[str] = None
    time_column: str = "time"
    scale: float = quantity("", 1.0)
    time_offset: float = quantity("s", 0.0)
    time_window: Optional[tuple[float, float]] = quantity("s", None)


@dataclass(frozen=True)
class Brake:
    """A shaft brake on ``body`` (default the body of role "generator"): ElastoDyn's HSS
    brake, torque rising linearly from 0 at ``deploy_time`` (s) to ``torque`` (N m,
    HSSBrTqF) over ``ramp_time`` (s, HSSBrDT), acting against the shaft's rotation and never
    driving it backwards: below ``stick_speed`` (rad/s) it is a stiff viscous stick
    (torque proportional to speed), so a stopped shaft stays stopped."""

    torque: float = quantity("N m", gt=0.0)
    deploy_time: float = quantity("s", 0.0, ge=0.0)
    ramp_time: float = quantity("s", 0.0, ge=0.0)
    body: Optional[str] = None
    stick_speed: float = quantity("rad/s", 1e-3, gt=0.0)


@dataclass(frozen=True)
class StressPoint:
    """A named point of a flexible body whose stress a run records: output ``stress:NAME``,
    the von Mises stress (Pa) at the FE stress node nearest to ``point`` (global, m)."""

    name: str
    body: str
    point: tuple[float, float, float] = quantity("m")


@dataclass(frozen=True)
class NacelleMotion:
    """``[[simulation.nacelle]]``: one component of the housing's prescribed acceleration at
    ``origin`` (global, m): ``dof`` "x", "y", "z" (m/s^2) or "rx", "ry", "rz" (rad/s^2, about
    the global axes), either ``amplitude`` sin(2 pi ``frequency`` t + ``phase``) (a constant
    when ``frequency`` is 0: ``amplitude`` sin(``phase``), so give ``phase_deg = 90``) or a series
    from ``table`` / ``openfast`` as a wind series is read."""

    dof: Literal["x", "y", "z", "rx", "ry", "rz"]
    amplitude: float = quantity("m/s^2 or rad/s^2", 0.0)
    frequency: float = quantity("Hz", 0.0, ge=0.0)
    phase: float = _angle(0.0)
    origin: tuple[float, float, float] = quantity("m", (0.0, 0.0, 0.0))
    table: Optional[str] = None
    openfast: Optional[str] = None
    column: Optional[str] = None
    time_column: str = "time"
    scale: float = quantity("", 1.0)
    time_offset: float = quantity("s", 0.0)
    time_window: Optional[tuple[float, float]] = quantity("s", None)


@dataclass(frozen=True)
class UnbalanceMass:
    """``[[simulation.unbalance]]``: an eccentric ``mass`` (kg) at ``radius`` (m) from ``body``'s
    axis (at ``interface`` of a flexible body), at angle ``phase`` (rad from the body's local x at
    t = 0), turning with the body's integrated rotation."""

    body: str
    mass: float = quantity("kg", gt=0.0)
    radius: float = quantity("m", gt=0.0)
    phase: float = _angle(0.0)
    interface: Optional[str] = None


@dataclass(frozen=True)
class SpeedDrive:
    """``[simulation.drive]``: a speed-controlled drive on ``body`` (default the reference, the
    body of role "rotor"): its speed follows ``omega_ref``, the starting speed until ``t_start``,
    then linear to ``end_speed`` (rad/s) at ``t_end`` (s), held after -- a run-up or run-down.
    A servo of ``bandwidth`` f_b (Hz), critically damped, on the body's rotation:
    ``T = J w_b^2 (theta_ref - theta) + 2 J w_b (omega_ref - omega)``, ``w_b = 2 pi f_b``, J the
    drivetrain's inertia referred to the body; drivetrain modes far above f_b see the body free,
    far below it held."""

    end_speed: float = quantity("rad/s")
    t_end: float = quantity("s", gt=0.0)
    t_start: float = quantity("s", 0.0, ge=0.0)
    body: Optional[str] = None
    bandwidth: float = quantity("Hz", 10.0, gt=0.0)


@dataclass(frozen=True)
class BearingRating:
    """``[[simulation.life.bearings]]``: the ISO 281 basic rating life of ``bearing`` (its
    name in the expanded scene, as ``force:BEARING``) from the run: the dynamic equivalent
    load ``P = radial_factor F_r + axial_factor F_a`` at each step (F_r the radial force
    magnitude in the bearing's axes, F_a the axial), its mean over the revolutions of the
    bearing's body relative to its frame with ``exponent`` p, ``L10 = (rating / P)^p``
    (1e6 rev); ``rating`` C (N) is the basic dynamic load rating, p 3 for ball and 10/3 for
    roller bearings."""

    bearing: str
    rating: float = quantity("N", gt=0.0)
    exponent: float = quantity("", 10.0 / 3.0, gt=0.0, le=100.0)
    radial_factor: float = quantity("", 1.0, ge=0.0)
    axial_factor: float = quantity("", 0.0, ge=0.0)


@dataclass(frozen=True)
class GearRating:
    """``[[simulation.life.gears]]``: the equivalent torque and Palmgren-Miner damage of the
    teeth of ``gear`` (a body of ``mesh``, default its gear1) from the run: the torque
    ``T = lever x F`` of the mesh force F about the gear's axis at each step, one load cycle
    per tooth per revolution of the gear relative to the frame it rides in (its carrier, or
    the housing), the S-N curve ``N_f = cycles_ref (torque_ref / T)^slope`` above
    ``torque_limit`` (N m; 0: no endurance limit)."""

    mesh: str
    torque_ref: float = quantity("N m", gt=0.0)
    cycles_ref: float = quantity("", gt=0.0)
    slope: float = quantity("", gt=0.0, le=100.0)
    gear: Optional[str] = None
    torque_limit: float = quantity("N m", 0.0, ge=0.0)


@dataclass(frozen=True)
class LifeTables:
    """``[simulation.life]``: the loads-to-life tables of a run (:mod:`assembly.dynamics.life`):
    for every output its rainflow damage-equivalent loads for the Woehler ``exponents`` at
    ``cycles_ref`` cycles (default the counted span's seconds: 1 Hz), and its load duration and
    load revolution distributions in ``bins`` bins, the revolutions of ``shaft`` (default the
    reference body); the bearings' L10 (:class:`BearingRating`) and the gears' damage
    (:class:`GearRating`). ``window`` (t0, t1) s: the span counted (default the whole record;
    a start-up transient is left out by starting it later)."""

    bearings: tuple[BearingRating, ...] = ()
    gears: tuple[GearRating, ...] = ()
    exponents: tuple[float, ...] = quantity("", (3.0, 4.0, 10.0), gt=0.0, le=100.0)
    cycles_ref: Optional[float] = quantity("", None, gt=0.0)
    bins: int = quantity("", 20, integer=True, ge=1, le=100_000)
    shaft: Optional[str] = None
    window: Optional[tuple[float, float]] = quantity("s", None, ge=0.0)

    def __post_init__(self):
        for f in ("bearings", "gears", "exponents"):
            if isinstance(getattr(self, f), list):  # Python callers may pass lists
                object.__setattr__(self, f, tuple(getattr(self, f)))


@dataclass(frozen=True)
class Simulation:
    """``[simulation]``: the settings of ``flexgear simulate``.

    ``speed`` (rad/s): the starting speed of ``reference`` (default the body of role
    "rotor") about its own axis; every body starts at its kinematic share of it, in static
    equilibrium under the loads at t = 0 (``static_start``; with inertia relief when they do
    not balance). ``loads``: :class:`TimeLoad` list; ``generator``, ``brake``; and
    ``gearbox_efficiency`` (ElastoDyn's GBoxEff, in (0, 1]: a friction torque on the
    generator body of (1/eta^s - 1) x the generator-side torque of the previous step, s the
    sign of the ``lss_shaft`` torque, default the shaft on the rotor). ``scheme``:
    "newmark" (average acceleration), "hht" (``alpha``) or "generalized-alpha"
    (``rho_inf``). ``consistent``: add the energy-consistent mesh term -1/2 dk/dtheta delta^2
    (Oh, Grosh & Barber 2005). ``points``: named stress points (:class:`StressPoint`); a run
    without outputs named records each point's stress and each nonlinear mesh's force.
    ``nacelle``: the housing's prescribed accelerations (:class:`NacelleMotion`), loading every
    body with its inertia; ``unbalance``: eccentric masses on turning bodies
    (:class:`UnbalanceMass`); ``drive``: a speed-controlled drive (:class:`SpeedDrive`), a
    run-up; ``life``: the loads-to-life tables of the run (:class:`LifeTables`)."""

    speed: float = quantity("rad/s", 0.0)
    reference: Optional[str] = None
    loads: tuple[TimeLoad, ...] = ()
    generator: Optional[Generator] = None
    brake: Optional[Brake] = None
    gearbox_efficiency: float = quantity("", 1.0, gt=0.0, le=1.0)
    lss_shaft: Optional[str] = None
    scheme: Literal["newmark", "hht", "generalized-alpha"] = "newmark"
    alpha: float = quantity("", 0.05, ge=0.0, le=1.0 / 3.0)
    rho_inf: float = quantity("", 0.9, ge=0.0, le=1.0)
    consistent: bool = True
    static_start: bool = True
    points: tuple[StressPoint, ...] = ()
    nacelle: tuple[NacelleMotion, ...] = ()
    unbalance: tuple[UnbalanceMass, ...] = ()
    drive: Optional[SpeedDrive] = None
    life: Optional[LifeTables] = None

    def __post_init__(self):
        for f in ("loads", "points", "nacelle", "unbalance"):
            if isinstance(getattr(self, f), list):  # Python callers may pass lists
                object.__setattr__(self, f, tuple(getattr(self, f)))
