"""A design study's results folder: the table, its plots and an index.

``--out DIR`` gets, atomically and with the folder rules of ``flexgear run``
(:mod:`assembly.app.output`):

* ``study.parquet`` and ``study.csv``: one row per variant in variant order: ``variant``,
  each parameter, ``status`` ("ok" / "error"), ``error`` and the kept results (SI: Hz, N,
  N m, Pa; empty where a variant failed). These depend only on the study, not on where or
  how fast it ran, so the same study gives the same files serially or on any cluster;
* ``runs.csv``: per variant its run time (s), the superelements it reused from the cache and
  built, and the worker process;
* per parameter, the kept results against it: ``frequencies_vs_<P>.png`` (every kept
  natural frequency) or ``<result>_vs_<P>.png``; failed variants are marked on the axis;
* ``sensitivity.csv``: each result's elasticity to each parameter and the fit's R^2
  (:mod:`assembly.app.study.sensitivity`), the largest also in index.html;
* ``index.html`` and ``flexgear_run.json``.
"""
from __future__ import annotations

import csv
import math
import re
import sys
import time
from pathlib import Path

import numpy as np

from ..report.page import Section, esc, files_list, grid, page
from .run import RUN_COLUMNS
from .sensitivity import physical_result, sensitivity_section, write_sensitivity

FIXED = ("variant", "status", "error")


def columns(rows: list[dict], parameters: list[str]) -> list[str]:
    """The table's columns: variant, the parameters, status, error, then the results in the
    order they first appear."""
    head = ["variant", *parameters, "status", "error"]
    seen = set(head) | set(RUN_COLUMNS)
    out = list(head)
    for r in rows:
        for k in r:
            if k not in seen:
                seen.add(k)
                out.append(k)
    return out


def write_table(rows: list[dict], parameters: list[str], folder: Path) -> list[str]:
    """study.parquet, study.csv and runs.csv; returns the result columns."""
    import pyarrow as pa
    import pyarrow.parquet as pq
    cols = columns(rows, parameters)
    data = {c: [r.get(c) for r in rows] for c in cols}
    pq.write_table(pa.table({c: _array(v) for c, v in data.items()}), folder / "study.parquet")
    with open(folder / "study.csv", "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        for r in rows:
            w.writerow([_text(r.get(c)) for c in cols])
    with open(folder / "runs.csv", "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(["variant", *RUN_COLUMNS])
        for r in rows:
            w.writerow([r["variant"], *(_text(r.get(c)) for c in RUN_COLUMNS)])
    return [c for c in cols if c not in FIXED and c not in parameters]


def _array(values: list):
    """A pyarrow column: float64 for numbers (with nulls), int64 for whole numbers, else
    text (a parameter may take text values)."""
    import pyarrow as pa
    given = [v for v in values if v is not None]
    if given and all(isinstance(v, bool) for v in given):
        return pa.array(values, pa.bool_())
    if given and all(isinstance(v, int) and not isinstance(v, bool) for v in given):
        return pa.array(values, pa.int64())
    if given and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in given):
        return pa.array([None if v is None else float(v) for v in values], pa.float64())
    return pa.array([None if v is None else str(v) for v in values], pa.string())


def _text(v) -> str:
    """A CSV cell: floats with every digit (repr round-trips), nothing for a missing value."""
    if v is None:
        return ""
    return repr(float(v)) if isinstance(v, float) else str(v)


def _slug(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "_", name).strip("_")[:60] or "value"


def plot_results(rows: list[dict], parameters: list[str], results: list[str], folder: Path, title: str) -> list:
    """One plot per parameter of the kept natural frequencies (sorted), one of the tracked modes
    (a line per mode), and one per other result and parameter; with two parameters, maps of
    the results over both (:func:`maps`); returns [(file, caption)]."""
    from ..plots import plot_figure
    ok = [r for r in rows if r["status"] == "ok"]
    bad = [r for r in rows if r["status"] != "ok"]
    freq = [c for c in results if re.fullmatch(r"(\w+_)?f\d+_hz", c)]
    tracked = [c for c in results if re.fullmatch(r"mode\d+_hz\[.*\]", c)]
    groups = ([("frequencies", "natural frequency [Hz]", freq)] if freq else []) + \
             ([("tracked modes", "natural frequency [Hz], one mode per line", tracked)] if tracked else []) + \
             [(c, c, [c]) for c in results if c not in freq + tracked and physical_result(c)]   # MACs: table only
    out = maps(ok, parameters, [c for _, _, cs in groups for c in cs if c not in freq], folder, title)
    for p in parameters:
        xs = [r[p] for r in rows]
        if not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in xs):
            continue   # a text parameter: the table shows it
        xs = np.asarray(xs, float)
        logx = xs.min() > 0 and xs.max() / xs.min() > 100
        for label, ylabel, cs in groups:
            name = f"{_slug(label)}_vs_{_slug(p)}.png"
            with plot_figure(folder / name, (8.0, 5.0)) as (fig, ax):
                for j, c in enumerate(cs):
                    pts = sorted((r[p], r[c]) for r in ok if r.get(c) is not None and math.isfinite(r[c]))
                    if pts:
                        x, y = np.array(pts).T
                        ax.plot(x, y, "-o" if len(parameters) == 1 else "o", ms=3, lw=1.0, color=f"C{j % 10}",
                                label=c if len(cs) <= 12 else None)
                if bad:
                    ax.plot([r[p] for r in bad], np.zeros(len(bad)), "x", color="red", ms=7, clip_on=False,
                            label=f"failed ({len(bad)})")
                if logx:
                    ax.set_xscale("log")
                ys = np.array([r[c] for r in ok for c in cs if isinstance(r.get(c), (int, float))], float)
                if ys.size and ys.min() > 0 and ys.max() / ys.min() > 100 and not bad:
                    ax.set_yscale("log")
                ax.set_xlabel(p)
                ax.set_ylabel(ylabel)
                ax.set_title(f"{title}: {label} vs {p}", fontsize=10)
                if ax.get_legend_handles_labels()[0]:
                    ax.legend(fontsize=6, ncol=2 if len(cs) > 6 else 1)
            out.append((name, f"{label} vs {p}"))
    return out


#: Results drawn as maps over two parameters (the first of them, in table order).
MAP_RESULTS = 8


def maps(ok: list, parameters: list, results: list, folder: Path, title: str) -> list:
    """With exactly two numeric parameters: each of the first :data:`MAP_RESULTS` results as a
    map over both (a scatter of the variants that ran, coloured by the result); returns
    [(file, caption)]."""
    from ..plots import plot_figure
    num = [p for p in parameters if ok and all(isinstance(r.get(p), (int, float)) and not isinstance(r.get(p), bool)
                                               for r in ok)]
    if len(parameters) != 2 or len(num) != 2:
        return []
    px, py = num
    out = []
    for c in results[:MAP_RESULTS]:
        pts = [(r[px], r[py], r[c]) for r in ok if isinstance(r.get(c), (int, float)) and math.isfinite(r[c])]
        if not pts:
            continue
        x, y, z = np.array(pts, float).T
        name = f"{_slug(c)}_map.png"
        with plot_figure(folder / name, (7.0, 5.5)) as (fig, ax):
            sc = ax.scatter(x, y, c=z, cmap="viridis", s=40)
            fig.colorbar(sc, ax=ax, label=c)
            for v, lo in ((x, ax.set_xscale), (y, ax.set_yscale)):
                if v.min() > 0 and v.max() / v.min() > 100:
                    lo("log")
            ax.set_xlabel(px)
            ax.set_ylabel(py)
            ax.set_title(f"{title}: {c} over {px} and {py}", fontsize=10)
        out.append((name, f"{c} over {px} and {py}"))
    return out


def index_html(title: str, info: dict, plots: list, rows: list[dict], more=()) -> str:
    """The study's page; ``more``: further sections (the sensitivities)."""
    failed = [r for r in rows if r["status"] != "ok"]
    sections = []
    if failed:
        sections.append(Section("Failed variants", "<ul>" + "".join(
            f"<li>variant {r['variant']}: {esc(str(r['error']))}</li>" for r in failed[:50]) + "</ul>", "Failed"))
    sections += [s for s in more if s is not None]
    if plots:
        sections.append(Section("Plots", grid(plots)))
    sections.append(Section("Files", files_list([
        ("study.csv", "one row per variant: its parameters, status and kept results (CSV)"),
        ("study.parquet", "the same table (Parquet)"), ("runs.csv", "run times and cache reuse per variant (CSV)"),
        ("sensitivity.csv", "each result's elasticity to each parameter (CSV)")])))
    meta = [f"Scene {info['scene']}, analysis {info['analysis']}, {info['variants']} variants "
            f"({info['failed']} failed), run {info['mode']} in {info['time_s']:.1f} s."]
    return page(f"{title}: study", sections, command="flexgear study", scene=info["scene"], meta=meta)


def study_to_dir(study, rows: list[dict], out_dir, mode: str, time_s: float) -> dict:
    """Write the folder (module notes) atomically; returns the manifest."""
    from ..output import staged_output, write_manifest, writing
    out_dir = Path(out_dir).absolute()
    t0 = time.perf_counter()
    with staged_output(out_dir) as work:
        with writing(out_dir, work, "study results"):
            results = write_table(rows, study.parameters, work)
            plots = plot_results(rows, study.parameters, results, work, study.name)
            sens = sensitivity_section(write_sensitivity(rows, study.parameters, results, work), study.parameters)
            info = dict(tool="flexgear study", study=study.name, study_source=study.source, scene=study.scene,
                        analysis=study.analysis, parameters=study.parameters, variants=len(rows),
                        failed=sum(r["status"] != "ok" for r in rows), mode=mode, time_s=round(time_s, 3),
                        files=["study.parquet", "study.csv", "runs.csv", "sensitivity.csv", *(f for f, _ in plots),
                               "index.html"],
                        python=sys.version.split()[0])
            (work / "index.html").write_text(index_html(study.name, info, plots, rows, [sens]), encoding="utf-8")
            info["write_s"] = round(time.perf_counter() - t0, 3)
            write_manifest(work, info)
    return info
