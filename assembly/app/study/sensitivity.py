"""Each kept result's sensitivity to each parameter of a study: the elasticity d ln(result) /
d ln(parameter), the slope of a least-squares fit of ln(result) on the ln of every numeric
parameter together over the variants that ran (a local-linear design's elasticities, global
for an LHS or a grid: exact for a power law, f ~ k^(1/2) gives 1/2), and the fit's R^2.

A result or parameter that is not positive in every row that ran has no logarithm: its cells
stay empty; so does every cell of a study with fewer rows than parameters + 2, and of one whose
parameters' logarithms are not independent over the rows that ran (collinear: m = 2 k, or
m = k^2 -- any split of the slope between them would fit; the rank of the fit is checked).
R^2 is empty where the result does not vary (its elasticities are then 0). What is not a
physical result has no sensitivity: a tracked mode's MAC, the rigid-body mode count.
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from ..report.page import Section, esc, link
from ..report.page import table as html_table


def _logs(values) -> np.ndarray | None:
    try:
        a = np.asarray(values, float)
    except (TypeError, ValueError):
        return None
    return np.log(a) if a.size and np.all(np.isfinite(a)) and np.all(a > 0) else None


def physical_result(column: str) -> bool:
    """Whether a study column is a physical result with a sensitivity (not a tracked mode's MAC,
    not the rigid-body mode count)."""
    return not (column.endswith("n_rigid") or "_mac[" in column)


def sensitivities(rows: list, parameters: list, results: list) -> list:
    """[{"result", "r2", "elasticity": {parameter: value or None}}] (module notes)."""
    ok = [r for r in rows if r.get("status") == "ok"]
    X, names = [], []
    for p in parameters:
        x = _logs([r.get(p) for r in ok])
        if x is not None and np.ptp(x) > 0:
            X.append(x)
            names.append(p)
    out = []
    A = np.column_stack([np.ones(len(ok)), *X]) if names else None
    independent = A is not None and np.linalg.matrix_rank(A) == A.shape[1]
    for c in (c for c in results if physical_result(c)):
        y = _logs([r.get(c) for r in ok]) if all(r.get(c) is not None for r in ok) else None
        row = {"result": c, "r2": None, "elasticity": {p: None for p in parameters}}
        if y is not None and independent and len(ok) >= len(names) + 2:
            coef, *_ = np.linalg.lstsq(A, y, rcond=None)
            row["elasticity"].update({p: float(b) for p, b in zip(names, coef[1:])})
            tot = float(np.sum((y - y.mean()) ** 2))
            if tot > 1e-30 * max(1.0, float(np.sum(y ** 2))):
                row["r2"] = 1.0 - float(np.sum((y - A @ coef) ** 2)) / tot
            else:                                  # a constant result: no variance to explain
                row["elasticity"].update({p: 0.0 for p in names})
        out.append(row)
    return out


def write_sensitivity(rows: list, parameters: list, results: list, folder: Path) -> list:
    """``sensitivity.csv``: a row per result, the elasticity to each parameter and the fit's R^2;
    returns the rows (:func:`sensitivities`)."""
    table = sensitivities(rows, parameters, results)
    with open(Path(folder) / "sensitivity.csv", "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(["result", *(f"dln/dln[{p}]" for p in parameters), "r2"])
        for t in table:
            w.writerow([t["result"], *("" if t["elasticity"][p] is None else f"{t['elasticity'][p]:.6g}"
                                       for p in parameters), "" if t["r2"] is None else f"{t['r2']:.6g}"])
    return table


def sensitivity_section(table: list, parameters: list, top: int = 30):
    """The index.html section (:class:`~assembly.app.report.page.Section`): the results with the
    largest elasticity first; None when no result has one."""
    rows = [t for t in table if any(v is not None for v in t["elasticity"].values())]
    rows.sort(key=lambda t: -max(abs(v) for v in t["elasticity"].values() if v is not None))
    if not rows:
        return None
    cells = [[t["result"], *("-" if t["elasticity"][p] is None or not math.isfinite(t["elasticity"][p])
                             else f"{t['elasticity'][p]:.3g}" for p in parameters),
              "-" if t["r2"] is None else format(t["r2"], ".3g")] for t in rows[:top]]
    intro = esc("Elasticity of each result to each parameter (a least-squares fit of the logarithms over the "
                "variants that ran), the largest first; every result in ")
    return Section("Sensitivities", f"<p>{intro}{link('sensitivity.csv')}.</p>"
                   + html_table(["result", *(f"d ln / d ln {p}" for p in parameters), "R^2"], cells, left=(0,)))
