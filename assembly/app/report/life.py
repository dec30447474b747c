"""The loads-to-life files of a run whose scene asks for them (``[simulation.life]``, or every
run-up): ``life.csv`` (per output its rainflow cycles and damage-equivalent loads),
``life_bearings.csv`` (per rated bearing P, revolutions, L10 in 1e6 rev and hours),
``life_gears.csv`` (per rated gear T_eq, tooth cycles, Miner damage, life in hours),
``life.json`` (all of it, with each output's load duration and load revolution distributions)
and a section of index.html (:class:`assembly.dynamics.life_tables.LifeResult`). A value that is
not finite is written empty (CSV), null (JSON) or "-" (HTML), with the row's note saying why.
"""
from __future__ import annotations

import csv
from pathlib import Path

from .. import strict_json
from .page import Section, esc, link, table

BEARING_COLUMNS = ("bearing", "rating_n", "exponent", "equivalent_load_n", "peak_load_n", "revolutions", "l10_mrev",
                   "l10_hours", "note")
GEAR_COLUMNS = ("mesh", "gear", "slope", "torque_eq", "peak_torque", "cycles", "damage", "life_hours", "note")
BEARING_HEADS = ("bearing", "C [N]", "p", "P [N]", "peak [N]", "revolutions", "L10 [1e6 rev]", "L10 [h]", "note")
GEAR_HEADS = ("mesh", "gear", "slope k", "T_eq [N m]", "peak [N m]", "tooth cycles", "damage D", "life [h]", "note")


def _cell(v) -> str:
    return "" if v is None else v if isinstance(v, str) else f"{v:.6g}"


def _del_key(m: float) -> str:
    return f"del_m{m:g}"


def _write_csv(path: Path, cols, rows) -> None:
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        for r in rows:
            w.writerow([_cell(r[c]) for c in cols])


def output_rows(life) -> list:
    """Per output: name, unit, cycles and the DEL of each exponent (``del_mM``)."""
    return [{"output": k, "unit": o.unit, "cycles": o.cycles, **{_del_key(m): o.dels[m] for m in life.exponents},
             "note": o.note} for k, o in life.outputs.items()]


def life_files(life, work: Path) -> list:
    """Write the files of the module notes into ``work``; returns their names."""
    work = Path(work)
    files = ["life.csv"]
    _write_csv(work / "life.csv", ("output", "unit", "cycles", *(_del_key(m) for m in life.exponents), "note"),
               output_rows(life))
    if life.bearings:
        _write_csv(work / "life_bearings.csv", BEARING_COLUMNS, [vars(b) for b in life.bearings])
        files.append("life_bearings.csv")
    if life.gears:
        _write_csv(work / "life_gears.csv", GEAR_COLUMNS, [vars(g) for g in life.gears])
        files.append("life_gears.csv")
    doc = life.as_dict()                          # the tables, and each output's distributions beside
    for k, o in life.outputs.items():
        doc["outputs"][k].update(
            ldd={"levels": o.ldd.levels.tolist(), "seconds": o.ldd.amounts.tolist()},
            lrd=None if o.lrd is None else {"levels": o.lrd.levels.tolist(), "revolutions": o.lrd.amounts.tolist(),
                                            "shaft": life.shaft})
    (work / "life.json").write_text(strict_json.dumps(doc, indent=1), encoding="utf-8")
    files.append("life.json")
    return files


def _table(cols, rows, heads) -> str:
    def cell(v):
        return "-" if v is None else v if isinstance(v, str) else f"{v:.4g}"
    return table(heads, [[cell(r[c]) for c in cols] for r in rows])


def life_section(life) -> Section:
    """The index.html section: the DEL table, and the bearings' and gears' tables when rated."""
    t0, t1 = life.window
    dels = [_del_key(m) for m in life.exponents]
    out = (f"<p>From {t0:g} s to {t1:g} s: rainflow (ASTM E1049-85), damage-equivalent "
           f"loads at N_eq = {life.cycles_ref:g} cycles; load duration and load revolution distributions (revolutions "
           f"of {esc(life.shaft)}) in {link('life.json')}, the table in {link('life.csv')}.</p>"
           + _table(("output", "unit", "cycles", *dels, "note"), output_rows(life),
                    ("output", "unit", "cycles", *(f"DEL m = {m:g}" for m in life.exponents), "note")))
    rated = (("Bearings: ISO 281 basic rating life", "P = X F_r + Y F_a, its mean over the bearing's revolutions "
              "with exponent p", "life_bearings.csv", BEARING_COLUMNS, life.bearings, BEARING_HEADS),
             ("Gears: equivalent torque and Miner damage", "One load cycle per tooth per revolution against the "
              "gear's frame", "life_gears.csv", GEAR_COLUMNS, life.gears, GEAR_HEADS))
    for title, how, name, cols, rows, heads in rated:
        if rows:
            out += (f"<h3>{title}</h3><p>{esc(how)} ({link(name)}).</p>"
                    + _table(cols, [vars(r) for r in rows], heads))
    return Section("Loads to life", out, "Life")
