"""One variant of a design study, run to one row of the study's table.

:func:`run_variant` takes only plain, picklable arguments (the scene file, the variant, the
analysis, its settings and what to keep) and returns a plain dict, so the same function
runs in-process or in a distributed worker. It runs with one BLAS thread (as a Dask worker
does), so a variant gives the same bits wherever it runs. A variant that fails (a value the
scene refuses, a mechanism, a solve that fails its checks, a run that diverges, a result
that is not finite: NaN or inf in any column) is a row with ``status = "error"`` and the
one-line message and no results, never an exception: one bad variant does not stop a study.

Results per analysis (:mod:`assembly.app.study.file` gives the settings):

* ``modes``: the first ``keep["modes"]`` elastic natural frequencies ``f1_hz``, ``f2_hz``,
  (sorted), and with ``keep["track"]`` (the default) the first variant's modes followed by
  shape (:func:`tracked_columns`: ``mode3_hz[rotational]`` is one mode in every row, with its
  MAC to the first variant's shape) -- the first ``keep["modes"]``, or those of
  ``keep["classes"]`` within ``keep["band_hz"]``;
  ... and the number of rigid-body modes ``n_rigid``;
* ``compare``: the same for each fidelity, ``torsional_f1_hz``, ``rigid_f1_hz``, ...;
* ``frf``: per output its largest magnitude ``peak[OUT]`` (output unit per input unit) and
  where it is, ``peak_hz[OUT]`` (Hz), and the same in each of ``[frf] bands``
  (``peak[OUT][LO-HI Hz]``);
* ``simulate``: per output the ``keep["stats"]`` of its history, ``peak[OUT]``,
  ``mean[OUT]``, ... (a stress output's history is its von Mises stress, Pa), and
  ``contact_losses`` over all meshes. The statistics are accumulated as the run goes and no
  history is kept (``simulate(..., arrays=False)``): a variant's memory is flat in ``t_end``
  unless it keeps its life tables (the scene's ``[simulation.life]``: :func:`life_columns`,
  the histories they count in memory) or a run-up's passages (``keep["passages"]``:
  :func:`passage_columns`).

Columns about the run, not the result (:data:`RUN_COLUMNS`): ``time_s``, the superelements
the variant took from the cache (``reductions_reused``) and built (``reductions_built``),
and the worker process (``pid``).
"""
from __future__ import annotations

import logging
import math
import os
import time
from pathlib import Path

from .spec import Variant

log = logging.getLogger(__name__)

RUN_COLUMNS = ("time_s", "reductions_reused", "reductions_built", "pid")


def run_variant(scene_source: str, variant: Variant, analysis: str = "modes", keep: dict | None = None,
                settings: dict | None = None, cache_dir: str | None = None) -> dict:
    """The row of ``variant`` (module notes): ``variant`` (its index), each parameter's
    value, ``status`` ("ok" or "error"), ``error`` (the message, "" when ok), the results
    and the run columns. ``cache_dir``: the cache root to use (default: the process's)."""
    import contextlib

    from threadpoolctl import threadpool_limits

    from cms.cache import STATS
    from cms.linsolve import default_backend
    from fe_components.meshing import cache_root

    from ..errors import user_errors
    default_backend()   # loads CHOLMOD's BLAS now, so that the one-thread limit below reaches it
    keep = {"modes": 10, "stats": ["peak", "mean"], **(keep or {})}
    row = {"variant": variant.index, **variant.params, "status": "ok", "error": ""}
    t0, before = time.perf_counter(), dict(STATS)
    try:
        with threadpool_limits(1), (cache_root(cache_dir) if cache_dir else contextlib.nullcontext()):
            row.update(finite(_results(scene_source, variant, analysis, keep, settings or {})))
    except user_errors() as exc:
        row.update(status="error", error=str(exc).splitlines()[0])
    except Exception as exc:  # noqa: BLE001 -- a study reports every failure as its variant's row
        row.update(status="error", error=f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}")
        log.exception("variant %d failed", variant.index)
    if row["status"] == "error":
        log.info("variant %d: %s", variant.index, row["error"])
    row.update(time_s=time.perf_counter() - t0, reductions_reused=STATS["hits"] - before["hits"],
               reductions_built=STATS["misses"] - before["misses"], pid=os.getpid())
    return row


def finite(results: dict) -> dict:
    """``results``, or SceneError naming the first result that is NaN or infinite: such a
    row is a failed variant, never an "ok" row with a number that is none."""
    bad = [k for k, v in results.items() if isinstance(v, float) and not math.isfinite(v)]
    if bad:
        from ...errors import SceneError
        raise SceneError(bad[0], results[bad[0]], f"the variant's result is not finite (NaN or inf in {len(bad)} of its "
                                                  f"{len(results)} results); none is kept")
    return results


def _results(scene_source: str, variant: Variant, analysis: str, keep: dict, settings: dict) -> dict:
    from ...errors import SceneError
    from ...model.assemble import assemble
    from ...scene.schema import load_scene
    scene = load_scene(scene_source).with_values(variant.values)
    if analysis == "modes":
        from ...analysis.modal import solve_modes
        res = solve_modes(assemble(scene))
        out = _frequencies(res, keep["modes"])
        if settings.get("reference") is not None:
            out.update(tracked_columns(settings["reference"], res))
        return out
    if analysis == "compare":
        from ...analysis.compare import compare
        out = {}
        for fid, res in compare(scene).results.items():
            out.update(_frequencies(res, keep["modes"], f"{fid}_"))
        return out
    if analysis == "frf":
        from ...dynamics.frf import frequency_response
        from ..report.frf import frequencies, peak
        from .file import band_label
        f = frequencies(settings["fmin"], settings["fmax"], settings["points"], settings["log"])
        r = frequency_response(assemble(scene), settings["input"], settings["outputs"], f,
                               method=settings["method"], modes_hz=settings["modes_hz"])
        out = {}
        for name, h in r.outputs.items():
            out[f"peak[{name}]"], out[f"peak_hz[{name}]"] = peak(r.frequency_hz, h)
            for band in settings.get("bands", ()):          # each band's own peak
                got = peak(r.frequency_hz, h, band)
                if got is not None:
                    out[f"peak[{name}][{band_label(*band)}]"], out[f"peak_hz[{name}][{band_label(*band)}]"] = got
        return out
    if analysis == "simulate":
        from ...dynamics.simulate import simulate
        from ...dynamics.transient import Diverged
        from ..report.simulate import summary
        try:
            r = simulate(scene, settings["t_end"], settings["dt"], settings["outputs"], base_dir=Path(scene_source).parent,
                         speed=settings["speed"], full_fe=settings["unreduced"], arrays=keep.get("passages", False))
        except Diverged as exc:
            raise SceneError("simulate", settings["t_end"], f"run stopped: {exc}") from None
        s = summary(r, scene.name)
        out = {f"{stat}[{name}]": row[stat] for name, row in s["outputs"].items() for stat in keep["stats"]}
        out["contact_losses"] = int(sum(m["contact_losses"] for m in r.meshes))
        if keep.get("life") and r.life is not None:
            out.update(life_columns(r.life))
        if keep.get("passages"):
            out.update(passage_columns(r, scene))
        return out
    raise SceneError("analysis", analysis, "must be one of modes, compare, frf, simulate")


def life_columns(life) -> dict:
    """The life tables' columns (:class:`assembly.dynamics.life_tables.LifeResult`):
    ``del_mM[OUT]`` per counted output and exponent, ``l10_hours[BEARING]`` and
    ``equivalent_load_n[BEARING]``, ``damage[MESH:GEAR]`` and ``torque_eq[MESH:GEAR]``; a value
    the table could not give (a bearing that does not turn) fails the variant with its note."""
    from ...errors import SceneError
    out = {f"del_m{m:g}[{k}]": o.dels[m] for k, o in life.outputs.items() for m in life.exponents}
    rows = [(f"[{b.bearing}]", b, {"l10_hours": b.l10_hours, "equivalent_load_n": b.equivalent_load_n})
            for b in life.bearings]
    rows += [(f"[{g.mesh}:{g.gear}]", g, {"damage": g.damage, "torque_eq": g.torque_eq}) for g in life.gears]
    for tag, row, cols in rows:
        for c, v in cols.items():
            if v is None:
                raise SceneError(f"{c}{tag}", None, row.note or "the life table has no value")
            out[f"{c}{tag}"] = v
    return out


def passage_columns(r, scene) -> dict:
    """A run-up's largest amplification over its resonance passages per output
    (:func:`assembly.dynamics.runup_orders.largest_amplifications`): ``amplification[OUT]`` and
    the speed of its peak ``amplification_rpm[OUT]``, the order ``amplification_order[OUT]`` and
    the mode ``amplification_hz[OUT]``."""
    from ...dynamics.runup_orders import largest_amplifications, run_orders
    got = run_orders(r, scene)
    if got is None:
        return {}
    out = {}
    for k, d in largest_amplifications(got[2]).items():
        out.update({f"amplification[{k}]": d["amplification"], f"amplification_rpm[{k}]": d["peak_speed_rpm"],
                    f"amplification_order[{k}]": d["order"], f"amplification_hz[{k}]": d["frequency_hz"]})
    return out


def tracked_columns(reference, res) -> dict:
    """Each followed base mode's partner in this variant (:func:`assembly.analysis.tracking.follow`):
    ``mode{N}_hz[CLASS]`` and ``mode{N}_mac[CLASS]``, N the base mode's elastic number; none for
    a variant whose bodies differ from the base's (a planet count changed: no shape to follow,
    its cells stay empty; its sorted frequencies are kept). A partner whose MAC is below
    :data:`assembly.analysis.tracking.MAC_THRESHOLD` is not the base mode any more: its
    frequency cell stays empty, its MAC says why."""
    from ...analysis.tracking import MAC_THRESHOLD, follow
    pairs = follow(reference, res)
    if pairs is None:
        return {}
    f = res.frequencies_hz[res.n_rigid:]
    out = {}
    for i, j, mac in sorted(pairs):
        tag = f"mode{reference.numbers[i]}"
        if mac >= MAC_THRESHOLD:   # below it the partner is no longer that mode: the cell stays empty
            out[f"{tag}_hz[{reference.labels[i]}]"] = float(f[j])
        out[f"{tag}_mac[{reference.labels[i]}]"] = min(float(mac), 1.0)
    return out


def _frequencies(res, n: int, prefix: str = "") -> dict:
    """The first ``n`` elastic frequencies (Hz) of a modal result and its rigid-body mode count."""
    elastic = res.frequencies_hz[res.n_rigid:res.n_rigid + n]
    return {f"{prefix}n_rigid": int(res.n_rigid), **{f"{prefix}f{i + 1}_hz": float(f) for i, f in enumerate(elastic)}}
