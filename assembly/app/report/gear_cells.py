"""The gear table of a report (text, HTML and JSON alike): every mesh's derived geometry,
contact ratios and stiffness (:mod:`assembly.analysis.gear_table`)."""
from __future__ import annotations

import math

from ...analysis.gear_table import gear_table

#: Title of the gear table of every report.
GEAR_TABLE_TITLE = ("gear meshes: geometry (ISO 21771), contact ratios and mesh stiffness as the model uses them "
                    "(radii negative for an internal gear; reference numbers need teeth)")


def _g(v, fmt=".6g") -> str:
    return "" if v is None else format(v, fmt)


def _deg(v) -> str:
    return "" if v is None else f"{math.degrees(v):.4f}"


def model_scene(model):
    """The scene as the user gave it (stages not expanded) of an assembled model."""
    return model.source if model.source is not None else model.scene


def gear_cells(model) -> dict:
    """Cells of the gear table of ``model``'s scene (empty ``rows`` without meshes)."""
    header = ["mesh", "gears", "planets", "r_b1 [m]", "r_b2 [m]", "r1 [m]", "r2 [m]", "alpha_t [deg]",
              "alpha_wt [deg]", "beta [deg]", "beta_b [deg]", "a_w [m]", "eps_alpha", "eps_beta", "k [N/m]",
              "k source"]
    rows = [[r.name, f"{r.gear1} / {r.gear2}", str(r.count) if r.count > 1 else "", _g(r.base_radius1),
             _g(r.base_radius2), _g(r.reference_radius1), _g(r.reference_radius2), _deg(r.transverse_pressure_angle),
             _deg(r.working_pressure_angle), _deg(r.helix_angle), _deg(r.base_helix_angle), _g(r.centre_distance),
             _g(r.contact_ratio, ".4f"), _g(r.overlap_ratio, ".4f"), _g(r.stiffness, ".4g"), r.stiffness_source]
            for r in gear_table(model_scene(model))]
    return dict(title=GEAR_TABLE_TITLE, header=header, rows=rows, left=(0, 1, 15), notes=[])


def gears_json(model) -> list:
    """The gear table as JSON-ready dicts (SI units, angles in rad)."""
    return [r.as_dict() for r in gear_table(model_scene(model))]


def write_gears_csv(model, path) -> int:
    """``gears.csv``: every field of each row of the gear table (SI: m, rad, N/m; empty without
    teeth); returns the rows written (none: no file is wanted)."""
    import csv
    import dataclasses
    rows = gear_table(model_scene(model))
    if not rows:
        return 0
    fields = [f.name for f in dataclasses.fields(rows[0])]
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(fields)
        for r in rows:
            w.writerow(["" if getattr(r, f) is None else (f"{getattr(r, f):.17g}" if isinstance(getattr(r, f), float)
                                                          else getattr(r, f)) for f in fields])
    return len(rows)
