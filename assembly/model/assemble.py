"""Assembly of a scene into one linear modal problem.

Absolute coordinates ``z`` stack every body's own DOFs (a rigid body: 6, global axes, at
its centre of mass; a flexible body: its component coordinates); all elements and mass
matrices are written in them. Independent coordinates ``q`` (``z = T q``) express each
rigid body's motion relative to its reference frame, minus the constrained directions
(fixed DOFs, rigid bearing directions, and the five non-spin DOFs of a torsional body).
So ``K = T' K_abs T`` and ``M = T' M_abs T``: a torsional model is literally the rigid
model with five DOFs per body constrained. Matrices are sparse (CSR), or dense numpy arrays
for a small rigid model assembled with ``dense=True`` (no SciPy import: ``flexgear modes``).
A small rigid model (at most :data:`DENSE_DOFS` absolute DOFs, no flexible body) is
assembled in dense arithmetic either way, and its sparse matrices are the dense ones
stored sparsely: both forms hold the very same numbers.
"""
from __future__ import annotations

import dataclasses
import logging
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .. import arguments
from ..mechanics.elements import Element, gear_mesh, relative_spring
from ..mechanics.kinematics import axis_frame, block_rotation, rigid_transfer
from ..scene.attach import bearing_point, component_masters, mesh_centers, shaft_points
from ..scene.paths import body_origins
from ..scene.tables import DOF_NAMES, HOUSING, FlexOptions, Scene, Shaft, scene_argument
from .bodies import RigidBodyModel
from .components import CacheDirs, mass_properties
from .constraints import candidates, constrained_dofs, rigidify
from .flexible import flexible_body
from .shaft_elements import beam_elements

if TYPE_CHECKING:
    import scipy.sparse as sp

log = logging.getLogger(__name__)

#: Rigid models with at most this many absolute DOFs (6 per body: 100 bodies) are assembled
#: in dense arithmetic: a few MB, faster than sparse products at this size, and no SciPy.
DENSE_DOFS = 600


@dataclass(frozen=True, eq=False)
class AssembledModel:
    """A scene assembled into one linear model (module notes), built whole by :func:`assemble`.

    ``scene``: the expanded scene it was built from (stages and beam shafts as plain
    bodies and elements), ``source`` the scene as the user gave it (for field paths).
    ``bodies`` {name: body model} in frame order (:class:`~assembly.model.bodies.RigidBodyModel`
    or :class:`~assembly.model.flexible.FlexibleBodyModel`), ``offsets`` {name: first index in
    z}, ``elements`` the springs (:class:`~assembly.mechanics.elements.Element`).
    On the absolute coordinates z: ``K_abs``, ``M_abs`` (sparse CSR; dense arrays for a
    small rigid model assembled with ``dense=True``, module notes), ``abs_dof_names``.
    On the independent coordinates q (``z = T q``): ``T``, ``K = T' K_abs T``, ``M``,
    ``dof_names`` and ``q_slices`` {body: its columns of q}. ``rigidified``: the near-rigid
    bearing directions made constraints, (bearing, field, stiffness). ``timings`` (s) and
    ``info``: ``replaced_mass_properties``, the typed mass properties a component's mesh
    replaced (:mod:`assembly.model.body_table`). SI units."""

    scene: Scene
    bodies: dict
    offsets: dict
    elements: list
    K_abs: sp.csr_matrix = field(repr=False)
    M_abs: sp.csr_matrix = field(repr=False)
    T: sp.csr_matrix = field(repr=False)
    dof_names: list
    abs_dof_names: list
    K: sp.csr_matrix = field(repr=False)
    M: sp.csr_matrix = field(repr=False)
    q_slices: dict
    source: Scene
    rigidified: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)
    info: dict = field(default_factory=dict)

    @property
    def n_abs(self) -> int:
        return self.K_abs.shape[0]

    @property
    def dense(self) -> bool:
        """Whether the matrices are dense arrays (``assemble(scene, dense=True)``)."""
        return isinstance(self.K, np.ndarray)

    def body_slice(self, name: str) -> slice:
        o = self.offsets[name]
        return slice(o, o + self.bodies[name].ndof)

    def element_stiffness_abs(self, el: Element) -> sp.csr_matrix:
        """Element stiffness scattered into absolute coordinates (dense for a dense model)."""
        return element_matrix(self.bodies, self.offsets, self.n_abs, el, el.stiffness(), self.dense)

    def element_damping_abs(self, el: Element) -> sp.csr_matrix:
        """Element damping (its dampers ``c``) scattered into absolute coordinates."""
        return element_matrix(self.bodies, self.offsets, self.n_abs, el, el.damping(), self.dense)

    def element_mass_abs(self, el: Element) -> sp.csr_matrix:
        """Element mass (a beam shaft's end masses) scattered into absolute coordinates."""
        return element_matrix(self.bodies, self.offsets, self.n_abs, el, el.mass, self.dense)

    def attachment_operator(self, el: Element, points: dict | None = None) -> sp.csr_matrix:
        """Sparse (a dense model: dense) map from ``z`` to the element's stacked attachment motions ``w``
        (``points``: body name -> the point to take that body's motion at instead of the
        element's, e.g. to see it with a body's axis moved, :mod:`assembly.analysis.lever_arms`)."""
        return attachment_operator(self.bodies, self.offsets, self.n_abs, el, points, self.dense)

    def rigid_coordinates(self, Z: np.ndarray) -> np.ndarray:
        """Rigid-equivalent motion (6 per body, global axes, at each COM) of columns of Z."""
        return np.vstack([self.bodies[b].rigid_projection() @ Z[self.body_slice(b)] for b in self.bodies])

    def rigid_mass_matrix(self):
        """Block-diagonal 6x6 rigid mass matrices of all bodies (for mass-weighted MAC):
        sparse CSR, a dense array for a dense model."""
        blocks = []
        for bm in self.bodies.values():
            B = np.zeros((6, 6))
            B[:3, :3] = bm.mass * np.eye(3)
            B[3:, 3:] = bm.inertia
            blocks.append(B)
        if self.dense:
            return block_diagonal(blocks)
        import scipy.sparse as sp
        return sp.block_diag(blocks, format="csr")


def block_diagonal(blocks: list) -> np.ndarray:
    """Dense block-diagonal matrix of square ``blocks``."""
    n = sum(b.shape[0] for b in blocks)
    out = np.zeros((n, n))
    i = 0
    for b in blocks:
        k = b.shape[0]
        out[i:i + k, i:i + k] = b
        i += k
    return out


def attachments(bodies: dict, el: Element, points: dict | None = None):
    """(slot j of the element, body, P) of each body attached to ``el`` (the housing has no
    motion: none): P its motion at the element's point (or at ``points[body]``), the 6 rows
    of the element's stacked attachment motions at slot j on that body's DOFs."""
    for j, (b, iface) in enumerate(zip(el.bodies, el.interfaces)):
        if b is not None:
            yield j, b, bodies[b].motion_at((points or {}).get(b, el.point), iface)


def attachment_operator(bodies: dict, offsets: dict, n_abs: int, el: Element,
                        points: dict | None = None, dense: bool = False):
    """Sparse (``dense``: a dense array) map from the absolute coordinates z (``n_abs`` of
    them; ``bodies`` and their ``offsets`` in z) to the element's stacked attachment motions
    (6 per attached body, the housing none): each body's motion at the element's point (or
    at ``points[body]``, :func:`attachments`)."""
    if dense:
        L = np.zeros((6 * len(el.bodies), n_abs))
        for j, b, P in attachments(bodies, el, points):
            P = np.asarray(P, float)
            L[6 * j:6 * j + 6, offsets[b]:offsets[b] + P.shape[1]] += P
        return L
    import scipy.sparse as sp
    rows, cols, vals = [], [], []
    for j, b, P in attachments(bodies, el, points):
        P = sp.coo_matrix(P)
        rows.append(P.row + 6 * j)
        cols.append(P.col + offsets[b])
        vals.append(P.data)
    if not vals:
        return sp.csr_matrix((6 * len(el.bodies), n_abs))
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(6 * len(el.bodies), n_abs))


def element_matrix(bodies: dict, offsets: dict, n_abs: int, el: Element, A: np.ndarray, dense: bool = False):
    """``L' A L``: a matrix ``A`` on the element's attachment motions, on z
    (:func:`attachment_operator` ``L``): sparse CSR, or (``dense``) a dense array."""
    if dense:
        out = np.zeros((n_abs, n_abs))
        add_element(out, bodies, offsets, el, A)
        return out
    import scipy.sparse as sp
    L = attachment_operator(bodies, offsets, n_abs, el)
    return (L.T @ sp.csr_matrix(A) @ L).tocsr()


def add_element(out: np.ndarray, bodies: dict, offsets: dict, el: Element, A: np.ndarray) -> None:
    """Add ``L' A L`` (:func:`element_matrix`) into the dense matrix ``out`` on z, formed on
    the columns of z the element touches only."""
    cols, blocks = [], []
    for j, b, P in attachments(bodies, el):
        P = np.asarray(P, float)
        cols.append(np.arange(offsets[b], offsets[b] + P.shape[1]))
        blocks.append((j, P))
    if not cols:
        return
    idx = np.concatenate(cols)
    L = np.zeros((6 * len(el.bodies), len(idx)))
    c = 0
    for j, P in blocks:
        L[6 * j:6 * j + 6, c:c + P.shape[1]] = P
        c += P.shape[1]
    np.add.at(out, np.ix_(idx, idx), L.T @ (np.asarray(A, float) @ L))


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
                             None if frame == HOUSING else frame, point, br.axes(bodies[br.body].axes), k,
                             br.diagonal_fields(), br.damping_diagonal())
        elements.append(_with_interfaces(el, (iface, br.frame_interface), ("bearings", i)))
    for i, s in enumerate(scene.shafts):
        name = s.name or f"shaft[{i}]:{s.body1}-{s.body2}"
        if s.is_beam:
            elements += beam_elements(s, i, by_name, masters, name)
            continue
        point, i1, i2 = shaft_points(s, by_name[s.body1], by_name[s.body2], masters, f"shafts[{i}]")
        el = relative_spring(name, "shaft", s.body1, s.body2, point,
                             bodies[s.body1].axes, s.diagonal(), Shaft.FIELDS, s.damping_diagonal())
        elements.append(_with_interfaces(el, (i1, i2), ("shafts", i)))
    for i, m in enumerate(scene.meshes):
        b1, b2 = by_name[m.gear1], by_name[m.gear2]
        c1, c2, i1, i2 = mesh_centers(m, b1, b2, masters, f"meshes[{i}]")
        el = gear_mesh(m.name or f"mesh[{i}]:{m.gear1}-{m.gear2}", m.gear1, m.gear2, b1.axis, c1, c2,
                       m.base_radius1, m.base_radius2, m.pressure_angle, m.helix_angle, m.drive_sign,
                       m.stiffness, m.contact_point, m.damping)
        elements.append(_with_interfaces(el, (i1, i2), ("meshes", i)))
    return elements


def _with_interfaces(el: Element, ifaces, item: tuple) -> Element:
    return dataclasses.replace(el, interfaces=tuple(ifaces), item=item)


def build_body_models(scene: Scene, full_fe: bool = False, progress=None, caches: CacheDirs | None = None,
                      paths: dict | None = None) -> dict:
    """Body models in frame order: rigid (plain or from a component's mesh) or flexible.
    ``caches``: where meshes and reductions are cached (default :class:`CacheDirs`);
    ``paths``: body name -> the scene table that made it, for error messages (default:
    the body's name)."""
    paths = paths or {}
    band = scene.band
    out = {}
    for b in _frame_order(scene):
        if b.component is None:
            out[b.name] = RigidBodyModel.from_body(b)
            continue
        caches = caches or CacheDirs()       # made when a body needs it: the default reads the meshing module
        path = paths.get(b.name, b.name)
        opts = b.flex or FlexOptions()
        if b.fidelity == "flexible":
            out[b.name] = flexible_body(b, opts, band, reduce=not full_fe, caches=caches, path=path)
        else:
            mass, com, J = mass_properties(b, opts, caches)
            out[b.name] = RigidBodyModel.from_mass_properties(b.name, com, axis_frame(b.axis), mass, J,
                                                              axis_point=b.position)
        if progress is not None:
            progress(b.name)
    return out


def assemble(scene: Scene, full_fe: bool = False, bodies: dict | None = None,
             caches: CacheDirs | None = None, source: Scene | None = None, dense: bool = False) -> AssembledModel:
    """Assemble ``scene`` (stages expanded) into sparse K, M on independent coordinates.

    ``dense=True``: a small rigid model (at most :data:`DENSE_DOFS` absolute DOFs, no
    flexible body) keeps its matrices as dense arrays, the same numbers as the sparse ones
    (module notes), and nothing imports SciPy: for the modal solve and its tables
    (:func:`assembly.analysis.modal.solve_modes`, ``flexgear modes``); the other analyses
    given it work on its sparse twin (:func:`sparse_model`). A larger model is sparse either way.

    ``full_fe=True`` keeps flexible bodies unreduced (every FE DOF): the reference model.
    ``bodies`` may pass pre-built body models (e.g. to reuse reductions across variants);
    ``caches`` says where meshes and reductions are cached. ``source``: the scene as the
    user wrote it when ``scene`` was derived from it (e.g. a fidelity variant), so that
    errors name the user's fields (default ``scene``).

    Near-rigid bearing directions become constraints (:func:`assembly.model.constraints.rigidify`),
    judged on the diagonal of the same assembly without their springs; the model is
    assembled again only if some direction became a constraint. Mass properties typed
    beside a component and replaced by its mesh's are logged (a warning naming the body,
    both values and their difference) and listed in ``model.info``.
    """
    scene_argument("scene", scene)
    arguments.flag("full_fe", full_fe)
    arguments.optional(arguments.table, "bodies", bodies)
    arguments.optional(arguments.instance, "caches", caches, CacheDirs, "a CacheDirs (or None)")
    arguments.optional(scene_argument, "source", source)
    arguments.flag("dense", dense)
    t0 = time.perf_counter()
    sc = scene.expanded()
    order = _frame_order(sc)
    if bodies is None:
        bodies = build_body_models(sc, full_fe=full_fe, caches=caches, paths=body_origins(scene, sc))
    t_bodies = time.perf_counter() - t0
    # every spring of a bearing with candidates is a candidate (its other directions are
    # 0 or inf, which make no spring): leaving out the whole element leaves out exactly them
    judged = {("bearings", i) for i, _ in candidates(sc)}
    src = source if source is not None else scene
    small = sum(bodies[b.name].ndof for b in order) <= DENSE_DOFS and not any(bm.flexible for bm in bodies.values())
    parts, diagonal = _model_on(sc, order, bodies, judged, small)
    rigidified = []
    if judged:
        held, rigidified = rigidify(sc, diagonal, sc.band)
        if rigidified:
            parts, _ = _model_on(held, order, bodies, small=small)
    if small and not dense:
        import scipy.sparse as sp
        parts.update({k: sp.csr_matrix(parts[k]) for k in ("K_abs", "M_abs", "T", "K", "M")})
    model = AssembledModel(**parts, source=src, rigidified=rigidified,
                           timings={"bodies_s": t_bodies, "assembly_s": time.perf_counter() - t0 - t_bodies})
    _report_replaced(model, warn=source is None)
    log.info("assembled %s: %d bodies, %d elements, %d DOFs", sc.name, len(bodies), len(model.elements),
             len(model.dof_names))
    return model


def _report_replaced(model: AssembledModel, warn: bool) -> None:
    """Record on ``model.info`` (and log, ``warn``: not for a variant of a scene reported
    already) the typed mass properties its components' meshes replace."""
    from .body_table import body_properties, replaced, replaced_note
    rows = replaced(body_properties(model))
    model.info["replaced_mass_properties"] = [r.as_dict() for r in rows]
    for r in rows if warn else ():
        log.warning("%s", replaced_note(r))


def _model_on(sc: Scene, order: list, bodies: dict, judged=frozenset(), small: bool = False) -> tuple[dict, dict]:
    """The fields of the :class:`AssembledModel` of the expanded scene ``sc`` (its matrices on
    z and on its independent coordinates; ``small``: dense arrays), and the diagonal that
    :func:`assembly.model.constraints.rigidify` judges on: DOF name -> (K'_xx, M_xx), K'
    being K without the elements whose ``item`` is in ``judged`` (empty without any)."""
    if small:
        parts, K_judged = _absolute_dense(sc, order, bodies, judged)
    else:
        parts, K_judged = _absolute_model(sc, order, bodies, judged)
    T, names, slices = (_coordinates_dense if small else _independent_coordinates)(sc, order, bodies)
    parts.update(T=T, dof_names=names, q_slices=slices, K=on_q(T, parts["K_abs"]), M=on_q(T, parts["M_abs"]))
    if not judged:
        return parts, {}
    return parts, dict(zip(names, zip(on_q(T, K_judged).diagonal(), parts["M"].diagonal())))


def on_q(T, A):
    """``T' A T`` symmetrised: a matrix of absolute coordinates on the independent ones
    (sparse CSR; dense arrays stay dense)."""
    if isinstance(T, np.ndarray) and isinstance(A, np.ndarray):
        A = T.T @ (A @ T)
        return (A + A.T) * 0.5
    A = (T.T @ A @ T).tocsr()
    return ((A + A.T) * 0.5).tocsr()


def _layout(sc: Scene, order: list, bodies: dict) -> dict:
    """The fields of an :class:`AssembledModel` that place the bodies on z: ``scene``,
    ``bodies`` in frame order, their ``offsets``, the ``elements`` and ``abs_dof_names``."""
    offsets, n = {}, 0
    for b in order:
        offsets[b.name] = n
        n += bodies[b.name].ndof
    return dict(scene=sc, bodies={b.name: bodies[b.name] for b in order}, offsets=offsets,
                elements=build_elements(sc, bodies, component_masters(sc)),
                abs_dof_names=[name for b in order for name in bodies[b.name].dof_names()])


def _absolute_model(sc: Scene, order: list, bodies: dict, judged=frozenset()) -> tuple[dict, sp.csr_matrix | None]:
    """Body mass and stiffness blocks plus every element (its stiffness, and its mass if it
    carries any), on the absolute coordinates z, as fields of an :class:`AssembledModel`;
    and K_abs without the elements whose ``item`` is in ``judged`` (None without any)."""
    fields = _layout(sc, order, bodies)
    ordered, offsets, elements = fields["bodies"], fields["offsets"], fields["elements"]
    n = sum(bm.ndof for bm in ordered.values())
    import scipy.sparse as sp
    M_abs = sp.block_diag([sp.csr_matrix(bodies[b.name].mass_matrix()) for b in order], format="csr")
    K_abs = sp.block_diag([sp.csr_matrix(bodies[b.name].stiffness_matrix()) for b in order], format="csr")
    parts = [element_matrix(ordered, offsets, n, el, el.stiffness()) for el in elements]
    masses = [element_matrix(ordered, offsets, n, el, el.mass) for el in elements if el.mass is not None]
    fields.update(K_abs=sum(parts, K_abs).tocsr(), M_abs=sum(masses, M_abs).tocsr())
    if not judged:
        return fields, None
    return fields, sum((p for p, el in zip(parts, elements) if el.item not in judged), K_abs).tocsr()


def _absolute_dense(sc: Scene, order: list, bodies: dict, judged=frozenset()) -> tuple[dict, np.ndarray | None]:
    """:func:`_absolute_model` of a small rigid model in dense arrays: each element's
    ``L' A L`` formed on the columns it touches and added in place."""
    fields = _layout(sc, order, bodies)
    ordered, offsets = fields["bodies"], fields["offsets"]
    M_abs = block_diagonal([np.asarray(bodies[b.name].mass_matrix(), float) for b in order])
    K_abs = block_diagonal([np.asarray(bodies[b.name].stiffness_matrix(), float) for b in order])
    K_judged = K_abs.copy() if judged else None
    for el in fields["elements"]:
        add_element(K_abs, ordered, offsets, el, el.stiffness())
        if judged and el.item not in judged:
            add_element(K_judged, ordered, offsets, el, el.stiffness())
        if el.mass is not None:
            add_element(M_abs, ordered, offsets, el, el.mass)
    fields.update(K_abs=K_abs, M_abs=M_abs)
    return fields, K_judged


def _coordinates_dense(sc: Scene, order: list, bodies: dict):
    """:func:`_independent_coordinates` of a small rigid model, T a dense array."""
    held = constrained_dofs(sc)
    free = {b.name: [i for i, d in enumerate(DOF_NAMES) if d not in held[b.name]] for b in order}
    col0, m = {}, 0
    for b in order:
        col0[b.name] = m
        m += len(free[b.name])
    rows, names = {}, []
    for b in order:
        bm = bodies[b.name]
        blk = np.zeros((bm.ndof, m))
        blk[:, col0[b.name]:col0[b.name] + len(free[b.name])] = \
            rigid_transfer(bm.position, bm.axis_point) @ block_rotation(bm.axes)[:, free[b.name]]
        names += [f"{b.name}.{DOF_NAMES[i]}" for i in free[b.name]]
        if b.frame != HOUSING:
            blk = blk + np.asarray(bodies[b.frame].motion_at(bm.position, _frame_interface(sc, b)), float) @ rows[b.frame]
        rows[b.name] = blk
    slices = {b.name: slice(col0[b.name], col0[b.name] + len(free[b.name])) for b in order}
    return np.vstack([rows[b.name] for b in order]) if order else np.zeros((0, 0)), names, slices


def _independent_coordinates(sc: Scene, order: list, bodies: dict):
    """(T, names, body -> slice of q) with z = T q: rigid bodies move with their frame plus their free relative
    DOFs (local axes, at the body's axis point); flexible bodies (housing frame only) keep
    all their DOFs."""
    import scipy.sparse as sp
    held = constrained_dofs(sc)
    ncols, col0 = {}, {}
    m = 0
    for b in order:
        k = bodies[b.name].ndof if b.fidelity == "flexible" else sum(d not in held[b.name] for d in DOF_NAMES)
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
            own = sp.csr_matrix(rigid_transfer(bm.position, bm.axis_point) @ block_rotation(bm.axes)[:, free])
            names += [f"{b.name}.{DOF_NAMES[i]}" for i in free]
        blk = sp.hstack([sp.csr_matrix((bm.ndof, col0[b.name])), own,
                         sp.csr_matrix((bm.ndof, m - col0[b.name] - ncols[b.name]))]).tocsr()
        if b.frame != HOUSING:
            iface = _frame_interface(sc, b)
            blk = blk + sp.csr_matrix(bodies[b.frame].motion_at(bm.position, iface)) @ rows[b.frame]
        rows[b.name] = blk.tocsr()
    slices = {b.name: slice(col0[b.name], col0[b.name] + ncols[b.name]) for b in order}
    return sp.vstack([rows[b.name] for b in order]).tocsr(), names, slices


def _frame_interface(scene: Scene, body) -> str | None:
    """Interface of the frame body at which ``body`` rides (its bearing's frame_interface)."""
    for br in scene.bearings:
        if br.body == body.name and (br.frame is None or br.frame == body.frame) and br.frame_interface:
            return br.frame_interface
    return None


def model_argument(name: str, value) -> AssembledModel:
    """``value``, a :class:`AssembledModel` (SceneError naming the argument ``name`` otherwise)."""
    return arguments.instance(name, value, AssembledModel, "an assembled model (assemble(scene))")


#: What an analysis of one model takes first, in words for its errors.
MODEL_OR_SCENE = "an assembled model (assemble(scene)) or a Scene"


def source_scene(name: str, value) -> Scene:
    """The scene as the user gave it behind ``value`` (an :class:`AssembledModel`: its
    ``source``; a :class:`Scene`: itself), for the checks an analysis makes before it has a
    model; SceneError naming the argument ``name`` for anything else."""
    if isinstance(value, AssembledModel):
        return value.source
    if isinstance(value, Scene):
        return value
    raise arguments.refuse(name, value, f"must be {MODEL_OR_SCENE}")


def model_of(name: str, value) -> AssembledModel:
    """The model an analysis of one model works on: ``value`` itself when it is an
    :class:`AssembledModel` (dense or sparse: an analysis that needs sparse matrices takes
    :func:`sparse_model` of it), a :class:`Scene` assembled as given (:func:`assemble`);
    SceneError naming the argument ``name`` for anything else."""
    return value if isinstance(value, AssembledModel) else assemble(source_scene(name, value))


def sparse_model(model: AssembledModel) -> AssembledModel:
    """``model`` with sparse matrices, for the analyses that work on sparse matrices (statics,
    FRF, time domain): itself, or, for a small rigid model assembled with ``dense=True`` (for
    the modal solve), the same model with its dense arrays stored sparse: the very same
    numbers, its bodies, elements and options untouched."""
    if not model.dense:
        return model
    import scipy.sparse as sp
    return dataclasses.replace(model, **{k: sp.csr_matrix(getattr(model, k)) for k in ("K_abs", "M_abs", "T", "K", "M")})
