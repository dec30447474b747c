"""Mode classification and cross-model pairing.

Classes (Lin & Parker for planetary stages, extended to helical stages as in Eritenel &
Parker): ``rotational`` (central members only spin, and move axially if helical),
``translational`` (central members only translate in-plane, and tilt if helical),
``planet`` (central members at rest), ``out-of-plane`` (a rotational or translational
mode whose energy is mostly axial/tilt), ``mixed`` (none of these), ``rigid-body`` (0 Hz),
``elastic`` (the mode is mostly the elastic deformation of one flexible body:
:data:`ELASTIC_SHARE`; ``ModeInfo.body`` names it and ``nodal_diameters`` counts its
circumferential waves). Modes local to a planetary stage get that stage's class; all
others (global modes, modes of a parallel stage or of one body) get the dominant motion
type of the whole mode (spin -> rotational, in-plane -> translational, axial/tilt ->
out-of-plane).

Every mode also gets a ``scope`` (Peeters, Vandepitte & Sas 2006; :mod:`assembly.analysis.locality`):
``"global"``, or the stage holding at least :data:`assembly.analysis.locality.LOCAL_SHARE` of its
total (kinetic + strain) energy, and ``energy``: its kinetic and strain shares per stage.

Every test is made on energies summed over a group of repeated frequencies, which do not
depend on the (arbitrary) basis the solver returns for that eigenspace.
"""
from __future__ import annotations

from contextlib import nullcontext
from dataclasses import dataclass

import numpy as np
from threadpoolctl import threadpool_limits

from .. import arguments
from .energy import kinetic_by_body, kinetic_by_category, strain_by_body
from .harmonics import body_nodal_diameters
from .locality import energy_table, group_shares, mode_scopes, total_share
from .modal import modes_argument

#: Relative energy below which a class condition counts as zero. Exact models give
#: zeros to round-off; FE-based bodies are symmetric only to mesh accuracy (~1e-4).
CLASS_TOL = 1e-3
CENTRAL = ("sun", "ring", "carrier")
#: A mode is the elastic deformation of flexible body b when more than half of its energy
#: is b's elastic energy. Over a cycle a mode's energy is half kinetic, half strain
#: (time averages of T and V are equal at resonance), so the share is the mean of b's
#: strain-energy share (its own stiffness vs the whole model's, springs included) and
#: its kinetic-energy share beyond its rigid-equivalent motion.
ELASTIC_SHARE = 0.5


#: Every class an elastic mode can be given (:func:`classify_modes`), for the checks of
#: what a user names (a study's ``keep.classes``).
MODE_CLASSES = ("rotational", "translational", "planet", "out-of-plane", "mixed", "elastic")

@dataclass(frozen=True)
class ModeInfo:
    index: int
    frequency_hz: float
    multiplicity: int
    mode_class: str
    stage: str | None
    dominant_bodies: tuple
    body: str | None = None              # elastic modes: the deforming flexible body
    nodal_diameters: int | None = None   # elastic modes: circumferential harmonic number
    scope: str | None = None             # "global", or the stage (group) holding the mode
    energy: tuple = ()                   # ((group, kinetic share, strain share), ...) per stage

    @property
    def label(self) -> str:
        """Class as shown: ``"elastic stage.carrier, 2 ND"`` for an elastic mode, else the class."""
        if self.mode_class != "elastic":
            return self.mode_class
        nd = f", {self.nodal_diameters} ND" if self.nodal_diameters is not None else ""
        return f"elastic {self.body}{nd}"


def classify_modes(result, nodal_diameters: bool = True) -> list[ModeInfo]:
    """Class and scope of every mode (see the module doc). ``nodal_diameters``: count them
    for the elastic modes (back-expands each such mode of a flexible body to its FE mesh,
    which loads the body's FE model once)."""
    modes_argument("result", result)
    arguments.flag("nodal_diameters", nodal_diameters)
    model = result.model
    names = list(model.bodies)
    sc_bodies = {b.name: b for b in model.scene.bodies}
    planetary = {b.stage for b in sc_bodies.values() if b.role == "planet"}
    stages = {b.stage for b in sc_bodies.values() if b.stage}
    E = kinetic_by_category(result)
    share = kinetic_by_body(result)
    mult = result.multiplicity()
    U = strain_by_body(result) if any(bm.flexible for bm in model.bodies.values()) else None
    table = energy_table(result)
    ke, se = group_shares(table, result.groups)
    scopes = mode_scopes(table, ke, se)
    top = [table.group_names[j] for j in total_share(ke, se).argmax(axis=1)]
    out = [None] * len(result.frequencies_hz)
    # the nodal-diameter fits are small dense products (a few thousand rim nodes x 25
    # harmonics): one BLAS thread (threads on a busy 2-core machine made them 10-50x slower)
    with threadpool_limits(1) if U is not None and nodal_diameters else nullcontext():
        for g in result.groups:
            Eg = E[g].sum(axis=0)  # (n_bodies, 5)
            total = Eg.sum()
            body = nd = None
            i = g[0]
            st = top[i] if top[i] in stages else None   # the stage holding most of the energy
            if i < result.n_rigid or total <= 0:
                cls, st = "rigid-body", None
            elif U is not None and (body := _elastic_body(U[g].mean(axis=0), Eg[:, 4] / total, names)):
                cls = "elastic"
                st = model.scene.body(body).stage
                if nodal_diameters:
                    bm = model.bodies[body]
                    nd = body_nodal_diameters(bm, result.abs_shapes[model.body_slice(body)][:, g])
            elif scopes[i] in planetary:
                stage = [sc_bodies[b].stage for b in names]
                cls = _planetary_class(Eg, names, sc_bodies, stage, scopes[i])
            else:
                cls = _motion_class(Eg.sum(axis=0))
            split = tuple((s, float(ke[i, j]), float(se[i, j])) for j, s in enumerate(table.group_names)
                          if ke[i, j] > 0 or se[i, j] > 0)
            for k in g:
                out[k] = ModeInfo(k, float(result.frequencies_hz[k]), int(mult[k]), cls, st,
                                  dominant_bodies(share[k], names), body, nd, scopes[i], split)
    return out


def dominant_bodies(share: np.ndarray, names, cover: float = 0.8, most: int = 3) -> tuple:
    """((name, kinetic-energy share), ...) of the bodies holding a mode's kinetic energy:
    largest first, until they hold ``cover`` of it or ``most`` are listed."""
    dom, cum = [], 0.0
    for j in np.argsort(-share)[:most]:
        if share[j] <= 0:
            break
        dom.append((names[j], float(share[j])))
        cum += share[j]
        if cum >= cover:
            break
    return tuple(dom)


def _elastic_body(strain_share: np.ndarray, elastic_ke_share: np.ndarray, names) -> str | None:
    """The flexible body holding more than :data:`ELASTIC_SHARE` of a mode's energy as
    elastic energy (mean of its strain and elastic kinetic shares), or None."""
    e = 0.5 * (strain_share + elastic_ke_share)
    j = int(np.argmax(e))
    return names[j] if e[j] > ELASTIC_SHARE else None


def _motion_class(cat: np.ndarray) -> str:
    inplane, axial, tilt, spin = cat[:4]
    if axial + tilt >= max(inplane, spin):
        return "out-of-plane"
    return "rotational" if spin >= inplane else "translational"


def _planetary_class(Eg, names, sc_bodies, stage, st) -> str:
    idx = [i for i, s in enumerate(stage) if s == st]
    Es = Eg[idx].sum()
    central = [i for i in idx if sc_bodies[names[i]].role in CENTRAL]
    Ec = Eg[central].sum(axis=0)  # inplane, axial, tilt, spin, elastic
    tol = CLASS_TOL * Es
    oop = Eg[idx][:, 1:3].sum() / Es
    if Ec[:4].sum() < tol:
        return "planet"
    # Tests use the central members' rigid-equivalent motion; a flexible carrier's own
    # deformation (Ec[4]) belongs to whichever class its rigid motion has.
    if Ec[0] + Ec[2] < tol:
        return "out-of-plane" if oop > 0.5 else "rotational"
    if Ec[1] + Ec[3] < tol:
        return "out-of-plane" if oop > 0.5 else "translational"
    return "mixed"


def mac_matrix(A: np.ndarray, B: np.ndarray, W=None) -> np.ndarray:
    """Modal assurance criterion between columns of A and B, weighted by W (e.g. mass)."""
    WA = A if W is None else W @ A
    WB = B if W is None else W @ B
    num = np.abs(A.T @ WB) ** 2
    den = np.outer(np.einsum("im,im->m", A, WA), np.einsum("im,im->m", B, WB))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den > 0, num / np.where(den > 0, den, 1.0), 0.0)


def subspace_mac(A: np.ndarray, B: np.ndarray, groups_b, W) -> np.ndarray:
    """MAC of each column of A with the span of each repeated-frequency group of B:
    the W-weighted fraction of a_i lying in that eigenspace (basis independent)."""
    out = np.zeros((A.shape[1], B.shape[1]))
    WA = W @ A
    na = np.einsum("im,im->m", A, WA)
    for g in groups_b:
        Bg = B[:, g]
        G = Bg.T @ (W @ Bg)
        C = Bg.T @ WA  # (len(g), n_a)
        proj = np.einsum("gm,gm->m", C, np.linalg.solve(G, C))
        with np.errstate(invalid="ignore", divide="ignore"):
            val = np.where(na > 0, proj / np.where(na > 0, na, 1.0), 0.0)
        out[:, g] = val[:, None]
    return out


def pair_modes(res_a, res_b, W=None):
    """Pair modes of two models of the same scene by (subspace) MAC on the absolute body
    motions. Returns a list of (i_a, i_b, mac). ``W`` defaults to res_b's mass matrix."""
    modes_argument("res_a", res_a)
    modes_argument("res_b", res_b)
    if list(res_a.model.bodies) != list(res_b.model.bodies):
        raise arguments.refuse("res_b", res_b, f"not the same bodies as res_a: {list(res_b.model.bodies)} against "
                                               f"{list(res_a.model.bodies)}")
    A = res_a.model.rigid_coordinates(res_a.abs_shapes)
    B = res_b.model.rigid_coordinates(res_b.abs_shapes)
    W = res_b.model.rigid_mass_matrix() if W is None else W
    return pair_shapes(A, B, res_b.groups, W)


def pair_shapes(A: np.ndarray, B: np.ndarray, groups_b, W, groups_a=None) -> list:
    """One-to-one pairing of the columns of A with those of B (repeated-frequency
    ``groups_b``) maximising the total (subspace) MAC: a list of (i_a, i_b, mac).
    ``groups_a``: repeated groups of A too; a pair then scores the larger of the two
    subspace MACs (a mode of B lying in the span of a group of A matches it fully)."""
    from scipy.optimize import linear_sum_assignment  # scipy.optimize is slow to import
    mac = subspace_mac(A, B, groups_b, W)
    if groups_a is not None:
        mac = np.maximum(mac, subspace_mac(B, A, groups_a, W).T)
    ia, ib = linear_sum_assignment(-mac)
    return [(int(i), int(j), float(mac[i, j])) for i, j in zip(ia, ib)]
