"""``flexgear export superelement``: a flexible body's Craig-Bampton superelement for other
tools, as a documented ``.npz`` and as Nastran DMIG bulk data (:mod:`cms.export`).

The body is built as every command builds it (``assemble``: the same mesh, couplings, cutoff
and reduction cache), and its superelement is written as reduced, in the body's *local*
component axes (the superelement's own coordinates): the interface node positions (m) and the
DOF directions are local; the npz ``frame_origin`` (m) and ``frame_axes`` (columns = local x,
y, z in global axes) place them in the scene, ``global = frame_origin + frame_axes @ local``.
The matrices are the superelement's K and M (not the body's rigid-deflated K, which differs by
the reduction's round-off). Files: ``<DIR>/<body>.npz`` and ``<DIR>/<body>.dmig``, each
written atomically, replacing only an earlier export (never a user's file of that name or a
symbolic link). Formats: docs/superelement_export.md.
"""
from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

log = logging.getLogger(__name__)

FORMATS = ("npz", "dmig")


def parse_formats(text: str) -> tuple:
    """``--format`` ("npz", "dmig" or "npz,dmig") -> the formats in FORMATS order; an argparse
    type, so anything else is a one-line usage error (exit 2)."""
    import argparse

    asked = {p.strip().lower() for p in text.split(",") if p.strip()}
    unknown = sorted(asked - set(FORMATS))
    if unknown or not asked:
        raise argparse.ArgumentTypeError(f"{text!r}: give npz, dmig or npz,dmig")
    return tuple(f for f in FORMATS if f in asked)


def _check_body(scene, name: str) -> None:
    """A one-line SceneError, before any meshing, if ``name`` is no flexible body of ``scene``."""
    from ...arguments import nearest
    from ...errors import SceneError

    bodies = {b.name: b for b in scene.expanded().bodies}
    flexible = sorted(n for n, b in bodies.items() if b.fidelity == "flexible")
    if name not in bodies:
        raise SceneError("--body", name, f"no such body in the scene; flexible bodies: {flexible or 'none'}"
                                         f"{nearest(name, bodies)}")
    if bodies[name].fidelity != "flexible":
        raise SceneError("--body", name, f"is not a flexible body (fidelity {bodies[name].fidelity!r}), so it "
                                         f"has no superelement; flexible bodies: {flexible or 'none'}")


def reduced_body(scene, name: str):
    """The :class:`~assembly.model.flexible.FlexibleBodyModel` of body ``name`` of the assembled
    scene; SceneError if it is not a flexible body with a Craig-Bampton reduction."""
    from ...errors import SceneError
    from ...model.assemble import assemble

    _check_body(scene, name)
    body = assemble(scene).bodies[name]
    if not getattr(body, "reduced", False) or getattr(body, "superelement", None) is None:
        raise SceneError("--body", name, "is not reduced (full FE model): no superelement to export")
    return body


def frame_text(body) -> str:
    """The coordinates of the export, in words (npz ``frame``, DMIG header)."""
    o = ", ".join(f"{v:.6g}" for v in body.origin)
    R = ", ".join("[" + ", ".join(f"{v:.6g}" for v in row) + "]" for row in np.asarray(body.axes))
    return (f"local component axes of body {body.name!r} (the superelement's own coordinates); in the "
            f"scene, global = origin + R @ local with origin ({o}) m and R = [{R}] (columns: the local x, "
            "y, z axes in global axes)")


def write_body(body, scene_name: str, out_dir, formats=FORMATS, version: str = "") -> list:
    """Write the superelement of the reduced flexible ``body`` to ``out_dir`` (created if
    missing) as ``<name>.npz`` and/or ``<name>.dmig``; returns the paths written. A file
    already there is replaced only if it is an earlier export (:func:`cms.export.is_export`),
    and never through a symbolic link: checked for both files before either is written
    (:class:`~assembly.app.output.OutputDirError` naming ``out_dir``)."""
    from cms.export import FORMAT, is_export, write_dmig, write_npz

    from ..output import check_own_file

    se, frame, name = body.superelement, frame_text(body), body.name
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = {f: out_dir / f"{name}.{f}" for f in FORMATS if f in formats}
    for path in paths.values():
        check_own_file(path, is_export, f"a superelement export flexgear wrote (an npz of format {FORMAT}, or "
                                        "DMIG bulk data with its header)", out=out_dir)
    written = []
    if "npz" in paths:
        written.append(write_npz(paths["npz"], se, frame=frame, frame_origin=body.origin, frame_axes=body.axes))
    if "dmig" in paths:
        title = f"flexgear {version or ''}: superelement of body {name!r} of scene {scene_name!r}"
        written.append(write_dmig(paths["dmig"], se, frame=frame, title=title))
    log.info("exported body %s: %d boundary DOFs, %d modal coordinates", name, se.n_boundary, se.n_modes)
    return written


def export(scene, name: str, out_dir, formats=FORMATS, version: str = "") -> list:
    """Build body ``name`` of ``scene`` and write its superelement (:func:`write_body`)."""
    return write_body(reduced_body(scene, name), scene.name, out_dir, formats, version)


def run(args) -> int:
    """``flexgear export superelement SCENE --body NAME --out DIR [--format npz,dmig]``
    (``args.format``: the tuple :func:`parse_formats` made)."""
    from ...scene.schema import load_scene
    from ..args import scene_file
    from ..output import OutputDirError
    from .elastodyn import flexgear_version

    scene = load_scene(scene_file(args))
    body = reduced_body(scene, args.body)
    try:
        written = write_body(body, scene.name, args.out, args.format, flexgear_version())
    except OSError as exc:
        raise OutputDirError(f"--out {args.out}: cannot write: {exc.strerror or exc}"
                             + (f": {exc.filename}" if exc.filename else "")) from exc
    se = body.superelement
    print(f"{scene.name}: superelement of {args.body} ({se.n_boundary} boundary DOFs, {se.n_modes} modal "
          f"coordinates, local axes) -> {', '.join(str(p) for p in written)}")
    return 0
