"""The files of ``flexgear coupling`` (:func:`assembly.dynamics.coupling.compare_coupling`):
``index.html`` (the verdicts, the spectra of the coupled and the one-way run side by side, the
peak table with the nearest modes' strain shares), ``coupling.json``, ``peaks.csv`` and
``spectrum_NN.png``, written atomically into ``--out``."""
from __future__ import annotations

import csv
from pathlib import Path

from .. import strict_json
from .page import Section, esc, files_list, grid, page, para, table


def coupling_json(c, scene: str) -> dict:
    """The comparison as one JSON object: runs' facts, spectra, peaks, verdicts, the two-mass model."""
    tm = c.two_mass
    return {"scene": scene, "window_s": list(c.window_s), "verdicts": c.verdicts, "peaks": c.peaks,
            "two_mass": {"rotor_inertia_kgm2": tm.rotor_inertia, "generator_inertia_kgm2": tm.generator_inertia,
                         "gear_ratio": abs(tm.speed_ratio), "stiffness_Nm_per_rad": tm.stiffness,
                         "damping_Nms_per_rad": tm.damping},
            "spectra": [{"channel": s.label, "output": s.output, "unit": s.unit, "rms": s.rms,
                         "frequency_hz": s.frequency_hz.tolist(), "coupled": s.coupled.tolist(),
                         "one_way": s.one_way.tolist()} for s in c.spectra],
            "modes": [{"frequency_hz": f, "class": k, "strain_shares": list(sh)} for f, k, sh in c.modes],
            "runs": {name: {k: v for k, v in r.info.items() if not k.startswith("_")}
                     for name, r in (("coupled", c.coupled), ("two_mass", c.two_mass_run), ("one_way", c.one_way))}}


def coupling_files(c, work: Path, scene: str, f_max: float) -> None:
    """Write the files of the module notes into the work folder ``work``."""
    from ..plots import plot_spectra_pair

    work = Path(work)
    (work / "coupling.json").write_text(strict_json.dumps(coupling_json(c, scene), indent=1), encoding="utf-8")
    with open(work / "peaks.csv", "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(["channel", "output", "frequency_hz", "coupled", "one_way", "ratio_db", "mode_hz", "mode_class",
                    "strain_shares"])
        for p in c.peaks:
            w.writerow([p["channel"], p["output"], f"{p['frequency_hz']:.6g}", f"{p['coupled']:.6g}",
                        f"{p['one_way']:.6g}", f"{p['ratio_db']:.3f}", "" if p["mode_hz"] is None else
                        f"{p['mode_hz']:.6g}", p["mode_class"] or "",
                        "; ".join(f"{n} {v:.3f}" for n, v in p["strain_shares"])])
    figs = []
    modes_hz = [f for f, _, _ in c.modes]
    for i, s in enumerate(c.spectra):
        name = f"spectrum_{i + 1:02d}.png"
        plot_spectra_pair(s.frequency_hz, s.coupled, s.one_way, work / name, title=f"{scene}: {s.label} ({s.output})",
                          ylabel=s.unit, modes_hz=modes_hz, f_max=f_max)
        figs.append((name, f"{s.label}: coupled (solid) and one-way (dashed)"))
    (work / "index.html").write_text(_index(c, scene, figs), encoding="utf-8")


def _index(c, scene: str, figs: list) -> str:
    rows = [[p["channel"], f"{p['frequency_hz']:.4g}", f"{p['coupled']:.4g}", f"{p['one_way']:.4g}",
             f"{p['ratio_db']:+.1f}", "-" if p["mode_hz"] is None else f"{p['mode_hz']:.4g} ({p['mode_class']})",
             ", ".join(f"{n} {100 * v:.0f} %" for n, v in p["strain_shares"])] for p in c.peaks]
    tm = c.two_mass
    lead = para(f"Spectra over {c.window_s[0]:g} .. {c.window_s[1]:g} s. One-way: the detailed drivetrain driven by "
                f"the rotor torque, thrust and generator torque of the same turbine with the two-mass drivetrain "
                f"(J_R {tm.rotor_inertia:.6g} kg m^2, J_G {tm.generator_inertia:.6g} kg m^2, ratio "
                f"{abs(tm.speed_ratio):.6g}, k {tm.stiffness:.6g} N m/rad, c {tm.damping or 0.0:.6g} N m s/rad).")
    sections = [
        Section("Where they differ", "<ul>" + "".join(f"<li>{esc(v)}</li>" for v in c.verdicts) + "</ul>", "Verdicts"),
        Section("Peaks", table(["channel", "Hz", "coupled", "one-way", "dB", "nearest mode [Hz]", "its strain energy"],
                               rows, left=(0, 5, 6))),
        Section("Spectra", grid(figs)),
        Section("Files", files_list([("coupling.json", "the runs, spectra, peaks and verdicts (JSON)"),
                                     ("peaks.csv", "the peak table (CSV)")]))]
    return page(f"{scene}: coupled against one-way", sections, command="flexgear coupling", scene=scene, lead=lead)
