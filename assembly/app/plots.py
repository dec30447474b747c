"""Matplotlib plots (Agg backend, PNG): frequencies per fidelity and parameter sweeps.

matplotlib is imported lazily inside each function with the non-interactive Agg backend.
All frequencies in Hz.
"""
from __future__ import annotations

import contextlib
import logging
from pathlib import Path

import numpy as np

log = logging.getLogger(__name__)

DPI = 120


def _plt():
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    plt.rcParams.update({"font.size": 10, "axes.grid": True, "grid.alpha": 0.3,
                         "svg.hashsalt": "flexgear", "path.simplify": False})
    return plt


@contextlib.contextmanager
def plot_figure(path, figsize):
    """(fig, ax) of a new figure, laid out and written to ``path`` (PNG) when the block
    ends without an error; always closed."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=figsize, dpi=DPI)
    try:
        yield fig, ax
        fig.tight_layout()
        fig.savefig(path, dpi=DPI, metadata={"Software": None})
    finally:
        plt.close(fig)


def _elastic(freqs, n_rigid: int) -> np.ndarray:
    return np.asarray(freqs, float)[n_rigid:]


def plot_fidelity_frequencies(columns, path, title: str = "", pairs=None, max_hz: float | None = None,
                              band_hz: float | None = None) -> Path:
    """Frequencies of several fidelities side by side (one column each, a short bar per mode).

    ``columns``: list of ``(label, frequencies_hz, n_rigid)``; rigid-body (0 Hz) modes are
    left out. ``pairs``: optional list of ``(col_a, col_b, [(i_a, i_b, mac), ...])`` drawn as
    lines joining paired modes (darker = higher MAC). ``max_hz`` clips the frequency axis
    (modes above it are left out and counted in a note); ``band_hz``: the band of interest,
    drawn as a dashed line.
    """
    with plot_figure(path, (2.2 + 2.0 * len(columns), 6.0)) as (fig, ax):
        tops, n_above = [], 0
        for k, (label, f, nr) in enumerate(columns):
            fe = _elastic(f, nr)
            if max_hz is not None:
                n_above = max(n_above, int((fe > max_hz).sum()))
                fe = fe[fe <= max_hz]
            ax.hlines(fe, k - 0.28, k + 0.28, color=f"C{k}", lw=2)
            tops.append(fe.max() if len(fe) else 0.0)
            # Multiplicity labels for repeated frequencies.
            vals, counts = np.unique(np.round(fe, 6), return_counts=True)
            for v, c in zip(vals, counts):
                if c > 1:
                    ax.text(k + 0.31, v, f"x{c}", va="center", fontsize=7, color=f"C{k}")
        for ca, cb, plist in (pairs or []):
            fa = np.asarray(columns[ca][1], float)
            fb = np.asarray(columns[cb][1], float)
            na, nb = columns[ca][2], columns[cb][2]
            for ia, ib, mac in plist:
                if ia < na or ib < nb:
                    continue
                if max_hz is not None and (fa[ia] > max_hz or fb[ib] > max_hz):
                    continue
                xa, xb = (ca + 0.28, cb - 0.28) if ca < cb else (ca - 0.28, cb + 0.28)
                ax.plot([xa, xb], [fa[ia], fb[ib]], color="k", lw=0.8, alpha=0.15 + 0.75 * mac,
                        ls="-" if mac >= 0.8 else "--")
        ax.set_xticks(range(len(columns)), [c[0] for c in columns])
        ax.set_xlim(-0.6, len(columns) - 0.4)
        ax.set_ylim(0, max_hz if max_hz is not None else 1.05 * max(tops + [1.0]))
        if band_hz is not None:
            ax.axhline(band_hz, color="0.35", ls="--", lw=1.0)
            ax.text(-0.55, band_hz, f"band {band_hz:.0f} Hz", va="bottom", fontsize=7, color="0.25")
        if n_above:
            ax.text(0.01, -0.11, f"{n_above} modes above {max_hz:.0f} Hz not shown (outside the band)",
                    transform=ax.transAxes, fontsize=7, va="top")
        ax.set_ylabel("frequency [Hz]")
        ax.grid(axis="x", visible=False)
        ax.set_title(title or "natural frequencies per fidelity", fontsize=10)
        if pairs:
            ax.text(0.01, -0.08, "lines: modes paired by MAC (solid MAC >= 0.8, dashed below)",
                    transform=ax.transAxes, fontsize=7, va="top")
    return Path(path)


def plot_sweep(x, F, path, xlabel: str, title: str = "", logx: bool = False, n_rigid=None,
               max_modes: int | None = None, logy: bool = False) -> Path:
    """Natural frequencies (Hz) against a swept parameter, one line per mode number.

    ``F``: (len(x), n_modes) ascending frequencies per parameter value. ``n_rigid``: per-value
    number of rigid-body modes (left out). ``max_modes`` limits the elastic modes drawn.
    """
    x = np.asarray(x, float)
    F = np.asarray(F, float)
    nr = np.zeros(len(x), int) if n_rigid is None else np.asarray(n_rigid, int)
    start = int(nr.max(initial=0))
    stop = F.shape[1] if max_modes is None else min(F.shape[1], start + max_modes)
    with plot_figure(path, (8.0, 5.5)) as (fig, ax):
        for j in range(start, stop):
            ax.plot(x, F[:, j], "-", marker="o", ms=2.5, lw=1.2, color=f"C{(j - start) % 10}")
        if logx:
            ax.set_xscale("log")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("natural frequency [Hz]")
        ax.set_title(title, fontsize=10)
        ax.set_xlim(x.min(), x.max())
        if logy:
            ax.set_yscale("log")
            ax.grid(True, which="minor", alpha=0.12)
        else:
            ax.set_ylim(bottom=0)
        ax.text(0.01, 0.99, f"elastic modes {start + 1}-{stop} (mode number by ascending frequency)",
                transform=ax.transAxes, fontsize=7, va="top")
    return Path(path)


#: Campbell diagram: the ranked crossings numbered on the plot (as in crossings.csv), and the
#: smallest gap between two order labels at the right edge (fraction of the axis height).
CAMPBELL_NUMBERED = 10
LABEL_GAP = 0.022


def spread_labels(y, gap: float) -> np.ndarray:
    """Label heights ``y`` (axis fractions) moved apart to at least ``gap`` from each other,
    each as little as it can: upward in order, then, if the column ran over the top, the top
    ones back down (below 0 only when the labels cannot fit at all)."""
    y = np.asarray(y, float)
    order = np.argsort(y, kind="stable")
    out = y[order].copy()
    for k in range(1, len(out)):
        out[k] = max(out[k], out[k - 1] + gap)
    if len(out) and out[-1] > 1.0:   # ran over the top: the top ones step back down
        out[-1] = 1.0
        for k in range(len(out) - 2, -1, -1):
            out[k] = min(out[k], out[k + 1] - gap)
    res = np.empty_like(out)
    res[order] = out
    return res


def plot_campbell(speeds, F, orders, crossings, path, title: str = "", rated_rpm: float | None = None,
                  speed_label: str = "reference speed [rpm]") -> Path:
    """Campbell diagram: natural frequencies (Hz; ``F`` is (len(speeds), n_lines), grey) and
    order lines f = slope x n (``orders``: (label, slope in Hz/rpm), coloured, labelled at
    their end, the labels at the right edge spread apart) against speed (rpm);
    ``crossings``: (speed, frequency, drivable[, share, rank]) -- a drivable crossing is a
    filled circle whose area grows with the exciter's share of the mode (the ranking of
    :meth:`assembly.dynamics.campbell.Campbell.ranked`), the first :data:`CAMPBELL_NUMBERED`
    numbered by their rank; one the exciter cannot drive is a small hollow circle.
    ``rated_rpm``: a dashed vertical line."""
    n = np.asarray(speeds, float)
    F = np.asarray(F, float)
    top = max([s * n[-1] for _, s in orders] + [1.0]) * 1.05
    with plot_figure(path, (9.0, 6.5)) as (fig, ax):
        for j in range(F.shape[1]):
            if F[:, j].min() <= top:
                ax.plot(n, F[:, j], "-", color="0.6", lw=0.6)
        right = []
        palette = _plt().get_cmap("tab20").colors   # 20 colours, then dashed: each label names one line
        for k, (label, slope) in enumerate(orders):
            c = palette[(2 * k) % 20 + (2 * k) // 20 % 2]   # dark shades first, then the light ones
            end = min(n[-1], top / slope) if slope > 0 else n[-1]
            ax.plot([n[0], end], [slope * n[0], slope * end], "-" if k < 20 else "--", color=c, lw=1.3)
            if end < n[-1]:
                ax.text(end, slope * end, f" {label}", color=c, fontsize=7, va="bottom", ha="right")
            else:
                right.append((label, slope * end / top, c))
        for (label, _, c), y in zip(right, spread_labels([y for _, y, _ in right], LABEL_GAP)):
            ax.text(1.0, y, f" {label}", color=c, fontsize=7, va="center", ha="left", transform=ax.transAxes)
        rows = [(*x, 1.0, None)[:5] for x in crossings]   # (speed, f, drivable, share, rank)
        out = np.array([(x, f) for x, f, ok, *_ in rows if not ok]).reshape(-1, 2)
        if len(out):
            ax.plot(out[:, 0], out[:, 1], "o", ms=3.0, mec="0.45", mew=0.6, mfc="none")
        able = [(x, f, sh, r) for x, f, ok, sh, r in rows if ok]
        if able:
            share = np.clip(np.array([a[2] for a in able], float), 0.0, 1.0)
            ax.scatter([a[0] for a in able], [a[1] for a in able], s=12 + 110 * share, c="k", zorder=3,
                       edgecolors="white", linewidths=0.5)
            for x, f, _, r in able:
                if r is not None and r <= CAMPBELL_NUMBERED:
                    ax.annotate(str(r), (x, f), xytext=(4, 4), textcoords="offset points", fontsize=8,
                                color="#b00000", fontweight="bold", zorder=4)
        if rated_rpm is not None:
            ax.axvline(rated_rpm, color="0.2", ls="--", lw=1.0)
            ax.text(rated_rpm, top * 0.98, f" rated {rated_rpm:g} rpm", fontsize=7, va="top")
        ax.set_xlim(n[0], n[-1] if n[-1] > n[0] else n[0] + 1.0)
        ax.set_ylim(0, top)
        ax.set_xlabel(speed_label)
        ax.set_ylabel("frequency [Hz]")
        ax.set_title(title or "Campbell diagram", fontsize=10)
        ax.text(0.0, -0.08, "grey: natural frequencies; filled: crossings the order can drive, area by the "
                f"exciter's share of the mode,\nthe first {CAMPBELL_NUMBERED} numbered by rank (crossings.csv); "
                "hollow: ruled out (mesh phasing, or no share of the mode)", transform=ax.transAxes, fontsize=7,
                va="top")
    return Path(path)


def plot_bode(frequency_hz, H, path, title: str = "", ylabel: str = "", natural_hz=(), logx: bool = False) -> Path:
    """Bode plot of one frequency response ``H`` (complex, per Hz of ``frequency_hz``), or
    of several in one figure (``H`` a dict {label: response}, with a legend): magnitude (log
    scale) above, phase (deg) below, the natural frequencies ``natural_hz`` inside the range
    marked by dotted lines."""
    plt = _plt()
    f = np.asarray(frequency_hz, float)
    curves = list(H.items()) if isinstance(H, dict) else [("", H)]
    fig, (am, ap) = plt.subplots(2, 1, figsize=(8.0, 6.0), dpi=DPI, sharex=True)
    try:
        for j, (label, h) in enumerate(curves):
            h = np.asarray(h, complex)
            mag = np.abs(h)
            am.plot(f, np.where(mag > 0, mag, np.nan), lw=1.1, color=f"C{j}", label=label or None)
            ap.plot(f, np.degrees(np.angle(h)), lw=1.1, color=f"C{j if len(curves) > 1 else 1}")
        if len(curves) > 1:
            am.legend(fontsize=7, loc="best")
        am.set_yscale("log")
        am.set_ylabel(f"|H| [{ylabel}]" if ylabel else "|H|")
        am.set_title(title, fontsize=10)
        ap.set_ylabel("phase [deg]")
        ap.set_ylim(-180, 180)
        ap.set_yticks([-180, -90, 0, 90, 180])
        ap.set_xlabel("frequency [Hz]")
        for fn in np.asarray(natural_hz, float):
            if f.min() <= fn <= f.max():
                for ax in (am, ap):
                    ax.axvline(fn, color="0.5", lw=0.6, ls=":")
        if logx:
            ap.set_xscale("log")
        ap.set_xlim(f.min(), f.max())
        fig.tight_layout()
        fig.savefig(path, dpi=DPI, metadata={"Software": None})
    finally:
        plt.close(fig)
    return Path(path)


def plot_time_trace(time_s, y, path, title: str = "", ylabel: str = "") -> Path:
    """One time history ``y`` against ``time_s`` (s)."""
    with plot_figure(path, (8.0, 3.4)) as (fig, ax):
        ax.plot(np.asarray(time_s, float), np.asarray(y, float), lw=0.8)
        ax.set_xlabel("time [s]")
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=10)
        ax.grid(True, lw=0.3)
    return Path(path)


#: How each kind of spectrum mark is drawn, and its legend entry.
MARK_STYLES = {"mesh": (dict(color="C3", lw=0.7, ls="-"), "mesh harmonics"),
               "sideband": (dict(color="C2", lw=0.6, ls=":"), "sidebands"),
               "shaft": (dict(color="C0", lw=0.6, ls="--"), "shaft 1x"),
               "rotor": (dict(color="C4", lw=0.7, ls="-."), "rotor 1P, 3P")}


def plot_spectrum(frequency_hz, amplitude, path, title: str = "", ylabel: str = "", marks=(),
                  log_frequency: bool = False) -> Path:
    """Amplitude spectrum (log scale) with vertical ``marks``: (Hz, label, kind) of the kinds of
    :data:`MARK_STYLES` (mesh harmonics labelled); marks outside the axis are left out.
    ``log_frequency``: a logarithmic frequency axis from the first line up (the low-frequency
    view)."""
    f, a = np.asarray(frequency_hz, float), np.asarray(amplitude, float)
    with plot_figure(path, (8.0, 3.8)) as (fig, ax):
        ax.plot(f, np.where(a > 0, a, np.nan), lw=0.8)
        ax.set_yscale("log")
        shown = [fm for fm, _, k in marks if fm > 0 and k in ("mesh", "sideband")]
        top = min(f.max(), 1.15 * max(shown)) if len(f) and shown else (f.max() if len(f) else 1.0)
        low = f[1] if log_frequency and len(f) > 1 else 0.0
        labelled = set()
        for fm, label, kind in marks:
            if low < fm <= top:
                style, name = MARK_STYLES[kind]
                ax.axvline(fm, label=None if kind in labelled else name, **style)
                labelled.add(kind)
                if kind in ("mesh", "rotor") and label:
                    ax.annotate(label, (fm, 1.0), xycoords=("data", "axes fraction"), fontsize=6,
                                rotation=90, va="top", ha="right")
        if labelled:
            ax.legend(fontsize=7, loc="upper right")
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel(f"amplitude [{ylabel}]" if ylabel else "amplitude")
        ax.set_title(title, fontsize=10)
        if log_frequency and low > 0:
            ax.set_xscale("log")
            ax.set_xlim(low, top)
        else:
            ax.set_xlim(0, top)
    return Path(path)


def plot_spectrogram(time_s, frequency_hz, amplitude, path, title: str = "", ylabel: str = "",
                     f_max: float | None = None) -> Path:
    """A short-time spectrum: ``amplitude`` (n_f, n_t) over ``frequency_hz`` and the segments'
    centre times ``time_s``, in decibels of its largest value (60 dB shown)."""
    f, t, A = np.asarray(frequency_hz, float), np.asarray(time_s, float), np.asarray(amplitude, float)
    top = f_max if f_max is not None else f.max()
    keep = f <= top
    ref = A[keep].max(initial=0.0)
    with plot_figure(path, (8.0, 4.2)) as (fig, ax):
        if ref > 0:
            db = 20.0 * np.log10(np.maximum(A[keep], ref * 1e-3) / ref)
            m = ax.pcolormesh(t, f[keep], db, shading="nearest", vmin=-60.0, vmax=0.0, cmap="viridis")
            fig.colorbar(m, ax=ax, label=f"dB re {ref:.3g} {ylabel}".strip())
        ax.set_xlabel("time [s]")
        ax.set_ylabel("frequency [Hz]")
        ax.set_title(title, fontsize=9)
    return Path(path)


def plot_spectra_pair(frequency_hz, first, second, path, labels=("coupled", "one-way"), title: str = "",
                      ylabel: str = "", modes_hz=(), f_max: float | None = None) -> Path:
    """Two spectral densities over one frequency axis (log scale), the model's natural
    frequencies ``modes_hz`` as thin grey lines."""
    f = np.asarray(frequency_hz, float)
    top = f_max if f_max is not None else (f.max() if len(f) else 1.0)
    with plot_figure(path, (8.0, 3.8)) as (fig, ax):
        for a, label, style in ((first, labels[0], dict(lw=1.0)), (second, labels[1], dict(lw=0.9, ls="--"))):
            a = np.asarray(a, float)
            ax.plot(f, np.where(a > 0, a, np.nan), label=label, **style)
        for i, fm in enumerate(m for m in modes_hz if 0 < m <= top):
            ax.axvline(fm, color="0.6", lw=0.5, ls=":", label="natural frequencies" if i == 0 else None)
        ax.set_yscale("log")
        ax.set_xlim(0, top)
        shown = np.concatenate([np.asarray(a, float)[(f > 0) & (f <= top)] for a in (first, second)])
        shown = shown[shown > 0]
        if len(shown):
            ax.set_ylim(0.5 * shown.min(), 2.0 * shown.max())
        ax.legend(fontsize=7, loc="upper right")
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel(f"spectral density [{ylabel}/sqrt(Hz)]" if ylabel else "spectral density")
        ax.set_title(title, fontsize=10)
    return Path(path)


def plot_response_campbell(speed_rpm, orders, amplitude, path, order_lines=(), natural_hz=(), title: str = "",
                           ylabel: str = "", f_max: float | None = None, columns: int = 800,
                           shaft: str = "") -> Path:
    """A run-up's response over speed and frequency: the order map ``amplitude`` (blocks x
    orders) at frequency = order x speed (dB of its largest value, 60 dB shown; orders pooled
    by their maximum into at most ``columns`` bands; the scale's top from order 1 up), the ``order_lines`` (label, order) as lines through the origin and the
    ``natural_hz`` as horizontal lines; ``shaft`` names whose speed it is."""
    order = np.argsort(np.asarray(speed_rpm, float), kind="stable")   # blocks by speed (a ringing drive wavers)
    n = np.asarray(speed_rpm, float)[order]
    o = np.asarray(orders, float)
    A = np.asarray(amplitude, float)[order]
    step = max(1, int(np.ceil(len(o) / columns)))
    cut = (len(o) // step) * step
    o_b = o[:cut].reshape(-1, step).mean(axis=1)
    A_b = A[:, :cut].reshape(len(n), -1, step).max(axis=2)
    # the colour scale from the tracked shaft's own order up: the quasi-static content near order 0
    # (the load's slow change over the run-up) would otherwise take its top and darken the rest
    shown = A_b[:, o_b >= 1.0]
    ref = shown.max(initial=0.0)
    f = o_b[None, :] * n[:, None] / 60.0
    top = f_max if f_max is not None else float(f.max())
    with plot_figure(path, (8.0, 4.6)) as (fig, ax):
        if ref > 0:
            db = 20.0 * np.log10(np.maximum(A_b, ref * 1e-3) / ref)
            m = ax.pcolormesh(np.repeat(n[:, None], len(o_b), axis=1), f, db, shading="gouraud", vmin=-60.0, vmax=0.0,
                              cmap="viridis")
            fig.colorbar(m, ax=ax, label=f"dB re {ref:.3g} {ylabel}".strip())
        x = np.array([n.min(), n.max()])
        for label, k in order_lines:
            ax.plot(x, k * x / 60.0, color="w", lw=0.6, ls="--")
            if k * x[1] / 60.0 <= top:
                ax.annotate(label, (x[1], k * x[1] / 60.0), fontsize=6, color="w", ha="right", va="bottom")
        for fn in natural_hz:
            if 0 < fn <= top:
                ax.axhline(fn, color="C3", lw=0.5, ls=":")
        ax.set_ylim(0, top)
        ax.set_xlim(x[0], x[1])
        ax.set_xlabel(f"speed of {shaft} [rpm]" if shaft else "speed [rpm]")
        ax.set_ylabel("frequency [Hz]")
        ax.set_title(title, fontsize=9)
    return Path(path)
