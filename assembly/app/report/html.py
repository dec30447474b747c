"""Static ``index.html`` of a run: tables and images with relative links, no server needed.

:func:`render_index` turns a plain report dict (built by :mod:`assembly.app.report.pipeline`) into one
self-contained HTML page (inline CSS, no scripts, no external resources).
"""
from __future__ import annotations

import html
import re
from pathlib import Path

CSS = """
body { font-family: system-ui, -apple-system, 'Segoe UI', Helvetica, Arial, sans-serif; margin: 1.5em 2em;
       color: #1a1a1a; max-width: 1500px; }
h1 { font-size: 1.5em; margin-bottom: 0.2em; } h2 { font-size: 1.2em; margin-top: 1.6em;
     border-bottom: 1px solid #ccc; padding-bottom: 0.2em; }
.meta { color: #555; font-size: 0.9em; }
table { border-collapse: collapse; font-size: 0.85em; margin: 0.5em 0; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.55em; text-align: right; }
th { background: #f0f0f0; } td.l, th.l { text-align: left; }
tr.weak td { color: #a04000; } tr.unpaired td { color: #666; }
.grid { display: grid; grid-template-columns: repeat(auto-fill, minmax(460px, 1fr)); gap: 14px; }
figure { margin: 0; border: 1px solid #ddd; padding: 6px; background: #fff; }
figure img { width: 100%; height: auto; display: block; }
figcaption { font-size: 0.85em; color: #333; margin-top: 4px; }
.note { background: #fff7e0; border-left: 4px solid #e0a000; padding: 0.4em 0.8em; font-size: 0.9em; }
"""


def _e(x) -> str:
    return html.escape(str(x), quote=True)


def _cell(v) -> str:
    """Escaped cell text; ``("link", href, text)`` becomes a link."""
    if isinstance(v, tuple) and len(v) == 3 and v[0] == "link":
        return f'<a href="{_e(v[1])}">{_e(v[2])}</a>'
    return _e(v)


def _table(header, rows, left=(), row_classes=None) -> str:
    out = ["<table>", "<tr>" + "".join(
        f'<th class="l">{_e(h)}</th>' if i in left else f"<th>{_e(h)}</th>" for i, h in enumerate(header)) + "</tr>"]
    for r, row in enumerate(rows):
        cls = f' class="{row_classes[r]}"' if row_classes and row_classes[r] else ""
        out.append(f"<tr{cls}>" + "".join(
            f'<td class="l">{_cell(v)}</td>' if i in left else f"<td>{_cell(v)}</td>" for i, v in enumerate(row)) + "</tr>")
    out.append("</table>")
    return "\n".join(out)


def figure(src: str, caption: str, alt: str = "") -> str:
    fid = "fig-" + re.sub(r"[^A-Za-z0-9]+", "-", Path(src).stem)
    return (f'<figure id="{fid}"><a href="{_e(src)}"><img src="{_e(src)}" alt="{_e(alt or caption)}" loading="eager"></a>'
            f"<figcaption>{_e(caption)}</figcaption></figure>")


def render_index(report: dict) -> str:
    """HTML text of the run page. ``report`` keys: title, scene, meta (list of str),
    modes (header, rows), modes_note (str: rows left out), bodies (title, header, rows, left,
    notes: the bodies' mass properties; optional), gears (the same keys: the gear table;
    optional), referred (the same keys: inertia referred to each shaft; optional), comparison (header, rows, row_classes,
    note) or None, sections [{title, note, tables: [(title, header, rows, left columns)]}]
    (optional), key_images [(path, caption)] shown first (optional), overview
    (path, caption) or None, images [(path, caption)], animations [(path, caption)] (optional),
    plots [(path, caption)], files [(path, description)], notes [str]."""
    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
             f"<title>{_e(report['title'])}</title>", f"<style>{CSS}</style></head><body>",
             f"<h1>{_e(report['title'])}</h1>"]
    parts.append('<p class="meta">' + "<br>".join(_e(m) for m in report.get("meta", [])) + "</p>")
    if report.get("key_images"):   # the drivetrain pictures come first
        parts.append("<h2>Drivetrain pictures</h2>")
        parts.append('<div class="grid">' + "".join(figure(p, c) for p, c in report["key_images"]) + "</div>")
    for n in report.get("notes", []):
        parts.append(f'<p class="note">{_e(n)}</p>')

    parts.append("<h2>Natural frequencies and mode table</h2>")
    hdr, rows = report["modes"]
    parts.append(_table(hdr, rows, left=set(range(3, len(hdr)))))
    if report.get("modes_note"):
        parts.append(f'<p class="meta">{_e(report["modes_note"])}</p>')

    bodies = report.get("bodies")
    if bodies:
        parts.append("<h2>Bodies: mass properties</h2>")
        parts.append(f'<p class="meta">{_e(bodies["title"])}</p>')
        parts.append(_table(bodies["header"], bodies["rows"], left=set(bodies.get("left", ()))))
        for n in bodies.get("notes", []):
            parts.append(f'<p class="note">{_e(n)}</p>')

    gears = report.get("gears")
    if gears:
        parts.append("<h2>Gear meshes: geometry, contact ratios, stiffness</h2>")
        parts.append(f'<p class="meta">{_e(gears["title"])}</p>')
        parts.append(_table(gears["header"], gears["rows"], left=set(gears.get("left", ()))))

    referred = report.get("referred")
    if referred:
        parts.append("<h2>Inertia referred to each shaft</h2>")
        parts.append(f'<p class="meta">{_e(referred["title"])}</p>')
        if referred["rows"]:
            parts.append(_table(referred["header"], referred["rows"], left=set(referred.get("left", ()))))
        for n in referred.get("notes", []):
            parts.append(f'<p class="note">{_e(n)}</p>')

    comp = report.get("comparison")
    if comp:
        fids = comp.get("fidelities") or ["torsional", "rigid"]
        parts.append(f"<h2>Fidelity comparison ({_e(' vs '.join(fids))}, modes paired by MAC)</h2>")
        if comp.get("note"):
            parts.append(f'<p class="meta">{_e(comp["note"])}</p>')
        parts.append(_table(comp["header"], comp["rows"], left=set(comp.get("left", ())),
                            row_classes=comp.get("row_classes")))

    for sec in report.get("sections", []):   # e.g. static load cases: (title, header, rows, left) tables
        parts.append(f"<h2>{_e(sec['title'])}</h2>")
        if sec.get("note"):
            parts.append(f'<p class="meta">{_e(sec["note"])}</p>')
        for title, header, rows, left in sec["tables"]:
            parts.append(f"<h3>{_e(title)}</h3>" + _table(header, rows, left=set(left)))

    if report.get("plots"):
        parts.append("<h2>Plots</h2>")
        parts.append('<div class="grid">' + "".join(figure(p, c) for p, c in report["plots"]) + "</div>")

    if report.get("overview") or report.get("images"):
        parts.append("<h2>Mode shapes</h2>")
        figs = []
        if report.get("overview"):
            figs.append(figure(*report["overview"]))
        figs += [figure(p, c) for p, c in report.get("images", [])]
        parts.append('<div class="grid">' + "".join(figs) + "</div>")

    if report.get("animations"):   # animated GIFs of the first drawn modes in the band
        parts.append("<h2>Mode animations</h2>")
        parts.append('<div class="grid">' + "".join(figure(p, c) for p, c in report["animations"]) + "</div>")

    if report.get("files"):
        parts.append("<h2>Files</h2><ul>")
        for p, d in report["files"]:
            parts.append(f'<li><a href="{_e(p)}">{_e(p)}</a> &mdash; {_e(d)}</li>')
        parts.append("</ul>")
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


_REF = re.compile(r'(?:src|href)="([^"]+)"')


def local_references(html_text: str) -> list[str]:
    """Relative file references (src/href) of a page, unescaped, without anchors/URLs."""
    out = []
    for ref in _REF.findall(html_text):
        ref = html.unescape(ref)
        if ref.startswith(("#", "http:", "https:", "mailto:", "data:")):
            continue
        out.append(ref)
    return out


def missing_references(index_path) -> list[str]:
    """References of ``index_path`` that do not name an existing file next to it."""
    p = Path(index_path)
    base = p.parent
    return [r for r in local_references(p.read_text(encoding="utf-8")) if not (base / r).is_file()]
