"""``flexgear part``: one user's part checked alone (:mod:`assembly.analysis.part_check`), printed as
a report or one JSON object.

Two forms: ``flexgear part FILE --units mm [--order 2] [--axis X,Y,Z] [--origin X,Y,Z]
[--mesh-size M]`` reads a part file as a free part (steel, no interfaces): the first look at
a file; ``flexgear part SCENE [--body NAME]`` checks the part of a scene's body as the scene
builds it (its interfaces, ``flex`` table and material).
"""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np


def parse_vector(text: str, flag: str) -> tuple:
    """``"0,1,0"`` -> (0.0, 1.0, 0.0); UsageError naming ``flag`` otherwise."""
    from ..errors import UsageError

    try:
        v = tuple(float(x) for x in text.split(","))
    except ValueError:
        v = ()
    if len(v) != 3 or not all(math.isfinite(x) for x in v):
        raise UsageError(f"{flag} = {text!r}: give three finite numbers, e.g. 0,1,0")
    return v


def _file_part(args):
    """The PartFile and FlexOptions of the FILE form."""
    from fe_components.errors import GeometryError
    from fe_components.part.file import PartFile

    from ...scene.tables import FlexOptions
    from ..errors import UsageError

    if args.body is not None:
        raise UsageError(f"--body {args.body}: names a body of a scene; {args.target} is a part file")
    from fe_components.part.file import CAD_SUFFIXES, UNITS

    from ... import arguments
    if args.mesh_size is not None:
        if Path(args.target).suffix.lower() not in CAD_SUFFIXES:
            raise UsageError(f"--mesh-size = {args.mesh_size!r}: a mesh file brings its own elements; the element "
                             "size is for a CAD file (STEP, BREP)")
        with_flag(lambda: arguments.number("--mesh-size", args.mesh_size, "m", gt=0.0))
    if args.units is not None and args.units not in UNITS:
        raise UsageError(f"--units = {args.units!r}: must be one of {list(UNITS)}{arguments.nearest(args.units, UNITS)}")
    fields = {"units": args.units, "order": args.order}
    if args.axis is not None:
        fields["axis"] = parse_vector(args.axis, "--axis")
    if args.origin is not None:
        fields["origin"] = parse_vector(args.origin, "--origin")
    try:
        part = PartFile(args.target, **fields)
    except GeometryError as err:
        raise flagged(err, {"axis": args.axis, "origin": args.origin}) from None
    return part, FlexOptions(mesh_size=args.mesh_size)


def with_flag(check):
    """``check()``, its SceneError (which names a flag) as a UsageError."""
    from ...errors import SceneError
    from ..errors import UsageError
    try:
        return check()
    except SceneError as err:
        raise UsageError(str(err)) from None


#: A part file's fields the FILE form takes from the command line.
FLAGS = {"units": "--units", "order": "--order", "axis": "--axis", "origin": "--origin", "file": "FILE"}


def flagged(err, typed: dict | None = None):
    """A part error of the FILE form as a SceneError naming the command-line flag, with the
    value as typed there when ``typed`` has it ({field: text})."""
    from ...errors import SceneError
    name = err.parameter.split("[")[0].split(".")[0]
    value = (typed or {}).get(name, err.value)
    return SceneError(FLAGS[name] if name in FLAGS else err.parameter, value, err.reason)


def check(args):
    """The :class:`~assembly.analysis.part_check.PartCheck` the command's arguments name."""
    from fe_components.errors import GeometryError
    from fe_components.part.file import CAD_SUFFIXES, MESH_SUFFIXES

    from ...analysis.part_check import check_body_part, check_part
    from ...errors import SceneError
    from ...scene.schema import load_scene
    from ..args import scene_file
    from ..errors import UsageError

    if Path(args.target).suffix.lower() in CAD_SUFFIXES + MESH_SUFFIXES:
        part, flex = _file_part(args)
        try:
            return check_part(part, flex, args.modes)
        except GeometryError as err:
            raise flagged(err) from None
    given = [f for f, v in (("--units", args.units), ("--order", args.order), ("--axis", args.axis),
                            ("--origin", args.origin), ("--mesh-size", args.mesh_size)) if v is not None]
    if given:
        raise UsageError(f"{given[0]}: applies to a part file; for a scene's part, set it in the body's "
                         "component or flex table")
    args.scene = args.target
    scene = load_scene(scene_file(args))
    try:
        return check_body_part(scene, args.body, args.modes)
    except SceneError as err:
        if err.path == "body":
            raise SceneError("--body", err.value, err.reason) from None
        raise


def _vec(v) -> str:
    return "[" + ", ".join(f"{x:.6g}" for x in v) + "]"


def report_text(c) -> str:
    """The check as a report (SI units)."""
    from fe_components.part.cells import counts_text

    m = c.material
    kind = "CAD, meshed by gmsh" if c.source == "cad" else "mesh file"
    size = "element size" if c.source == "cad" else "median edge"
    lines = [f"part {c.file} ({kind})",
             f"  elements: P{c.order} tetrahedra, {c.n_elements} elements, {c.n_nodes} nodes, {c.n_dofs} DOFs, "
             f"{size} {c.mesh_size:.4g} m",
             f"  material: E {m.E:.4g} Pa, nu {m.nu:.4g}, rho {m.rho:.6g} kg/m^3"]
    if c.read is not None:
        lines.append(f"  read: {c.read.text()}")
        if c.read.left_out:
            lines.append(f"  left out of the model: {counts_text(c.read.left_out)}")
    if c.order == 1:
        lines.append("  linear tetrahedra: too stiff in bending; P2 is flex order = 2 for a CAD part, order = 2 "
                     "(--order 2) for a mesh file")
    lines += ["", "mass properties (local axes; inertia about the centre of mass)"]
    cad = c.cad is not None
    lines.append((f"  {'':<22} {'FE':>16}" + (f" {'CAD (exact)':>16}  rel. diff" if cad else "")).rstrip())
    rows = [("mass [kg]", lambda t: t[0], "mass_rel")]
    rows += [(f"centre {x} [m]", lambda t, i=i: t[1][i], "center_of_mass_rel" if i == 0 else None)
             for i, x in enumerate("xyz")]
    rows += [(f"I{'xyz'[i]}{'xyz'[j]} [kg m^2]", lambda t, i=i, j=j: t[2][i, j], "inertia_rel" if k == 0 else None)
             for k, (i, j) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)))]
    fe = (c.mass, c.center_of_mass, c.inertia)
    for name, value, key in rows:
        row = f"  {name:<22} {value(fe):>16.8g}"
        if cad:
            row += f" {value(c.cad):>16.8g}" + (f"  {c.cad_rel.get(key, float('nan')):.2g}" if key else "")
        lines.append(row)
    expected = "" if c.n_rigid == 6 else "  <- a free solid has 6" + (
        f" (the part is {c.n_pieces} pieces that do not touch)" if c.n_pieces > 1 else "")
    lines += ["", f"free-free modes: {c.n_rigid} rigid-body modes{expected}"]
    lines += [f"  {k + 1:>3}  {f:12.6g} Hz" + ("  (rigid)" if k < c.n_rigid else "")
              for k, f in enumerate(c.frequencies_hz)]
    lines += ["", "interfaces" + ("" if c.interfaces else ": none (a free part)")]
    if c.interfaces:
        lines.append(f"  {'name':<14} {'rule':<9} {'coupling':<8} {'faces':>6} {'nodes':>6} {'area [m^2]':>11}  master [m]")
        lines += [f"  {i.name:<14} {i.select:<9} {i.coupling:<8} {i.n_faces:>6} {i.n_nodes:>6} {i.area:>11.4g}  "
                  f"{_vec(i.master)}" for i in c.interfaces]
    return "\n".join(lines)


def report_json(c) -> dict:
    """The check as plain data (SI units)."""
    m = c.material
    out = {"file": c.file, "source": c.source, "order": c.order, "n_elements": c.n_elements, "n_nodes": c.n_nodes,
           "n_dofs": c.n_dofs, "mesh_size_m": c.mesh_size, "material": {"E": m.E, "nu": m.nu, "rho": m.rho},
           "read": None if c.read is None else {
               "text": c.read.text(), "solid": c.read.solid, "n_solid": c.read.n_solid,
               "dropped": [{"name": d.name, "count": d.count, "kind": d.kind} for d in c.read.dropped],
               "loose_nodes": c.read.loose_nodes, "renumbered": c.read.renumbered, "lifted": c.read.lifted},
           "fe": {"mass_kg": c.mass, "center_of_mass_m": list(c.center_of_mass), "inertia_kg_m2": c.inertia.tolist()},
           "cad": None if c.cad is None else {"mass_kg": c.cad[0], "center_of_mass_m": list(c.cad[1]),
                                              "inertia_kg_m2": np.asarray(c.cad[2]).tolist(), "relative": c.cad_rel},
           "frequencies_hz": list(c.frequencies_hz), "n_rigid": c.n_rigid, "n_pieces": c.n_pieces,
           "interfaces": [{"name": i.name, "select": i.select, "coupling": i.coupling, "n_faces": i.n_faces,
                           "n_nodes": i.n_nodes, "area_m2": i.area, "master_m": list(i.master)} for i in c.interfaces]}
    return json.loads(json.dumps(out, default=float))


def run(args) -> int:
    """``flexgear part``: print the check of one part."""
    c = check(args)
    if args.json:
        json.dump(report_json(c), sys.stdout, indent=1, allow_nan=False)
        sys.stdout.write("\n")
    else:
        print(report_text(c))
    return 0
