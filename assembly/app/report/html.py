"""Static ``index.html`` of a run: tables and images with relative links, no server needed.

:func:`render_index` turns a plain report dict (built by :mod:`assembly.app.report.pipeline`) into one
self-contained HTML page in the style of every flexgear page (:mod:`assembly.app.report.page`).
"""
from __future__ import annotations

from pathlib import Path
from urllib.parse import urlsplit

from .links import read_page
from .page import Section, esc, figure, files_list, grid, note, page, para, table

__all__ = ["render_index", "run_sections", "figure", "local_references", "missing_references"]


def render_index(report: dict) -> str:
    """HTML text of the run page (:func:`assembly.app.report.page.page`). ``report`` keys: title,
    scene, meta (list of str), modes (header, rows), modes_note (str: rows left out), bodies
    (title, header, rows, left, notes: the bodies' mass properties; optional), gears (the same
    keys: the gear table; optional), referred (the same keys: inertia referred to each shaft;
    optional), comparison (header, rows, row_classes, note) or None, sections [{title, note,
    tables: [(title, header, rows, left columns)], label (optional: the navigation's name, by
    default the title without its parenthesis)}] (optional), key_images [(path, caption)]
    shown first (optional), overview (path, caption) or None, images [(path, caption)], animations [(path, caption)]
    (optional), plots
    [(path, caption)], stresses and modal_stresses [(path, caption)]: the von Mises images of
    the load cases and of the drawn modes (optional), files [(path, description)], notes [str] (after the pictures), pages [(file,
    label)]: the folder's pages (optional)."""
    return page(report["title"], run_sections(report), command="flexgear run", scene=report.get("scene", ""),
                meta=report.get("meta", []), pages=report.get("pages", ()))


def _described(title: str, label: str, t: dict) -> Section:
    """A table of ``t`` (title, header, rows, left, notes) under ``title``."""
    body = [para(t["title"], "meta")]
    if t["rows"]:
        body.append(table(t["header"], t["rows"], left=t.get("left", ())))
    body += [note(n) for n in t.get("notes", [])]
    return Section(title, "\n".join(body), label)


def run_sections(report: dict) -> list:
    """The run page's :class:`Section` list, in page order (keys of :func:`render_index`)."""
    out = []
    if report.get("key_images"):   # the drivetrain pictures come first
        out.append(Section("Drivetrain pictures", grid(report["key_images"]), "Pictures"))
    if report.get("notes"):
        out.append(Section("Notes", "".join(note(n) for n in report["notes"])))
    hdr, rows = report["modes"]
    body = table(hdr, rows, left=range(3, len(hdr)))
    if report.get("modes_note"):
        body += "\n" + para(report["modes_note"], "meta")
    out.append(Section("Natural frequencies and mode table", body, "Modes"))
    for key, title, label in (("bodies", "Bodies: mass properties", "Bodies"),
                              ("gears", "Gear meshes: geometry, contact ratios, stiffness", "Gears"),
                              ("referred", "Inertia referred to each shaft", "Referred inertia")):
        if report.get(key):
            out.append(_described(title, label, report[key]))
    comp = report.get("comparison")
    if comp:
        fids = comp.get("fidelities") or ["torsional", "rigid"]
        body = (para(comp["note"], "meta") if comp.get("note") else "") + table(
            comp["header"], comp["rows"], left=comp.get("left", ()), row_classes=comp.get("row_classes"))
        out.append(Section(f"Fidelity comparison ({' vs '.join(fids)}, modes paired by MAC)", body, "Fidelities"))
    for sec in report.get("sections", []):   # e.g. static load cases: (title, header, rows, left) tables
        body = para(sec["note"], "meta") if sec.get("note") else ""
        body += "".join(f"<h3>{esc(title)}</h3>" + table(header, rows, left=left)
                        for title, header, rows, left in sec["tables"])
        out.append(Section(sec["title"], body, sec.get("label") or sec["title"].split(" (")[0]))
    if report.get("plots"):
        out.append(Section("Plots", grid(report["plots"])))
    if report.get("stresses"):
        out.append(Section("Stresses under the load cases", grid(report["stresses"]), "Stresses"))
    if report.get("modal_stresses"):
        out.append(Section("Modal stresses (drawn modes)", grid(report["modal_stresses"]), "Modal stresses"))
    if report.get("overview") or report.get("images"):
        figs = ([report["overview"]] if report.get("overview") else []) + list(report.get("images", []))
        out.append(Section("Mode shapes", grid(figs)))
    if report.get("animations"):   # animated GIFs of the first drawn modes in the band
        out.append(Section("Mode animations", grid(report["animations"]), "Animations"))
    if report.get("files"):
        out.append(Section("Files", files_list(report["files"])))
    return out


def local_references(html_text: str) -> list[str]:
    """Relative file references (src/href) of a page, unescaped, without anchors/URLs: the
    page read as the folder checker reads it (:func:`assembly.app.report.links.read_page`)."""
    return [ref for _, _, ref in read_page(html_text).refs if not ref.startswith("#") and not urlsplit(ref).scheme]


def missing_references(index_path) -> list[str]:
    """References of ``index_path`` that do not name an existing file next to it."""
    p = Path(index_path)
    base = p.parent
    return [r for r in local_references(p.read_text(encoding="utf-8")) if not (base / r).is_file()]
