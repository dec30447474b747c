"""Assembly of a scene into one linear modal problem.

Absolute coordinates ``z`` stack every body's own DOFs (a rigid body: 6, global axes, at
its centre of mass; a flexible body: its component coordinates); all elements and mass
matrices are written in them. Independent coordinates ``q`` (``z = T q``) express each
rigid body's motion relative to its reference frame, minus the constrained directions
(fixed DOFs, rigid bearing directions, and the five non-spin DOFs of a torsional body).
So ``K = T' K_abs T`` and ``M = T' M_abs T``: a torsional model is literally the rigid
model with five DOFs per body constrained. Matrices are sparse (CSR) throughout.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from .attach import bearing_point, component_masters, mesh_centers, shaft_points
from .bodies import RigidBodyModel
from .elements import Element, gear_mesh, relative_spring
from .geometry import block_rotation, rigid_transfer
from .scene import DOF_NAMES, HOUSING, Scene

log = logging.getLogger(__name__)


@dataclass
class AssembledModel:
    scene: Scene
    bodies: dict
    offsets: dict
    elements: list
    K_abs: sp.csr_matrix
    M_abs: sp.csr_matrix
    T: sp.csr_matrix
    dof_names: list
    abs_dof_names: list
    K: sp.csr_matrix = field(repr=False)
    M: sp.csr_matrix = field(repr=False)
    timings: dict = field(default_factory=dict)

    @property
    def n_abs(self) -> int:
        return self.K_abs.shape[0]

    def body_slice(self, name: str) -> slice:
        o = self.offsets[name]
        return slice(o, o + self.bodies[name].ndof)

    def element_stiffness_abs(self, el: Element) -> sp.csr_matrix:
        """Element stiffness scattered into absolute coordinates."""
        L = self.attachment_operator(el)
        return (L.T @ sp.csr_matrix(el.stiffness()) @ L).tocsr()

    def attachment_operator(self, el: Element) -> sp.csr_matrix:
        """Sparse map from ``z`` to the element's stacked attachment motions ``w``."""
        blocks = []
        for b, iface in zip(el.bodies, el.interfaces):
            if b is None:
                blocks.append(sp.csr_matrix((6, self.n_abs)))
                continue
            P = sp.csr_matrix(self.bodies[b].motion_at(el.point, iface))
            o = self.offsets[b]
            P = sp.hstack([sp.csr_matrix((6, o)), P, sp.csr_matrix((6, self.n_abs - o - P.shape[1]))])
            blocks.append(P.tocsr())
        return sp.vstack(blocks).tocsr()

    def rigid_coordinates(self, Z: np.ndarray) -> np.ndarray:
        """Rigid-equivalent motion (6 per body, global axes, at each COM) of columns of Z."""
        return np.vstack([self.bodies[b].rigid_projection() @ Z[self.body_slice(b)] for b in self.bodies])

    def rigid_mass_matrix(self) -> np.ndarray:
        """Block-diagonal 6x6 rigid mass matrices of all bodies (for mass-weighted MAC)."""
        blocks = []
        for bm in self.bodies.values():
            B = np.zeros((6, 6))
            B[:3, :3] = bm.mass * np.eye(3)
            B[3:, 3:] = bm.inertia
            blocks.append(B)
        return sp.block_diag(blocks, format="csr")


def _frame_order(scene: Scene) -> list:
    """Bodies ordered so that every frame comes before the bodies that live in it."""
    by_name = {b.name: b for b in scene.bodies}
    done, order = set(), []

    def visit(b):
        if b.name in done:
            return
        if b.frame != HOUSING:
            visit(by_name[b.frame])
        done.add(b.name)
        order.append(b)

    for b in scene.bodies:
        visit(b)
    return order


#: A bearing direction stiffer than RIGID_RATIO x the scene's reference stiffness (largest
#: gear-mesh or shaft stiffness, N/m; times the largest base radius squared for rotations)
#: is modelled as an exact constraint. Such a spring changes the physical frequencies by
#: about 1/RIGID_RATIO relative, but as a spring it puts eigenvalues RIGID_RATIO times
#: above the physics and costs the low modes their accuracy (eps * lambda_max).
RIGID_RATIO = 1e8


def rigidify(scene: Scene) -> tuple[Scene, list]:
    """Scene with near-rigid bearing directions replaced by ``inf`` (constraints), and the
    list of (bearing, direction) converted. Only bearings that may carry a constraint (a
    plain rigid body, at its position, to its own frame) are converted."""
    import dataclasses
    import math
    ks = [m.stiffness for m in scene.meshes] + [max(s.k_axial, s.k_shear) for s in scene.shafts]
    if not ks or max(ks) <= 0:
        return scene, []
    k_ref = max(ks)
    r = max([abs(m.base_radius1) for m in scene.meshes] + [abs(m.base_radius2) for m in scene.meshes] + [0.0])
    kr_ref = max([k_ref * r * r] + [max(s.k_torsion, s.k_bending) for s in scene.shafts])
    by_name = {b.name: b for b in scene.bodies}
    out, changed = [], []
    for br in scene.bearings:
        body = by_name[br.body]
        eligible = (body.component is None and (br.frame is None or br.frame == body.frame)
                    and (br.position is None or np.allclose(br.position, body.position, rtol=0, atol=1e-12)))
        new = {}
        if eligible:
            for f, ref in (("k_radial", k_ref), ("k_axial", k_ref), ("k_tilt", kr_ref), ("k_torsion", kr_ref)):
                v = getattr(br, f)
                if math.isfinite(v) and v > RIGID_RATIO * ref:
                    new[f] = math.inf
                    changed.append((br.name or br.body, f, v))
        out.append(dataclasses.replace(br, **new) if new else br)
    if changed:
        log.info("near-rigid bearing directions modelled as constraints: %s", changed)
    return dataclasses.replace(scene, bearings=tuple(out)), changed


def constrained_dofs(scene: Scene) -> dict:
    """Local DOF names held at zero, per body (fixed DOFs, rigid bearings, torsional)."""
    out = {b.name: set() for b in scene.bodies}
    for f in scene.fixed:
        out[f.body].update(f.dofs)
    for br in scene.bearings:
        for name, ki in zip(DOF_NAMES, br.diagonal()):
            if np.isinf(ki):
                out[br.body].add(name)
    for b in scene.bodies:
        if b.fidelity == "torsional":
            out[b.name].update(d for d in DOF_NAMES if d != "rz")
    return out


def build_elements(scene: Scene, bodies: dict, masters: dict) -> list:
    """Bearings, shafts and gear meshes of an (expanded) scene as :class:`Element`s."""
    by_name = {b.name: b for b in scene.bodies}
    elements = []
    for i, br in enumerate(scene.bearings):
        body = by_name[br.body]
        frame = br.frame if br.frame is not None else body.frame
        point, iface = bearing_point(br, body, masters, f"bearings[{i}]")
        k = np.where(np.isinf(br.diagonal()), 0.0, br.diagonal())
        el = relative_spring(br.name or f"bearing[{i}]:{br.body}", "bearing", br.body,
                             None if frame == HOUSING else frame, point, bodies[br.body].axes, k)
        elements.append(_with_interfaces(el, (iface, br.frame_interface)))
    for i, s in enumerate(scene.shafts):
        point, i1, i2 = shaft_points(s, by_name[s.body1], by_name[s.body2], masters, f"shafts[{i}]")
        el = relative_spring(s.name or f"shaft[{i}]:{s.body1}-{s.body2}", "shaft", s.body1, s.body2, point,
                             bodies[s.body1].axes, s.diagonal())
        elements.append(_with_interfaces(el, (i1, i2)))
    for i, m in enumerate(scene.meshes):
        b1, b2 = by_name[m.gear1], by_name[m.gear2]
        c1, c2, i1, i2 = mesh_centers(m, b1, b2, masters, f"meshes[{i}]")
        el = gear_mesh(m.name or f"mesh[{i}]:{m.gear1}-{m.gear2}", m.gear1, m.gear2, b1.axis, c1, c2,
                       m.base_radius1, m.base_radius2, m.pressure_angle, m.helix_angle, m.drive_sign,
                       m.stiffness, m.contact_point)
        elements.append(_with_interfaces(el, (i1, i2)))
    return elements


def _with_interfaces(el: Element, ifaces) -> Element:
    import dataclasses
    return dataclasses.replace(el, interfaces=tuple(ifaces))


def build_body_models(scene: Scene, full_fe: bool = False, progress=None) -> dict:
    """Body models in frame order: rigid (plain or from a component's mesh) or flexible."""
    from .flexible import DEFAULT_BAND_HZ, FlexOptions, component_params, flexible_body, mass_properties
    from .geometry import axis_frame
    band = scene.band_hz or DEFAULT_BAND_HZ
    out = {}
    for b in _frame_order(scene):
        if b.component is None:
            out[b.name] = RigidBodyModel.from_body(b)
            continue
        params = component_params(b, b.name)
        opts = b.flex or FlexOptions()
        if b.fidelity == "flexible":
            out[b.name] = flexible_body(b, params, opts, band, reduce=not full_fe)
        else:
            mass, com, J, _ = mass_properties(b, params, opts)
            out[b.name] = RigidBodyModel.from_mass_properties(b.name, com, axis_frame(b.axis), mass, J,
                                                              axis_point=b.position)
        if progress is not None:
            progress(b.name)
    return out


def assemble(scene: Scene, full_fe: bool = False, bodies: dict | None = None) -> AssembledModel:
    """Assemble ``scene`` (stages expanded) into sparse K, M on independent coordinates.

    ``full_fe=True`` keeps flexible bodies unreduced (every FE DOF): the reference model.
    ``bodies`` may pass pre-built body models (e.g. to reuse reductions across variants).
    """
    t0 = time.perf_counter()
    sc, rigidified = rigidify(scene.expanded())
    order = _frame_order(sc)
    origin = {b.name: b.name for b in sc.bodies}
    masters = component_masters(sc, origin)
    if bodies is None:
        bodies = build_body_models(sc, full_fe=full_fe)
    t_bodies = time.perf_counter() - t0
    offsets, n = {}, 0
    for b in order:
        offsets[b.name] = n
        n += bodies[b.name].ndof
    elements = build_elements(sc, bodies, masters)

    abs_names = []
    for b in order:
        abs_names += bodies[b.name].dof_names()
    M_abs = sp.block_diag([sp.csr_matrix(bodies[b.name].mass_matrix()) for b in order], format="csr")
    K_abs = sp.block_diag([sp.csr_matrix(bodies[b.name].stiffness_matrix()) for b in order], format="csr")
    model = AssembledModel(sc, {b.name: bodies[b.name] for b in order}, offsets, elements, K_abs, M_abs,
                           None, [], abs_names, None, None)
    parts = [K_abs]
    for el in elements:
        parts.append(model.element_stiffness_abs(el))
    model.K_abs = sum(parts[1:], parts[0]).tocsr()

    # z = T q: rigid bodies move with their frame plus free relative DOFs (local axes);
    # flexible bodies (housing frame only) keep all their DOFs.
    held = constrained_dofs(sc)
    ncols, col0 = {}, {}
    m = 0
    for b in order:
        bm = bodies[b.name]
        k = bm.ndof if b.fidelity == "flexible" else sum(d not in held[b.name] for d in DOF_NAMES)
        col0[b.name], ncols[b.name] = m, k
        m += k
    rows, names = {}, []
    for b in order:
        bm = bodies[b.name]
        if b.fidelity == "flexible":
            own = sp.identity(bm.ndof, format="csr")
            names += bm.dof_names()
        else:
            free = [i for i, d in enumerate(DOF_NAMES) if d not in held[b.name]]
            # relative DOFs live at the body's axis point, in its axes (spin about the axis)
            own = sp.csr_matrix(rigid_transfer(bm.position, bm.axis_point) @ block_rotation(bm.axes)[:, free])
            names += [f"{b.name}.{DOF_NAMES[i]}" for i in free]
        blk = sp.hstack([sp.csr_matrix((bm.ndof, col0[b.name])), own,
                         sp.csr_matrix((bm.ndof, m - col0[b.name] - ncols[b.name]))]).tocsr()
        if b.frame != HOUSING:
            fr = bodies[b.frame]
            iface = _frame_interface(sc, b)
            blk = blk + sp.csr_matrix(fr.motion_at(bm.position, iface)) @ rows[b.frame]
        rows[b.name] = blk.tocsr()
    model.T = sp.vstack([rows[b.name] for b in order]).tocsr()
    model.dof_names = names
    K = (model.T.T @ model.K_abs @ model.T).tocsr()
    M = (model.T.T @ model.M_abs @ model.T).tocsr()
    model.K = ((K + K.T) * 0.5).tocsr()
    model.M = ((M + M.T) * 0.5).tocsr()
    model.timings = {"bodies_s": t_bodies, "assembly_s": time.perf_counter() - t0 - t_bodies}
    model.rigidified = rigidified
    log.info("assembled %s: %d bodies, %d elements, %d DOFs", sc.name, len(bodies), len(elements), len(names))
    return model


def _frame_interface(scene: Scene, body) -> str | None:
    """Interface of the frame body at which ``body`` rides (its bearing's frame_interface)."""
    for br in scene.bearings:
        if br.body == body.name and (br.frame is None or br.frame == body.frame) and br.frame_interface:
            return br.frame_interface
    return None
