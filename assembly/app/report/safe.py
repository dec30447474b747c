"""Interference (SAFE) diagrams of a Campbell run (:mod:`assembly.dynamics.safe`): one picture per
planetary stage (``safe_STAGE.png``), the table (``safe.csv``, and ``"safe"`` in
``campbell.json``) and the section of the Campbell page. Frequencies in Hz, speeds in rpm of
the Campbell reference body.
"""
from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np

from ...dynamics.safe import SafeDiagram, folded, zigzag
from .campbell_page import verdict

CSV_HEAD = ("stage", "order", "harmonic", "index_k", "abs_k", "mode", "class", "mode_indices", "frequency_hz",
            "speed_rpm", "share", "safe", "why", "campbell_excitable")
CLASS_COLOURS = {"rotational": "C0", "translational": "C1", "planet": "C2", "elastic": "C4"}


def png_names(diagrams) -> dict:
    """Stage -> its picture's file name (:func:`png_name`), made unique: stages whose names
    differ only in what a file name cannot hold ('a b', 'a/b') get _2, _3 ..."""
    out, used = {}, set()
    for d in diagrams:
        name, k = png_name(d.stage), 1
        while name in used:
            k += 1
            name = png_name(d.stage)[:-4] + f"_{k}.png"
        used.add(name)
        out[d.stage] = name
    return out


def png_name(stage: str) -> str:
    """``safe_STAGE.png``, the stage name with anything but letters, digits, ``-`` and ``_`` as ``_``."""
    return f"safe_{re.sub(r'[^A-Za-z0-9_-]+', '_', stage)}.png"


def safe_json(diagrams) -> list:
    """The diagrams as JSON-ready objects (rpm, Hz)."""
    return [{"stage": d.stage, "n_planets": d.n_planets, "sun_teeth": d.sun_teeth, "equally_spaced": d.equally_spaced,
             "mesh_hz_per_rpm": d.mesh_hz_per_rpm, "speed_range_rpm": list(d.speed_range_rpm),
             "excitations": [{"order": e.order, "harmonic": e.harmonic, "index": e.index,
                              "abs_index": int(folded(e.index, d.n_planets)), "hz_per_rpm": e.hz_per_rpm,
                              "excites": e.excites} for e in d.excitations],
             "modes": [{"mode": m.mode, "frequency_hz": m.frequency_hz, "class": m.label, "indices": list(m.indices)}
                       for m in d.modes],
             "crossings": [{"order": r.order, "harmonic": r.harmonic, "index": r.index, "mode": r.mode,
                            "class": r.mode_class, "mode_indices": list(r.mode_indices),
                            "frequency_hz": r.frequency_hz, "speed_rpm": r.speed_rpm, "share": r.share,
                            "safe": r.verdict, "why": r.why, "campbell_excitable": r.excitable} for r in d.rows],
             "notes": list(d.notes)} for d in diagrams]


def write_csv(diagrams, path) -> Path:
    """One row per crossing of a stage mesh harmonic (:data:`CSV_HEAD`): interferences first."""
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(CSV_HEAD)
        for d in diagrams:
            for r in d.rows:
                w.writerow([d.stage, r.order, r.harmonic, r.index, int(folded(r.index, d.n_planets)), r.mode,
                            r.mode_class, " ".join(str(k) for k in r.mode_indices), f"{r.frequency_hz:.9g}",
                            f"{r.speed_rpm:.9g}", f"{r.share:.3g}", r.verdict, r.why, verdict(r.excitable)])
    return Path(path)


def plot_safe(d: SafeDiagram, path, rated_rpm: float | None = None, speed_label: str = "reference") -> Path:
    """The SAFE diagram of one stage: phase index |k| across, frequency up. Modes as short bars
    at their indices (coloured by class), each mesh harmonic's band over the speed range at its
    index, Singh's zig-zag order line at ``rated_rpm`` (else the top speed) with the harmonics
    on it, interferences circled."""
    from ..plots import plot_figure

    n = d.n_planets
    lo, hi = d.speed_range_rpm
    ref = rated_rpm if rated_rpm is not None else hi
    h_max = max(e.harmonic for e in d.excitations)
    top = max(h_max * d.mesh_hz_per_rpm * max(hi, ref), 1e-9) * 1.08
    xmax = n // 2
    with plot_figure(path, (7.5, 6.0)) as (fig, ax):
        if n > 1:                                  # one planet: a single index, nothing to fold
            nu, x = zigzag(h_max * d.sun_teeth * 1.04, n)
            ax.plot(x, nu * d.mesh_hz_per_rpm * ref / d.sun_teeth, "-", color="0.6", lw=0.6)
        for e in d.excitations:
            k = int(folded(e.index, n))
            ax.plot([k, k], [e.hz_per_rpm * lo, e.hz_per_rpm * hi], "-", color="C3", lw=9, alpha=0.18,
                    solid_capstyle="butt")
            f = e.hz_per_rpm * ref
            ax.plot([k], [f], "D", color="C3", ms=5)
            ax.annotate(f"x{e.harmonic}", (k, f), textcoords="offset points", xytext=(6, 2), fontsize=8, color="C3")
        for cls, colour in CLASS_COLOURS.items():
            seg = [(int(folded(k, n)), m.frequency_hz) for m in d.modes if m.label.split()[0] == cls
                   for k in set(int(folded(k, n)) for k in m.indices) if m.frequency_hz <= top]
            if seg:
                xy = np.array(seg, float)
                ax.plot(np.repeat(xy[:, 0], 3) + np.tile([-0.14, 0.14, np.nan], len(xy)),
                        np.repeat(xy[:, 1], 3), "-", color=colour, lw=2.0, label=f"{cls} modes")
        hit = np.array([(folded(r.index, n), r.frequency_hz) for r in d.interferences], float).reshape(-1, 2)
        if len(hit):
            ax.plot(hit[:, 0], hit[:, 1], "o", ms=11, mfc="none", mec="k", mew=1.2, label="interference")
        ax.set_xlim(-0.4, n / 2 + 0.4)
        ax.set_xticks(range(xmax + 1))
        ax.set_xticklabels([str(k) if k == 0 or 2 * k == n else f"±{k}" for k in range(xmax + 1)])
        ax.set_ylim(0, top)
        ax.set_xlabel(f"phase index |k| over the planets (N = {n}, Z_s = {d.sun_teeth})")
        ax.set_ylabel("frequency [Hz]")
        ax.set_title(f"{d.stage}: interference (SAFE) diagram", fontsize=10)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7, loc="upper left")
        ax.text(0.0, -0.10, f"bands: mesh harmonics over {lo:g}-{hi:g} rpm ({speed_label}); grey zig-zag and "
                f"diamonds: at {ref:g} rpm; k = (l Z_s) mod N", transform=ax.transAxes, fontsize=7, va="top")
    return Path(path)


def write_plots(diagrams, out_dir, rated_rpm: float | None = None, speed_label: str = "reference") -> list:
    """``safe_STAGE.png`` of every diagram in ``out_dir``; their names."""
    names = png_names(diagrams)
    for d in diagrams:
        plot_safe(d, Path(out_dir) / names[d.stage], rated_rpm, speed_label)
    return [names[d.stage] for d in diagrams]


def safe_section(diagrams):
    """The Campbell page's section (:class:`assembly.app.report.page.Section`): each stage's
    picture and its interferences."""
    from .page import Section, figure, note, para, table

    if not diagrams:
        return Section("Interference (SAFE) diagrams", para("No planetary stage with a mesh order."), "SAFE")
    out = [para("Phase index k = (l Z_s) mod N of mesh harmonic l across, frequency up: a mode is excited only "
                "where its index (rotational 0, translational ±1, planet the others) matches the harmonic's and "
                "its frequency lies in the harmonic's band. Every crossing of the stages' mesh harmonics with its "
                "verdict: safe.csv.")]
    names = png_names(diagrams)
    for d in diagrams:
        out.append(figure(names[d.stage], f"{d.stage}: N = {d.n_planets}, Z_s = {d.sun_teeth}"))
        ruled = sum(1 for r in d.rows if r.verdict == "ruled out")
        out.append(para(f"{d.stage}: {len(d.interferences)} interferences, {ruled} crossings ruled out by phasing "
                        "or no modal force."))
        if d.interferences:
            out.append(table(["harmonic", "k", "mode", "class", "frequency [Hz]", "speed [rpm]", "share"],
                             [[r.order, r.index, r.mode, r.mode_class, f"{r.frequency_hz:.4g}", f"{r.speed_rpm:.5g}",
                               f"{r.share:.3g}"] for r in d.interferences]))
        out += [note(n) for n in d.notes]
    return Section("Interference (SAFE) diagrams", "\n".join(out), "SAFE")
