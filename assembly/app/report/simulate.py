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

With ``--out`` (and no ``--json``) the histories stream: the run writes
``partial_simulation.h5`` in the work folder as it goes (:class:`assembly.dynamics.history.H5History`),
renamed ``simulation.h5`` when it completes, and the summary's statistics are accumulated on
the fly. The pictures are made from the file read back in blocks (never the whole history):
a trace draws the min and max of each of :data:`PLOT_COLUMNS` columns (:func:`envelope`;
the file keeps every step), a spectrum longer than :data:`SEGMENT` samples is averaged over
segments (:func:`spectrum_blocks`), and a spectrum of more than 2 x :data:`PLOT_COLUMNS` lines
draws its min and max per column too. A run killed (SIGKILL) leaves its history, marked
incomplete, in the work folder ``.DIR.partial-<hex>/partial_simulation.h5`` beside DIR
until the next run into DIR clears it (:mod:`assembly.app.output`).
"""
from __future__ import annotations

import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

from ...dynamics.history import read_blocks
from ...dynamics.simulate import SimulationResult
from .. import strict_json
from .page import Section, esc, figure, files_list, grid, page, para, table

#: Mesh harmonics marked on the spectra.
MARKED_HARMONICS = 3
#: The history file of a complete run and of a run that stopped.
H5_COMPLETE, H5_PARTIAL = "simulation.h5", "partial_simulation.h5"
#: Columns of a time trace's picture: a longer history draws each column's min and max.
PLOT_COLUMNS = 2000
#: Samples of a spectrum's segment: a longer history's spectrum is the segments' average.
SEGMENT = 2 ** 17


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


def blocks(r: SimulationResult, name: str):
    """(t, y) blocks of output ``name``, in order: read back from ``r.history_file`` when
    the run streamed there, else the arrays as one block."""
    if r.history_file is not None:
        yield from read_blocks(r.history_file, name)
    else:
        yield r.time_s, r.outputs[name]


def envelope(parts, n: int, columns: int = PLOT_COLUMNS) -> tuple[np.ndarray, np.ndarray]:
    """What a trace draws of the ``n`` samples of the (t, y) blocks ``parts``: all of them
    when ``n <= 2 columns``, else per column (consecutive samples ``c n / columns`` to ``(c +
    1) n / columns``) its min and max at its first time, in order: every extreme is drawn."""
    if n <= 2 * columns:
        got = list(parts)
        return (np.concatenate([t for t, _ in got]) if got else np.zeros(0),
                np.concatenate([y for _, y in got]) if got else np.zeros(0))
    lo, hi, tc = np.full(columns, np.inf), np.full(columns, -np.inf), np.full(columns, np.nan)
    start = 0
    for t, y in parts:
        k = len(y)
        if not k:
            continue
        col = (np.arange(start, start + k) * columns) // n
        cuts = np.flatnonzero(np.diff(col)) + 1
        first = np.concatenate([[0], cuts])
        c = col[first]
        lo[c] = np.minimum(lo[c], np.minimum.reduceat(y, first))
        hi[c] = np.maximum(hi[c], np.maximum.reduceat(y, first))
        tc[c] = np.fmin(tc[c], t[first])
        start += k
    seen = np.isfinite(tc)
    return np.repeat(tc[seen], 2), np.column_stack([lo[seen], hi[seen]]).ravel()


def spectrum_blocks(parts, n: int, mean: float, segment: int = SEGMENT) -> tuple[np.ndarray, np.ndarray]:
    """:func:`spectrum` of the ``n`` samples of the (t, y) blocks ``parts`` (``mean``: the
    history's): the whole history's when ``n <= segment``, else the average of the power of
    consecutive segments of ``segment`` samples (Welch, Hann window, no overlap; a remainder
    shorter than a segment left out), so that a sinusoid of amplitude A still shows A."""
    if n <= segment:
        got = list(parts)
        if not got:
            return np.zeros(0), np.zeros(0)
        return spectrum(np.concatenate([t for t, _ in got]), np.concatenate([y for _, y in got]))
    w = np.hanning(segment)
    power, count, buf, fill, dt = np.zeros(segment // 2 + 1), 0, np.empty(segment), 0, None
    for t, y in parts:
        if dt is None and len(t) > 1:
            dt = float(t[1] - t[0])
        a = 0
        while a < len(y):
            k = min(segment - fill, len(y) - a)
            buf[fill:fill + k] = y[a:a + k]
            fill, a = fill + k, a + k
            if fill == segment:
                power += np.abs(np.fft.rfft((buf - mean) * w)) ** 2
                count, fill = count + 1, 0
    return np.fft.rfftfreq(segment, dt), 2.0 * np.sqrt(power / count) / w.sum()


def release_memory() -> None:
    """Give the memory freed so far back to the system (glibc's ``malloc_trim``; nothing
    elsewhere): the pictures' arrays and renderers, freed after each output, otherwise stay in
    a fragmented heap and the process's peak grows by picture, by some 100-250 MB over 13
    outputs of a long run (measured), whatever the run's length."""
    import ctypes
    import ctypes.util
    import gc
    gc.collect()
    name = ctypes.util.find_library("c")
    try:
        trim = getattr(ctypes.CDLL(name), "malloc_trim", None) if name else None
    except OSError:
        trim = None
    if trim is not None:
        trim(0)


def marks(r: SimulationResult) -> list:
    """(Hz, label, kind) to mark on the spectra, at the starting speed: the mesh harmonics and
    sidebands, each distinct shaft speed's 1x (its first body named), and the rotor's 1P and 3P
    when the run's reference is a rotor."""
    out = []
    for src, fm in r.mesh_frequencies_hz.items():
        out += [(h * fm, f"{src} x{h}", "mesh") for h in range(1, MARKED_HARMONICS + 1)]
        side = r.sidebands_hz.get(src, 0.0)
        out += [(fm + k * side, "", "sideband") for k in (-2, -1, 1, 2) if side > 0]
    seen = []
    for body, f in r.shaft_speeds_hz.items():
        f = abs(f)
        if f > 0 and all(abs(f - g) > 1e-9 * f for g in seen):
            seen.append(f)
            out.append((f, f"{body} 1x", "shaft"))
    ref = r.info.get("reference")
    if ref is not None and abs(r.shaft_speeds_hz.get(ref, 0.0)) > 0:
        f = abs(r.shaft_speeds_hz[ref])
        out += [(k * f, f"{k}P", "rotor") for k in (1, 3)]
    return out


def windowed(parts, t0: float, t1: float):
    """The (t, y) blocks ``parts`` cut to ``t0 <= t <= t1``."""
    for t, y in parts:
        keep = (t >= t0) & (t <= t1)
        if keep.any():
            yield t[keep], y[keep]


#: A short-time spectrum is drawn of a window of at most this many samples (read whole).
SPECTROGRAM_MAX = 4_000_000


def short_time_spectrum(parts, n: int):
    """(segment centre times, Hz, amplitude (n_f, n_t)) of the (t, y) blocks ``parts`` of ``n``
    samples: Hann windows of about n/64 samples (at least 256), half overlap, mean removed;
    None above :data:`SPECTROGRAM_MAX` samples or below four segments."""
    from scipy.signal import spectrogram
    if n > SPECTROGRAM_MAX:
        return None
    got = list(parts)
    if not got:
        return None
    t = np.concatenate([a for a, _ in got])
    y = np.concatenate([b for _, b in got])
    seg = max(256, 1 << int(np.log2(max(len(y) // 64, 1))))
    if len(y) < 4 * seg:
        return None
    f, tc, S = spectrogram(y - y.mean(), fs=1.0 / float(t[1] - t[0]), window="hann", nperseg=seg, noverlap=seg // 2,
                           scaling="spectrum", mode="magnitude")
    return t[0] + tc, f, S


def summary(r: SimulationResult, scene: str) -> dict:
    """Per output its mean, RMS, min, max and peak |value| with its time (the statistics the
    run accumulated, :class:`assembly.dynamics.history.Statistics`); the meshes' contact
    losses; the life tables when the run has them."""
    rows = {k: {"unit": v["unit"], **{s: float(v[s]) for s in ("mean", "rms", "min", "max", "peak", "peak_time_s")}}
            for k, v in r.statistics.items()}
    return {"scene": scene, "complete": r.complete, "stopped": None if r.complete else r.info.get("stopped"),
            "t_end_s": float(r.t_last_s), "steps": r.steps,
            "outputs": rows, "meshes": r.meshes, "mesh_frequencies_hz": r.mesh_frequencies_hz,
            "warnings": r.warnings, "info": {k: v for k, v in r.info.items() if not k.startswith("_")},
            **({"life": r.life.as_dict()} if r.life is not None else {})}


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
    lines += [f"  turbine: {k} {v if v in ('scene', 'default') else 'from ' + v}"
              for k, v in r.info.get("turbine_sources", {}).items()]
    if "controller_calls" in r.info:
        lines.append(f"  controller: {r.info['controller_calls']} calls, every {r.info['controller_period_s']:g} s")
    lines += life_lines(r.life)
    lines += [f"  warning: {w}" for w in r.warnings]
    return "\n".join(lines)


def life_lines(life) -> list:
    """The summary's lines of a run's life tables (none without them)."""
    if life is None:
        return []

    def num(v, fmt=".4g"):
        return "-" if v is None else format(v, fmt)
    m = max(life.exponents)
    out = [f"  life ({life.window[0]:g} .. {life.window[1]:g} s): {k} DEL m={m:g} {num(o.dels[m])} {o.unit}"
           for k, o in life.outputs.items()]
    out += [f"  bearing {b.bearing}: P {num(b.equivalent_load_n)} N, L10 {num(b.l10_hours)} h"
            + (f" ({b.note})" if b.note else "") for b in life.bearings]
    out += [f"  gear {g.gear} ({g.mesh}): T_eq {num(g.torque_eq)} N m, damage {num(g.damage)}, life "
            f"{num(g.life_hours)} h" + (f" ({g.note})" if g.note else "") for g in life.gears]
    return out


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


def finish_h5(path, scene: str, facts: dict) -> Path:
    """A streamed history file (:class:`assembly.dynamics.history.H5History`, closed) given
    the attributes :func:`write_h5` writes: ``scene`` and ``summary`` (``facts``)."""
    import h5py
    with h5py.File(path, "r+") as f:
        f.attrs["scene"] = scene
        f.attrs["summary"] = strict_json.dumps(facts)
    return Path(path)


def _index(r: SimulationResult, scene: str, s: dict, plots: list, more=(), pages=()) -> str:
    """The page; ``more``: sections of the same run (a run-up's orders, the life tables)."""
    rows = [[k, v["unit"], *(f"{v[c]:.6g}" for c in ("mean", "rms", "min", "max", "peak_time_s"))]
            for k, v in s["outputs"].items()]
    sections = [Section("Outputs", table(["output", "unit", "mean", "RMS", "min", "max", "peak at [s]"], rows))]
    if r.meshes:
        sections.append(Section("Nonlinear meshes", table(
            ["mesh", "backlash [m]", "harmonics", "contact losses"],
            [[m["name"], "-" if m["backlash_m"] is None else m["backlash_m"], str(m["harmonics"]), m["contact_losses"]]
             for m in r.meshes]), "Meshes"))
    if "turbine_sources" in r.info:
        sections.append(Section("The turbine", para(f"Controller: {r.info['controller_calls']} calls, every "
                                                    f"{r.info['controller_period_s']:g} s.")
                                + table(["value", "from"], [[k, str(v)] for k, v in r.info["turbine_sources"].items()]),
                                "Turbine"))
    if r.warnings:
        sections.append(Section("Warnings", "<ul>" + "".join(f"<li>{esc(w)}</li>" for w in r.warnings) + "</ul>"))
    sections += list(more)
    sections.append(Section("Plots", para("Spectra: mesh harmonics (red) and sidebands (green dotted) at the "
                                          "starting speed.", "meta") + grid(figure(p, n) for n, p in plots)))
    h5, partial = h5_name(r), "" if r.complete else " (partial)"
    sections.append(Section("Files", files_list([
        (h5, "the histories (HDF5: /time_s, /outputs/NAME with units)" + partial),
        ("summary.json", "the statistics and run facts (JSON)")])))
    stopped = "" if r.complete else (f'<p class="stopped"><strong>Partial result: the run stopped</strong> at t = '
                                     f"{s['t_end_s']:g} s of {r.info['t_end_s']:g} s: {esc(str(s['stopped']))}</p>")
    wall = f", {r.info['wall_s']:.3g} s wall" if "wall_s" in r.info else ""
    meta = [f"{s['steps']} steps of {r.info['dt_s']:g} s to {s['t_end_s']:g} s, {r.info['scheme']}, "
            f"{r.info['dofs']} DOFs{wall}"]
    return page(f"{scene}: time-domain simulation{partial}", sections, command="flexgear simulate", scene=scene,
                meta=meta, lead=stopped, pages=pages)


def sim_to_dir(r: SimulationResult, out_dir, scene: str, scene_source: str = "", window=None, extra=None) -> dict:
    """Write simulation.h5, the traces and spectra, summary.json and index.html atomically;
    the partial result of a stopped run (``r.complete`` False) likewise, marked as partial
    (module notes)."""
    from ..output import check_output_dir, staged_output, writing

    out_dir = Path(out_dir).absolute()
    check_output_dir(out_dir)
    with staged_output(out_dir) as work:
        with writing(out_dir, work, "simulation results"):
            return sim_files(r, work, scene, scene_source, window, extra)


def sim_files(r: SimulationResult, work, scene: str, scene_source: str = "", window=None, extra=None) -> dict:
    """The files of :func:`sim_to_dir` written into the work folder ``work``: the history
    file from the arrays, or the streamed one (``r.history_file``: moved there, named for a
    complete or partial run, when it is in ``work``, else copied); the pictures from it read
    back in blocks (module notes). ``window`` (t0, t1): the spectra's part of the record
    (default all of it). ``extra(work)`` -> (file names, sections of index.html,
    :class:`~assembly.app.report.page.Section`): more files of the same run (a run-up's orders);
    the life tables' (:mod:`assembly.app.report.life`) when the run has them. Returns the
    manifest."""
    import shutil

    from ..output import write_manifest
    from ..plots import plot_spectrogram, plot_spectrum, plot_time_trace
    from .life import life_files, life_section
    from .runup import PAGES

    work, t0 = Path(work), time.perf_counter()
    s = summary(r, scene)
    plots, mk = [], marks(r)
    h5 = work / h5_name(r)
    if r.history_file is None:
        write_h5(r, h5, scene, s)
    else:
        src = Path(r.history_file)
        if src.absolute().parent == work.absolute():
            src.rename(h5)
        else:
            shutil.copyfile(src, h5)
        finish_h5(h5, scene, s)
        r = dataclasses.replace(r, history_file=str(h5))
    (work / "summary.json").write_text(strict_json.dumps(s, indent=1), encoding="utf-8")
    n = r.steps + 1
    pictured = {k: row for k, row in s["outputs"].items() if k not in r.info.get("life_channels", ())}
    for i, (k, row) in enumerate(pictured.items()):      # the channels only the life tables read: no pictures
        unit = row["unit"]
        p = f"trace_{i + 1:02d}.png"
        plot_time_trace(*envelope(blocks(r, k), n), work / p, title=f"{scene}: {k}", ylabel=f"{k} [{unit}]")
        plots.append((f"{k}: time history", p))
        t0, t1 = window if window is not None else (0.0, np.inf)
        count, total = 0, 0.0
        for _, y in windowed(blocks(r, k), t0, t1):       # the window's samples and mean, a first pass
            count, total = count + len(y), total + float(np.sum(y))
        span = "" if window is None else f", {t0:g} .. {t1:g} s"
        f, a = spectrum_blocks(windowed(blocks(r, k), t0, t1), count, total / max(count, 1))
        if len(f):
            p = f"spectrum_{i + 1:02d}.png"
            plot_spectrum(*envelope([(f, a)], len(f)), work / p, title=f"{scene}: {k}{span}", ylabel=unit, marks=mk)
            plots.append((f"{k}: spectrum{span}", p))
            p = f"spectrum_low_{i + 1:02d}.png"
            plot_spectrum(f, a, work / p, title=f"{scene}: {k}{span}, low frequencies", ylabel=unit, marks=mk,
                          log_frequency=True)
            plots.append((f"{k}: spectrum, logarithmic frequency{span}", p))
        st = short_time_spectrum(windowed(blocks(r, k), t0, t1), count)
        if st is not None:
            p = f"spectrogram_{i + 1:02d}.png"
            top = max((fm for fm, _, kind in mk if kind == "mesh"), default=None)
            plot_spectrogram(*st, work / p, title=f"{scene}\n{k}{span}: short-time spectrum", ylabel=unit,
                             f_max=None if top is None else 1.1 * top * r.info.get("speed_scale", 1.0))
            plots.append((f"{k}: short-time spectrum{span}", p))
        release_memory()
    more_files, more = extra(work) if extra is not None else ([], [])
    if r.life is not None:                                  # [simulation.life], or a run-up's ramp
        more_files, more = [*more_files, *life_files(r.life, work)], [*more, life_section(r.life)]
    pages = PAGES if "orders.html" in more_files else ()
    (work / "index.html").write_text(_index(r, scene, s, plots, more, pages), encoding="utf-8")
    files = [h5_name(r), "summary.json", *(p for _, p in plots), *more_files, "index.html"]
    info = dict(tool="flexgear simulate", scene=scene, scene_source=str(scene_source), files=files,
                complete=r.complete, outputs=list(s["outputs"]), time_s=round(time.perf_counter() - t0, 4),
                python=sys.version.split()[0])
    write_manifest(work, info)
    return info
