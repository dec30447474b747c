"""``flexgear campbell SCENE --speed-range MIN MAX``: Campbell diagram output.

Builds the diagram (:func:`assembly.dynamics.campbell.campbell`) and writes it: a crossing
table on stdout, one JSON object (``--json``), or ``--out DIR`` with ``campbell.png``,
``crossings.csv``, ``campbell.json``, each planetary stage's interference (SAFE) diagram
``safe_STAGE.png`` with ``safe.csv`` (:mod:`.safe`) and ``index.html`` (atomically, with the
folder rules of ``flexgear run``, :mod:`assembly.app.output`). Speeds in rpm of the reference
body, frequencies in Hz.
"""
from __future__ import annotations

import csv
import logging
import sys
import time
from pathlib import Path

from ...dynamics.campbell import Campbell
from ...dynamics.safe import safe_diagrams
from .. import strict_json
from . import safe
from .campbell_page import campbell_page, verdict

log = logging.getLogger(__name__)

FILES = ("campbell.png", "crossings.csv", "campbell.json", "safe.csv", "index.html")   # and safe_STAGE.png
CSV_HEAD = ("rank", "order", "harmonic", "speed_rpm", "frequency_hz", "mode", "class", "scope", "share", "energy",
            "excitable", "rule")


def _energy_text(energy) -> str:
    """``"stage1 ke 0.99 se 0.98; rotor ke 0.01 se 0.02"``: kinetic and strain shares per group."""
    return "; ".join(f"{g} ke {k:.3g} se {s:.3g}" for g, k, s in energy)


def campbell_json(c: Campbell, rated_rpm: float | None = None, diagrams=None) -> dict:
    """The diagram as one JSON-ready object (rpm, Hz), with each planetary stage's SAFE diagram
    (``diagrams``: :func:`assembly.dynamics.safe.safe_diagrams` of ``c``, made here if None)."""
    diagrams = safe_diagrams(c) if diagrams is None else diagrams
    return {
        "scene": c.scene, "reference": c.reference, "units": {"speed": "rpm", "frequency": "Hz"},
        "speed_range_rpm": [float(c.speeds_rpm[0]), float(c.speeds_rpm[-1])], "gyroscopic": c.gyroscopic,
        "rated_rpm": rated_rpm, "speed_ratios": c.ratios,
        "orders": [{"name": o.name, "kind": o.kind, "source": o.source, "harmonic": o.harmonic,
                    "hz_per_rpm": o.hz_per_rpm, "teeth": o.teeth, "stage": o.stage, "sun_teeth": o.sun_teeth,
                    "n_planets": o.n_planets, "equally_spaced": o.equally_spaced} for o in c.orders],
        "modes": [{"mode": m.index + 1, "frequency_hz": m.frequency_hz, "class": m.mode_class, "scope": m.scope}
                  for m in c.modes],
        "speeds_rpm": c.speeds_rpm.tolist(),
        "frequencies_hz": c.frequencies_hz.tolist() if c.gyroscopic else [m.frequency_hz for m in c.modes],
        "crossings": [{"order": x.order, "harmonic": x.harmonic, "speed_rpm": x.speed_rpm,
                       "frequency_hz": x.frequency_hz, "mode": x.mode, "class": x.mode_class, "scope": x.scope,
                       "energy": [{"group": g, "kinetic": k, "strain": s} for g, k, s in x.energy],
                       "share": x.share, "excitable": x.excitable, "rule": x.rule} for x in c.ranked()],
        "safe": safe.safe_json(diagrams),
        "notes": list(c.notes),
    }


def write_csv(c: Campbell, path) -> Path:
    """One row per crossing (:data:`CSV_HEAD`), ranked (:meth:`Campbell.ranked`: the exciter's share
    of the mode, largest first; what it cannot excite last)."""
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(CSV_HEAD)
        for k, x in enumerate(c.ranked()):
            w.writerow([k + 1, x.order, x.harmonic, f"{x.speed_rpm:.9g}", f"{x.frequency_hz:.9g}", x.mode,
                        x.mode_class, x.scope or "", f"{x.share:.3g}", _energy_text(x.energy), verdict(x.excitable),
                        x.rule])
    return Path(path)


def write_plot(c: Campbell, path, rated_rpm: float | None = None) -> Path:
    from ..plots import plot_campbell

    return plot_campbell(c.speeds_rpm, c.frequencies_hz, [(o.name, o.hz_per_rpm) for o in c.orders],
                         [(x.speed_rpm, x.frequency_hz, x.excitable is not False, x.share, k + 1)
                          for k, x in enumerate(c.ranked())], path,
                         title=f"{c.scene}: Campbell diagram" + (" (gyroscopic)" if c.gyroscopic else ""),
                         rated_rpm=rated_rpm, speed_label=f"{c.reference} speed [rpm]")


def crossings_text(c: Campbell) -> str:
    """The crossing table as text, ranked (:meth:`Campbell.ranked`), each planetary stage's SAFE
    summary and the notes."""
    able = sum(1 for x in c.crossings if x.excitable is not False)
    lines = [f"{c.scene}: Campbell diagram, {c.reference} {c.speeds_rpm[0]:g}-{c.speeds_rpm[-1]:g} rpm, "
             f"{len(c.orders)} orders, {len(c.crossings)} crossings ({able} the exciter can drive), ranked by the "
             f"exciter's share of the mode's energy",
             f"{'#':>4} {'order':<22} {'h':>2} {'speed rpm':>11} {'freq Hz':>10} {'mode':>5}  {'class':<13} "
             f"{'scope':<10} {'share':>8} {'excites':<9} rule"]
    for k, x in enumerate(c.ranked()):
        lines.append(f"{k + 1:>4} {x.order:<22} {x.harmonic:>2} {x.speed_rpm:>11.5g} {x.frequency_hz:>10.4f} "
                     f"{x.mode:>5}  {x.mode_class:<13} {x.scope or '':<10} {x.share:>8.2g} "
                     f"{verdict(x.excitable):<9} {x.rule}")
    for d in safe_diagrams(c):
        at = ", ".join(f"x{e.harmonic} {e.index}" for e in d.excitations)
        lines.append(f"SAFE {d.stage}: N = {d.n_planets}, Z_s = {d.sun_teeth}, phase index k = (l Z_s) mod N: {at}; "
                     f"{len(d.interferences)} interferences" + ("" if d.equally_spaced else " (not equally spaced)"))
    lines += [f"note: {n}" for n in c.notes]
    return "\n".join(lines)


def campbell_to_dir(c: Campbell, out_dir, rated_rpm: float | None = None, scene_source: str = "") -> dict:
    """Write :data:`FILES` and the run manifest into ``out_dir`` atomically."""
    from ..output import check_output_dir, staged_output, write_manifest, writing

    out_dir = Path(out_dir).absolute()
    t0 = time.perf_counter()
    check_output_dir(out_dir)
    diagrams = safe_diagrams(c)
    with staged_output(out_dir) as work:
        with writing(out_dir, work, "campbell results"):
            write_plot(c, work / "campbell.png", rated_rpm)
            write_csv(c, work / "crossings.csv")
            (work / "campbell.json").write_text(strict_json.dumps(campbell_json(c, rated_rpm, diagrams), indent=1),
                                                encoding="utf-8")
            safe.write_csv(diagrams, work / "safe.csv")
            pngs = safe.write_plots(diagrams, work, rated_rpm, f"{c.reference} speed")
            (work / "index.html").write_text(campbell_page(c, rated_rpm, more=[safe.safe_section(diagrams)]),
                                             encoding="utf-8")
            info = dict(tool="flexgear campbell", scene=c.scene, scene_source=str(scene_source),
                        files=list(FILES) + pngs,
                        n_crossings=len(c.crossings), time_s=round(time.perf_counter() - t0, 4),
                        python=sys.version.split()[0])
            write_manifest(work, info)
    return info
