"""``flexgear run SCENE.toml --out DIR``: the whole pipeline into one results folder.

Steps (a list, so later steps such as meshing, reduction and recovery for flexible
bodies slot in): load scene, assemble, eigen solve, fidelity comparison (torsional vs rigid
variant of the same scene, paired by MAC), tables, mode-shape images, plots, ``index.html``.
Each step gets a tqdm bar on stderr (off when stderr is not a TTY or with ``--quiet``).

Everything is written into a staged folder (:mod:`assembly.app.output`): DIR is either the
complete new result, or untouched (also after a kill or a full disk); an existing DIR is
replaced only when it is empty or an earlier flexgear run, and files a user added to it are
carried over. A step that writes files (``Step.writes``) turns an OSError about its files
into one ``--out DIR: writing ...: <reason>`` line.

Files in DIR: ``modes.csv``, ``modes.json``, ``modes_table.txt``, ``energy_by_mode.csv``,
``fidelity_comparison.csv``, ``images/overview.png``, ``images/global_torsional.png`` and
``images/stage_local.png`` (modes picked by :mod:`assembly.app.report.key_modes`), ``images/mode_NNN.png``,
``animations/mode_NNN_anim.gif`` (the first ``RunOptions.animated_modes`` drawn modes in the band),
``plots/frequencies_by_fidelity.png``, ``index.html``, ``flexgear_run.json``; with a load case also
``static.csv``, ``static.json``, ``static_table.txt`` (:func:`step_static`); with roles "rotor" and
"generator", planetary stages and damping ``frf.csv`` and ``images/frf_generator.png``
(:mod:`assembly.app.report.run_frf`); flexible bodies:
``stress.csv``, ``modal_stress.csv``, ``images/stress_*.png``, ``vtu/*.vtu``, ``results.pvd``
(docs/results.md: band, valid range, modal stress amplitude).
"""
from __future__ import annotations

import csv
import logging
import os
import sys
import time
from contextlib import nullcontext
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Optional

import numpy as np

from ...analysis.classify import classify_modes, pair_modes
from ...analysis.compare import FIDELITIES as ALL_FIDELITIES  # torsional, rigid, flexible
from ...analysis.compare import compare
from ...analysis.energy import NEGLIGIBLE_STRAIN_SHARE
from ...analysis.modal import solve_modes
from ...analysis.reactions import static_report
from ...analysis.static import solve_static_cases
from ...model.assemble import assemble
from ...scene.gears import ISO_SOURCE, iso_stiffnesses
from ...scene.schema import load_scene
from ...scene.tables import DISPLAY_BAND_FACTOR, Scene
from .. import strict_json
from ..errors import ModeSelectionError, user_errors
from ..output import MANIFEST, staged_output, write_manifest, writing
from ..progress import Progress
from .background import Background
from .gear_cells import gear_cells, write_gears_csv
from .html import render_index
from .inertia_cells import referred_cells
from .run_frf import step_frf
from .static_tables import case_summary, static_json, static_tables, static_text, write_static_csv
from .tables import (
    BODY_TABLE_TITLE,
    ENERGY_SPLIT_HEADER,
    band_note,
    body_cells,
    comparison_cells,
    dominant_text,
    flexible_lines,
    in_band,
    modes_json,
    modes_table,
    stage_split_text,
    write_bodies_csv,
    write_comparison_csv,
    write_energy_csv,
    write_modes_csv,
)

log = logging.getLogger(__name__)


@dataclass
class RunOptions:
    """``n_modes``: how many elastic modes in the band are drawn (images, modal stresses,
    VTU); ``mode_numbers``: instead, these modes (1-based, as numbered in the mode table,
    in or outside the band); ``animated_modes``: how many of the drawn modes in the band
    are also written as animated GIFs (``animations/mode_NNN_anim.gif``; 0: none); ``compare``:
    torsional vs rigid comparison; ``images``: render PNGs (and the animations);
    ``window_size``: image size (pixels)."""

    n_modes: int = 12
    mode_numbers: Optional[tuple] = None
    animated_modes: int = 3
    compare: bool = True
    images: bool = True
    window_size: tuple = (1200, 900)


@dataclass
class RunContext:
    """State passed from step to step. ``work`` is the temporary output folder."""

    scene_source: str
    out_dir: Path
    work: Path
    options: RunOptions
    scene: object = None
    model: object = None
    result: object = None
    infos: list = field(default_factory=list)
    variants: dict = field(default_factory=dict)      # fidelity -> (model, result, infos)
    comparison: list = field(default_factory=list)    # rows (dicts)
    overview: Optional[tuple] = None
    key_images: list = field(default_factory=list)    # (relpath, caption): shown first (_render_key_images)
    images: list = field(default_factory=list)        # (relpath, caption, mode index)
    animations: list = field(default_factory=list)    # (relpath, caption, mode index): animated GIFs
    plots: list = field(default_factory=list)         # (relpath, caption)
    stresses: list = field(default_factory=list)      # (relpath, caption): von Mises under the load cases
    modal_stresses: list = field(default_factory=list)  # (relpath, caption): von Mises of the drawn modes
    files: list = field(default_factory=list)         # (relpath, description)
    notes: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)
    statics: list = field(default_factory=list)       # StaticResult per load case (step_static)
    static_reports: list = field(default_factory=list)  # StaticReport per load case
    timings_detail: dict = field(default_factory=dict)   # sub-parts of steps (per image, per case), s
    skipped: list = field(default_factory=list)        # what --no-images left out
    overlap_recovery: bool = False   # step_render starts the modal stress recovery (run_pipeline sets it)
    recovery: Optional[tuple] = None  # (amplitudes, seconds they took, Background job) of that recovery

    def add_file(self, rel: str, description: str) -> Path:
        self.files.append((rel, description))
        p = self.work / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        return p

    def elastic_modes(self) -> list:
        r = self.result
        return list(range(r.n_rigid, len(r.frequencies_hz)))

    def drawn_modes(self) -> list:
        """0-based indices of the modes drawn (images, modal stresses, VTU): the selection
        ``options.mode_numbers``, else the first ``options.n_modes`` elastic modes in the band
        (:func:`assembly.app.report.tables.in_band`)."""
        if self.options.mode_numbers is not None:
            return [n - 1 for n in self.options.mode_numbers]
        band = in_band(self.result)
        return [i for i in self.elastic_modes() if band[i]][: self.options.n_modes]

    def animated_modes(self) -> list:
        """0-based indices of the modes animated: the first ``options.animated_modes`` elastic
        drawn modes in the band (:meth:`drawn_modes`)."""
        band, r = in_band(self.result), self.result
        return [i for i in self.drawn_modes() if band[i] and i >= r.n_rigid][: self.options.animated_modes]


@dataclass(frozen=True)
class Step:
    """A pipeline step: ``run(ctx, bar)``; ``total(ctx)`` sizes its progress bar;
    ``writes``: it writes result files (OSErrors about them become one-line errors)."""

    name: str
    run: Callable
    total: Callable = lambda ctx: 1
    unit: str = "step"
    writes: bool = False


# --------------------------------------------------------------------------------------
# Steps
# --------------------------------------------------------------------------------------

def step_load(ctx: RunContext, bar) -> None:
    """Read the scene file, unless the caller gave a Scene object (``ctx.scene``); note the mesh
    stiffnesses that came from ISO 6336-1."""
    if ctx.scene is None:
        ctx.scene = load_scene(ctx.scene_source)
    derived = iso_stiffnesses(ctx.scene)
    if derived:
        ctx.notes.append(f"mesh stiffness from {ISO_SOURCE} (c_gamma_alpha x face width, solid gears; typed "
                         f"where given): " + "; ".join(f"{p} = {k:.4g} N/m" for p, k in derived))


def scene_source(scene) -> str:
    """What ``scene`` (a path, a shipped name or a Scene object) is called in the report."""
    return f"Python scene object {scene.name!r}" if isinstance(scene, Scene) else str(scene)


def step_assemble(ctx: RunContext, bar) -> None:

    ctx.model = assemble(ctx.scene)


def step_solve(ctx: RunContext, bar) -> None:

    ctx.result = solve_modes(ctx.model)
    ctx.infos = classify_modes(ctx.result)
    check_mode_numbers(ctx.options.mode_numbers, len(ctx.result.frequencies_hz))


def check_mode_numbers(numbers, n: int) -> None:
    """Raise ModeSelectionError unless every mode number (1-based) is within 1..n."""
    bad = [k for k in numbers or () if not 1 <= k <= n]
    if bad:
        raise ModeSelectionError(f"--modes {','.join(map(str, numbers))}: mode {bad[0]} does not exist: "
                                 f"the scene has {n} modes (1-{n})")


def step_compare(ctx: RunContext, bar) -> None:
    """Torsional, rigid (and flexible) variants of the scene, paired by MAC ->
    ``ctx.comparison`` (rows of :func:`assembly.analysis.compare.compare`)."""

    if not ctx.options.compare:
        bar.update(bar.total - bar.n)
        return
    try:
        c = compare(ctx.scene, given=ctx.result)  # the scene as given is solved already
    except user_errors() as exc:
        ctx.notes.append(f"fidelity comparison not possible: {exc}")
        log.warning("comparison failed: %s", exc)
        bar.update(bar.total - bar.n)
        return
    for fid, r in c.results.items():
        ctx.variants[fid] = (r.model, r, classify_modes(r))
    ctx.comparison = [row for row in c.rows if row["class"] != "rigid-body"]
    ctx.timings.update({f"{k} model": v["total_s"] for k, v in c.timings.items()})
    bar.update(bar.total - bar.n)


def comparison_fields(ctx) -> list:
    fids = [f for f in ALL_FIDELITIES if f in ctx.variants]
    return ["mode"] + fids + [f"mac_{f}" for f in fids[:-1]] + ["class", "dominant_body"]


def step_tables(ctx: RunContext, bar) -> None:
    res = ctx.result
    write_modes_csv(ctx.infos, ctx.add_file("modes.csv", "frequencies and mode table, every mode, in_band flag (CSV)"),
                    in_band(res))
    write_energy_csv(ctx.result, ctx.infos,
                     ctx.add_file("energy_by_mode.csv", "kinetic and strain energy shares of every mode per stage, "
                                  "body, bearing, mesh and shaft (CSV)"))
    with open(ctx.add_file("modes.json", "frequencies, classes, energy shares and shapes (JSON)"), "w") as fh:
        fh.write(strict_json.dumps(modes_json(res), indent=1))
    ctx.add_file("modes_table.txt", "mode table (text)").write_text(
        modes_table(res, title=f"{ctx.scene.name}  ({ctx.scene_source})") + "\n")
    write_bodies_csv(ctx.model, ctx.add_file("bodies.csv", "bodies: mass, polar and transverse inertia, centre "
                                                           "of mass and their source (CSV; kg, kg m^2, m)"))
    if ctx.model.scene.meshes:
        write_gears_csv(ctx.model, ctx.add_file("gears.csv", "gear table: derived radii, angles, centre distance, "
                                                             "contact ratios, mesh stiffness and its source (CSV; m, rad, N/m)"))
    if ctx.comparison:
        write_comparison_csv(ctx.comparison, comparison_fields(ctx),
                             ctx.add_file("fidelity_comparison.csv", "fidelities side by side, paired by MAC (CSV; Hz)"))


def _render_total(ctx: RunContext) -> int:
    if not ctx.options.images:
        return 1
    return 3 + len(ctx.drawn_modes()) + len(ctx.animated_modes())


def _band_text(ctx, i: int) -> str:
    return "" if in_band(ctx.result)[i] else "; outside the band"


def step_render(ctx: RunContext, bar) -> None:
    from ..render.renderer import AssemblyRenderer

    if ctx.overlap_recovery:
        _start_modal_recovery(ctx)
    if not ctx.options.images:
        ctx.skipped += ["the overview", f"{len(ctx.drawn_modes())} mode-shape images"]
        if ctx.animated_modes():
            ctx.skipped.append(f"{len(ctx.animated_modes())} mode animations")
        bar.update(1)
        return
    rnd = AssemblyRenderer(ctx.model, window_size=ctx.options.window_size)
    try:
        _render_images(ctx, rnd, bar)
    finally:
        rnd.close()


def _render_images(ctx: RunContext, rnd, bar) -> None:
    from ..render.renderer import mode_title

    rel = "images/overview.png"
    t0 = time.perf_counter()
    rnd.render_overview(ctx.add_file(rel, "undeformed assembly, one label per stage (PNG)"),
                        title=f"{ctx.scene.name}: assembly")
    ctx.timings_detail[rel] = time.perf_counter() - t0
    capped = [f"{n} is lumped: drawn as a hub of the largest gear's radius"
              for n, s in rnd.shapes.items() if s.equivalent_radius > 0]
    ctx.key_images.append((rel, "assembly, undeformed, one colour and label per stage (springs: bearings grey, "
                                "meshes red, shafts blue; beam shafts as cylinders of their diameter)"
                           + "".join(f"; {c}" for c in capped)))
    bar.update(1)
    _render_key_modes(ctx, rnd, bar)
    for i in ctx.drawn_modes():
        mi = ctx.infos[i]
        rel = f"images/mode_{i + 1:03d}.png"
        t0 = time.perf_counter()
        rnd.render_mode(ctx.result, i, ctx.add_file(rel, f"mode {i + 1} shape (PNG)"),
                        title=mode_title(ctx.scene.name, mi))
        ctx.timings_detail[rel] = time.perf_counter() - t0
        dom = dominant_text(mi)
        ctx.images.append((rel, f"mode {i + 1}: {mi.frequency_hz:.2f} Hz, {mi.mode_class}"
                                + (f" (x{mi.multiplicity})" if mi.multiplicity > 1 else "")
                                + (f"; kinetic energy: {dom}" if dom else "") + _band_text(ctx, i), i))
        bar.update(1)
    _render_animations(ctx, rnd, bar)


def _render_animations(ctx: RunContext, rnd, bar) -> None:
    """``animations/mode_NNN_anim.gif`` of :meth:`RunContext.animated_modes`
    (:mod:`assembly.app.render.animation`), drawn with the stills' renderer; a run without
    such a mode (none asked for, or none drawn in the band) says so in a note."""
    from ..render.animation import FRAMES, PERIOD_S, animate_modes
    from ..render.renderer import mode_title

    modes = ctx.animated_modes()
    if not modes:
        why = ("animated_modes = 0" if ctx.options.animated_modes <= 0 else
               f"no elastic mode drawn is in the band (up to {ctx.scene.display_limit_hz:.0f} Hz)")
        ctx.notes.append(f"no mode animations: {why}")
        return
    rels = {i: f"animations/mode_{i + 1:03d}_anim.gif" for i in modes}
    jobs = [(i, ctx.add_file(rels[i], f"mode {i + 1} shape over one period, {FRAMES} frames (animated GIF)"),
             mode_title(ctx.scene.name, ctx.infos[i])) for i in modes]
    for a in animate_modes(rnd, ctx.result, jobs):
        mi = ctx.infos[a.mode]
        ctx.timings_detail[rels[a.mode]] = a.seconds
        ctx.animations.append((rels[a.mode], f"mode {a.mode + 1}: {mi.frequency_hz:.2f} Hz, {mi.mode_class}: one "
                               f"period in {FRAMES} frames ({PERIOD_S:g} s a loop), the still image's deformation "
                               "times cos(2 pi t); colour: displacement at that instant / largest", a.mode))
        bar.update(1)


def _render_key_modes(ctx: RunContext, rnd, bar) -> None:
    """``images/global_torsional.png`` (twist arrows, whole drivetrain framed) and
    ``images/stage_local.png`` (framed on the stage), picked by :mod:`assembly.app.report.key_modes`;
    a scene without such a mode gets a note instead of the picture."""
    from ..render.renderer import mode_title
    from .key_modes import global_torsional_mode, stage_local_mode
    n_rigid = ctx.result.n_rigid
    picks = [("global_torsional", global_torsional_mode(ctx.infos, n_rigid), "the lowest rotational global mode"),
             ("stage_local", stage_local_mode(ctx.infos, n_rigid, ctx.model.scene), "the lowest stage-local mode")]
    for tag, i, what in picks:
        if i is None:
            ctx.notes.append(f"no images/{tag}.png: the scene has no {what.replace('the lowest ', '')}")
            bar.update(1)
            continue
        mi = ctx.infos[i]
        rel = f"images/{tag}.png"
        t0 = time.perf_counter()
        if tag == "global_torsional":
            rnd.render_mode(ctx.result, i, ctx.add_file(rel, f"{what} (mode {i + 1}) with twist arrows (PNG)"),
                            title=mode_title(ctx.scene.name, mi), focus=tuple(ctx.model.bodies), twist=True)
            cap = (f"{what}: mode {i + 1}, {mi.frequency_hz:.2f} Hz; arrows: each body's angle divided by its "
                   f"speed ratio (referred to the rotor shaft), bodies undeformed, coloured by displacement")
        else:
            focus = tuple(b.name for b in ctx.model.scene.bodies   # a ring would hide its planets: faint
                          if (b.stage or b.name) == mi.scope and b.role != "ring") or None
            rnd.render_mode(ctx.result, i, ctx.add_file(rel, f"{what} (mode {i + 1}) (PNG)"),
                            title=mode_title(ctx.scene.name, mi), focus=focus)
            cap = f"{what}: mode {i + 1}, {mi.frequency_hz:.2f} Hz, {mi.mode_class}, held by {mi.scope}"
        ctx.timings_detail[rel] = time.perf_counter() - t0
        ctx.key_images.append((rel, cap + _band_text(ctx, i)))
        bar.update(1)


def step_plots(ctx: RunContext, bar) -> None:
    from ..plots import plot_fidelity_frequencies


    cols, pairs = [], []
    if ctx.variants:
        fids = [f for f in ALL_FIDELITIES if f in ctx.variants]
        for fid in fids:
            r = ctx.variants[fid][1]
            cols.append((fid, r.frequencies_hz, r.n_rigid))
        for k in range(len(fids) - 1):
            lo, hi = ctx.variants[fids[k]][1], ctx.variants[fids[k + 1]][1]
            pairs.append((k, k + 1, [(i, j, mac) for j, i, mac in pair_modes(hi, lo)
                                     if i >= lo.n_rigid and j >= hi.n_rigid]))
    else:
        cols.append(("this scene", ctx.result.frequencies_hz, ctx.result.n_rigid))
    rel = "plots/frequencies_by_fidelity.png"
    sc = ctx.scene
    plot_fidelity_frequencies(cols, ctx.add_file(rel, "natural frequencies per fidelity (PNG)"),
                              title=f"{sc.name}: natural frequencies per fidelity", pairs=pairs,
                              max_hz=sc.display_limit_hz, band_hz=sc.band)
    ctx.plots.append((rel, f"natural frequencies (Hz) per fidelity up to {sc.display_limit_hz:.0f} Hz "
                           f"(band {sc.band:.0f} Hz dashed); lines join modes paired by MAC"))


def build_report(ctx: RunContext) -> dict:
    """Plain dict for :func:`assembly.app.report.html.render_index`."""
    res = ctx.result
    img_of = {i: rel for rel, _, i in ctx.images}
    band = in_band(res)
    strain = _strain_text(ctx)
    modes_rows = []
    for mi in ctx.infos:
        if not (band[mi.index] or mi.index in img_of):
            continue
        modes_rows.append([mi.index + 1, f"{mi.frequency_hz:.2f}" + ("" if band[mi.index] else " (outside the band)"),
                           mi.multiplicity, mi.mode_class, mi.scope or "", stage_split_text(mi), dominant_text(mi),
                           strain[mi.index],
                           ("link", f"#fig-mode-{mi.index + 1:03d}", "image") if mi.index in img_of else ""])
    comp = None
    if ctx.comparison:
        fids = [f for f in ALL_FIDELITIES if f in ctx.variants]
        limit = ctx.scene.display_limit_hz           # the mode table's modes: those up to its limit
        shown = [r for r in ctx.comparison if r.get(fids[-1]) is None or r[fids[-1]] <= limit]
        cells = comparison_cells(shown, fids)
        if len(shown) < len(ctx.comparison):
            cells["notes"] = [*cells["notes"], f"{len(ctx.comparison) - len(shown)} modes above {limit:.0f} Hz left "
                                               f"out, as in the mode table (fidelity_comparison.csv has them)."]
        comp = dict(header=cells["header"], rows=cells["rows"], row_classes=cells["row_classes"],
                    left=cells["left"], fidelities=fids, note=" ".join(cells["notes"])
                    + " Orange rows: a MAC < 0.8; grey: no partner one fidelity down.")
    meta = [f"scene: {ctx.scene.name} ({ctx.scene_source})",
            f"{len(ctx.model.bodies)} bodies, {len(ctx.model.elements)} springs, {ctx.model.K.shape[0]} DOFs, "
            f"{len(res.frequencies_hz)} modes ({res.n_rigid} rigid-body), "
            f"max relative eigen-residual {res.max_residual:.1e}",
            "units: frequency Hz, length m, angle rad; mode shapes mass-normalised (modal mass 1 kg)",
            f"band of interest band_hz = {ctx.scene.band:.0f} Hz; tables, plots and images show modes up to "
            f"{ctx.scene.display_limit_hz:.0f} Hz ({DISPLAY_BAND_FACTOR:g} x band)"]
    meta += flexible_lines(ctx.model)
    if ctx.timings:
        meta.append("time: " + ", ".join(f"{k} {v:.2f} s" for k, v in ctx.timings.items()))
    notes = list(ctx.notes) + ([skipped_text(ctx)] if ctx.skipped else [])
    files = list(ctx.files) + [("index.html", "this page"), (MANIFEST, "run manifest (JSON)")]
    files = [(p, d) for p, d in files if not p.startswith("images/mode_")]
    cells = body_cells(ctx.model)
    bodies = dict(title=BODY_TABLE_TITLE, header=cells["header"], rows=cells["rows"], left=cells["left"],
                  notes=cells["notes"])
    gears = gear_cells(ctx.model)
    return dict(title=f"flexgear run: {ctx.scene.name}", scene=ctx.scene.name, meta=meta, bodies=bodies,
                gears=gears if gears["rows"] else None,
                referred=referred_cells(ctx.model, ctx.result),
                modes=(["mode", "f [Hz]", "mult.", "class", "scope", ENERGY_SPLIT_HEADER, "dominant bodies (kinetic energy)",
                        "strain energy in flexible bodies", ""], modes_rows),
                modes_note=band_note(res, int(len(ctx.infos) - len(modes_rows))),
                comparison=comp, sections=static_sections(ctx), overview=ctx.overview, key_images=list(ctx.key_images),
                images=[(rel, cap) for rel, cap, _ in ctx.images], plots=list(ctx.plots),
                stresses=list(ctx.stresses), modal_stresses=list(ctx.modal_stresses),
                animations=[(rel, cap) for rel, cap, _ in ctx.animations],
                files=files, notes=notes)


def skipped_text(ctx) -> str:
    """What ``--no-images`` left out (one line; "" when nothing was)."""
    if not ctx.skipped:
        return ""
    what = ", ".join(ctx.skipped[:-1]) + (" and " if len(ctx.skipped) > 1 else "") + ctx.skipped[-1]
    return f"--no-images: skipped {what}; VTU files, stress tables and plots are still written"


def _strain_text(ctx) -> list:
    """Per mode: the flexible bodies' shares of its strain energy, largest first ("" without
    flexible bodies); the rest of the strain energy is in the springs."""
    from ...analysis.energy import strain_by_body
    flex = [j for j, b in enumerate(ctx.model.bodies) if ctx.model.bodies[b].flexible]
    if not flex:
        return [""] * len(ctx.infos)
    names = list(ctx.model.bodies)
    S = strain_by_body(ctx.result)
    return ["; ".join(f"{names[j]} {100 * S[i, j]:.3g}%" for j in sorted(flex, key=lambda j: -S[i, j]))
            for i in range(S.shape[0])]


def step_static(ctx: RunContext, bar) -> None:
    """Every load case of the scene on the assembled model (one factorisation): mesh
    forces, bearing reactions, shaft loads and checks -> ``static.csv``, ``static.json``,
    ``static_table.txt`` and a report section; the solutions are kept for stress recovery."""
    if not ctx.scene.load_cases():
        bar.update(bar.total - bar.n)
        return
    ctx.statics = solve_static_cases(ctx.model)
    ctx.static_reports = [static_report(st) for st in ctx.statics]
    write_static_csv(ctx.static_reports, ctx.add_file("static.csv", "static load cases: forces, reactions, "
                                                                   "checks (CSV; N, N m)"))
    with open(ctx.add_file("static.json", "static load cases: forces, reactions, checks (JSON; N, N m)"), "w") as fh:
        fh.write(strict_json.dumps(static_json(ctx.scene.name, ctx.static_reports, ctx.model, ctx.result), indent=1))
    ctx.add_file("static_table.txt", "static load cases (text)").write_text(
        static_text(ctx.static_reports, title=f"{ctx.scene.name}  ({ctx.scene_source})", model=ctx.model,
                    result=ctx.result) + "\n")
    for r in ctx.static_reports:
        note = f"load case {r.case!r}: {case_summary(r)}; equilibrium error {r.equilibrium['relative_error']:.1e}"
        if r.balance:
            note += f", torque balance error {r.balance['relative_error']:.1e}"
        if r.ratio:
            note += (f", ratio check error {r.ratio['relative_error']:.1e}" if r.ratio["relative_error"] is not None
                     else f", ratio check: {r.ratio['note']}")
        ctx.notes.append(note)
    bar.update(bar.total - bar.n)


def static_sections(ctx) -> list:
    """Report sections (title, note, tables) of the static load cases."""
    return [dict(title=f"Static load case {r.case!r} ({case_summary(r)})",
                 note="Forces from the springs (stiffness x relative deflection); sign conventions: docs/static.md.",
                 tables=[t for t in static_tables(r) if t[2]]) for r in ctx.static_reports]


def _flexible_bodies(ctx) -> list:
    return [n for n, bm in ctx.model.bodies.items() if bm.flexible]


def _recovery_total(ctx) -> int:
    n_cases = len(ctx.scene.load_cases())
    return 1 + len(_flexible_bodies(ctx)) * (n_cases + len(ctx.drawn_modes()))


def step_recovery(ctx: RunContext, bar) -> None:
    """Flexible bodies: static load case (if the scene has one; MPa of the physical load)
    and modal stresses of the drawn modes, each mode scaled to MODAL_PEAK_DISPLACEMENT_M
    peak displacement of the flexible bodies (:mod:`assembly.analysis.modal_stress`), back-expanded
    to the FE meshes; bodies without strain energy in a mode are skipped. Stress images,
    VTU files + one .pvd collection, ``stress.csv`` (load cases) and ``modal_stress.csv``."""
    from ...analysis.modal_stress import IMAGE_STRAIN_SHARE, MODAL_AMPLITUDE_LABEL, drawn, modal_amplitudes
    from ..render.fe import StressImages

    flex = _flexible_bodies(ctx)
    if not flex:
        bar.update(bar.total - bar.n)
        return
    cases = []  # (label, model, z)
    cases += [(st.load.name, st.model, st.z) for st in ctx.statics]   # solved by step_static
    titled = {st.load.name: _case_label(st, r) for st, r in zip(ctx.statics, ctx.static_reports)}
    if ctx.recovery is not None:   # the drawn modes' stresses and VTU files, computed during step_render
        amps, scaling_s, job = ctx.recovery
        done = job.results()
        ctx.recovery = None
    else:
        t0 = time.perf_counter()
        amps, done = modal_amplitudes(ctx.result, ctx.drawn_modes()), {}
        scaling_s = time.perf_counter() - t0
    ctx.timings_detail["stress: modal scaling"] = scaling_s
    bar.update(1)
    rows, mrows, collection = [], [], []
    images = StressImages(ctx.options.window_size) if ctx.options.images else None
    n_images = undrawn = 0
    try:
        for b in flex:
            bm = ctx.model.bodies[b]
            entries = [(lbl, "load" if len(cases) == 1 else f"load_{k + 1:02d}", z[m.body_slice(b)], None)
                       for k, (lbl, m, z) in enumerate(cases)]
            entries += [(f"mode {a.mode + 1} ({ctx.result.frequencies_hz[a.mode]:.1f} Hz)", f"mode_{a.mode + 1:03d}",
                         a.factor * ctx.result.abs_shapes[ctx.model.body_slice(b), a.mode], a) for a in amps]
            for label, tag, zb, a in entries:
                if a is not None and b in a.skipped:
                    mrows.append(_modal_row(ctx, b, a, None))
                    bar.update(1)
                    continue
                vtu = f"vtu/{b}_{tag}.vtu"
                what = "" if a is None else f" at {MODAL_AMPLITUDE_LABEL}"
                path = ctx.add_file(vtu, f"{b}: {label}{what} (VTU)")
                if a is not None and (b, a.mode) in done:   # written by the background job
                    st, dt = done[(b, a.mode)]
                else:
                    t1 = time.perf_counter()
                    st = _stress_and_vtu(bm, zb, path)
                    dt = time.perf_counter() - t1
                j = int(np.argmax(st.von_mises))
                loc = bm.origin + bm.axes @ st.points[j]
                where = {"x_m": float(loc[0]), "y_m": float(loc[1]), "z_m": float(loc[2])}
                if a is None:
                    rows.append({"body": b, "case": label, "max_von_mises_Pa": float(st.von_mises[j]), **where})
                else:
                    mrows.append(_modal_row(ctx, b, a, (float(st.von_mises[j]), where)))
                collection.append((len(collection), vtu))
                ctx.timings_detail[f"stress+vtu {b} {tag}"] = dt
                if a is not None and not drawn(a, b):       # too small a share of the mode: no picture
                    undrawn += 1
                else:                     # von Mises image for the load case and every drawn mode
                    if images is not None:
                        _stress_image(ctx, images, b, st, titled.get(label, label) if a is None else label, tag, a)
                    n_images += 1
                bar.update(1)
    finally:
        if images is not None:
            images.close()
    if images is None:
        ctx.skipped.append(f"{n_images} stress images")
    if undrawn:
        ctx.notes.append(f"modal stress images: {undrawn} of a body holding less than {IMAGE_STRAIN_SHARE:.0%} of "
                         f"the mode's strain energy not drawn (their stresses are in modal_stress.csv)")
    _write_recovery_files(ctx, rows, mrows, collection)


def _stress_and_vtu(bm, zb, path):
    """Stresses of flexible body ``bm`` for body DOFs ``zb`` and their VTU file at ``path``."""
    st = bm.stress(zb)
    _write_body_vtu(bm, zb, st, path)
    return st


def _start_modal_recovery(ctx: RunContext) -> None:
    """Start the stresses and VTU files of the drawn modes of every flexible body in a
    background thread (:class:`assembly.app.report.background.Background`), collected by
    :func:`step_recovery`; the load cases (solved later, by step_static) stay there. The
    bodies' FE models are loaded here first, so the thread and the renderer never build one
    at the same time."""
    from ...analysis.modal_stress import modal_amplitudes

    flex = _flexible_bodies(ctx)
    if not flex:
        return
    t0 = time.perf_counter()
    amps = modal_amplitudes(ctx.result, ctx.drawn_modes())
    scaling_s = time.perf_counter() - t0
    items = []
    for b in flex:
        bm = ctx.model.bodies[b]
        bm.coupled()
        for a in amps:
            if b in a.skipped:
                continue
            path = ctx.work / f"vtu/{b}_mode_{a.mode + 1:03d}.vtu"
            path.parent.mkdir(parents=True, exist_ok=True)
            items.append(((b, a.mode), (bm, a.factor * ctx.result.abs_shapes[ctx.model.body_slice(b), a.mode], path)))
    ctx.recovery = (amps, scaling_s, Background(items, _stress_and_vtu, "modal stress recovery"))


def _case_label(st, rep) -> str:
    """A load case as named in stress tables and images: its name and the torque it puts in."""
    if rep.torque_Nm is None:
        return st.load.name
    return f"{st.load.name} ({rep.torque_Nm:.4g} N m into {rep.input})"


def _stress_image(ctx: RunContext, images, b: str, st, label: str, tag: str, a) -> None:
    """The von Mises image of flexible body ``b`` for stresses ``st`` of a load case
    (``a`` None) or of a drawn mode (``a``: its ModalAmplitude), with title and caption."""
    from ...analysis.modal_stress import MODAL_AMPLITUDE_LABEL
    rel = f"images/stress_{b}_{tag}.png"
    what = "" if a is None else f" at {MODAL_AMPLITUDE_LABEL}"
    if a is None:
        title = f"{ctx.scene.name}: {b}, von Mises [MPa], {label}"
        cap = f"von Mises stress on {b}: {label} (MPa)"
    else:
        title = (f"{ctx.scene.name}: {b}, {label}, von Mises [MPa] at {MODAL_AMPLITUDE_LABEL}\n"
                 f"strain energy: {_share_text(a)} of the mode's")
        cap = (f"von Mises stress on {b}: {label}, MPa at {MODAL_AMPLITUDE_LABEL}; strain energy "
               f"{_share_text(a)}" + _band_text(ctx, a.mode))
    images.render(ctx.model.bodies[b], st, ctx.add_file(rel, f"{b} von Mises, {label}{what} (PNG)"), title)
    ctx.timings_detail[rel] = images.timings[-1]
    (ctx.stresses if a is None else ctx.modal_stresses).append((rel, cap))


def _write_recovery_files(ctx: RunContext, rows: list, mrows: list, collection: list) -> None:
    """``stress.csv`` (load cases), ``modal_stress.csv`` (drawn modes), the ``results.pvd``
    collection of the VTU files and the notes of :func:`step_recovery`."""
    from ...analysis.modal_stress import MODAL_AMPLITUDE_LABEL
    if rows:
        with open(ctx.add_file("stress.csv", "max von Mises per flexible body and load case (CSV; Pa, m)"), "w",
                  newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    if mrows:
        with open(ctx.add_file("modal_stress.csv", f"max von Mises per flexible body and drawn mode at "
                                                   f"{MODAL_AMPLITUDE_LABEL} (CSV; Pa, m)"), "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(mrows[0]))
            w.writeheader()
            w.writerows(mrows)
    pvd = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="0.1">', "<Collection>"]
    pvd += [f'<DataSet timestep="{t}" part="0" file="{f}"/>' for t, f in collection]
    pvd += ["</Collection>", "</VTKFile>"]
    ctx.add_file("results.pvd", "ParaView collection of all VTU files of this run").write_text("\n".join(pvd) + "\n")
    for r in rows:
        ctx.notes.append(f"{r['body']}, {r['case']}: max von Mises {r['max_von_mises_Pa'] / 1e6:.4g} MPa at "
                         f"({r['x_m']:.4f}, {r['y_m']:.4f}, {r['z_m']:.4f}) m")
    if mrows:
        ctx.notes.append(f"modal stresses: each drawn mode scaled to {MODAL_AMPLITUDE_LABEL} (stresses scale "
                         "linearly with the amplitude); a flexible body with less than "
                         f"{NEGLIGIBLE_STRAIN_SHARE:g} of a mode's strain energy is skipped in that mode")


def _share_text(a) -> str:
    return ", ".join(f"{b} {100 * v:.3g}%" for b, v in sorted(a.strain_share.items(), key=lambda kv: -kv[1]))


def _modal_row(ctx, body: str, a, peak) -> dict:
    """modal_stress.csv row of ``body`` in mode ``a`` (ModalAmplitude); ``peak``:
    (max von Mises Pa, location dict) or None for a body skipped (no strain energy)."""
    from ...analysis.modal_stress import MODAL_PEAK_DISPLACEMENT_M, MODAL_STRESS_COLUMN
    vm, where = peak if peak is not None else (None, {"x_m": None, "y_m": None, "z_m": None})
    return {"mode": a.mode + 1, "frequency_hz": float(ctx.result.frequencies_hz[a.mode]), "body": body,
            "strain_energy_share": a.strain_share[body], "carries_most_strain_energy": int(body == a.carrier),
            "peak_displacement_m": MODAL_PEAK_DISPLACEMENT_M, "modal_coordinate_kg05": a.factor,
            MODAL_STRESS_COLUMN: vm, **where,
            "skipped": "" if peak is not None else "negligible strain energy"}


def _write_body_vtu(bm, zb, stress, path) -> None:
    """Deformed shape (global displacement, m) and von Mises (Pa) of one flexible body."""
    import meshio
    fe, _ = bm.coupled()
    nodes = bm.nodes_global()
    cells = fe.basis.element_dofs[0::3, :].T // 3
    data = {"displacement_m": bm.displacement_global(zb), "von_mises_Pa": stress.von_mises[: len(nodes)]}
    tmp = path.with_name(path.name + ".tmp")
    meshio.write(tmp, meshio.Mesh(nodes, [("tetra10" if fe.order == 2 else "tetra", cells)], point_data=data),
                 file_format="vtu")
    os.replace(tmp, path)


def step_html(ctx: RunContext, bar) -> None:

    text = render_index(build_report(ctx))
    (ctx.work / "index.html").write_text(text, encoding="utf-8")


DEFAULT_STEPS = [
    Step("load scene", step_load),
    Step("assemble", step_assemble),
    Step("eigen solve", step_solve),
    Step("fidelity comparison", step_compare, total=lambda ctx: 3 if ctx.options.compare else 1, unit="model"),
    Step("tables", step_tables, writes=True),
    Step("mode-shape images", step_render, total=_render_total, unit="image", writes=True),
    Step("plots", step_plots, writes=True),
    Step("frequency response", step_frf, writes=True),
    Step("static load cases", step_static, writes=True),
    Step("stress recovery and VTU", step_recovery, total=_recovery_total, unit="case", writes=True),
    Step("index.html", step_html, writes=True),
]


def run_pipeline(scene, out_dir, options: RunOptions | None = None, progress=None,
                 steps: list | None = None) -> RunContext:
    """Run ``steps`` (default :data:`DEFAULT_STEPS`) on ``scene`` (path, shipped name or a
    :class:`~assembly.scene.tables.Scene`) and place the results in ``out_dir`` atomically. Returns the final context."""

    options = options or RunOptions()
    progress = progress or Progress(enabled=False)
    out_dir = Path(out_dir).absolute()
    t_all = time.perf_counter()
    with staged_output(out_dir) as work:
        ctx = RunContext(scene_source(scene), out_dir, work, options, scene=scene if isinstance(scene, Scene) else None)
        runs = [st.run for st in steps or DEFAULT_STEPS]
        ctx.overlap_recovery = step_render in runs and step_recovery in runs[runs.index(step_render):]
        try:
            for st in steps or DEFAULT_STEPS:
                t0 = time.perf_counter()
                with progress.step(st.name, total=max(1, int(st.total(ctx))), unit=st.unit) as bar, \
                        (writing(out_dir, work, st.name) if st.writes else nullcontext()):
                    st.run(ctx, bar)
                ctx.timings[st.name] = time.perf_counter() - t0
        finally:   # an interrupted run: no thread keeps writing into the folder being removed
            if ctx.recovery is not None:
                ctx.recovery[2].stop()
        ctx.timings["total"] = time.perf_counter() - t_all
        manifest = dict(
            tool="flexgear run", scene=ctx.scene.name if ctx.scene is not None else None,
            scene_source=ctx.scene_source, options=dict(n_modes=options.n_modes, animated_modes=options.animated_modes,
                                                        compare=options.compare,
                                                        images=options.images,
                                                        window_size=list(options.window_size)),
            files=[p for p, _ in ctx.files] + ["index.html"],
            timings_s={k: round(v, 4) for k, v in ctx.timings.items()},
            timings_detail_s={k: round(v, 4) for k, v in ctx.timings_detail.items()},
            notes=ctx.notes, python=sys.version.split()[0])
        with writing(out_dir, work, MANIFEST):
            write_manifest(work, manifest)
    ctx.work = out_dir
    log.info("wrote %s in %.2f s", out_dir, ctx.timings["total"])
    return ctx
