"""``flexgear simulate SCENE --t-end T --dt DT --output NAME ...``: time-domain output.

Runs :func:`assembly.dynamics.simulate.simulate` and writes its histories: one JSON object
(``--json``: ``{"time_s": [...], "outputs": {NAME: [...]}, "units": {...}}`` and run facts),
or ``--out DIR`` with ``simulation.h5`` (HDF5: ``/time_s`` and ``/outputs/NAME``, each with
its unit; run facts as attributes), per output a time trace ``trace_NN.png`` and an
amplitude spectrum ``spectrum_NN.png`` (mesh harmonics 1-3 of each stage or pair at the
starting speed marked, and the sidebands at +-1, +-2 x the carrier's or the slower gear's
speed around the first), ``summary.json`` and ``index.html``, atomically with the folder
rules of ``flexgear run`` (:mod:`assembly.app.output`); otherwise a summary line per
output. A stress output's history is its von Mises stress; its peak is in the summary.

A run that stops (diverges, or a step does not converge) keeps what it computed: with
``--out``, the folder is written as for a complete run, under the same rules, but marked as
partial: the history is ``partial_simulation.h5`` (attributes ``complete`` False and
``stopped``, the reason), ``summary.json`` has ``"complete": false`` and ``"stopped"``,
``index.html`` says so at the top. Without ``--out`` nothing is written (the summary or
``--json`` is printed). The command ends with the reason and exit code 1.
"""
from __future__ import annotations

import html
import sys
import time
from pathlib import Path

import numpy as np

from ...dynamics.simulate import SimulationResult
from .. import strict_json
from .html import figure

#: Mesh harmonics marked on the spectra.
MARKED_HARMONICS = 3
#: The history file of a complete run and of a run that stopped.
H5_COMPLETE, H5_PARTIAL = "simulation.h5", "partial_simulation.h5"


def h5_name(r: SimulationResult) -> str:
    """The history file's name: :data:`H5_PARTIAL` for the partial result of a stopped run."""
    return H5_COMPLETE if r.complete else H5_PARTIAL


def spectrum(time_s: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One-sided amplitude spectrum (Hz, units of ``y``) of a uniformly sampled history:
    mean removed, Hann window, scaled so a sinusoid of amplitude A shows A at its frequency."""
    y = np.asarray(y, float) - np.mean(y)
    n = len(y)
    if n < 4:
        return np.zeros(0), np.zeros(0)
    w = np.hanning(n)
    Y = np.fft.rfft(y * w)
    return np.fft.rfftfreq(n, time_s[1] - time_s[0]), 2.0 * np.abs(Y) / w.sum()


def marks(r: SimulationResult) -> list:
    """(Hz, label, kind) of the mesh harmonics and sidebands to mark on the spectra."""
    out = []
    for src, fm in r.mesh_frequencies_hz.items():
        out += [(h * fm, f"{src} x{h}", "mesh") for h in range(1, MARKED_HARMONICS + 1)]
        side = r.sidebands_hz.get(src, 0.0)
        out += [(fm + k * side, "", "sideband") for k in (-2, -1, 1, 2) if side > 0]
    return out


def summary(r: SimulationResult, scene: str) -> dict:
    """Per output its mean, RMS, min, max and peak |value|; the meshes' contact losses."""
    rows = {}
    for k, y in r.outputs.items():
        rows[k] = {"unit": r.units[k], "mean": float(np.mean(y)), "rms": float(np.sqrt(np.mean(y * y))),
                   "min": float(np.min(y)), "max": float(np.max(y)),
                   "peak": float(np.max(np.abs(y))), "peak_time_s": float(r.time_s[int(np.argmax(np.abs(y)))])}
    return {"scene": scene, "complete": r.complete, "stopped": None if r.complete else r.info.get("stopped"),
            "t_end_s": float(r.time_s[-1]), "steps": len(r.time_s) - 1,
            "outputs": rows, "meshes": r.meshes, "mesh_frequencies_hz": r.mesh_frequencies_hz,
            "warnings": r.warnings, "info": {k: v for k, v in r.info.items() if not k.startswith("_")}}


def summary_text(r: SimulationResult, scene: str) -> str:
    s = summary(r, scene)
    rate = f"{r.info['steps_per_s']:.0f} steps/s, " if "steps_per_s" in r.info else ""
    lines = [f"{scene}: {s['steps']} steps to {s['t_end_s']:g} s ({r.info.get('scheme')}, {rate}"
             f"{r.info.get('dofs')} DOFs)"
             + ("" if r.complete else f" -- PARTIAL: the run stopped: {s['stopped']}")]
    for k, row in s["outputs"].items():
        lines.append(f"  {k}: mean {row['mean']:.6g}, min {row['min']:.6g}, max {row['max']:.6g} {row['unit']}")
    lost = [m for m in r.meshes if m["contact_losses"]]
    losses = ", ".join(f"{m['name']} {m['contact_losses']}" for m in lost) or "none"
    lines.append(f"  contact losses: {losses}")
    lines += [f"  warning: {w}" for w in r.warnings]
    return "\n".join(lines)


def write_h5(r: SimulationResult, path, scene: str, facts: dict | None = None) -> Path:
    """``/time_s`` (s) and ``/outputs/NAME`` (attribute ``unit``); run facts (``facts``,
    default :func:`summary`) as file attributes."""
    import h5py
    with h5py.File(path, "w") as f:
        f.create_dataset("time_s", data=r.time_s).attrs["unit"] = "s"
        g = f.create_group("outputs")
        for k, y in r.outputs.items():
            g.create_dataset(k.replace("/", "|"), data=y).attrs["unit"] = r.units[k]
        f.attrs["scene"] = scene
        f.attrs["complete"] = r.complete
        if not r.complete:
            f.attrs["stopped"] = str(r.info.get("stopped", ""))
        f.attrs["summary"] = strict_json.dumps(facts if facts is not None else summary(r, scene))
    return Path(path)


def _index(r: SimulationResult, scene: str, s: dict, plots: list) -> str:
    e = html.escape
    rows = "".join(f"<tr><td>{e(k)}</td><td>{e(v['unit'])}</td><td>{v['mean']:.6g}</td><td>{v['rms']:.6g}</td>"
                   f"<td>{v['min']:.6g}</td><td>{v['max']:.6g}</td><td>{v['peak_time_s']:.6g}</td></tr>"
                   for k, v in s["outputs"].items())
    meshes = "".join(f"<tr><td>{e(m['name'])}</td><td>{m['backlash_m'] if m['backlash_m'] is not None else '-'}"
                     f"</td><td>{m['harmonics']}</td><td>{m['contact_losses']}</td></tr>" for m in r.meshes)
    warn = "".join(f"<li>{e(w)}</li>" for w in r.warnings)
    figs = "\n".join(figure(p, n) for n, p in plots)
    h5, partial = h5_name(r), "" if r.complete else " (partial)"
    stopped = "" if r.complete else (f"<p><strong>Partial result: the run stopped</strong> at t = {s['t_end_s']:g} s "
                                     f"of {r.info['t_end_s']:g} s: {e(str(s['stopped']))}</p>")
    wall = f", {r.info['wall_s']:.3g} s wall" if "wall_s" in r.info else ""
    return (f"<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>{e(scene)}: simulation{partial}</title>"
            f"</head><body><h1>{e(scene)}: time-domain simulation{partial}</h1>{stopped}<p>{s['steps']} steps of "
            f"{r.info['dt_s']:g} s to {s['t_end_s']:g} s, {e(r.info['scheme'])}, {r.info['dofs']} DOFs{wall}. "
            f'Data: <a href="{h5}">{h5}</a>, <a href="summary.json">summary.json</a>.</p>'
            f"<table border=1><tr><th>output</th><th>unit</th><th>mean</th><th>RMS</th><th>min</th><th>max</th>"
            f"<th>peak at [s]</th></tr>{rows}</table>"
            + (f"<h2>Nonlinear meshes</h2><table border=1><tr><th>mesh</th><th>backlash [m]</th><th>harmonics"
               f"</th><th>contact losses</th></tr>{meshes}</table>" if r.meshes else "")
            + (f"<h2>Warnings</h2><ul>{warn}</ul>" if warn else "")
            + f"<p>Spectra: mesh harmonics (red) and sidebands (green dotted) at the starting speed.</p>\n"
            f"{figs}\n</body></html>\n")


def sim_to_dir(r: SimulationResult, out_dir, scene: str, scene_source: str = "") -> dict:
    """Write simulation.h5, the traces and spectra, summary.json and index.html atomically;
    the partial result of a stopped run (``r.complete`` False) likewise, marked as partial
    (module notes)."""
    from ..output import check_output_dir, staged_output, write_manifest, writing
    from ..plots import plot_spectrum, plot_time_trace

    out_dir = Path(out_dir).absolute()
    t0 = time.perf_counter()
    check_output_dir(out_dir)
    s = summary(r, scene)
    plots, mk = [], marks(r)
    with staged_output(out_dir) as work:
        with writing(out_dir, work, "simulation results"):
            write_h5(r, work / h5_name(r), scene, s)
            (work / "summary.json").write_text(strict_json.dumps(s, indent=1), encoding="utf-8")
            for i, (k, y) in enumerate(r.outputs.items()):
                unit = r.units[k]
                p = f"trace_{i + 1:02d}.png"
                plot_time_trace(r.time_s, y, work / p, title=f"{scene}: {k}", ylabel=f"{k} [{unit}]")
                plots.append((f"{k}: time history", p))
                f, a = spectrum(r.time_s, y)
                if len(f):
                    p = f"spectrum_{i + 1:02d}.png"
                    plot_spectrum(f, a, work / p, title=f"{scene}: {k}", ylabel=unit, marks=mk)
                    plots.append((f"{k}: spectrum", p))
            (work / "index.html").write_text(_index(r, scene, s, plots), encoding="utf-8")
            files = [h5_name(r), "summary.json", *(p for _, p in plots), "index.html"]
            info = dict(tool="flexgear simulate", scene=scene, scene_source=str(scene_source), files=files,
                        complete=r.complete, outputs=list(r.outputs), time_s=round(time.perf_counter() - t0, 4),
                        python=sys.version.split()[0])
            write_manifest(work, info)
    return info
