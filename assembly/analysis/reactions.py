"""Forces of a static solution, from the springs: mesh forces, bearing reactions, shaft
section loads, support and constraint reactions, the output reaction torque, and the
checks (equilibrium of all external loads; torque balance and ratio for a torque case).

Every spring's force is its stiffness times its relative deflection, ``f = k * (B @ w)``
(:class:`assembly.mechanics.elements.Element`, ``w`` the attachment motions); the wrench it puts on
each attached body is ``-B' f`` (force N and moment N m at the element's point, global
axes). A held direction (a fixed DOF, a rigid bearing direction, the five held DOFs of a
torsional body, the output hold) carries the reaction that balances the spring wrenches on
its body -- worked out body by body, riders before their frames -- in the held directions
only; what remains in the free directions is the solve's own imbalance, which the torque
balance then shows. Conventions (docs/static.md):

* mesh ``force_N`` > 0: the flank ``drive_sign`` names in compression (``drive_flank``);
  < 0: the linear spring is in tension there, i.e. the load case drives the other flank;
  in ISO terms also F_t (reference circle), F_r, F_a (:mod:`assembly.analysis.iso_forces`);
* planet load sharing: K_gamma = max / mean of each stage's planet mesh forces
  (:func:`assembly.analysis.iso_forces.load_sharing`);
* bearing reaction: the force and moment the bearing exerts on its body, in the body's
  axes at the bearing point (a rigid direction: the constraint reaction of that DOF);
* shaft section load: ``k`` times (body1 - body2) relative motion, body1's axes; the torque
  is positive when body1 is twisted ahead of body2 about body1's axis;
* output reaction torque: the moment the hold exerts on the output about its own axis;
* support reaction: the force and moment the support exerts on its body, in the body's
  axes at the support point (from the solve's residual, :mod:`assembly.analysis.static`);
* equilibrium: applied loads + every reaction from the housing (springs to it, held
  directions of bodies in its frame, supports, the output hold) sum to zero, force and
  moment about one point (the first applied load's).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .. import arguments
from ..mechanics.kinematics import block_rotation
from ..model.constraints import constrained_dofs
from ..model.frame_motion import body_weights
from ..model.probes import load_point
from ..scene.tables import DOF_NAMES, HOUSING
from .gear_table import mesh_rows
from .iso_forces import iso_mesh_forces, load_sharing
from .load_cases import Applied, applied_loads, speed_ratio
from .static import StaticResult

_FORCE = ("Fx_N", "Fy_N", "Fz_N", "Mx_Nm", "My_Nm", "Mz_Nm")
_SECTION = ("shear_x_N", "shear_y_N", "axial_N", "bending_x_Nm", "bending_y_Nm", "torque_Nm")


@dataclass(frozen=True)
class StaticReport:
    """Forces of one load case (SI: N, N m) and its checks; :meth:`as_dict` for JSON."""

    case: str
    path: str
    input: str | None
    output: str | None
    torque_Nm: float | None
    output_torque_Nm: float | None
    meshes: list = field(default_factory=list)
    bearings: list = field(default_factory=list)
    shafts: list = field(default_factory=list)
    constraints: list = field(default_factory=list)
    balance: dict = field(default_factory=dict)
    ratio: dict = field(default_factory=dict)
    loads: list = field(default_factory=list)
    supports: list = field(default_factory=list)
    equilibrium: dict = field(default_factory=dict)
    load_sharing: list = field(default_factory=list)

    def as_dict(self) -> dict:
        return dict(case=self.case, path=self.path, input=self.input, output=self.output,
                    input_torque_Nm=self.torque_Nm, output_reaction_torque_Nm=self.output_torque_Nm,
                    applied_loads=self.loads, meshes=self.meshes, bearings=self.bearings, shafts=self.shafts,
                    supports=self.supports, constraints=self.constraints, torque_balance=self.balance,
                    ratio_check=self.ratio, equilibrium=self.equilibrium,
                    planet_load_sharing=self.load_sharing)


def _shift(wrench: np.ndarray, point, to) -> np.ndarray:
    """Wrench [F, M at ``point``] expressed at ``to``."""
    out = wrench.copy()
    out[3:] += np.cross(np.asarray(point, float) - np.asarray(to, float), wrench[:3])
    return out


def element_wrenches(model, el, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(spring forces ``k * (B @ w)`` per row, (n_bodies x 6) wrenches on the attached
    bodies at ``el.point``, global axes)."""
    w = model.attachment_operator(el) @ z
    f = el.k * (el.B @ w)
    return f, -(el.B.T @ f).reshape(len(el.bodies), 6)


def _reference_point(model, body: str, load):
    """Where a body's held directions act: a rigid body's axis point; for the held
    flexible output of a torque case, its interface master."""
    bm = model.bodies[body]
    if bm.flexible:
        if load.has_torque and body == load.output:
            return bm.masters[load.output_interface][0]
        return bm.position
    return bm.axis_point


def static_report(st) -> StaticReport:
    """Applied loads, mesh forces, bearing reactions, shaft loads, support and constraint
    reactions and checks of one :class:`assembly.analysis.static.StaticResult`."""
    arguments.instance("st", st, StaticResult, "a StaticResult (solve_static)")
    model, z, load = st.model, st.z, st.load
    sc = model.scene
    frames = {b.name: b.frame for b in sc.bodies}
    totals = {b: np.zeros(6) for b in model.bodies}        # spring + applied wrench at reference point
    refs = {b: _reference_point(model, b, load) for b in model.bodies}
    housing = []                                           # (wrench, point) on bodies, from the housing
    meshes, bearings, shafts = [], [], []
    for el in model.elements:
        f, wr = element_wrenches(model, el, z)
        for b, wb in zip(el.bodies, wr):
            if b is not None:
                totals[b] += _shift(wb, el.point, refs[b])
                if None in el.bodies:
                    housing.append((wb, el.point))
        if el.kind == "mesh":
            meshes.append(_mesh_row(model, el, f[0]))
        elif el.kind == "bearing":
            R = block_rotation(model.bodies[el.bodies[0]].axes)
            bearings.append(dict(bearing=el.name, body=el.bodies[0], frame=el.bodies[1] or HOUSING,
                                 item=list(el.item), **dict(zip(_FORCE, (R.T @ wr[0]).tolist()))))
        elif el.kind == "shaft":
            R = block_rotation(model.bodies[el.bodies[0]].axes)
            shafts.append(dict(shaft=el.name, body1=el.bodies[0], body2=el.bodies[1],
                               **dict(zip(_SECTION, (-(R.T @ wr[0])).tolist()))))
    applied = applied_loads(model, load) + [Applied(b, p, w, None, f"weight of {b}")
                                            for b, p, w in body_weights(model, sc.turbine)]
    for a in applied:
        totals[a.body] += _shift(a.wrench, a.point, refs[a.body])
    supports = support_reactions(st)
    for row, w, p in supports:
        totals[row["body"]] += _shift(w, p, refs[row["body"]])
        housing.append((w, p))
    held = constrained_dofs(sc)
    output = load.output if load.has_torque else None
    if st.output_held:
        held[output].add("rz")
    reactions = _constraint_reactions(model, frames, totals, refs, held, output)
    constraints, out_torque = [], 0.0
    for b, (C, local) in reactions.items():
        for d in held[b]:
            v = float(local[DOF_NAMES.index(d)])
            if b == output and d == "rz":
                out_torque = v
                continue
            constraints.append(dict(body=b, dof=d, value=v, unit="N m" if d.startswith("r") else "N",
                                    source=_hold_source(sc, b, d)))
        if frames[b] == HOUSING:
            Ch = C.copy()
            if b == output:
                Ch[3:] -= out_torque * model.bodies[b].axes[:, 2]
            housing.append((Ch, refs[b]))
    _add_rigid_directions(sc, bearings, constraints)
    external = [(a.wrench, a.point) for a in applied] + housing
    if output is not None:
        external.append((np.concatenate([np.zeros(3), out_torque * model.bodies[output].axes[:, 2]]), refs[output]))
    src = model.source if model.source is not None else sc
    rows = mesh_rows(src)
    for m in meshes:
        if m["mesh"] in rows:
            m.update(iso_mesh_forces(m["force_N"], rows[m["mesh"]]))
    forces = [abs(float(m["force_N"])) for m in meshes] + [
        float(np.linalg.norm([r.get(k, 0.0) for k in _FORCE[:3]])) for r in bearings] + [
        float(np.linalg.norm(a.wrench[:3])) for a in applied]
    sharing = load_sharing(src, {m["mesh"]: m["force_N"] for m in meshes}, max(forces, default=0.0))
    balance = _torque_balance(model, load, applied, housing, out_torque) if load.has_torque else {}
    ratio = _ratio_check(model, load, out_torque) if load.has_torque else {}
    return StaticReport(load.name, st.path, load.input, output, load.torque, out_torque if output else None,
                        meshes, bearings, shafts, constraints, balance, ratio,
                        [_applied_row(a) for a in applied], [row for row, _, _ in supports],
                        equilibrium(external, applied[0].point if applied else np.zeros(3)), sharing)


def _applied_row(a) -> dict:
    return dict(load=a.label, body=a.body, interface=a.interface, point_m=a.point.tolist(),
                **dict(zip(_FORCE, a.wrench.tolist())))


def support_reactions(st) -> list:
    """(row, global wrench, point) per support of the case: the force and moment the
    support exerts on its body, from the hold reactions of its held DOFs (local axes at the
    support point; a DOF a constraint already holds reports 0 here and its reaction under
    the held directions)."""
    load, model = st.load, st.model
    local = {j: np.zeros(6) for j in range(len(load.supports))}
    points = {}
    for h, lam in zip(st.held, st.hold_reactions):
        if h.support is not None:
            local[h.support][DOF_NAMES.index(h.dof)] = lam
            points[h.support] = h.point
    out = []
    for j, su in enumerate(load.supports):
        bm = model.bodies[su.body]
        p = points.get(j, None)
        if p is None:
            p = load_point(model, su.body, su.interface)
        row = dict(support=j, body=su.body, interface=su.interface, dofs=list(su.dofs), point_m=p.tolist(),
                   **dict(zip(_FORCE, local[j].tolist())))
        out.append((row, block_rotation(bm.axes) @ local[j], p))
    return out


def equilibrium(wrenches, point) -> dict:
    """Sum of external wrenches ``(w, p)`` (applied loads and every reaction from the
    housing) about ``point``: force (N) and moment (N m), and its size relative to the
    magnitudes that enter it: moment against ``sum |M_i| + |p_i - point| |F_i|``, force
    against ``sum |F_i| + sum |M_i| / l`` (``l`` the largest arm: a couple is a force pair
    over the assembly, so the force sum is read at the scale of the forces its couples
    carry, not only of the net external forces, which may all be zero); the larger of the
    two is ``relative_error`` (0 for a sum of zeros)."""
    o = np.asarray(point, float)
    F, M = np.zeros(3), np.zeros(3)
    fs = ms = msum = arm = 0.0
    for w, p in wrenches:
        f, r = np.asarray(w[:3], float), np.linalg.norm(np.asarray(p, float) - o)
        F += f
        M += _shift(np.asarray(w, float), p, o)[3:]
        fs += np.linalg.norm(f)
        msum += np.linalg.norm(w[3:])
        ms += np.linalg.norm(w[3:]) + r * np.linalg.norm(f)
        arm = max(arm, r)
    if arm > 0:
        fs += msum / arm
    rel = max(np.linalg.norm(F) / fs if fs else 0.0, np.linalg.norm(M) / ms if ms else 0.0)
    return dict(point_m=o.tolist(), force_N=F.tolist(), moment_Nm=M.tolist(), relative_error=float(rel))


def _torque_balance(model, load, applied, housing, out_torque: float) -> dict:
    """Moments about the input axis (through the input point): input torque, output
    reaction, housing reactions (springs, held directions, supports) and the other applied
    loads; their sum relative to the input torque."""
    p_in = applied[0].point
    axis = model.bodies[load.input].axes[:, 2]
    out_axis = model.bodies[load.output].axes[:, 2]
    housing_moment = sum((float(axis @ _shift(w, p, p_in)[3:]) for w, p in housing), 0.0)
    loads_moment = sum((float(axis @ _shift(a.wrench, a.point, p_in)[3:]) for a in applied[1:]), 0.0)
    total = load.torque + out_torque * float(out_axis @ axis) + housing_moment + loads_moment
    return dict(input_Nm=load.torque, output_Nm=out_torque * float(out_axis @ axis), housing_Nm=housing_moment,
                loads_Nm=loads_moment, sum_Nm=total, relative_error=abs(total) / abs(load.torque),
                axis=axis.tolist())


def _mesh_row(model, el, force: float) -> dict:
    n = el.B[0, :3]
    ez = model.bodies[el.bodies[0]].axes[:, 2]
    axial = float(n @ ez)
    return dict(mesh=el.name, gear1=el.bodies[0], gear2=el.bodies[1], force_N=float(force),
                transverse_N=float(force * math.sqrt(max(0.0, 1.0 - axial * axial))), axial_N=float(force * axial),
                force_on_gear2_N=(force * n).tolist(), drive_flank=bool(force >= 0.0))


def _constraint_reactions(model, frames, totals, refs, held, output) -> dict:
    """Body -> (reaction wrench on it at its reference point, global; the same in its local
    axes) for every body with held directions: balances its spring and applied wrenches and
    the reactions of the bodies riding in its frame, in the held directions only."""
    out = {}
    for b in reversed(list(model.bodies)):                  # riders before their frames
        S = totals[b].copy()
        for r, (Cr, _) in out.items():
            if frames[r] == b:
                S -= _shift(Cr, refs[r], refs[b])
        if not held[b] or (model.bodies[b].flexible and b != output):
            continue
        R = block_rotation(model.bodies[b].axes)
        local = -(R.T @ S)
        mask = np.array([d in held[b] for d in DOF_NAMES])
        local[~mask] = 0.0
        out[b] = (R @ local, local)
    return out


def _hold_source(sc, body: str, dof: str) -> str:
    """What holds ``dof`` of ``body``: a fixed DOF, a rigid bearing direction, the
    torsional fidelity."""
    if any(f.body == body and dof in f.dofs for f in sc.fixed):
        return "fixed"
    for i, br in enumerate(sc.bearings):
        if br.body == body and math.isinf(br.diagonal()[DOF_NAMES.index(dof)]):
            return f"bearing {br.name or f'bearing[{i}]:{br.body}'} (rigid)"
    return "torsional fidelity"


def _add_rigid_directions(sc, bearings: list, constraints: list) -> None:
    """A rigid bearing direction's constraint reaction goes into that bearing's row (the
    first bearing rigid in that direction, when several are)."""
    rows = {r["bearing"]: r for r in bearings}
    for c in constraints:
        if c["source"].startswith("bearing "):
            name = c["source"][len("bearing "):-len(" (rigid)")]
            if name in rows:
                rows[name][_FORCE[DOF_NAMES.index(c["dof"])]] += c["value"]


def _ratio_check(model, load, out_torque: float) -> dict:
    """Output reaction / input torque against the kinematic speed ratio: virtual work on
    the rigid-body mode gives ``T_out = -T_in omega_in / omega_out`` whenever that mode
    exists (the housing holds only bodies that stand still in it) and the torque is the
    only load and the output the only hold of the case."""
    torque_ratio = -out_torque / load.torque
    if load.forces or load.supports:
        return dict(torque_ratio=torque_ratio, speed_ratio=None, relative_error=None,
                    note="not applicable: the case has point loads or supports besides the torque")
    ratio, note = speed_ratio(model, load)
    row = dict(torque_ratio=torque_ratio, speed_ratio=ratio, note=note, relative_error=None)
    if ratio is not None:
        row["relative_error"] = abs(torque_ratio - ratio) / abs(ratio)
    return row
