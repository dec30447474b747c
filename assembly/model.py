"""Assembly of a scene into one linear modal problem.

Absolute coordinates ``z`` stack every body's own DOFs (global axes); all elements and
mass matrices are written in them. Independent coordinates ``q`` (``z = T q``) express each
body's motion relative to its reference frame, minus the constrained directions (fixed
DOFs, rigid bearing directions, and the five non-spin DOFs of a torsional body). So
``K = T' K_abs T`` and ``M = T' M_abs T``; a torsional model is literally the rigid model
with five DOFs per body constrained.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from .bodies import RigidBodyModel
from .elements import Element, gear_mesh, relative_spring
from .geometry import block_rotation
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
    K: np.ndarray = field(repr=False)
    M: np.ndarray = field(repr=False)

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
        rows = []
        for b in el.bodies:
            if b is None:
                rows.append(sp.csr_matrix((6, self.n_abs)))
                continue
            P = self.bodies[b].motion_at(el.point)
            blk = sp.lil_matrix((6, self.n_abs))
            blk[:, self.body_slice(b)] = P
            rows.append(blk.tocsr())
        return sp.vstack(rows).tocsr()


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


def constrained_dofs(scene: Scene) -> dict:
    """Local DOF names held at zero, per body (fixed DOFs, rigid bearings, torsional)."""
    out = {b.name: set() for b in scene.bodies}
    for f in scene.fixed:
        out[f.body].update(f.dofs)
    by_name = {b.name: b for b in scene.bodies}
    for br in scene.bearings:
        k = br.diagonal()
        for name, ki in zip(DOF_NAMES, k):
            if np.isinf(ki):
                out[br.body].add(name)
    for b in scene.bodies:
        if b.fidelity == "torsional":
            out[b.name].update(d for d in DOF_NAMES if d != "rz")
    del by_name
    return out


def build_elements(scene: Scene, bodies: dict) -> list:
    """Bearings, shafts and gear meshes of an (expanded) scene as :class:`Element`s."""
    by_name = {b.name: b for b in scene.bodies}
    elements = []
    for i, br in enumerate(scene.bearings):
        body = by_name[br.body]
        frame = br.frame if br.frame is not None else body.frame
        point = br.position if br.position is not None else body.position
        k = np.where(np.isinf(br.diagonal()), 0.0, br.diagonal())
        elements.append(relative_spring(br.name or f"bearing[{i}]:{br.body}", "bearing", br.body,
                                        None if frame == HOUSING else frame, point,
                                        bodies[br.body].axes, k))
    for i, s in enumerate(scene.shafts):
        point = s.position if s.position is not None else 0.5 * (
            np.asarray(by_name[s.body1].position) + np.asarray(by_name[s.body2].position))
        elements.append(relative_spring(s.name or f"shaft[{i}]:{s.body1}-{s.body2}", "shaft",
                                        s.body1, s.body2, point, bodies[s.body1].axes, s.diagonal()))
    for i, m in enumerate(scene.meshes):
        b1, b2 = by_name[m.gear1], by_name[m.gear2]
        c1 = m.center1 if m.center1 is not None else b1.position
        c2 = m.center2 if m.center2 is not None else b2.position
        elements.append(gear_mesh(m.name or f"mesh[{i}]:{m.gear1}-{m.gear2}", m.gear1, m.gear2,
                                  b1.axis, c1, c2, m.base_radius1, m.base_radius2, m.pressure_angle,
                                  m.helix_angle, m.drive_sign, m.stiffness, m.contact_point))
    return elements


def assemble(scene: Scene) -> AssembledModel:
    """Assemble ``scene`` (any stages expanded) into K, M on independent coordinates."""
    sc = scene.expanded()
    order = _frame_order(sc)
    bodies, offsets, n = {}, {}, 0
    for b in order:
        bodies[b.name] = RigidBodyModel.from_body(b)
        offsets[b.name] = n
        n += bodies[b.name].ndof
    elements = build_elements(sc, bodies)

    abs_names = []
    for b in order:
        abs_names += bodies[b.name].dof_names()
    M_abs = sp.block_diag([bodies[b.name].mass_matrix() for b in order], format="csr")
    K_abs = sp.block_diag([bodies[b.name].stiffness_matrix() for b in order], format="csr")

    model = AssembledModel(sc, bodies, offsets, elements, K_abs, M_abs, None, [], abs_names, None, None)
    for el in elements:
        K_abs = K_abs + model.element_stiffness_abs(el)
    model.K_abs = K_abs.tocsr()

    # z = T q: each body moves with its frame plus its free relative DOFs (local axes).
    held = constrained_dofs(sc)
    T = np.zeros((n, 0))
    names = []
    for b in order:
        bm = bodies[b.name]
        sl = model.body_slice(b.name)
        free = [i for i, d in enumerate(DOF_NAMES) if d not in held[b.name]]
        cols = np.zeros((n, len(free)))
        cols[sl, :] = block_rotation(bm.axes)[:, free]
        if b.frame != HOUSING:
            fr = bodies[b.frame]
            T[sl, :] = fr.motion_at(bm.position) @ T[model.body_slice(b.frame), :]
        T = np.hstack([T, cols])
        names += [f"{b.name}.{DOF_NAMES[i]}" for i in free]
    model.T = sp.csr_matrix(T)
    model.dof_names = names
    model.K = (model.T.T @ model.K_abs @ model.T).toarray()
    model.M = (model.T.T @ model.M_abs @ model.T).toarray()
    model.K = 0.5 * (model.K + model.K.T)
    model.M = 0.5 * (model.M + model.M.T)
    log.info("assembled %s: %d bodies, %d elements, %d DOFs", sc.name, len(bodies), len(elements), len(names))
    return model
