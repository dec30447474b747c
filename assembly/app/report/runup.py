"""The order analysis files of ``flexgear runup`` (:mod:`assembly.dynamics.runup_orders`): per
output a response Campbell image ``orders_NN.png`` (the order map over speed and frequency with
the excitation orders and the natural frequencies), ``passages.csv`` (order, mode, speed, peak,
amplification) and ``orders.html``, written into the run's work folder beside the simulation's
files and linked from its ``index.html``."""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from .page import Section, esc, files_list, grid, page, para, table

#: The pages of a run-up's folder: the run and its orders.
PAGES = (("index.html", "The run"), ("orders.html", "Orders of the run-up"))


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
    def num(x):
        return "-" if x is None or (isinstance(x, float) and not np.isfinite(x)) else f"{x:.4g}"
    rows = [[d["output"], d["order_label"], f"{d['order']:.4g}", d["excitation"], d["mode_class"],
             f"{d['frequency_hz']:.4g}", f"{d['speed_rpm']:.4g}", num(d["peak_speed_rpm"]), num(d["peak"]),
             num(d["quasi_static"]), num(d["amplification"]), d["note"]] for d in ro.passages]
    head = ["output", "order", "", "excitation", "mode class", "f_n [Hz]", "passage [rpm]", "peak at [rpm]", "peak",
            "quasi-static", "amplification", "note"]
    body = table(head, rows, left=(0, 1, 3, 4, 11)) if rows else para("No resonance passage in the run-up.")
    sections = [Section("Resonance passages", body, "Passages")]
    if ro.skipped:
        sections.append(Section("Orders not tracked", "<ul>" + "".join(
            f"<li>{esc(k)}: {esc(v)}</li>" for k, v in ro.skipped.items()) + "</ul>", "Not tracked"))
    imgs = [p for p in files if p.endswith(".png")]             # one per map, in order
    if imgs:
        sections.append(Section("Order maps", grid((p, f"{name}: order map over the run-up")
                                                   for p, name in zip(imgs, ro.maps)), "Maps"))
    sections.append(Section("Files", files_list([("passages.csv", "the resonance passages (CSV)")])))
    lead = para(f"Orders per revolution of the reference; dashed lines: the excitation orders; dotted: natural "
                f"frequencies; speeds of {shaft or 'the reference'}. Amplification: the peak over the order's "
                f"quasi-static level (a mesh order's: the parametric level, its low-speed r^2 rise taken out).")
    return page(f"{scene}: orders of the run-up", sections, command="flexgear runup", scene=scene, lead=lead,
                pages=PAGES, here="orders.html")
