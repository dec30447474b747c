"""Forces of a static solution, from the springs: mesh forces, bearing reactions, shaft
section loads, constraint reactions, the output reaction torque, and two checks.

Every spring's force is its stiffness times its relative deflection, ``f = k * (B @ w)``
(:class:`assembly.elements.Element`, ``w`` the attachment motions); the wrench it puts on
each attached body is ``-B' f`` (force N and moment N m at the element's point, global
axes). A held direction (a fixed DOF, a rigid bearing direction, the five held DOFs of a
torsional body, the output hold) carries the reaction that balances the spring wrenches on
its body -- worked out body by body, riders before their frames -- in the held directions
only; what remains in the free directions is the solve's own imbalance, which the torque
balance then shows. Conventions (docs/static.md):

* mesh ``force_N`` > 0: the flank ``drive_sign`` names in compression (``drive_flank``);
  < 0: the linear spring is in tension there, i.e. the load case drives the other flank;
* bearing reaction: the force and moment the bearing exerts on its body, in the body's
  axes at the bearing point (a rigid direction: the constraint reaction of that DOF);
* shaft section load: ``k`` times (body1 - body2) relative motion, body1's axes; the torque
  is positive when body1 is twisted ahead of body2 about body1's axis;
* output reaction torque: the moment the hold exerts on the output about its own axis.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .constraints import constrained_dofs
from .kinematics import block_rotation
from .loads import input_load, speed_ratio
from .scene import DOF_NAMES, HOUSING

_FORCE = ("Fx_N", "Fy_N", "Fz_N", "Mx_Nm", "My_Nm", "Mz_Nm")
_SECTION = ("shear_x_N", "shear_y_N", "axial_N", "bending_x_Nm", "bending_y_Nm", "torque_Nm")


@dataclass(frozen=True)
class StaticReport:
    """Forces of one load case (SI: N, N m) and its checks; :meth:`as_dict` for JSON."""

    case: str
    path: str
    input: str
    output: str
    torque_Nm: float
    output_torque_Nm: float
    meshes: list = field(default_factory=list)
    bearings: list = field(default_factory=list)
    shafts: list = field(default_factory=list)
    constraints: list = field(default_factory=list)
    balance: dict = field(default_factory=dict)
    ratio: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        return dict(case=self.case, path=self.path, input=self.input, output=self.output,
                    input_torque_Nm=self.torque_Nm, output_reaction_torque_Nm=self.output_torque_Nm,
                    meshes=self.meshes, bearings=self.bearings, shafts=self.shafts,
                    constraints=self.constraints, torque_balance=self.balance, ratio_check=self.ratio)


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


def _reference_point(model, body: str, load=None):
    """Where a body's held directions act: a rigid body's axis point; for the held
    flexible output, its interface master."""
    bm = model.bodies[body]
    if bm.flexible:
        return bm.masters[load.output_interface][0] if load is not None else bm.position
    return bm.axis_point


def static_report(st) -> StaticReport:
    """Mesh forces, bearing reactions, shaft loads, constraint reactions and checks of one
    :class:`assembly.static.StaticResult`."""
    model, z, load = st.model, st.z, st.load
    sc = model.scene
    frames = {b.name: b.frame for b in sc.bodies}
    totals = {b: np.zeros(6) for b in model.bodies}        # spring + applied wrench at reference point
    refs = {b: _reference_point(model, b, load if b == load.output else None) for b in model.bodies}
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
    Fin = input_load(model, load)[model.body_slice(load.input)]
    bin_ = model.bodies[load.input]
    if bin_.flexible:
        p_in = bin_.masters[load.input_interface][0]
        applied = np.concatenate([np.zeros(3), load.torque * bin_.axes[:, 2]])
    else:
        p_in = bin_.axis_point
        applied = Fin.copy()
    totals[load.input] += _shift(applied, p_in, refs[load.input])
    held = constrained_dofs(sc)
    if st.held is not None:
        held[load.output].add("rz")
    reactions = _constraint_reactions(model, frames, totals, refs, held, load)
    constraints, out_torque = [], 0.0
    for b, (C, local) in reactions.items():
        for d in held[b]:
            v = float(local[DOF_NAMES.index(d)])
            if b == load.output and d == "rz":
                out_torque = v
                continue
            constraints.append(dict(body=b, dof=d, value=v, unit="N m" if d.startswith("r") else "N",
                                    source=_hold_source(sc, b, d)))
        if frames[b] == HOUSING:
            Ch = C.copy()
            if b == load.output:
                Ch[3:] -= out_torque * model.bodies[b].axes[:, 2]
            housing.append((Ch, refs[b]))
    _add_rigid_directions(sc, bearings, constraints)
    axis = bin_.axes[:, 2]
    out_axis = model.bodies[load.output].axes[:, 2]
    housing_moment = sum((float(axis @ _shift(w, p, p_in)[3:]) for w, p in housing), 0.0)
    total = load.torque + out_torque * float(out_axis @ axis) + housing_moment
    balance = dict(input_Nm=load.torque, output_Nm=out_torque * float(out_axis @ axis),
                   housing_Nm=housing_moment, sum_Nm=total, relative_error=abs(total) / abs(load.torque),
                   axis=axis.tolist())
    return StaticReport(load.name, st.path, load.input, load.output, load.torque, out_torque, meshes, bearings,
                        shafts, constraints, balance, _ratio_check(model, load, out_torque))


def _mesh_row(model, el, force: float) -> dict:
    n = el.B[0, :3]
    ez = model.bodies[el.bodies[0]].axes[:, 2]
    axial = float(n @ ez)
    return dict(mesh=el.name, gear1=el.bodies[0], gear2=el.bodies[1], force_N=float(force),
                transverse_N=float(force * math.sqrt(max(0.0, 1.0 - axial * axial))), axial_N=float(force * axial),
                force_on_gear2_N=(force * n).tolist(), drive_flank=bool(force >= 0.0))


def _constraint_reactions(model, frames, totals, refs, held, load) -> dict:
    """Body -> (reaction wrench on it at its reference point, global; the same in its local
    axes) for every body with held directions: balances its spring and applied wrenches and
    the reactions of the bodies riding in its frame, in the held directions only."""
    out = {}
    for b in reversed(list(model.bodies)):                  # riders before their frames
        S = totals[b].copy()
        for r, (Cr, _) in out.items():
            if frames[r] == b:
                S -= _shift(Cr, refs[r], refs[b])
        if not held[b] or (model.bodies[b].flexible and b != load.output):
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
    exists (the housing holds only bodies that stand still in it)."""
    ratio, note = speed_ratio(model, load)
    torque_ratio = -out_torque / load.torque
    row = dict(torque_ratio=torque_ratio, speed_ratio=ratio, note=note, relative_error=None)
    if ratio is not None:
        row["relative_error"] = abs(torque_ratio - ratio) / abs(ratio)
    return row
