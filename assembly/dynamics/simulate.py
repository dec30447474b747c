"""A time-domain run of a scene, ``flexgear simulate``: its model, loads, start and outputs.

The assembled model (any fidelity; flexible bodies by their Craig-Bampton reduction, or
unreduced with ``full_fe``) with its damping (:func:`assembly.dynamics.damping.damping_on_q`),
the nonlinear meshes (:mod:`assembly.dynamics.mesh_contact`), the generator, brake and
gearbox friction (:mod:`assembly.dynamics.drive_torques`) and the ``[simulation]`` loads
(:mod:`assembly.dynamics.load_series`) are integrated by
:func:`assembly.dynamics.transient.integrate`.

Start (``static_start``): every body turns at its share of ``speed`` in the model's rigid-body
mode phi, and q0 is the static equilibrium under the loads at t = 0 with the rigid-body
acceleration they give taken out (inertia relief: ``K q + U nu = f - M phi alpha``, alpha =
phi' f / phi' M phi, phi' M q = 0), solved by Newton's method on the meshes' contact.

The linear model turns its rotations as coordinates, so planets stay where they are and
centrifugal and gyroscopic terms are left out (the usual lumped-parameter drivetrain model;
Park et al., Lin & Parker). Outputs are :mod:`assembly.dynamics.frf_channels`' names, plus
``speed:BODY`` (rad/s about the body's own axis); a nonlinear mesh's ``force:MESH`` is its
contact force, ``stress:BODY:X,Y,Z`` the von Mises stress (Pa) of the six back-expanded
components at each instant. A section load (``torque:``, ``force:``, ``stress:``) carries
its share of the scene's ``[damping]`` as the frequency response does,
``k_e B_e G q'`` (:mod:`assembly.dynamics.damping`; a nonlinear mesh: its contact force
plus the share of its mean spring ``k0``, the spring the damping matrix was built with), so
that each body's balance ``M q'' + C q' + K q + U nu = f`` holds with the recorded loads.
"""
from __future__ import annotations

import dataclasses
import logging
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from threadpoolctl import threadpool_limits

from .. import arguments as check
from ..analysis.modal import SMALL_DENSE
from ..model.assemble import AssembledModel, assemble, source_scene, sparse_model
from ..scene.tables import with_simulation
from ..scene.time_domain import Simulation
from .body_loads import body_loads
from .history import H5History, Statistics, Tee, chunk_steps, read_blocks
from .integrators import check_step
from .life_tables import check_life, life_channels, life_result
from .load_series import range_warning
from .mesh_contact import Meshes
from .run_checks import brake_warnings, mesh_frequencies, step_warnings, undamped_band
from .run_loads import RunLoads, run_loads
from .run_model import model_matrices, scheme_of
from .run_outputs import recorded_channels, recorder
from .run_start import GAP_SLOPE, start_velocity, static_start
from .speed_drive import speed_drive
from .transient import Diverged, Stack, check_history, integrate
from .turbine_run import OUTPUTS, TurbineRun

log = logging.getLogger(__name__)

@dataclass(frozen=True)
class SimulationResult:
    """``time_s`` (s) and ``outputs`` {name: (n_t,) array in ``units``}; ``meshes``: per
    nonlinear mesh its name, mesh frequency at the start (Hz) and contact-loss events;
    ``mesh_frequencies_hz`` {stage or mesh: Hz at the starting speed}, ``shaft_speeds_hz``
    {body: rev/s}, ``sidebands_hz`` {stage or mesh: the modulation's spacing, Hz: a stage's
    carrier speed, a pair's slower gear}; ``warnings``; ``info`` (run statistics);
    ``complete`` False for the partial result of a run that stopped. ``statistics``: per
    output its mean, RMS, min, max, peak |value| and the peak's time
    (:class:`assembly.dynamics.history.Statistics`, accumulated as the run went);
    ``history_file``: the HDF5 file the histories were streamed to (then ``time_s`` is empty
    and ``outputs`` {}), None when they are in ``outputs``. ``life``: the loads-to-life tables
    of a complete run whose scene asks for them (``[simulation.life]``:
    :class:`assembly.dynamics.life_tables.LifeResult`), else None; the channels recorded for
    them alone (a rated bearing's forces, the speeds) are in ``outputs`` and named in
    ``info["life_channels"]``."""

    time_s: np.ndarray
    outputs: dict
    units: dict
    meshes: list = field(default_factory=list)
    mesh_frequencies_hz: dict = field(default_factory=dict)
    shaft_speeds_hz: dict = field(default_factory=dict)
    sidebands_hz: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)
    info: dict = field(default_factory=dict)
    complete: bool = True
    statistics: dict = field(default_factory=dict)
    history_file: str | None = None
    life: object = None

    @property
    def steps(self) -> int:
        """Steps done (the history holds one row more: the start)."""
        return int(self.info.get("steps", len(self.time_s) - 1))

    @property
    def t_last_s(self) -> float:
        """Time reached (s): the last row's."""
        return self.steps * float(self.info["dt_s"]) if "dt_s" in self.info else float(self.time_s[-1])

    def as_json(self) -> dict:
        """``{"time_s": [...], "outputs": {NAME: [...]}, "units": {...}}`` plus run facts."""
        return {"time_s": self.time_s.tolist(), "outputs": {k: v.tolist() for k, v in self.outputs.items()},
                "units": dict(self.units), "complete": self.complete, "meshes": self.meshes,
                "warnings": self.warnings, "info": {k: v for k, v in self.info.items() if not k.startswith("_")},
                **({"life": self.life.as_dict()} if self.life is not None else {})}


def simulate(model, t_end: float, dt: float, outputs=None, simulation=None, base_dir=None,
             speed: float | None = None, progress=None, full_fe: bool = False, history=None,
             arrays: bool = True) -> SimulationResult:
    """Integrate ``model`` (an :class:`AssembledModel`, or a Scene assembled here, unreduced
    when ``full_fe``) to ``t_end`` with step ``dt`` (s) as its scene's ``[simulation]`` table
    says (defaults when it has none; ``simulation``: a :class:`Simulation` table in its place,
    checked against the scene as the scene's own is), recording ``outputs`` (names; module
    notes; None: every named stress point of ``simulation.points`` and every nonlinear mesh's
    force). ``speed`` (rad/s) overrides ``simulation.speed``; ``base_dir``: where the scene's
    load files are (default: cwd). A run that stops raises
    :class:`assembly.dynamics.transient.Diverged` whose ``partial`` is the
    :class:`SimulationResult` so far (``complete`` False). A run whose history does not fit the
    memory budget is refused (SceneError at ``t_end``) before anything is assembled or
    allocated (:func:`assembly.dynamics.transient.check_history`).

    ``history``: an HDF5 file (path; it must not exist) the outputs are streamed to as the run
    goes (:class:`assembly.dynamics.history.H5History`, layout in docs/output.md): memory
    stays flat in ``t_end``, the result has the ``statistics`` and ``history_file`` but no
    arrays, and a run that stops or is killed leaves the file marked incomplete with every
    step flushed. ``arrays`` False (and no ``history``): keep only the ``statistics``, in flat
    memory too."""
    scene, t_end, dt, outputs, speed = _arguments(model, t_end, dt, outputs, simulation, base_dir, speed,
                                                  progress, full_fe)
    if history is not None:
        history = Path(check.file_path("history", history))
        if history.exists() or history.is_symlink():
            raise check.refuse("history", str(history), "exists; a streamed history is written to a new file only")
    check.flag("arrays", arrays)
    sim = scene.simulation or Simulation()
    # the life tables count whole histories: kept in memory unless they stream to a file
    streaming = history is not None or not (arrays or sim.life is not None)
    check_history(dt, t_end, 0, streaming=streaming)    # the run's length alone, before assembling
    model = sparse_model(model) if isinstance(model, AssembledModel) else assemble(scene, full_fe=full_fe)
    base_dir = Path(base_dir or ".")
    n = model.K.shape[0]
    M, K, C, G = model_matrices(model)
    v0, phi, reference = start_velocity(model, scene, sim, speed)
    meshes = Meshes(model, sim.consistent)
    loads = run_loads(model, scene, sim, dt, v0, base_dir, phi if reference else None)
    turbine = None
    if scene.turbine is not None and scene.turbine.wind is not None:
        turbine = TurbineRun(model, scene, sim, dt, t_end, v0, base_dir, phi)
    body = body_loads(model, scene, sim, dt, t_end, base_dir, phi, turbine.data.tilt if turbine else None)
    loads = RunLoads(np.hstack([loads.vectors, body.vectors]), (*loads.histories, *body.histories), loads.torques)
    start_force, drive_scale = (turbine.start_force if turbine else None), None
    if sim.drive is not None:                   # a run-up: the servo's spring and damper, its load
        drive = speed_drive(model, sim.drive, reference, v0, phi, sp.issparse(K))
        K, C = K + drive.K, C + drive.C
        loads = RunLoads(np.hstack([loads.vectors, drive.vector[:, None]]), (*loads.histories, drive.history),
                         loads.torques)
        # the start: the servo's damper at the starting speed balances the load's c omega_0
        start_force = -(drive.C @ v0) + (start_force if start_force is not None else 0.0)
        phi = None                              # the servo holds the drivetrain: no inertia relief
        w0 = abs(drive.ramp.omega0)
        drive_scale = max(abs(drive.ramp.end_speed), w0) / w0 if w0 > 0 else None
    try:
        return _run(model, scene, sim, t_end, dt, outputs, n, M, K, C, G, v0, phi, meshes, loads, turbine,
                    body.nonlinear, history, streaming, progress, start_force, reference, drive_scale)
    finally:
        if turbine is not None:
            turbine.close()


def _run(model, scene, sim, t_end, dt, outputs, n, M, K, C, G, v0, phi, meshes, loads, turbine, unbalances,
         history, streaming, progress, start_force=None, reference=None, drive_scale=None) -> SimulationResult:
    """:func:`simulate`'s run, its parts made (``drive_scale``: a run-up's largest speed over its
    starting one, for the reports' frequency axes)."""
    nl = Stack([meshes, loads.torques, *(turbine.nonlinear if turbine else ()), *unbalances], n)
    q0 = _start(M, K, nl, meshes, loads, sim, phi, v0, start_force)
    if outputs is None:                         # every named stress point and nonlinear mesh force
        outputs = [*(f"stress:{p.name}" for p in sim.points), *(f"force:{mi.name}" for mi in meshes.info),
                   *(OUTPUTS if turbine else ())]
    outputs = list(dict.fromkeys(outputs))
    shaft = None
    if sim.life is not None:
        shaft = check_life(model, sim.life, t_end, reference)
        # the channels the outputs asked for record (a bearing's name: one a direction), and those
        # the tables need besides, recorded for them alone
        chans, speeds = recorded_channels(model, sim.points, [k for k in outputs if k not in OUTPUTS])
        asked = {c.name for c in chans} | set(speeds) | set(outputs)
        life_only = [k for k in life_channels(model, sim.life, shaft) if k not in asked]
        outputs = [*outputs, *life_only]
    else:
        life_only = []
    extra = [(k, OUTPUTS[k]) for k in outputs if k in OUTPUTS]
    rec = recorder(model, sim.points, [k for k in outputs if k not in OUTPUTS], G, meshes, tuple(extra))
    observe = rec.observe(meshes)
    if turbine is not None:
        observe = turbine.observer(observe, [k for k, _ in extra])
    check_history(dt, t_end, rec.size, n, nl.U.shape[1], streaming=streaming)   # before it starts
    stats = Statistics(rec.histories)
    sink = None if not streaming else stats if history is None else Tee(
        H5History(history, rec.histories, {"scene": scene.name}, chunk_steps(rec.size)), stats)
    freqs, shaft_hz, side_hz = mesh_frequencies(model, scene, v0)
    top = drive_scale or 1.0                    # a run-up's mesh frequencies grow to its top speed
    warnings = (step_warnings(dt, {k: f * top for k, f in freqs.items()}, meshes, scene.band)
                + undamped_band(model, M, K, C, scene.band)
                + [w for w in (range_warning(h, check_step(dt, t_end) * dt) for h in loads.recorded) if w]
                + brake_warnings(model, scene, sim, dt, loads.torques) + (turbine.warnings if turbine else []))
    for w in warnings:
        log.warning(w)
    try:
        # one BLAS thread for small models: threads cost more than products of this size
        with threadpool_limits(1 if n <= SMALL_DENSE else None):
            run = integrate(M, C, K, loads, q0, v0, dt, t_end, scheme_of(sim), nl, observe,
                            progress, model.dof_names, history=sink, sampled=turbine.sampled if turbine else None)
        stopped = None
    except Diverged as exc:
        run, stopped = exc.partial, exc
    result = _result(run, rec, stats, history, meshes, dt, t_end, n, freqs, shaft_hz, side_hz, warnings,
                     stopped is None, {**(turbine.info() if turbine else {}), "reference": reference,
                                       **({"life_channels": life_only} if life_only else {}),
                                       **({"speed_scale": drive_scale} if drive_scale else {})})
    if stopped is not None:
        raise Diverged(str(stopped), result)
    if sim.life is not None:
        t, read = histories_of(result)
        # the loads the life tables count: every channel recorded (a bearing's name gives one per
        # direction) but the speeds and the channels recorded for the tables alone
        counted = [k for k in result.units if not k.startswith("speed:") and k not in life_only]
        result = dataclasses.replace(result, life=life_result(model, sim.life, t, read, result.units, counted, shaft))
    return result


def histories_of(r: SimulationResult):
    """(time_s, read(name) -> history) of a run's outputs: its arrays, or read back from the file
    it streamed to one channel at a time (a channel's n_t values in memory, not the run's)."""
    if r.history_file is None:
        return r.time_s, r.outputs.__getitem__

    def read(name):
        return np.concatenate([y for _, y in read_blocks(r.history_file, name)])
    return np.concatenate([t for t, _ in read_blocks(r.history_file, next(iter(r.units)))]), read


def _arguments(model, t_end, dt, outputs, simulation, base_dir, speed, progress, full_fe):
    """The arguments of :func:`simulate`, checked (one SceneError naming the argument), and
    the scene the run follows (the model's, its simulation table replaced by ``simulation``)."""
    scene = source_scene("model", model)
    t_end, dt = check.number("t_end", t_end, "s", gt=0.0), check.number("dt", dt, "s", gt=0.0)
    outputs = None if outputs is None else check.names("outputs", outputs, empty=True)
    if simulation is not None:
        check.instance("simulation", simulation, Simulation, "a Simulation table")
        scene = with_simulation(scene, simulation)
    check.optional(check.file_path, "base_dir", base_dir)
    speed = check.optional(check.number, "speed", speed, "rad/s")
    check.function("progress", progress)
    check.flag("full_fe", full_fe)
    if full_fe and isinstance(model, AssembledModel):
        raise check.refuse("full_fe", full_fe, "applies to a scene assembled here; the model given is assembled "
                                               "already (assemble(scene, full_fe=True))")
    bodies = [b.name for b in scene.expanded().bodies]          # the bodies a name here must be
    if scene.simulation is not None and scene.simulation.reference is not None:
        check.one_of("simulation.reference", scene.simulation.reference, bodies)
    for i, name in enumerate(outputs or ()):
        if name in OUTPUTS and (scene.turbine is None or scene.turbine.wind is None):
            raise check.refuse(f"outputs[{i}]", name, "is a turbine output: the scene has no [turbine] rotor "
                                                      "(a [turbine] table with its wind)")
        if name.startswith("speed:") and (body := name[6:].split(":")[0]) not in bodies:
            raise check.refuse(f"outputs[{i}]", name,
                               f"no body {body!r}; have {bodies}{check.nearest(body, bodies)}")
    return scene, t_end, dt, outputs, speed


def _start(M, K, nl, meshes, loads, sim, phi, v0, extra=None) -> np.ndarray:
    """q0: the static start (:func:`assembly.dynamics.run_start.static_start`) when the table
    asks for it and anything loads the model, else rest (``extra``: a load at t = 0 besides
    ``loads``, the controller's starting torque)."""
    U = nl.U
    if not (sim.static_start and (loads.histories or U.shape[1])):
        return np.zeros(K.shape[0])
    f0 = loads.force(0.0) if extra is None else loads.force(0.0) + extra
    meshes.gap_slope = GAP_SLOPE
    closing = np.nan_to_num(meshes.k0 * meshes.backlash)
    pad = np.zeros(U.shape[1] - meshes.U.shape[1])          # the meshes' columns come first
    q0 = static_start(M, K, U, nl, f0, phi, U.T @ v0, float(closing.max(initial=0.0)),
                      lambda x: np.concatenate([meshes.coast_preload(x[:meshes.U.shape[1]]), pad]))
    meshes.gap_slope = 0.0
    return q0


def _result(run, rec, stats, history, meshes, dt, t_end, n, freqs, shaft_hz, side_hz, warnings,
            complete, more: dict) -> SimulationResult:
    """The :class:`SimulationResult` of a run (whole, or stopped: ``complete`` False):
    ``stats`` accumulated as it went, or now from the arrays when they are in memory."""
    units = rec.histories(np.zeros((0, rec.size)))[1]
    if run.y is not None:
        values, units = rec.histories(run.y)
        stats.add(run.time_s, values, units)
        time_s = run.time_s
    else:
        values, time_s = {}, np.zeros(0)
    info = dict(run.info)
    info.setdefault("steps", len(run.time_s) - 1 if run.time_s is not None else 0)
    info.update({"dt_s": dt, "t_end_s": t_end, "scheme": run.scheme.name, "dofs": n,
                 "losses_total": int(meshes.losses.sum()), **more})
    return SimulationResult(time_s, values, units,
                            [{"name": mi.name, "path": mi.path, "teeth": mi.teeth, "backlash_m": None if
                              math.isnan(mi.backlash) else mi.backlash, "harmonics": mi.harmonics,
                              "contact_losses": int(meshes.losses[j])} for j, mi in enumerate(meshes.info)],
                            freqs, shaft_hz, side_hz, warnings, info, complete, stats.result(),
                            None if history is None else str(history))
