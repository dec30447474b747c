"""Plain-text and JSON views of modal results and fidelity comparisons (no plotting here)."""
from __future__ import annotations

import csv

import numpy as np

from ...analysis.classify import classify_modes
from ...analysis.energy import kinetic_by_body, strain_by_body, strain_by_element
from ...analysis.locality import energy_table, group_shares
from ...analysis.modal import mechanisms
from ...dynamics.damped_modes import damped_modes
from ...model.body_table import body_properties, replaced, replaced_note
from ...model.damping import has_damping
from ...model.flexible import FlexibleBodyModel
from ...scene.tables import DISPLAY_BAND_FACTOR
from .gear_cells import gear_cells, gears_json
from .inertia_cells import referred_cells, referred_json


def in_band(result) -> np.ndarray:
    """(n_modes,) True for the modes shown by default: frequency up to the scene's
    display limit (Hz; ``Scene.display_limit_hz`` = DISPLAY_BAND_FACTOR x band)."""
    return np.asarray(result.frequencies_hz) <= result.model.scene.display_limit_hz


def modes_table(result, title: str = "", all_modes: bool = False) -> str:
    """Mode table: index, frequency (Hz), multiplicity, class, scope ("global" or the stage
    holding the mode), energy by stage (kinetic % / strain %), dominant bodies (% KE): the
    modes in the band (:func:`in_band`; every mode with ``all_modes``), then one line on
    those left out, the flexible bodies' valid ranges and the solve. A scene with damping
    (:func:`assembly.dynamics.damped_modes.has_damping`) adds the columns "damping ratio"
    and "damped frequency [Hz]" of the paired damped mode."""
    infos = classify_modes(result)
    keep = in_band(result) | all_modes
    lines = []
    if title:
        lines.append(title)
    shown = [mi for mi in infos if keep[mi.index]]
    w_scope = max([len("scope")] + [len(mi.scope or "") for mi in shown])
    splits = [stage_split_text(mi) for mi in shown]
    w_split = max([len(ENERGY_SPLIT_HEADER)] + [len(t) for t in splits])
    dm = damped_modes(result) if has_damping(result.model.scene) else None
    damped = (lambda i: f"  {dm.ratios[i]:>13.4f}  {dm.damped_hz[i]:>21.2f}") if dm else (lambda i: "")
    lines.append(f"{'mode':>4}  {'frequency [Hz]':>14}{'  damping ratio  damped frequency [Hz]' if dm else ''}"
                 f"  {'mult':>4}  {'class':<13}  {'scope':<{w_scope}}  "
                 f"{ENERGY_SPLIT_HEADER:<{w_split}}  dominant bodies (kinetic energy)")
    for mi, split in zip(shown, splits):
        dom = ", ".join(f"{b} {100 * s:.0f}%" for b, s in mi.dominant_bodies)
        lines.append(f"{mi.index + 1:>4}  {mi.frequency_hz:>14.2f}{damped(mi.index)}  {mi.multiplicity:>4}  "
                     f"{mi.mode_class:<13}  {mi.scope or '':<{w_scope}}  {split:<{w_split}}  {dom}")
    left_out = band_note(result, int((~keep).sum()))
    if left_out:
        lines.append(left_out)
    if dm:
        lines.append(f"damped modes: {dm.method}")
    for k, text in enumerate(mechanisms(result)):
        lines.append(f"rigid-body mode {k + 1} (free motion): {text}")
    lines += flexible_lines(result.model)
    lines.append(f"{len(infos)} modes, {result.model.K.shape[0]} DOFs, max relative eigen-residual "
                 f"{result.max_residual:.1e}, solve {result.solve_time_s * 1e3:.1f} ms")
    lines += ["", *body_lines(result.model), *gear_lines(result.model),
              *referred_lines(result.model, result)]
    return "\n".join(lines)


#: Title of the body table of every report.
BODY_TABLE_TITLE = "bodies: the mass properties the model uses (about each centre of mass) and their source"


def body_cells(model) -> dict:
    """Cells of the body table (text, HTML and CSV alike): body, scene table, mass (kg),
    polar and transverse inertia (kg m^2, about the centre of mass), centre of mass (m,
    global), source of the numbers (:mod:`assembly.model.body_table`); a body whose component's
    mesh replaced typed mass properties adds them with the relative difference (column
    "typed, replaced")."""
    rows = body_properties(model)
    header = ["body", "table", "mass [kg]", "J polar [kg m^2]", "J transverse [kg m^2]", "centre of mass [m]",
              "source"]
    out = [[r.name, r.path, f"{r.mass:.6g}", f"{r.polar_inertia:.6g}", f"{r.transverse_inertia:.6g}",
            " ".join(f"{x:.6g}" for x in r.center_of_mass), r.source] for r in rows]
    swapped = {r.name for r in replaced(rows)}
    notes = [replaced_note(r) for r in rows if r.name in swapped]
    if swapped:
        header.append("typed, replaced [kg, kg m^2]")
        for cells, r in zip(out, rows):
            diff = r.differences()
            cells.append("; ".join(f"{q} {v:.6g} ({100 * diff[q]:+.1f} %)" for q, v in r.typed.items())
                         if r.name in swapped else "")
    return dict(header=header, rows=out, left=(0, 1, 5, 6, 7), notes=notes)


def body_lines(model) -> list:
    """The body table as text lines: title, table, one note per replaced body."""
    c = body_cells(model)
    return [BODY_TABLE_TITLE, text_table(c["header"], c["rows"], set(c["left"])), *c["notes"]]


def gear_lines(model) -> list:
    """The gear table as text lines (blank line, title, table; none without meshes)."""
    c = gear_cells(model)
    return ["", c["title"], text_table(c["header"], c["rows"], set(c["left"]))] if c["rows"] else []


def referred_lines(model, result=None) -> list:
    """The referred-inertia table as text lines (blank line, title, table or why there is
    none); ``result``: the model's modal result (its rigid-body mode is used)."""
    c = referred_cells(model, result)
    return ["", c["title"], *([text_table(c["header"], c["rows"], set(c["left"]))] if c["rows"] else []),
            *c["notes"]]


def bodies_json(model) -> list:
    """The body table as JSON-ready dicts (SI units; ``typed`` and ``relative_difference``
    for a component that replaced typed mass properties)."""
    return [r.as_dict() for r in body_properties(model)]


def write_bodies_csv(model, path) -> None:
    """The body table as CSV (kg, kg m^2, m)."""
    c = body_cells(model)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(c["header"])
        w.writerows(c["rows"])


#: Column header of :func:`stage_split_text`.
ENERGY_SPLIT_HEADER = "energy by stage (kinetic%/strain%)"


def stage_split_text(info, floor: float = 0.005) -> str:
    """``"planetary 88/1, wheel/planetary 0/99"``: a mode's kinetic and strain energy shares
    (%) per stage (or link between stages), largest total first; stages holding less than
    ``floor`` of both are left out."""
    parts = sorted(info.energy, key=lambda e: -(e[1] + e[2]))
    return ", ".join(f"{g} {100 * k:.0f}/{100 * v:.0f}" for g, k, v in parts if max(k, v) >= floor)


def band_note(result, n_left_out: int) -> str:
    """One line: how many modes a table leaves out and why ("" for none)."""
    if n_left_out <= 0:
        return ""
    sc = result.model.scene
    return (f"{n_left_out} modes above {sc.display_limit_hz:.0f} Hz ({DISPLAY_BAND_FACTOR:g} x band_hz "
            f"{sc.band:.0f} Hz) not shown: outside the band of interest (all modes, flagged, in modes.csv "
            "and modes.json)")


def valid_up_to_hz(model) -> float | None:
    """Lowest valid range (Hz) of the model's reduced flexible bodies (None without any):
    assembled frequencies above it include Ritz values of residual vectors, not modes."""
    v = [r["accurate_to_hz"] for r in flexible_summary(model).values() if r["accurate_to_hz"] is not None]
    return min(v) if v else None


def flexible_lines(model) -> list:
    """One line per flexible body: FE DOFs, valid range (cutoff), fixed-interface modes,
    residual vectors (static corrections, not modes), reduced or cached; then a line on the
    lowest valid range of the assembled model."""
    lines = []
    for name, r in flexible_summary(model).items():
        if r["reduced"]:
            upto = (f"reduced model accurate to {r['accurate_to_hz']:.0f} Hz" if r["accurate_to_hz"] is not None
                    else "reduced model")
            how = (f"{upto} ({'cutoff' if r['cutoff_hz'] else 'highest kept mode'}; "
                   f"{r['fixed_interface_modes']} fixed-interface modes below it"
                   f" + {r['residual_vectors']} residual vectors, static corrections, not modes)")
            src = " (from cache)" if r["from_cache"] else f" (reduced in {r['reduce_time_s']:.2f} s)"
        else:
            how, src = "unreduced (full FE)", ""
        lines.append(f"flexible body {name}: {r['fe_dofs']} FE DOFs, {how}{src}")
    lim = valid_up_to_hz(model)
    if lim is not None:
        lines.append(f"frequencies above {lim:.0f} Hz (lowest flexible-body cutoff) are not trustworthy: they "
                     "include Ritz values of residual vectors")
    return lines


def flexible_summary(model) -> dict:
    """How each flexible body was modelled: FE DOFs, fixed-interface modes, residual
    vectors, cutoff (Hz), the frequency up to which its reduction is accurate (Hz: the
    cutoff, or with ``flex.n_modes`` the highest kept fixed-interface mode; None unreduced),
    reduction time (s) and whether it came from the cache."""
    out = {}
    for name, bm in model.bodies.items():
        if not isinstance(bm, FlexibleBodyModel):
            continue
        info = bm.info
        n = info.get("n_modes")
        upto = info.get("cutoff_hz")
        if upto is None and bm.reduced and n:
            upto = float(np.max(bm.superelement.mode_frequencies_hz[:n]))
        out[name] = {"reduced": bm.reduced, "fe_dofs": info.get("n_full_dofs"),
                     "fixed_interface_modes": n,
                     "residual_vectors": info.get("n_residual_vectors", 0),
                     "cutoff_hz": info.get("cutoff_hz"), "accurate_to_hz": upto,
                     "reduce_time_s": info.get("reduce_time_s"),
                     "from_cache": bool(info.get("cache_hits"))}
    return out


def modes_json(result) -> dict:
    """JSON-ready dict; ``frequencies_hz`` lists every frequency ascending (0 Hz included).
    Every mode is listed; ``in_band`` flags those up to ``display_limit_hz`` (the rest are
    outside the band of interest); ``valid_up_to_hz``: the lowest flexible-body cutoff."""
    infos = classify_modes(result)
    m = result.model
    dm = damped_modes(result) if has_damping(m.scene) else None
    ke = kinetic_by_body(result)
    se = strain_by_element(result)
    sb = strain_by_body(result)
    band = in_band(result)
    flex = [j for j, b in enumerate(m.bodies) if m.bodies[b].flexible]
    bodies = list(m.bodies)
    elems = [e.name for e in m.elements]
    modes = []
    for mi in infos:
        i = mi.index
        modes.append({
            "index": i + 1,
            "frequency_hz": mi.frequency_hz,
            "multiplicity": mi.multiplicity,
            "in_band": bool(band[i]),
            "class": mi.mode_class,
            "stage": mi.stage,
            "scope": mi.scope,
            "energy_by_stage": {g: {"kinetic": k, "strain": v} for g, k, v in mi.energy},
            "dominant_bodies": [b for b, _ in mi.dominant_bodies],
            "kinetic_energy_share": {b: float(ke[i, j]) for j, b in enumerate(bodies) if ke[i, j] > 1e-12},
            "strain_energy_share": {e: float(se[i, j]) for j, e in enumerate(elems) if se[i, j] > 1e-12},
            "flexible_body_strain_energy_share": {bodies[j]: float(sb[i, j]) for j in flex},
            "shape": {b: {d: float(v) for d, v in zip(("ux", "uy", "uz", "rx", "ry", "rz"),
                                                      result.body_motion(i, b))} for b in bodies},
        })
        if dm:
            modes[-1].update(damping_ratio=float(dm.ratios[i]), damped_frequency_hz=float(dm.damped_hz[i]),
                             damped_eigenvalue=[float(dm.s[i].real), float(dm.s[i].imag)])
    return {
        "scene": m.scene.name,
        "units": {"frequency": "Hz", "translation": "m", "rotation": "rad", "mass_normalised": "kg^-1/2"},
        "n_dofs": int(m.K.shape[0]),
        "dof_names": m.dof_names,
        "frequencies_hz": [float(f) for f in np.sort(result.frequencies_hz)],
        "band_hz": m.scene.band,
        "display_limit_hz": m.scene.display_limit_hz,
        "n_outside_band": int((~band).sum()),
        "valid_up_to_hz": valid_up_to_hz(m),
        "n_rigid_body_modes": result.n_rigid,
        "rigid_body_modes": mechanisms(result),
        "max_relative_residual": result.max_residual,
        "solve_time_s": result.solve_time_s,
        "flexible_bodies": flexible_summary(m),
        "bodies": bodies_json(m),
        "gears": gears_json(m),
        "referred_inertia_kgm2": referred_json(m, result),
        "modes": modes,
    }


#: MAC below which a pairing is flagged weak (the shapes differ noticeably).
WEAK_MAC = 0.8
#: MAC below which a pair has no meaningful partner: its frequency shift is not shown.
NO_PARTNER_MAC = 0.5
SHORT = {"torsional": "tors", "rigid": "rigid", "flexible": "flex"}


def comparison_cells(rows, fids) -> dict:
    """Cells of the fidelity comparison, shared by the text table and the HTML report.

    ``rows``: :func:`assembly.analysis.compare.compare` rows; ``fids``: the fidelities present, low to
    high. A lower fidelity's shift (%) is shown only when every MAC on the pairing chain
    down to it is at least :data:`NO_PARTNER_MAC` ("--" otherwise); a MAC below
    :data:`WEAK_MAC` is starred. Returns header, rows (strings), row_classes ("weak",
    "unpaired" or ""), notes (footnotes, each once) and left (indices of text columns)."""
    top, lows = fids[-1], fids[-2::-1]      # lower fidelities from the next one down
    header = ["mode"] + [f"{f} [Hz]" for f in fids]
    header += [f"shift vs {f} [%]" for f in lows]
    chain = [top] + list(lows)
    header += [f"MAC {SHORT[a]}-{SHORT[b]}" for a, b in zip(chain, chain[1:])]
    header += ["class", "dominant body"]
    out, classes, hidden, weak = [], [], False, False
    for r in rows:
        cells = [str(r["mode"])] + [("-" if r.get(f) is None else f"{r[f]:.2f}") for f in fids]
        macs = [r.get(f"mac_{f}") for f in lows]
        shifts, mac_cells, ok = [], [], True
        for f, mac in zip(lows, macs):
            ok = ok and mac is not None and mac >= NO_PARTNER_MAC
            v = r.get(f)
            if v is None or mac is None or not v > 0 or r["class"] == "rigid-body":
                shifts.append("-")
            elif not ok:
                shifts.append("--")
                hidden = True
            else:
                shifts.append(f"{100.0 * (r[top] / v - 1):+.2f}")
            mac_cells.append("-" if mac is None else f"{mac:.2f}" + ("*" if mac < WEAK_MAC else ""))
        weak = weak or any(m is not None and m < WEAK_MAC for m in macs)
        out.append(cells + shifts + mac_cells + [r["class"], r.get("dominant_body") or ""])
        classes.append("unpaired" if macs[0] is None else
                       ("weak" if any(m is not None and m < WEAK_MAC for m in macs) else ""))
    notes = [f"shift = f_{top} / f_other - 1 of the MAC-paired modes; MAC mass-weighted on the "
             "rigid-equivalent body motions, one fidelity down at a time (subspace MAC for repeated "
             "frequencies, one-to-one assignment)."]
    if weak:
        notes.append(f"* MAC < {WEAK_MAC}: weak pairing, the partner's shape differs noticeably.")
    if hidden:
        notes.append(f"-- MAC < {NO_PARTNER_MAC} on the pairing chain: no meaningful partner in that model "
                     "(the paired mode has another shape), so no shift is given.")
    notes.append(f"Rayleigh-Ritz: each lower fidelity constrains the next, so the k-th frequency in "
                 f"ascending order obeys {' <= '.join(chain)}; a MAC pair need not be the k-th with "
                 "the k-th, so a paired shift can be positive.")
    left = (len(header) - 2, len(header) - 1)
    return dict(header=header, rows=out, row_classes=classes, notes=notes, left=left)


def text_table(header, rows, left=()) -> str:
    """Plain-text table, every column as wide as its widest cell (header included);
    columns in ``left`` left-aligned, the others right-aligned."""
    w = [max(len(str(x)) for x in col) for col in zip(header, *rows)]
    fmt = lambda cells: "  ".join(str(c).ljust(w[k]) if k in left else str(c).rjust(w[k])
                                  for k, c in enumerate(cells)).rstrip()
    return "\n".join([fmt(header)] + [fmt(r) for r in rows])


def comparison_table(c) -> str:
    """Text table of a :class:`assembly.analysis.compare.Comparison`: frequencies (Hz) per fidelity,
    shifts (%), MACs along the pairing chain, class and dominant body of each mode, then
    the footnotes and the cost of each model."""
    fids = [k for k in ("torsional", "rigid", "flexible") if k in c.results]
    if len(fids) < 2:
        cells = dict(header=["mode", f"{fids[0]} [Hz]", "class", "dominant body"], left=(2, 3), notes=[],
                     rows=[[str(r["mode"]), f"{r[fids[0]]:.2f}", r["class"], r.get("dominant_body") or ""]
                           for r in c.rows])
    else:
        cells = comparison_cells(c.rows, fids)
    lines = [text_table(cells["header"], cells["rows"], set(cells["left"]))]
    lines += cells["notes"]
    lines.append("models: " + ", ".join(f"{k}: {v['n_dofs']} DOFs {v['total_s']:.2f} s"
                                       for k, v in c.timings.items()))
    return "\n".join(lines)


def dominant_text(info) -> str:
    """``"pinion 60%; wheel 38%"``: kinetic-energy shares of a mode's dominant bodies."""
    return "; ".join(f"{b} {100 * s:.0f}%" for b, s in info.dominant_bodies)


def write_modes_csv(infos, path, band=None) -> None:
    """Mode table as CSV: index, frequency (Hz), multiplicity, class, stage, scope, energy by
    stage (kinetic %/strain %), dominant bodies, ``in_band`` (1, or 0 for a mode outside the
    band of interest; ``band``: the mask of :func:`in_band`, default all in band). Every mode
    is written."""
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["mode", "frequency_hz", "multiplicity", "class", "stage", "scope", "energy_by_stage_ke_strain_pct",
                    "dominant_bodies_ke_share", "in_band"])
        for mi in infos:
            w.writerow([mi.index + 1, f"{mi.frequency_hz:.9g}", mi.multiplicity, mi.mode_class,
                        mi.stage or "", mi.scope or "", stage_split_text(mi), dominant_text(mi),
                        int(True if band is None else band[mi.index])])


#: Columns of :func:`write_energy_csv`.
ENERGY_FIELDS = ("mode", "frequency_hz", "scope", "level", "name", "group", "kinetic_share", "strain_share")


def write_energy_csv(result, infos, path) -> None:
    """Every mode's energy breakdown as CSV (one row per mode and stage, body, bearing, mesh
    or shaft; ``level`` says which): the part's or stage's share of the mode's kinetic and
    of its strain energy (each sums to 1 per mode and level kind, or 0 for a rigid-body
    mode's strain), ``group`` the stage it belongs to (:mod:`assembly.analysis.locality`). Repeated
    frequencies share the split of their eigenspace."""
    table = energy_table(result)
    ks, ss = group_shares(table, result.groups)
    kp, sp = group_shares(table, result.groups, parts=True)
    rows = [("stage", g, g) for g in table.group_names] + list(zip(table.kinds, table.names, table.groups))
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(ENERGY_FIELDS)
        for mi in infos:
            i = mi.index
            k = np.concatenate([ks[i], kp[i]])
            v = np.concatenate([ss[i], sp[i]])
            for (level, name, group), a, b in zip(rows, k, v):
                w.writerow([i + 1, f"{mi.frequency_hz:.9g}", mi.scope or "", level, name, group, f"{a:.6g}", f"{b:.6g}"])


def write_comparison_csv(rows, fields, path) -> None:
    """Fidelity comparison rows (see :func:`assembly.analysis.compare.compare`) as CSV (Hz)."""
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
