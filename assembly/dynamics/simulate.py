"""A time-domain run of a scene: ``flexgear simulate``'s model, loads, start and outputs.

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
import scipy.linalg as sla
import scipy.sparse as sp
from threadpoolctl import threadpool_limits

from ..analysis.drivetrain import chain_ends, rigid_mode
from ..errors import MechanismError, SceneError
from ..analysis.load_cases import single_rigid_mode
from ..analysis.modal import SMALL_DENSE
from ..mechanics.nullity import rigid_body_count
from ..scene.time_domain import Simulation
from ..model.damping import damping_matrix
from .damping import damping_on_q, every_mode, needs_modes, section_share
from ..model.probes import body_point, point_vector, spin_row, unit_wrench
from .frf_channels import output_channels, output_rows
from .integrators import check_step, generalized_alpha, hht, newmark
from .frf import UNDAMPED_ZETA
from .load_series import constant, file_history, generator_history, ramp, range_warning
from .mesh_contact import Meshes
from .drive_torques import ShaftTorques
from .transient import DENSE_INVERSE_MAX, EPS, ROUNDOFF, Diverged, Stack, check_history, integrate, tangent
from ..model.assemble import model_argument
from ..scene.tables import scene_argument

log = logging.getLogger(__name__)

#: Fewer steps than this per period of the highest mesh harmonic or of the band draw a
#: warning (average acceleration's period error W^2/12 is 3.3 % at 10 steps a period).
STEPS_PER_PERIOD = 10
#: Contact slope of an open gap in the static start's Newton tangent (a fraction of the
#: mesh stiffness): the exact tangent, 0, leaves a mechanism where a load pushes a gear across
#: its backlash. The first guess already rests each mesh on the flank the linear solution
#: loads (:meth:`Meshes.coast_preload`), so a gap is rarely crossed; the residual stays exact,
#: so the start is still the exact equilibrium.
GAP_SLOPE = 1e-3


@dataclass
class SimulationResult:
    """``time_s`` (s) and ``outputs`` {name: (n_t,) array in ``units``}; ``meshes``: per
    nonlinear mesh its name, mesh frequency at the start (Hz) and contact-loss events;
    ``mesh_frequencies_hz`` {stage or mesh: Hz at the starting speed}, ``shaft_speeds_hz``
    {body: rev/s}, ``sidebands_hz`` {stage or mesh: the modulation's spacing, Hz: a stage's
    carrier speed, a pair's slower gear}; ``warnings``; ``info`` (run statistics);
    ``complete`` False for the partial result of a run that stopped."""

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

    def as_json(self) -> dict:
        """``{"time_s": [...], "outputs": {NAME: [...]}, "units": {...}}`` plus run facts."""
        return {"time_s": self.time_s.tolist(), "outputs": {k: v.tolist() for k, v in self.outputs.items()},
                "units": dict(self.units), "complete": self.complete, "meshes": self.meshes,
                "warnings": self.warnings, "info": {k: v for k, v in self.info.items() if not k.startswith("_")}}


def scheme_of(sim: Simulation):
    """The integration scheme the ``[simulation]`` table names."""
    if sim.scheme == "hht":
        return hht(sim.alpha)
    if sim.scheme == "generalized-alpha":
        return generalized_alpha(sim.rho_inf)
    return newmark()


def load_history(ld, path: str, base_dir: Path):
    """The :class:`assembly.dynamics.load_series.Series` of a ``[[simulation.loads]]`` entry."""
    unit = "N m" if ld.kind != "force" else "N"
    if ld.end_value is not None and (ld.table is not None or ld.openfast is not None):
        raise SceneError(f"{path}.end_value", ld.end_value, "a table or openfast file gives the history itself")
    s = file_history(ld, path, base_dir, unit)
    if s is not None:
        return s
    for key in ("time_offset", "time_window"):
        if getattr(ld, key):
            raise SceneError(f"{path}.{key}", getattr(ld, key), "applies to a table or openfast file only")
    if ld.end_value is not None or ld.t_end is not None:
        if ld.end_value is None or ld.t_end is None:
            missing = "end_value" if ld.end_value is None else "t_end"
            raise SceneError(f"{path}.{missing}", None, "missing: a ramp needs end_value and t_end")
        return ramp(ld.value, ld.end_value, ld.t_start, ld.t_end, f"{path}", unit, field=path)
    return constant(ld.value, path, unit)


def load_vector(model, ld, path: str) -> np.ndarray:
    """Load vector on q of a unit load of ``ld``'s kind, body and direction."""
    where = ld.body if ld.interface is None else f"{ld.body}:{ld.interface}"
    body, iface = body_point(model, where, f"{path}.body", where)
    if ld.kind == "torque":
        w = unit_wrench(model, body, "spin")
    else:
        d = np.asarray(ld.direction, float)
        if not np.linalg.norm(d) > 0:
            raise SceneError(f"{path}.direction", ld.direction, "must be a nonzero vector")
        w = np.zeros(6)
        w[(0 if ld.kind == "force" else 3):][:3] = d / np.linalg.norm(d)
    return point_vector(model, body, iface, w)


def _rigid_mode(model, reference: str, path: str):
    """(the rigid-body mode at a unit speed of ``reference``, "") or (None, why there is not
    one); SceneError at ``path`` when the reference stands still in it."""
    phi, why = single_rigid_mode(model)
    if phi is None:
        return None, why
    try:
        return rigid_mode(model, reference), ""
    except MechanismError:
        raise SceneError(path, reference, "this body stands still in the rigid-body mode: it cannot set the "
                                          "speed") from None


def model_matrices(model):
    """(M, C, K, G) of a run on q: dense for a reduced model, sparse above
    DENSE_INVERSE_MAX DOFs (C: :func:`run_damping`; G: the section loads' share of the
    scene damping, :func:`assembly.dynamics.damping.section_share`)."""
    sparse = model.K.shape[0] > DENSE_INVERSE_MAX
    M, K = (model.M, model.K) if sparse else (model.M.toarray(), model.K.toarray())
    return (M, K, *run_damping(model))


def run_damping(model):
    """(C, G) on q: dense for a reduced model; the unreduced model's element dampers and
    Rayleigh beta (sparse C, scalar G). One modal basis serves both, so that the section
    loads' shares add up to the damping force integrated."""
    d = model.scene.damping
    n = model.K.shape[0]
    if n <= DENSE_INVERSE_MAX:
        modes = every_mode(model) if needs_modes(model) else None
        return damping_on_q(model, modes), section_share(model, modes)
    if needs_modes(model):
        raise SceneError("damping", d, f"modal ratios and Rayleigh alpha need every mode: the model has {n} "
                                       "DOFs; use element dampers or rayleigh_beta")
    C = damping_matrix(model)
    C = C + d.rayleigh_beta * model.K if d is not None and d.rayleigh_beta else C
    return C, section_share(model)


def static_start(M, K, U, nl, f0, phi, xd0, force_scale: float = 0.0, preload=None):
    """q0 of the module notes: Newton on ``K q + U nu(U'q, xd0) + M phi lam = f0``,
    ``phi' M q = 0`` (no rigid-body mode: phi None, plain ``K q + U nu = f0``). Converged when
    the step reaches round-off or the force residual is below 1e-12 x ``force_scale`` (N; the
    force that closes a mesh's backlash: a smaller load cannot say on which flank it rests)
    or below the round-off of the forces it sums.
    ``preload(x)``: forces along U that put the linear solution's meshes on the flank it
    loads (the first guess, so that Newton's method rarely has to cross a gap)."""
    n = K.shape[0]
    dense = not sp.issparse(K)
    if phi is not None:
        Mphi = M @ phi
        B = (np.block([[K, Mphi[:, None]], [Mphi[None, :], np.zeros((1, 1))]]) if dense else
             sp.bmat([[K, sp.csr_matrix(Mphi[:, None])], [sp.csr_matrix(Mphi[None, :]), None]]).tocsc())
        Ub = np.vstack([U, np.zeros((1, U.shape[1]))])
        rhs = np.concatenate([f0, [0.0]])
    else:
        B, Ub, rhs = K, U, f0
    lu = sla.lu_factor(B) if dense else sp.linalg.splu(sp.csc_matrix(B))
    solve = (lambda b: sla.lu_solve(lu, b)) if dense else lu.solve
    W = solve(Ub) if U.shape[1] else np.zeros((len(rhs), 0))
    S = Ub.T @ W
    z = solve(rhs)
    if preload is not None and U.shape[1]:
        p = preload(Ub.T @ z)
        if np.any(p):
            z = solve(rhs - Ub @ p)
    step = np.inf
    absB, absU = abs(B), np.abs(Ub)
    for _ in range(60):
        nu, dk, _ = nl.forces(0.0, Ub.T @ z, xd0)
        r = B @ z + Ub @ nu - rhs
        # or r at round-off: each row sums the forces |B| |z|, |U| (the terms of nu) and rhs,
        # rounded to about ROUNDOFF eps x their size (transient.ROUNDOFF)
        floor = ROUNDOFF * EPS * np.linalg.norm(absB @ np.abs(z) + absU @ nl.force_scale(nu) + np.abs(rhs))
        if not len(nu) or np.linalg.norm(r) <= max(1e-12 * max(np.linalg.norm(rhs), force_scale), floor):
            break
        # Newton step with the tangent B + Ub diag(dk) Ub' by Woodbury
        y = solve(r)
        Kt = tangent(dk)
        corr = np.linalg.solve(np.eye(len(nu)) + Kt @ S, Kt @ (Ub.T @ y))
        dz = y - W @ corr
        z = z - dz
        last, step = step, np.linalg.norm(dz)
        # converged: a step at round-off, or steps that stopped shrinking at a level the
        # conditioning of the bordered matrix allows (a piecewise-linear contact converges exactly)
        if step <= 1e-12 * max(np.linalg.norm(z), 1e-300) or (step <= 1e-8 * np.linalg.norm(z) and step >= 0.5 * last):
            break
    else:
        raise SceneError("simulation.static_start", True, "the static equilibrium at t = 0 did not converge "
                                                          "(meshes opening and closing); set static_start = false")
    return z[:n]


def simulate(scene, t_end: float, dt: float, outputs=None, model=None, base_dir=None, speed: float | None = None,
             progress=None, full_fe: bool = False) -> SimulationResult:
    """Integrate ``scene`` (its ``[simulation]`` table, or defaults) to ``t_end`` with step
    ``dt`` (s), recording ``outputs`` (names; module notes; None: every named stress point of
    ``simulation.points`` and every nonlinear mesh's force). ``speed`` (rad/s) overrides
    ``simulation.speed``; ``base_dir``: where the scene's load files are (default: cwd).
    A run that stops raises :class:`assembly.dynamics.transient.Diverged` whose ``partial``
    is the :class:`SimulationResult` so far (``complete`` False). A run whose history does not
    fit the memory budget is refused (SceneError at ``t_end``) before anything is assembled or
    allocated (:func:`assembly.dynamics.transient.check_history`)."""
    from .. import arguments as check                # each argument's kind, one SceneError naming it
    scene_argument("scene", scene)
    t_end, dt = check.number("t_end", t_end, "s", gt=0.0), check.number("dt", dt, "s", gt=0.0)
    outputs = None if outputs is None else check.names("outputs", outputs, empty=True)
    check.optional(model_argument, "model", model)
    check.optional(check.file_path, "base_dir", base_dir)
    speed = check.optional(check.number, "speed", speed, "rad/s")
    check.function("progress", progress)
    check.flag("full_fe", full_fe)
    bodies = [b.name for b in scene.expanded().bodies]          # the bodies a name here must be
    if scene.simulation is not None and scene.simulation.reference is not None:
        check.one_of("simulation.reference", scene.simulation.reference, bodies)
    for i, name in enumerate(outputs or ()):
        if name.startswith("speed:") and (body := name[6:].split(":")[0]) not in bodies:
            raise check.refuse(f"outputs[{i}]", name,
                               f"no body {body!r}; have {bodies}{check.nearest(body, bodies)}")
    from ..model.assemble import assemble
    check_history(dt, t_end, 0)                 # the run's length alone, before assembling
    sim = scene.simulation or Simulation()
    model = model if model is not None else assemble(scene, full_fe=full_fe)
    base_dir = Path(base_dir or ".")
    n = model.K.shape[0]
    M, K, C, G = model_matrices(model)
    speed = sim.speed if speed is None else speed
    reference = sim.reference
    if reference is None:
        have = [b for b in scene.expanded().bodies if b.role == "rotor"]
        reference = have[0].name if have else None
    if reference is None:               # no speed reference: the rigid-body mode still relieves the loads
        phi, why = single_rigid_mode(model)
        phi = None if phi is None else phi[:, 0]
    else:
        phi, why = _rigid_mode(model, reference, "simulation.reference")
    if speed and (phi is None or reference is None):
        raise SceneError("simulation.speed", speed, "a starting speed needs a rotor (simulation.reference or a "
                                                    "body of role 'rotor') and one rigid-body mode" +
                         (f": {why}" if why else ""))
    v0 = speed * phi if speed else np.zeros(n)
    # loads (a generator of constant or recorded torque among them)
    meshes = Meshes(model, sim.consistent)
    torques, generator_load = _shaft_torques(model, scene, sim, dt, v0, base_dir, phi if reference else None)
    vecs, hist = [], []
    for i, ld in enumerate(sim.loads):
        path = f"simulation.loads[{i}]"
        hist.append(load_history(ld, path, base_dir))
        vecs.append(load_vector(model, ld, path))
    if generator_load is not None:
        vecs.append(generator_load[0])
        hist.append(generator_load[1])
    V = np.array(vecs).T if vecs else np.zeros((n, 0))

    def force(t):
        return V @ np.array([h(t) for h in hist]) if hist else np.zeros(n)

    nl = Stack([meshes, torques], n)
    U = nl.U
    q0 = np.zeros(n)
    if sim.static_start and (hist or U.shape[1]):
        meshes.gap_slope = GAP_SLOPE
        closing = np.nan_to_num(meshes.k0 * meshes.backlash)
        pad = np.zeros(U.shape[1] - meshes.U.shape[1])          # the meshes' columns come first
        q0 = static_start(M, K, U, nl, force(0.0), phi, U.T @ v0, float(closing.max(initial=0.0)),
                          lambda x: np.concatenate([meshes.coast_preload(x[:meshes.U.shape[1]]), pad]))
        meshes.gap_slope = 0.0
    # outputs: as named, or every named stress point and nonlinear mesh force
    points = {f"stress:{p.name}": (i, p) for i, p in enumerate(sim.points)}
    if outputs is None:
        outputs = [*points, *(f"force:{mi.name}" for mi in meshes.info)]
    names = list(dict.fromkeys(outputs))
    chans, speed_rows = recorded_channels(model, sim.points, names)
    Ok, Oc = output_rows(chans) if chans else (np.zeros((0, n)), np.zeros((0, n)))
    Os = _scene_share(Ok, chans, G)
    acc = np.array([c.derivative == 2 for c in chans], bool)
    Oa, Ok, Oc, Os = Ok[acc], Ok[~acc], Oc[~acc] + Os[~acc], Os[~acc]
    chans = [c for c in chans if c.derivative != 2] + [c for c in chans if c.derivative == 2]
    mesh_idx = {f"force:{mi.name}": j for j, mi in enumerate(meshes.info)}
    swap = [(i, mesh_idx[c.name]) for i, c in enumerate(chans) if c.name in mesh_idx]
    Sv = np.array(list(speed_rows.values())).reshape(len(speed_rows), n)
    check_history(dt, t_end, len(chans) + len(speed_rows), n, U.shape[1])   # the whole run, before it starts

    def observe(q, v, a, nu):
        y = Ok @ q + Oc @ v
        for i, j in swap:
            y[i] = meshes.last_force[j] + Os[i] @ v
        return np.concatenate([y, Oa @ a, Sv @ v])

    freqs, shaft_hz, side_hz = _mesh_frequencies(model, scene, v0)
    warnings = step_warnings(dt, freqs, meshes, scene.band) + undamped_band(model, M, K, C, scene.band)
    recorded = [*hist, *([torques.history] if torques is not None and torques.history is not None else [])]
    warnings += [w for w in (range_warning(h, check_step(dt, t_end) * dt) for h in recorded) if w]
    if sim.brake is not None and torques is not None and torques.i_brake is not None:
        # below the stick speed the brake is a damper T/stick on the braked body: the trapezoidal
        # rule keeps its decay positive only for dt < 2 J stick / T (J: the body's own inertia)
        J_b = _polar_inertia(model, _brake_body(model, scene, sim))
        if J_b > 0 and dt > 2 * J_b * sim.brake.stick_speed / sim.brake.torque:
            warnings.append(f"dt = {dt:g} s > 2 J stick_speed / torque = "
                            f"{2 * J_b * sim.brake.stick_speed / sim.brake.torque:.3g} s: once stopped, the "
                            "braked shaft's speed alternates in sign inside the stick band (raise "
                            "simulation.brake.stick_speed or lower dt)")
    for w in warnings:
        log.warning(w)
    try:
        # one BLAS thread for small models: threads cost more than products of this size
        with threadpool_limits(1 if n <= SMALL_DENSE else None):
            run = integrate(M, C, K, force, q0, v0, dt, t_end, scheme_of(sim), nl, observe, progress,
                            model.dof_names)
        complete = True
    except Diverged as exc:
        run, complete = exc.partial, False
        stopped = exc
    values, units = _collect(run.y, chans, list(speed_rows))
    info = dict(run.info)
    info.update({"dt_s": dt, "t_end_s": t_end, "scheme": run.scheme.name, "dofs": n,
                 "losses_total": int(meshes.losses.sum())})
    result = SimulationResult(run.time_s, values, units,
                              [{"name": mi.name, "path": mi.path, "teeth": mi.teeth, "backlash_m": None if
                                math.isnan(mi.backlash) else mi.backlash, "harmonics": mi.harmonics,
                                "contact_losses": int(meshes.losses[j])} for j, mi in enumerate(meshes.info)],
                              freqs, shaft_hz, side_hz, warnings, info, complete)
    if not complete:
        raise Diverged(str(stopped), result)
    return result


def _scene_share(Ok: np.ndarray, chans: list, G) -> np.ndarray:
    """The damper rows of the scene-damping share of each output (zero but for section loads):
    ``Ok G`` (module notes)."""
    out = np.zeros_like(Ok)
    sec = np.array([c.section for c in chans], bool)
    if G is not None and sec.any():
        out[sec] = Ok[sec] @ G if np.ndim(G) else G * Ok[sec]
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


def recorded_channels(model, points, names, arg: str = "--output") -> tuple[list, dict]:
    """The channels and the speed rows (``speed:BODY``) that record ``names``: a named stress
    point of ``points`` (``simulation.points``) or an output of
    :func:`assembly.dynamics.frf_channels.output_channels`; SceneError at ``arg`` for a name
    the model does not have."""
    named = {f"stress:{p.name}": (i, p) for i, p in enumerate(points)}
    chans, speed_rows = [], {}
    for name in names:
        if name.startswith("speed:"):
            body, _ = body_point(model, name[6:], arg, name)
            speed_rows[name] = spin_row(model, body)
        elif name in named:
            i, p = named[name]
            where = f"stress:{p.body}:" + ",".join(f"{v:.17g}" for v in p.point)
            chans.extend(dataclasses.replace(c, name=f"{name}:{c.name.rsplit(':', 1)[1]}", group=name)
                         for c in output_channels(model, where, f"simulation.points[{i}]"))
        else:
            chans.extend(output_channels(model, name, arg))
    return chans, speed_rows


def _shaft_torques(model, scene, sim: Simulation, dt: float, v0: np.ndarray, base_dir=Path("."), phi=None):
    """(the generator / brake / friction part or None, (load vector, history) or None): a
    generator of a constant or recorded torque alone is a plain load (its vector on q times
    the torque), needing no nonlinear part. The generator's sense is its starting sense; from
    standstill, for a recorded torque, the sense it turns in when the reference turns
    positively (``phi``)."""
    gen, brake, eta = sim.generator, sim.brake, sim.gearbox_efficiency
    if gen is None and brake is None and eta >= 1.0:
        return None, None
    if gen is not None and gen.law == "pi" and gen.rated_speed is None:
        raise SceneError("simulation.generator.rated_speed", None, "missing: the PI law needs the generator's "
                                                                   "rated speed (rad/s)")
    history = generator_history(gen, "simulation.generator", base_dir) if gen is not None else None

    g_body = _table_body(model, scene, gen, "simulation.generator")
    r_gen = spin_row(model, g_body)
    sense = float(np.sign(r_gen @ v0)) or (float(np.sign(r_gen @ phi)) if history is not None and phi is not None
                                           else 0.0) or 1.0
    if gen is not None and gen.law != "pi" and brake is None and eta >= 1.0:
        torque = history if history is not None else constant(gen.torque, "generator", "N m")
        return None, (-sense * r_gen, torque)
    r_brake = spin_row(model, _brake_body(model, scene, sim)) if brake is not None else None
    lss = None
    if eta < 1.0:
        rotor = chain_ends(scene)[0]
        name = sim.lss_shaft or next((el.name.split(":")[0] for el in model.elements if el.kind == "shaft"
                                      and rotor in el.bodies), None)
        if name is None:
            raise SceneError("simulation.lss_shaft", None, "missing: no shaft joins the rotor; name the "
                                                           "low-speed shaft whose torque sign sets the friction")
        ch = output_channels(model, f"torque:{name}", "simulation.lss_shaft")[0]
        s_rot = float(np.sign(spin_row(model, rotor) @ v0)) or 1.0
        lss = [s_rot * ch.k_row, s_rot * (ch.c_row if ch.c_row is not None else np.zeros_like(ch.k_row))]
    J = _polar_inertia(model, g_body)
    return ShaftTorques(model.K.shape[0], dt, gen, r_gen, sense, brake, r_brake, eta, lss, J, history), None


def _table_body(model, scene, table, path: str) -> str:
    """The body a generator or brake table names, default the body of role "generator"."""
    if table is not None and table.body is not None:
        return body_point(model, table.body, f"{path}.body", table.body)[0]
    return chain_ends(scene)[1]


def _brake_body(model, scene, sim) -> str:
    return _table_body(model, scene, sim.brake, "simulation.brake")


def _polar_inertia(model, body: str) -> float:
    """The body's inertia about its own axis (kg m^2): its rigid-body rotation's kinetic
    energy per unit speed squared, x 2."""
    bm = model.bodies[body]
    sl = model.body_slice(body)
    Mb = model.M_abs[sl][:, sl]
    P = bm.rigid_projection()
    w = np.zeros(6)
    w[3:] = bm.axes[:, 2]
    try:
        u = np.linalg.lstsq(P, w, rcond=None)[0]           # the body's motion of a unit spin
    except np.linalg.LinAlgError:
        return 0.0
    return float(u @ (Mb @ u))


def _mesh_frequencies(model, scene, v0: np.ndarray):
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


def step_warnings(dt: float, freqs: dict, meshes, band_hz: float) -> list:
    """Warnings when ``dt`` gives fewer than :data:`STEPS_PER_PERIOD` steps per period of a
    mesh's highest harmonic kept or of the band (Hz)."""
    out = []
    harmonics = {}
    for mi in meshes.info:
        key = mi.name.split(".")[0] if mi.name.split(".")[0] in freqs else mi.name
        harmonics[key] = max(harmonics.get(key, 1), mi.harmonics or 1)
    for src, f in freqs.items():
        top = f * harmonics.get(src, 1)
        if top > 0 and 1.0 / (dt * top) < STEPS_PER_PERIOD:
            out.append(f"dt = {dt:g} s gives {1 / (dt * top):.1f} steps per period of {src}'s mesh harmonic "
                       f"{harmonics.get(src, 1)} ({top:.4g} Hz): below {STEPS_PER_PERIOD}, the period error "
                       f"exceeds {100 * (2 * math.pi / STEPS_PER_PERIOD) ** 2 / 12:.1f} %")
    if 1.0 / (dt * band_hz) < STEPS_PER_PERIOD:
        out.append(f"dt = {dt:g} s gives {1 / (dt * band_hz):.1f} steps per period at the band's top "
                   f"({band_hz:g} Hz): modes there are not resolved")
    return out


def _collect(Y: np.ndarray, chans: list, speed_names: list):
    """{name: history} and units from the recorded rows (stress components -> von Mises)."""
    values, units = {}, {}
    for j, c in enumerate(chans):
        if c.group is None:
            values[c.name], units[c.name] = Y[:, j], c.unit
        elif c.group not in values:
            cols = [i for i, o in enumerate(chans) if o.group == c.group]
            values[c.group], units[c.group] = von_mises(Y[:, cols]), c.unit
    for k, name in enumerate(speed_names):
        values[name], units[name] = Y[:, len(chans) + k], "rad/s"
    return values, units


def von_mises(S: np.ndarray) -> np.ndarray:
    """von Mises stress of Voigt rows (xx, yy, zz, yz, xz, xy), one per instant."""
    xx, yy, zz, yz, xz, xy = S.T
    return np.sqrt(0.5 * ((xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2) + 3 * (yz ** 2 + xz ** 2 + xy ** 2))
