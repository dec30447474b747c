"""One variant of a design study, run to one row of the study's table.

:func:`run_variant` takes only plain, picklable arguments (the scene file, the variant, the
analysis and what to keep) and returns a plain dict, so the same function runs in-process
or in a distributed worker. A variant that fails (a value the scene refuses, a mechanism, a
solve that fails its checks) is a row with ``status = "error"`` and the one-line message,
never an exception: one bad variant does not stop a study.

Analyses: ``"modes"``: the first ``keep["modes"]`` (default 10) elastic natural frequencies
``f1_hz``, ``f2_hz``, ... and the number of rigid-body modes ``n_rigid``.
"""
from __future__ import annotations

import logging
import time

from .study_spec import Variant

log = logging.getLogger(__name__)

ANALYSES = ("modes",)


def run_variant(scene_source: str, variant: Variant, analysis: str = "modes", keep: dict | None = None) -> dict:
    """The row of ``variant`` (module notes): ``variant`` (its index), each parameter path
    and value, ``status`` ("ok" or "error"), ``error`` (the message, "" when ok), ``time_s``
    and the analysis's results."""
    from ..errors import MechanismError, SceneError, SolverError
    from ..modal import solve_modes
    from ..model import assemble
    from ..schema import load_scene
    keep = keep or {}
    row = {"variant": variant.index, **variant.values, "status": "ok", "error": ""}
    t0 = time.perf_counter()
    try:
        if analysis not in ANALYSES:
            raise SceneError("analysis", analysis, f"must be one of {list(ANALYSES)}")
        scene = load_scene(scene_source).with_values(variant.values)
        res = solve_modes(assemble(scene))
        n = int(keep.get("modes", 10))
        row["n_rigid"] = int(res.n_rigid)
        elastic = res.frequencies_hz[res.n_rigid:res.n_rigid + n]
        row.update({f"f{i + 1}_hz": float(f) for i, f in enumerate(elastic)})
    except (SceneError, MechanismError, SolverError) as exc:
        row.update(status="error", error=str(exc).splitlines()[0])
        log.info("variant %d: %s", variant.index, row["error"])
    row["time_s"] = time.perf_counter() - t0
    return row
