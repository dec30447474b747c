"""``flexgear frf SCENE --input I --output O``: frequency response output.

Computes the FRF (:func:`assembly.dynamics.frf.frequency_response`, every mode superposed)
and writes it: one JSON object (``--json``: magnitude and phase per output), or ``--out
DIR`` with ``frf.csv`` (real and imaginary part, magnitude, phase per output),
``frf.json``, one Bode plot per output (``bode_NN.png``, natural frequencies marked) and
``index.html``, atomically with the folder rules of ``flexgear run``
(:mod:`assembly.app.output`); otherwise a one-line summary per output. Frequencies in Hz,
responses per unit input (SI units in ``units``).
"""
from __future__ import annotations

import csv
import sys
import time
from pathlib import Path

import numpy as np

from ...dynamics.frf import FRF
from .. import strict_json
from .page import Section, figure, files_list, grid, note, page, para, table


def frequencies(fmin: float, fmax: float, points: int, log: bool) -> np.ndarray:
    """The frequency grid (Hz); ValueError naming the argument on bad values."""
    if not (np.isfinite(fmin) and fmin >= 0):
        raise ValueError(f"--fmin = {fmin}: must be a frequency >= 0 Hz")
    if not (np.isfinite(fmax) and fmax > fmin):
        raise ValueError(f"--fmax = {fmax}: must be finite and above --fmin = {fmin}")
    if points < 2:
        raise ValueError(f"--points = {points}: must be >= 2")
    if log and fmin <= 0:
        raise ValueError(f"--fmin = {fmin}: --log needs a frequency > 0 Hz")
    return np.geomspace(fmin, fmax, points) if log else np.linspace(fmin, fmax, points)


def frf_json(r: FRF, scene: str = "") -> dict:
    """The FRF as one JSON-ready object: magnitude and phase (deg) per output."""
    return {"scene": scene, "input": r.input, "method": r.method, "frequency_hz": r.frequency_hz.tolist(),
            "outputs": {k: {"magnitude": np.abs(h).tolist(), "phase_deg": np.degrees(np.angle(h)).tolist()}
                        for k, h in r.outputs.items()},
            "units": {"frequency": "Hz", **r.units}, "natural_hz": r.natural_hz.tolist(),
            "warnings": list(r.warnings)}


def write_csv(r: FRF, path) -> Path:
    """One row per frequency: Hz, then per output real, imaginary, magnitude, phase (deg)."""
    names = list(r.outputs)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["frequency_hz"] + [f"{n} {part} [{r.units[n]}]" if part != "phase" else f"{n} phase [deg]"
                                       for n in names for part in ("real", "imag", "magnitude", "phase")])
        for j, f in enumerate(r.frequency_hz):
            row = [f"{f:.9g}"]
            for n in names:
                h = r.outputs[n][j]
                row += [f"{h.real:.9g}", f"{h.imag:.9g}", f"{abs(h):.9g}", f"{np.degrees(np.angle(h)):.6g}"]
            w.writerow(row)
    return Path(path)


def peak(frequency_hz, h, band=None) -> tuple[float, float] | None:
    """(the largest magnitude of the response ``h``, the frequency in Hz it is at) over every
    sample, or over those of ``band`` (lo, hi in Hz, inclusive); None when the band holds no
    sample."""
    f = np.asarray(frequency_hz, float)
    idx = np.arange(len(f)) if band is None else np.flatnonzero((f >= band[0]) & (f <= band[1]))
    if not idx.size:
        return None
    j = int(idx[np.argmax(np.abs(h[idx]))])
    return float(abs(h[j])), float(f[j])


def peaks(r: FRF) -> list:
    """Per output (name, the largest magnitude, its frequency in Hz)."""
    return [(k, *peak(r.frequency_hz, h)) for k, h in r.outputs.items()]


def summary_text(r: FRF, scene: str) -> str:
    """Per output: the largest magnitude and where."""
    lines = [f"{scene}: FRF from {r.input}, {len(r.frequency_hz)} points "
             f"{r.frequency_hz[0]:g}-{r.frequency_hz[-1]:g} Hz ({r.method}, {r.time_s:.3g} s)"]
    for k, m, f in peaks(r):
        lines.append(f"  {k}: max |H| {m:.6g} {r.units[k]} at {f:.6g} Hz")
    lines += [f"  warning: {w}" for w in r.warnings]
    return "\n".join(lines)


def _index(r: FRF, scene: str, plots: list) -> str:
    rows = [[n, r.units[n], f"{m:.6g}", f"{f:.6g}"] for n, m, f in peaks(r)]
    lead = "".join(note(f"Warning: {w}") for w in r.warnings)
    sections = [
        Section("Largest response per output", table(["output", "unit", "max |H|", "at [Hz]"], rows), "Peaks"),
        Section("Bode plots", para("Dotted lines: undamped natural frequencies.", "meta")
                + grid(figure(p, f"{n} [{r.units[n]}]", alt=n) for n, p in plots), "Plots"),
        Section("Files", files_list([("frf.csv", "real and imaginary part, magnitude and phase per output and "
                                                 "frequency (CSV)"), ("frf.json", "magnitude and phase (JSON)")]))]
    meta = [f"{len(r.frequency_hz)} points, {r.frequency_hz[0]:g}-{r.frequency_hz[-1]:g} Hz, {r.method}; "
            f"input {r.input}, responses per unit input"]
    return page(f"{scene}: frequency response from {r.input}", sections, command="flexgear frf", scene=scene,
                meta=meta, lead=lead)


def frf_to_dir(r: FRF, out_dir, scene: str, scene_source: str = "", log: bool = False) -> dict:
    """Write frf.csv, frf.json, the Bode plots and index.html into ``out_dir`` atomically."""
    from ..output import check_output_dir, staged_output, write_manifest, writing
    from ..plots import plot_bode

    out_dir = Path(out_dir).absolute()
    t0 = time.perf_counter()
    check_output_dir(out_dir)
    plots = [(n, f"bode_{i + 1:02d}.png") for i, n in enumerate(r.outputs)]
    files = ["frf.csv", "frf.json", *(p for _, p in plots), "index.html"]
    with staged_output(out_dir) as work:
        with writing(out_dir, work, "frf results"):
            write_csv(r, work / "frf.csv")
            (work / "frf.json").write_text(strict_json.dumps(frf_json(r, scene), indent=1), encoding="utf-8")
            for n, p in plots:
                plot_bode(r.frequency_hz, r.outputs[n], work / p, title=f"{scene}: {r.input} -> {n}",
                          ylabel=r.units[n], natural_hz=r.natural_hz, logx=log)
            (work / "index.html").write_text(_index(r, scene, plots), encoding="utf-8")
            info = dict(tool="flexgear frf", scene=scene, scene_source=str(scene_source), files=files,
                        input=r.input, outputs=list(r.outputs), time_s=round(time.perf_counter() - t0, 4),
                        python=sys.version.split()[0])
            write_manifest(work, info)
    return info
