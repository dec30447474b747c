"""One page style for every HTML page flexgear writes (``run``, ``frf``, ``campbell``,
``simulate``, ``runup``, ``coupling``, ``study``).

:func:`page` builds the whole page: the same inline CSS, a header with the page's title, the
command and the scene, a navigation bar with the sibling pages of the same output folder and
the page's sections (in-page anchors), then the sections. Tables go through :func:`table`
(text columns left-aligned, numbers right-aligned), pictures through :func:`figure`. No
scripts and no external resources: a page works from a ``file://`` URL and in an e-mail zip.
A page is a list of :class:`Section`; adding one is appending one.
"""
from __future__ import annotations

import html
import re
from dataclasses import dataclass, replace
from numbers import Number
from pathlib import Path

CSS = """
body { font-family: system-ui, -apple-system, 'Segoe UI', Helvetica, Arial, sans-serif; margin: 1.5em 2em;
       color: #1a1a1a; max-width: 1500px; }
h1 { font-size: 1.5em; margin-bottom: 0.2em; } h2 { font-size: 1.2em; margin-top: 1.6em;
     border-bottom: 1px solid #ccc; padding-bottom: 0.2em; scroll-margin-top: 2.8em; }
h3 { font-size: 1.0em; margin-top: 1.1em; }
header { border-bottom: 2px solid #2a5d9f; padding-bottom: 0.3em; }
.cmd { font-size: 0.95em; color: #333; margin: 0.2em 0; } code { background: #f3f3f3; padding: 0 0.25em; }
nav { position: sticky; top: 0; z-index: 1; background: #f5f8fc; border: 1px solid #d5dde9; border-top: 0;
      padding: 0.35em 0.7em; font-size: 0.88em; line-height: 1.6; }
nav a { color: #2a5d9f; text-decoration: none; margin-right: 0.9em; white-space: nowrap; }
nav a:hover { text-decoration: underline; } nav .here { font-weight: 600; margin-right: 0.9em; }
nav .group { color: #666; margin-right: 0.5em; } nav .pages { margin-right: 1.2em; }
.meta { color: #555; font-size: 0.9em; }
table { border-collapse: collapse; font-size: 0.85em; margin: 0.5em 0; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.55em; text-align: right; }
th { background: #f0f0f0; } td.l, th.l { text-align: left; }
tr.weak td { color: #a04000; } tr.unpaired td { color: #666; }
.grid { display: grid; grid-template-columns: repeat(auto-fill, minmax(460px, 1fr)); gap: 14px; }
figure { margin: 0; border: 1px solid #ddd; padding: 6px; background: #fff; }
figure img { width: 100%; height: auto; display: block; }
figure.single { max-width: 1100px; }
figcaption { font-size: 0.85em; color: #333; margin-top: 4px; }
.note { background: #fff7e0; border-left: 4px solid #e0a000; padding: 0.4em 0.8em; font-size: 0.9em; }
.stopped { background: #fde8e8; border-left: 4px solid #c02020; padding: 0.4em 0.8em; }
"""


def esc(x) -> str:
    """``x`` as HTML text (quotes escaped too: safe in attributes)."""
    return html.escape(str(x), quote=True)


def link(href: str, text: str | None = None) -> str:
    """``<a href=...>``; the text defaults to the target's name."""
    return f'<a href="{esc(href)}">{esc(href if text is None else text)}</a>'


def cell(v) -> str:
    """Escaped cell text; ``("link", href, text)`` becomes a link."""
    if isinstance(v, tuple) and len(v) == 3 and v[0] == "link":
        return link(v[1], v[2])
    return esc(v)


def is_number(v) -> bool | None:
    """Whether a cell is a number (a number, or a text that reads as one, ``"12 %"`` too);
    None for an empty or ``"-"`` cell (either kind of column may hold one)."""
    if isinstance(v, bool):
        return False
    if isinstance(v, Number):
        return True
    if isinstance(v, tuple):
        return False
    s = str(v).strip().rstrip("%").strip()
    if s in ("", "-"):
        return None
    try:
        float(s)
    except ValueError:
        return False
    return True


def text_columns(rows) -> set:
    """The columns of ``rows`` holding a cell that is not a number (:func:`is_number`)."""
    return {i for row in rows for i, v in enumerate(row) if is_number(v) is False}


def table(header, rows, left=None, row_classes=None) -> str:
    """A table: text columns left-aligned, numbers right-aligned. ``left``: the left-aligned
    columns (default: :func:`text_columns`); ``row_classes``: a CSS class per row or None."""
    rows = [list(r) for r in rows]
    left = text_columns(rows) if left is None else set(left)
    out = ["<table>", "<tr>" + "".join(
        f'<th class="l">{esc(h)}</th>' if i in left else f"<th>{esc(h)}</th>" for i, h in enumerate(header)) + "</tr>"]
    for r, row in enumerate(rows):
        cls = f' class="{row_classes[r]}"' if row_classes and row_classes[r] else ""
        out.append(f"<tr{cls}>" + "".join(
            f'<td class="l">{cell(v)}</td>' if i in left else f"<td>{cell(v)}</td>" for i, v in enumerate(row))
            + "</tr>")
    out.append("</table>")
    return "\n".join(out)


def figure(src: str, caption: str, alt: str = "", single: bool = False) -> str:
    """A picture (a link to itself) with its caption; its id is ``fig-`` and the file's stem.
    ``single``: a picture on its own, not in a :func:`grid` (kept to a readable width)."""
    fid = "fig-" + re.sub(r"[^A-Za-z0-9]+", "-", Path(src).stem)
    cls = ' class="single"' if single else ""
    return (f'<figure id="{fid}"{cls}><a href="{esc(src)}"><img src="{esc(src)}" alt="{esc(alt or caption)}" '
            'loading="eager"></a>'
            f"<figcaption>{esc(caption)}</figcaption></figure>")


def grid(figures) -> str:
    """Pictures side by side: ``figures`` [(src, caption)] or figure HTML texts."""
    return '<div class="grid">' + "".join(f if isinstance(f, str) else figure(*f) for f in figures) + "</div>"


def note(text: str) -> str:
    return f'<p class="note">{esc(text)}</p>'


def para(text: str, cls: str = "") -> str:
    """A paragraph of plain text (escaped)."""
    return (f'<p class="{cls}">' if cls else "<p>") + esc(text) + "</p>"


def files_list(files) -> str:
    """The page's data files: [(name, description)] as a list of links."""
    return "<ul>" + "".join(f"<li>{link(p)} &mdash; {esc(d)}</li>" for p, d in files) + "</ul>"


def slug(text: str) -> str:
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-") or "section"


@dataclass(frozen=True)
class Section:
    """One ``<h2>`` section: ``body`` is HTML; ``label`` its name in the navigation bar
    (default the title); ``id`` its anchor (default ``s-`` and the label's slug)."""
    title: str
    body: str
    label: str = ""
    id: str = ""

    @property
    def nav(self) -> str:
        return self.label or self.title

    @property
    def anchor(self) -> str:
        return self.id or "s-" + slug(self.nav)


def unique_anchors(sections) -> list:
    """``sections`` with anchors made unique: a second section whose anchor repeats an earlier
    one's (two load cases named "Rated torque" and "rated-torque") gets ``-2``, ``-3`` ..."""
    seen, out = set(), []
    for s in sections:
        a, k = s.anchor, 1
        while a in seen:
            k += 1
            a = f"{s.anchor}-{k}"
        seen.add(a)
        out.append(s if a == s.anchor else replace(s, id=a))
    return out


def nav_bar(sections, pages=(), here: str = "index.html") -> str:
    """The navigation: the folder's pages ([(file, label)], this one ``here`` unlinked; left out
    when the folder has one page) and this page's sections."""
    parts = ["<nav>"]
    if len(pages) > 1:
        parts.append('<span class="pages"><span class="group">Pages:</span>' + "".join(
            f'<span class="here">{esc(t)}</span>' if p == here else link(p, t) for p, t in pages) + "</span>")
    if sections:
        parts.append('<span class="group">On this page:</span>'
                     + "".join(f'<a href="#{esc(s.anchor)}">{esc(s.nav)}</a>' for s in sections))
    parts.append("</nav>")
    return "".join(parts)


def page(title: str, sections, *, command: str, scene: str, meta=(), lead: str = "", pages=(),
         here: str = "index.html") -> str:
    """The whole page: head with the CSS, a header (``title``; ``command`` and ``scene``; ``meta``
    lines), the navigation (:func:`nav_bar`), ``lead`` (HTML: what must be read first) and the
    :class:`Section` list ``sections``."""
    sections = unique_anchors([s for s in sections if s is not None])
    out = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
           '<meta name="viewport" content="width=device-width, initial-scale=1">',
           f"<title>{esc(title)}</title>", f"<style>{CSS}</style></head><body>",
           f"<header><h1>{esc(title)}</h1>",
           f'<p class="cmd"><code>{esc(command)}</code> &middot; scene <b>{esc(scene)}</b></p>']
    if meta:
        out.append('<p class="meta">' + "<br>".join(esc(m) for m in meta) + "</p>")
    out += ["</header>", nav_bar(sections, pages, here)]
    if lead:
        out.append(lead)
    for s in sections:
        out.append(f'<h2 id="{esc(s.anchor)}">{esc(s.title)}</h2>')
        out.append(s.body)
    out.append("</body></html>")
    return "\n".join(out) + "\n"
