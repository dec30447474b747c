"""Mode tracking along a parameter change: follow each mode of one scene from one
parameter value to the next by its shape (MAC), not by its place in the frequency order.

Between neighbouring steps the modes are paired one to one by mass-weighted MAC
(:func:`assembly.analysis.classify.pair_shapes`). A group of repeated frequencies has no basis of
its own (the solver picks one at random), so it is compared as a subspace on either side:
a mode that lies in the span of a group of the previous step matches it fully, whichever
mode of the group it is paired with. A branch that had a shape of its own keeps it as its
reference through a step where it is part of a repeated group, so it passes an exact
crossing (two equal frequencies, any basis) and comes out on its own shape.

Flags per step: ``low-mac`` (MAC to the reference < ``threshold``: the shape changed
between steps; refine the steps), ``crossing`` (the branch changed places in the frequency
order with another branch: frequencies crossed while the shapes kept apart) and
``veering`` (two branches neighbouring in frequency both lost their shape without
crossing: the shapes exchange as the frequencies veer apart; Perkins & Mote, J. Sound
Vib. 106, 1986).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import arguments
from .classify import pair_shapes
from .modal import modes_argument

#: MAC below which a step of a branch is flagged (the threshold of the fidelity comparison).
MAC_THRESHOLD = 0.8


@dataclass(frozen=True)
class Branch:
    """One mode followed along the steps. ``modes[k]``: its index in step k's result;
    ``frequencies_hz[k]`` (Hz); ``mac[k]``: MAC with the branch's shape before step k (nan
    at step 0); ``flags[k]``: a tuple of ``low-mac``, ``crossing``, ``veering``."""

    modes: np.ndarray
    frequencies_hz: np.ndarray
    mac: np.ndarray
    flags: tuple

    @property
    def flagged(self) -> bool:
        return any(self.flags)


def _shapes(result, common_abs: bool):
    """(shape columns, weight matrix) on which steps are compared: the absolute DOFs with
    the mass matrix when all steps have the same DOFs, else rigid-equivalent body motions."""
    m = result.model
    if common_abs:
        return result.abs_shapes, m.M_abs
    return m.rigid_coordinates(result.abs_shapes), m.rigid_mass_matrix()


def track_modes(results: list, threshold: float = MAC_THRESHOLD) -> list[Branch]:
    """Branches (one per mode of the first result) through ``results``: the ModalResults
    of one scene at successive parameter values, in order. Every step must have the same
    bodies and the same number of modes."""
    if not isinstance(results, (list, tuple)):
        raise arguments.refuse("results", results, "must be a list of the modes of each step (solve_modes results)")
    for k, r in enumerate(results):
        modes_argument(f"results[{k}]", r)
    arguments.number("threshold", threshold, ge=0.0, le=1.0)
    if not results:
        return []
    n = len(results[0].frequencies_hz)
    for k, r in enumerate(results):
        if len(r.frequencies_hz) != n or list(r.model.bodies) != list(results[0].model.bodies):
            raise arguments.refuse(f"results[{k}]", r, "not the same bodies and mode count as results[0]")
    common_abs = len({r.abs_shapes.shape[0] for r in results}) == 1
    steps = len(results)
    modes = np.zeros((n, steps), int)
    mac = np.full((n, steps), np.nan)
    modes[:, 0] = np.arange(n)
    ref, _ = _shapes(results[0], common_abs)
    ref = ref.copy()
    ref_group = _group_ids(results[0], 0, np.arange(n))  # which repeated group each reference came from
    for k in range(1, steps):
        B, W = _shapes(results[k], common_abs)
        groups_ref = [list(np.flatnonzero(ref_group == g)) for g in np.unique(ref_group)]
        for b, j, m in pair_shapes(ref, B, results[k].groups, W, groups_ref):
            modes[b, k], mac[b, k] = j, m
        gid = _group_ids(results[k], k, modes[:, k])
        repeated = results[k].multiplicity()[modes[:, k]] > 1
        ref_single = np.array([np.count_nonzero(ref_group == g) == 1 for g in ref_group])
        # a branch takes its new shape, except at a repeated frequency after a shape of its
        # own (an exact crossing): it keeps that shape to come out of the crossing on it
        new = ~repeated | ~ref_single
        ref[:, new] = B[:, modes[new, k]]
        ref_group[new] = gid[new]
    freqs = np.array([[results[k].frequencies_hz[modes[b, k]] for k in range(steps)] for b in range(n)])
    flags = _flags(freqs, mac, threshold)
    return [Branch(modes[b], freqs[b], mac[b], flags[b]) for b in range(n)]


def _group_ids(result, step: int, modes: np.ndarray) -> np.ndarray:
    """An id per branch, unique over all steps: shared by branches whose modes at this step
    lie in one group of repeated frequencies."""
    gid = np.empty(len(result.frequencies_hz), int)
    for i, g in enumerate(result.groups):
        gid[g] = i
    return step * len(gid) + gid[modes]


def _flags(freqs: np.ndarray, mac: np.ndarray, threshold: float) -> list:
    n, steps = freqs.shape
    side = _sides(freqs)
    out = [[()] * steps for _ in range(n)]
    for k in range(1, steps):
        low = mac[:, k] < threshold
        order = np.argsort(freqs[:, k], kind="stable")
        place = np.empty(n, int)
        place[order] = np.arange(n)
        for b in range(n):
            f = ["low-mac"] if low[b] else []
            if np.any(side[b, :, k] != 0) and np.any((side[b, :, k] * _last_side(side, b, k)) < 0):
                f.append("crossing")
            elif low[b] and any(low[c] and abs(place[c] - place[b]) == 1 for c in range(n) if c != b):
                f.append("veering")
            out[b][k] = tuple(f)
    return [tuple(row) for row in out]


#: Relative frequency difference under which two branches count as level (an exact crossing).
LEVEL_RTOL = 1e-9


def _sides(freqs: np.ndarray) -> np.ndarray:
    """side[b, c, k]: +1 when branch b is above branch c at step k, -1 below, 0 level."""
    d = freqs[:, None, :] - freqs[None, :, :]
    scale = np.maximum(np.abs(freqs[:, None, :]), np.abs(freqs[None, :, :]))
    return np.where(np.abs(d) <= LEVEL_RTOL * scale, 0, np.sign(d)).astype(int)


def _last_side(side: np.ndarray, b: int, k: int) -> np.ndarray:
    """For each other branch: the side branch b was on at the last step before k where
    the two were not level (0 if never)."""
    last = np.zeros(side.shape[1], int)
    for j in range(k):
        s = side[b, :, j]
        last = np.where(s != 0, s, last)
    return last


@dataclass(frozen=True)
class Reference:
    """Modes of a base scene that the variants of a design study follow by shape: ``shapes``
    their rigid-equivalent body motions (6 per body, :meth:`AssembledModel.rigid_coordinates`),
    ``numbers`` their elastic mode numbers (1-based, as ``f1_hz`` counts), ``labels`` their
    classes, ``frequencies_hz``, ``bodies`` the base's bodies in order and ``groups`` the repeated
    frequencies among them (column lists). Plain arrays and lists: it pickles to a worker."""

    shapes: np.ndarray
    numbers: tuple
    labels: tuple
    frequencies_hz: tuple
    bodies: tuple
    groups: list


def reference_modes(result, labels, count: int | None = None, classes=None, band_hz=None) -> Reference:
    """The :class:`Reference` of a base scene's ``result`` (``labels``: each elastic mode's class):
    its first ``count`` elastic modes, or those of ``classes`` and within ``band_hz`` (Hz, lo, hi)."""
    r = result.n_rigid
    f = np.asarray(result.frequencies_hz[r:], float)
    keep = [j for j in range(len(f)) if (classes is None or labels[j] in classes)
            and (band_hz is None or band_hz[0] <= f[j] <= band_hz[1])]
    if count is not None and classes is None and band_hz is None:
        keep = keep[:count]
    R = result.model.rigid_coordinates(result.abs_shapes[:, [r + j for j in keep]])
    where = {j: i for i, j in enumerate(keep)}
    groups = [[where[g - r] for g in grp if g - r in where] for grp in result.groups]
    return Reference(R, tuple(j + 1 for j in keep), tuple(labels[j] for j in keep), tuple(float(f[j]) for j in keep),
                     tuple(result.model.bodies), [g for g in groups if g])


def follow(reference: Reference, result) -> list | None:
    """Each reference mode's partner among ``result``'s elastic modes by mass-weighted MAC on the
    rigid-equivalent body motions (:func:`assembly.analysis.classify.pair_shapes`, repeated
    groups compared as subspaces): (reference column, elastic index, MAC); None when the bodies
    differ from the base's (no shape to compare)."""
    m = result.model
    if tuple(m.bodies) != reference.bodies or not len(reference.numbers):
        return None
    r = result.n_rigid
    B = m.rigid_coordinates(result.abs_shapes[:, r:])
    groups_b = [[g - r for g in grp if g >= r] for grp in result.groups]
    return pair_shapes(reference.shapes, B, [g for g in groups_b if g], m.rigid_mass_matrix(), reference.groups)
