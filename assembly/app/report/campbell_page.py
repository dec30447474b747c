"""``index.html`` of ``flexgear campbell --out``: the diagram, the ranked crossings (the first
:data:`SHOWN` of them; ``crossings.csv`` has all), the excitation orders and the modes, in the
style of every flexgear page (:mod:`assembly.app.report.page`)."""
from __future__ import annotations

from .page import Section, figure, files_list, note, page, table

#: Ranked crossings shown on the page.
SHOWN = 60


def verdict(ok) -> str:
    """A crossing's ``excitable`` as a word: yes, no or undecided."""
    return {True: "yes", False: "no", None: "undecided"}[ok]


def campbell_page(c, rated_rpm: float | None = None, more=()) -> str:
    """The page of the Campbell diagram ``c`` (:class:`assembly.dynamics.campbell.Campbell`);
    ``more``: further :class:`~assembly.app.report.page.Section` (after the crossings)."""
    ranked = c.ranked()
    able = sum(1 for x in c.crossings if x.excitable is not False)
    rows = [[k + 1, x.order, x.harmonic, f"{x.speed_rpm:.5g}", f"{x.frequency_hz:.4f}", x.mode, x.mode_class,
             x.scope or "", f"{x.share:.2g}", verdict(x.excitable), x.rule] for k, x in enumerate(ranked[:SHOWN])]
    shown = ("" if len(ranked) <= SHOWN else
             f"<p class=\"meta\">The first {SHOWN} of {len(ranked)} crossings; crossings.csv has every one.</p>")
    crossings = (f'<p class="meta">{len(c.crossings)} crossings, {able} the exciter can drive, ranked by the '
                 "exciter's share of the mode's energy (what it cannot excite last).</p>" + shown
                 + table(["#", "order", "h", "speed [rpm]", "f [Hz]", "mode", "class", "scope", "share", "excites",
                          "rule"], rows))
    orders = table(["order", "kind", "source", "harmonic", "Hz per rpm"],
                   [[o.name, o.kind, o.source, o.harmonic, f"{o.hz_per_rpm:.6g}"] for o in c.orders])
    modes = table(["mode", "f [Hz]", "class", "scope"],
                  [[m.index + 1, f"{m.frequency_hz:.4f}", m.mode_class, m.scope or ""] for m in c.modes])
    rated = "" if rated_rpm is None else f", rated {rated_rpm:g} rpm"
    diagram = figure("campbell.png", f"{c.scene}: natural frequencies against {c.reference} speed, the excitation "
                     "orders and their crossings", single=True)
    sections = [Section("Campbell diagram", diagram, "Diagram"),
                Section("Crossings, ranked", crossings, "Crossings"), *more,
                Section("Excitation orders", orders, "Orders"), Section("Modes", modes),
                Section("Files", files_list([("crossings.csv", "every crossing, ranked (CSV)"),
                                             ("campbell.json", "orders, modes, speeds, frequencies and crossings "
                                                               "(JSON)"), ("campbell.png", "the diagram (PNG)")]))]
    meta = [f"reference {c.reference}, {c.speeds_rpm[0]:g}-{c.speeds_rpm[-1]:g} rpm{rated}, {len(c.orders)} orders, "
            f"{len(c.modes)} modes" + (", gyroscopic" if c.gyroscopic else ""),
            "units: speed rpm of the reference, frequency Hz"]
    return page(f"{c.scene}: Campbell diagram", sections, command="flexgear campbell", scene=c.scene, meta=meta,
                lead="".join(note(n) for n in c.notes))
