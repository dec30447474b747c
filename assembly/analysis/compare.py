"""Torsional, rigid and flexible variants of one scene, solved and paired by MAC.

Variants (each contains the next, so the k-th frequency satisfies
flexible <= rigid <= torsional by Rayleigh-Ritz): the flexible model is the scene as
given; the rigid variant makes each flexible body rigid (mass and inertia from its mesh,
springs at the same attachment points); the torsional variant is the rigid one with five
DOFs per body constrained.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np

from .. import arguments
from ..model.assemble import assemble
from ..model.body_table import body_properties, replaced, replaced_note
from ..scene.tables import scene_argument, with_fidelity
from .classify import classify_modes, pair_modes
from .modal import modes_argument, solve_modes

log = logging.getLogger(__name__)
FIDELITIES = ("torsional", "rigid", "flexible")


def variants(scene, flexible_components: bool = False) -> dict:
    """Scene per fidelity (stages kept as stages, so errors name the user's tables). The
    flexible variant is the scene as given when it has flexible bodies; otherwise, with
    ``flexible_components``, the scene with every body that has a component flexible (the
    others as given), if there is one."""
    bodies = scene.expanded().bodies
    flex = [b.name for b in bodies if b.fidelity == "flexible"]
    out = {"torsional": with_fidelity(scene, "torsional"), "rigid": with_fidelity(scene, "rigid", bodies=flex)}
    if flex:
        out["flexible"] = scene
    elif flexible_components and (components := [b.name for b in bodies if b.component is not None]):
        out["flexible"] = with_fidelity(scene, "flexible", bodies=components)
    return out


def given_fidelity(scene) -> str:
    """The variant of :func:`variants` that is the scene as given."""
    return "flexible" if any(b.fidelity == "flexible" for b in scene.expanded().bodies) else "rigid"


@dataclass(frozen=True)
class Comparison:
    """The variants of one scene solved and paired: ``results`` {variant: ModalResult}
    (:func:`variants`: torsional, rigid, flexible), ``rows`` one dict per mode of the most detailed
    variant (mode, class, dominant_body, its frequency under each variant's name and the MAC
    of each pairing, :func:`assembly.analysis.classify.pair_modes`, under ``mac_<variant>``;
    None where a mode has no partner), ``timings`` {variant: solve seconds}."""

    results: dict
    rows: list
    timings: dict = field(default_factory=dict)

    def frequencies(self) -> dict:
        """{variant: its natural frequencies (Hz), ascending}."""
        return {k: [float(f) for f in np.sort(r.frequencies_hz)] for k, r in self.results.items()}


def compare(scene, n_rows: int | None = None, given=None, flexible_components: bool = False) -> Comparison:
    """Solve every variant of ``scene`` (:func:`variants`) and pair their modes. ``given`` is
    an already solved ModalResult of the scene as given (rigid or flexible), reused instead
    of solved again."""
    scene_argument("scene", scene)
    arguments.optional(arguments.integer, "n_rows", n_rows, 0)
    arguments.optional(modes_argument, "given", given)
    arguments.flag("flexible_components", flexible_components)
    res, times = {}, {}
    vs = variants(scene, flexible_components)
    top = "flexible" if "flexible" in vs else "rigid"
    as_given = given_fidelity(scene)
    for name, sc in vs.items():
        t0 = time.perf_counter()
        if name == as_given and given is not None:
            res[name] = given
            m = given.model
        else:
            m = assemble(sc, source=scene)
            res[name] = solve_modes(m)
        total = time.perf_counter() - t0
        if name == as_given and given is not None:  # its cost was paid by the caller's solve
            total = sum(m.timings.values()) + given.solve_time_s
        times[name] = {"total_s": total, **m.timings, "solve_s": res[name].solve_time_s,
                       "n_dofs": int(m.K.shape[0])}
    if given is None:   # the caller that solved the scene as given reported it already
        for r in replaced(body_properties(res[top].model)):
            log.warning("%s", replaced_note(r))
    infos = classify_modes(res[top])
    pairs = {}
    chain = [k for k in ("flexible", "rigid", "torsional") if k in res]
    for hi, lo in zip(chain, chain[1:]):
        pairs[(hi, lo)] = {i: (j, mac) for i, j, mac in pair_modes(res[hi], res[lo])}
    rows = []
    n = len(res[top].frequencies_hz) if n_rows is None else min(n_rows, len(res[top].frequencies_hz))
    for i in range(n):
        row = {"mode": i + 1, "class": infos[i].mode_class,
               "dominant_body": infos[i].dominant_bodies[0][0] if infos[i].dominant_bodies else None,
               top: float(res[top].frequencies_hz[i])}
        idx = i
        for hi, lo in zip(chain, chain[1:]):
            if idx is None or idx not in pairs[(hi, lo)]:
                idx = None
                row[lo] = row[f"mac_{lo}"] = None
                continue
            j, mac = pairs[(hi, lo)][idx]
            row[lo] = float(res[lo].frequencies_hz[j])
            row[f"mac_{lo}"] = mac
            idx = j
        rows.append(row)
    return Comparison(res, rows, times)
