"""Text, CSV, JSON and HTML-table views of static load cases
(:class:`assembly.analysis.reactions.StaticReport`); sign conventions in docs/static.md."""
from __future__ import annotations

import csv

from .gear_cells import gears_json
from .inertia_cells import referred_json
from .tables import bodies_json, body_lines, gear_lines, referred_lines


def _g(v) -> str:
    return "" if v is None else f"{v:.6g}"


_WRENCH = ("Fx_N", "Fy_N", "Fz_N", "Mx_Nm", "My_Nm", "Mz_Nm")
_WRENCH_HEAD = ["Fx [N]", "Fy [N]", "Fz [N]", "Mx [N m]", "My [N m]", "Mz [N m]"]


#: A load below this fraction of the case's largest is the solve's round-off: printed as 0.
ROUND_OFF = 1e-10


def _scale(rep) -> float:
    """The case's largest force or moment magnitude (N, N m), for :data:`ROUND_OFF`."""
    vals = [abs(float(d[k])) for group in (rep.loads, rep.meshes, rep.bearings, rep.supports) for d in group
            for k in (*_WRENCH, "force_N") if isinstance(d.get(k), (int, float))]
    return max(vals, default=0.0)


def static_tables(rep) -> list:
    """(title, header, rows, left-aligned columns) of one load case: applied loads, meshes,
    bearings, shafts, supports, held directions, checks; a load that is round-off of the case's
    largest (below :data:`ROUND_OFF` of it) is printed as 0 (the JSON keeps every digit)."""
    tiny = ROUND_OFF * _scale(rep)

    def _g(v) -> str:                      # the tables' numbers, round-off shown as 0
        return "" if v is None else "0" if abs(v) <= tiny else f"{v:.6g}"
    out = []
    if rep.loads:
        out.append(("applied loads (global axes, at the point)", ["load", "body", "point [m]"] + _WRENCH_HEAD,
                    [[a["load"], a["body"], " ".join(_g(x) for x in a["point_m"])] + [_g(a[k]) for k in _WRENCH]
                     for a in rep.loads], (0, 1, 2)))
    out.append(("gear meshes (force along the line of action; > 0: drive flank in compression; ISO 6336-1: "
                "F_t tangential at the reference circle (the working pitch circle without teeth), F_r radial, "
                "F_a axial)",
                ["mesh", "gear 1", "gear 2", "force [N]", "transverse [N]", "axial [N]", "flank", "F_t [N]",
                 "F_r [N]", "F_a [N]", "F_t at"],
                [[m["mesh"], m["gear1"], m["gear2"], _g(m["force_N"]), _g(m["transverse_N"]), _g(m["axial_N"]),
                  "drive" if m["drive_flank"] else "opposite", _g(m.get("F_t_N")), _g(m.get("F_r_N")),
                  _g(m.get("F_a_N")), m.get("circle", "")] for m in rep.meshes], (0, 1, 2, 6, 10)))
    if rep.load_sharing:
        out.append(("planet load sharing (ISO 6336-1 K_gamma = max / mean of the stage's planet mesh forces)",
                    ["stage", "mesh", "K_gamma", "planet mesh forces [N]"],
                    [[s["stage"], s["mesh"], _g(s["K_gamma"]), " ".join(_g(f) for f in s["forces_N"])]
                     for s in rep.load_sharing], (0, 1, 3)))
    out.append(("bearing reactions on the body (bearing axes, at the bearing point)",
                ["bearing", "body", "frame"] + _WRENCH_HEAD,
                [[b["bearing"], b["body"], b["frame"]] + [_g(b[k]) for k in _WRENCH] for b in rep.bearings],
                (0, 1, 2)))
    if rep.shafts:
        out.append(("shaft section loads (k x (body1 - body2) motion, body1 axes)",
                    ["shaft", "body 1", "body 2", "torque [N m]", "shear x [N]", "shear y [N]", "axial [N]",
                     "bending x [N m]", "bending y [N m]"],
                    [[s["shaft"], s["body1"], s["body2"]] + [_g(s[k]) for k in
                                                            ("torque_Nm", "shear_x_N", "shear_y_N", "axial_N",
                                                             "bending_x_Nm", "bending_y_Nm")]
                     for s in rep.shafts], (0, 1, 2)))
    if rep.supports:
        out.append(("support reactions on the body (body axes, at the support point)",
                    ["support", "body", "held"] + _WRENCH_HEAD,
                    [[f"supports[{s['support']}]", s["body"] + (f".{s['interface']}" if s["interface"] else ""),
                      " ".join(s["dofs"])] + [_g(s[k]) for k in _WRENCH] for s in rep.supports], (0, 1, 2)))
    held = [c for c in rep.constraints if c["value"] != 0.0]
    if held:
        out.append(("reactions of held directions (body axes)", ["body", "DOF", "reaction", "unit", "held by"],
                    [[c["body"], c["dof"], _g(c["value"]), c["unit"], c["source"]] for c in held], (0, 1, 3, 4)))
    out.append(("checks", ["check", "value", "expected", "relative error", "note"], _check_rows(rep), (0, 1, 4)))
    return out


def _check_rows(rep) -> list:
    e = rep.equilibrium
    rows = [["equilibrium: applied loads + reactions [N, N m]",
             f"F {' '.join(_g(x) for x in e['force_N'])}; M {' '.join(_g(x) for x in e['moment_Nm'])}", "0",
             _g(e["relative_error"]), f"moments about {' '.join(_g(x) for x in e['point_m'])} m"]]
    b, r = rep.balance, rep.ratio
    if b:
        rows.append(["torque balance about the input axis [N m]",
                     f"{_g(b['input_Nm'])} + {_g(b['output_Nm'])} + {_g(b['housing_Nm'])} + {_g(b['loads_Nm'])} "
                     "(in + out + housing + other loads)", "0", _g(b["relative_error"]),
                     "sum relative to the input torque"])
    if r:
        rows.append(["-T_out / T_in vs speed ratio omega_in / omega_out", _g(r["torque_ratio"]),
                     _g(r["speed_ratio"]), _g(r["relative_error"]), r["note"]])
    return rows


def case_summary(rep) -> str:
    """One line: what loads the case and what holds it."""
    parts = []
    if rep.torque_Nm is not None:
        parts.append(f"{_g(rep.torque_Nm)} N m into {rep.input}, {rep.output} held: output reaction torque "
                     f"{_g(rep.output_torque_Nm)} N m")
    if rep.loads[1 if rep.torque_Nm is not None else 0:]:
        parts.append(f"{len(rep.loads) - (rep.torque_Nm is not None)} point load(s)")
    if rep.supports:
        parts.append(f"{len(rep.supports)} support(s)")
    return "; ".join(parts)


def _text_table(header, rows) -> list:
    widths = [max(len(str(x)) for x in col) for col in zip(header, *rows)]
    fmt = lambda row: "  ".join(str(x).rjust(w) if i else str(x).ljust(w) for i, (x, w) in enumerate(zip(row, widths)))
    return [fmt(header), "  ".join("-" * w for w in widths)] + [fmt(r) for r in rows]


def static_text(reports, title: str = "", model=None, result=None) -> str:
    """Every load case as plain-text tables, then (``model``: the assembled model solved)
    the bodies' mass properties and their source, the gear table and the inertia referred
    to each shaft (from ``result``'s rigid-body mode when the model's modes are given)."""
    lines = [title] if title else []
    for rep in reports:
        lines += ["", f"load case {rep.path} {rep.case!r}: {case_summary(rep)}"]
        for t, header, rows, _ in static_tables(rep):
            if rows:
                lines += ["", t] + _text_table(header, rows)
    if model is not None:
        lines += ["", *body_lines(model), *gear_lines(model), *referred_lines(model, result)]
    return "\n".join(lines)


def static_json(scene_name: str, reports, model=None, result=None) -> dict:
    """JSON-ready load cases; with ``model``, its bodies' mass properties (``bodies``), gear
    table (``gears``) and referred inertias (``referred_inertia_kgm2``; ``result`` as in
    :func:`static_text`)."""
    out = {"scene": scene_name, "units": {"force": "N", "moment": "N m", "angle": "rad", "mass": "kg",
                                          "inertia": "kg m^2", "length": "m"},
           "load_cases": [r.as_dict() for r in reports]}
    if model is not None:
        out["bodies"] = bodies_json(model)
        out["gears"] = gears_json(model)
        out["referred_inertia_kgm2"] = referred_json(model, result)
    return out


def write_static_csv(reports, path) -> None:
    """One row per quantity: case, kind, item, quantity, value (SI), unit."""
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["case", "kind", "item", "quantity", "value", "unit"])
        for rep in reports:
            if rep.output is not None:
                w.writerow([rep.case, "output", rep.output, "reaction_torque", rep.output_torque_Nm, "N m"])
            for m in rep.meshes:
                for q in ("force_N", "transverse_N", "axial_N", "F_t_N", "F_r_N", "F_a_N"):
                    if q in m:
                        w.writerow([rep.case, "mesh", m["mesh"], q[:-2], m[q], "N"])
            for sh in rep.load_sharing:
                w.writerow([rep.case, "load_sharing", f"{sh['stage']}.{sh['mesh']}", "K_gamma", sh["K_gamma"], ""])
            for kind, rows, key in (("bearing", rep.bearings, "bearing"), ("shaft", rep.shafts, "shaft"),
                                    ("support", rep.supports, "support")):
                for r in rows:
                    for q, v in r.items():
                        if q.endswith(("_N", "_Nm")):
                            w.writerow([rep.case, kind, r[key], q.rsplit("_", 1)[0], v,
                                        "N m" if q.endswith("_Nm") else "N"])
            for c in rep.constraints:
                w.writerow([rep.case, "held", f"{c['body']}.{c['dof']}", "reaction", c["value"], c["unit"]])
            w.writerow([rep.case, "check", "equilibrium", "relative_error", rep.equilibrium["relative_error"], ""])
            if rep.balance:
                w.writerow([rep.case, "check", "torque_balance", "relative_error", rep.balance["relative_error"], ""])
            if rep.ratio:
                w.writerow([rep.case, "check", "speed_ratio", "relative_error", rep.ratio["relative_error"], ""])
