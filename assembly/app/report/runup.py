"""The order analysis files of ``flexgear runup`` (:mod:`assembly.dynamics.runup_orders`): per
output a response Campbell image ``orders_NN.png`` (the order map over speed and frequency with
the excitation orders and the natural frequencies), ``passages.csv`` (order, mode, speed, peak,
amplification) and ``orders.html``, written into the run's work folder beside the simulation's
files and linked from its ``index.html``."""
from __future__ import annotations

import csv
import html
import math
from pathlib import Path

import numpy as np


def runup_files(ro, work: Path, scene: str, natural_hz, f_max: float | None, shaft: str = "") -> list:
    """Write the files of the module notes (speeds: of the tracked ``shaft``); returns their names."""
    from ..plots import plot_response_campbell

    work = Path(work)
    files = []
    lines = list(ro.orders.items())
    for i, (name, omap) in enumerate(ro.maps.items()):
        p = f"orders_{i + 1:02d}.png"
        plot_response_campbell(omap.speed * 30 / math.pi, omap.orders, omap.amplitude, work / p, lines, natural_hz,
                               title=f"{scene}\n{name}: order map over the run-up", f_max=f_max, shaft=shaft)
        files.append(p)
    with open(work / "passages.csv", "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        cols = ["output", "shaft", "order_label", "order", "excitation", "mode_class", "frequency_hz", "speed_rpm", "peak_speed_rpm", "peak",
                "quasi_static", "level_r", "amplification", "note"]
        w.writerow(cols)
        for d in ({**p, "shaft": shaft} for p in ro.passages):
            w.writerow(["" if d[c] is None else (f"{d[c]:.6g}" if isinstance(d[c], float) else d[c]) for c in cols])
    files.append("passages.csv")
    (work / "orders.html").write_text(_page(ro, scene, files, shaft), encoding="utf-8")
    files.append("orders.html")
    return files


def _page(ro, scene: str, files: list, shaft: str = "") -> str:
    e = html.escape

    def num(x):
        return "-" if x is None or (isinstance(x, float) and not np.isfinite(x)) else f"{x:.4g}"
    rows = "".join(f"<tr><td>{e(d['output'])}</td><td>{e(d['order_label'])}</td><td>{d['order']:.4g}</td>"
                   f"<td>{e(d['excitation'])}</td><td>{e(d['mode_class'])}</td><td>{d['frequency_hz']:.4g}</td><td>{d['speed_rpm']:.4g}</td>"
                   f"<td>{num(d['peak_speed_rpm'])}</td><td>{num(d['peak'])}</td><td>{num(d['quasi_static'])}</td>"
                   f"<td>{num(d['amplification'])}</td><td>{e(d['note'])}</td></tr>" for d in ro.passages)
    imgs = "".join(f'<figure><img src="{e(p)}" alt="{e(p)}"></figure>' for p in files if p.endswith(".png"))
    skipped = "".join(f"<li>{e(k)}: {e(v)}</li>" for k, v in ro.skipped.items())
    return (f"<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>{e(scene)}: run-up orders</title></head><body>"
            f"<h1>{e(scene)}: orders of the run-up</h1><p>Orders per revolution of the reference; dashed lines: the "
            f"excitation orders; dotted: natural frequencies; speeds of {e(shaft or 'the reference')}. Amplification: the peak over the order's "
            f"quasi-static level (a mesh order's: the parametric level, its low-speed r^2 rise taken out). "
            f"<a href=\"index.html\">The run</a>, "
            f"<a href=\"passages.csv\">passages.csv</a>.</p><h2>Resonance passages</h2><table border=1><tr>"
            f"<th>output</th><th>order</th><th></th><th>excitation</th><th>mode class</th><th>f_n [Hz]</th><th>passage [rpm]</th>"
            f"<th>peak at [rpm]</th><th>peak</th><th>quasi-static</th><th>amplification</th><th>note</th></tr>{rows}</table>"
            + (f"<h2>Orders not tracked</h2><ul>{skipped}</ul>" if skipped else "") + f"{imgs}</body></html>\n")
