"""Plain-text and JSON views of modal results and fidelity comparisons (no plotting here)."""
from __future__ import annotations

import csv

import numpy as np

from ..classify import classify_modes
from ..energy import kinetic_by_body, strain_by_element
from ..flexible import FlexibleBodyModel
from ..modal import mechanisms


def modes_table(result, title: str = "") -> str:
    """Mode table: index, frequency (Hz), multiplicity, class, dominant bodies (% KE)."""
    infos = classify_modes(result)
    lines = []
    if title:
        lines.append(title)
    lines.append(f"{'mode':>4}  {'frequency [Hz]':>14}  {'mult':>4}  {'class':<13}  dominant bodies (kinetic energy)")
    for mi in infos:
        dom = ", ".join(f"{b} {100 * s:.0f}%" for b, s in mi.dominant_bodies)
        lines.append(f"{mi.index + 1:>4}  {mi.frequency_hz:>14.2f}  {mi.multiplicity:>4}  {mi.mode_class:<13}  {dom}")
    for k, text in enumerate(mechanisms(result)):
        lines.append(f"rigid-body mode {k + 1} (free motion): {text}")
    lines += flexible_lines(result.model)
    lines.append(f"{len(infos)} modes, {result.model.K.shape[0]} DOFs, max relative eigen-residual "
                 f"{result.max_residual:.1e}, solve {result.solve_time_s * 1e3:.1f} ms")
    return "\n".join(lines)


def flexible_lines(model) -> list:
    """One line per flexible body: FE DOFs, modes, residual vectors, reduced or cached."""
    lines = []
    for name, r in flexible_summary(model).items():
        how = (f"{r['fixed_interface_modes']} fixed-interface modes"
               + (f" below {r['cutoff_hz']:.0f} Hz" if r["cutoff_hz"] else "")
               + f" + {r['residual_vectors']} residual vectors" if r["reduced"] else "unreduced (full FE)")
        src = (" (from cache)" if r["from_cache"] else f" (reduced in {r['reduce_time_s']:.2f} s)") \
            if r["reduced"] else ""
        lines.append(f"flexible body {name}: {r['fe_dofs']} FE DOFs, {how}{src}")
    return lines


def flexible_summary(model) -> dict:
    """How each flexible body was modelled: FE DOFs, fixed-interface modes, residual
    vectors, cutoff (Hz), reduction time (s) and whether it came from the cache."""
    out = {}
    for name, bm in model.bodies.items():
        if not isinstance(bm, FlexibleBodyModel):
            continue
        info = bm.info
        out[name] = {"reduced": bm.reduced, "fe_dofs": info.get("n_full_dofs"),
                     "fixed_interface_modes": info.get("n_modes"),
                     "residual_vectors": info.get("n_residual_vectors", 0),
                     "cutoff_hz": info.get("cutoff_hz"), "reduce_time_s": info.get("reduce_time_s"),
                     "from_cache": bool(info.get("cache_hits"))}
    return out


def modes_json(result) -> dict:
    """JSON-ready dict; ``frequencies_hz`` lists every frequency ascending (0 Hz included)."""
    infos = classify_modes(result)
    m = result.model
    ke = kinetic_by_body(result)
    se = strain_by_element(result)
    bodies = list(m.bodies)
    elems = [e.name for e in m.elements]
    modes = []
    for mi in infos:
        i = mi.index
        modes.append({
            "index": i + 1,
            "frequency_hz": mi.frequency_hz,
            "multiplicity": mi.multiplicity,
            "class": mi.mode_class,
            "stage": mi.stage,
            "dominant_bodies": [b for b, _ in mi.dominant_bodies],
            "kinetic_energy_share": {b: float(ke[i, j]) for j, b in enumerate(bodies) if ke[i, j] > 1e-12},
            "strain_energy_share": {e: float(se[i, j]) for j, e in enumerate(elems) if se[i, j] > 1e-12},
            "shape": {b: {d: float(v) for d, v in zip(("ux", "uy", "uz", "rx", "ry", "rz"),
                                                      result.body_motion(i, b))} for b in bodies},
        })
    return {
        "scene": m.scene.name,
        "units": {"frequency": "Hz", "translation": "m", "rotation": "rad", "mass_normalised": "kg^-1/2"},
        "n_dofs": int(m.K.shape[0]),
        "dof_names": m.dof_names,
        "frequencies_hz": [float(f) for f in np.sort(result.frequencies_hz)],
        "n_rigid_body_modes": result.n_rigid,
        "rigid_body_modes": mechanisms(result),
        "max_relative_residual": result.max_residual,
        "solve_time_s": result.solve_time_s,
        "flexible_bodies": flexible_summary(m),
        "modes": modes,
    }


def comparison_table(c) -> str:
    """Text table of a :class:`assembly.compare.Comparison`: frequencies (Hz) per fidelity,
    shifts (%), MAC, class and dominant body of each mode."""
    cols = [k for k in ("torsional", "rigid", "flexible") if k in c.results]
    top = cols[-1]
    head = f"{'mode':>4}  " + "  ".join(f"{k + ' [Hz]':>15}" for k in cols)
    head += "  " + "  ".join(f"{'shift ' + k[:4] + ' %':>13}" for k in cols[:-1]) + f"  {'MAC':>5}  {'class':<13} dominant"
    lines = [head]
    for r in c.rows:
        cells = []
        for k in cols:
            v = r.get(k)
            cells.append(f"{v:>15.2f}" if v is not None else f"{'-':>15}")
        shifts = []
        for k in cols[:-1]:
            v = r.get(k)
            ok = v is not None and r["class"] != "rigid-body" and v > 0
            shifts.append(f"{100 * (r[top] / v - 1):>13.2f}" if ok else f"{'-':>13}")
        mac = r.get(f"mac_{cols[-2]}") if len(cols) > 1 else None
        mac_s = "-" if mac is None else f"{mac:.2f}"
        lines.append(f"{r['mode']:>4}  " + "  ".join(cells) + "  " + "  ".join(shifts)
                     + f"  {mac_s:>5}  {r['class']:<13} {r['dominant_body']}")
    t = ", ".join(f"{k}: {v['n_dofs']} DOFs {v['total_s']:.2f} s" for k, v in c.timings.items())
    lines.append(f"shift = {top} / other - 1; MAC of the {top} mode with its partner one fidelity down. {t}")
    return "\n".join(lines)


def dominant_text(info) -> str:
    """``"pinion 60%; wheel 38%"``: kinetic-energy shares of a mode's dominant bodies."""
    return "; ".join(f"{b} {100 * s:.0f}%" for b, s in info.dominant_bodies)


def write_modes_csv(infos, path) -> None:
    """Mode table as CSV: index, frequency (Hz), multiplicity, class, stage, dominant bodies."""
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["mode", "frequency_hz", "multiplicity", "class", "stage", "dominant_bodies_ke_share"])
        for mi in infos:
            w.writerow([mi.index + 1, f"{mi.frequency_hz:.9g}", mi.multiplicity, mi.mode_class,
                        mi.stage or "", dominant_text(mi)])


def write_comparison_csv(rows, fields, path) -> None:
    """Fidelity comparison rows (see :func:`assembly.compare.compare`) as CSV (Hz)."""
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fields)
        w.writeheader()
        for r in rows:
            w.writerow({k: _fmt_csv(r.get(k)) for k in fields})


def _fmt_csv(v):
    if v is None:
        return ""
    if isinstance(v, float):
        return f"{v:.9g}"
    return v
