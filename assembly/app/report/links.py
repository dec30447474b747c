"""A written output folder's pages checked as a reader would open them: every relative link
and picture of every ``*.html`` page names a file of the folder (no absolute path, no ``..``,
no remote resource: a page must work from a ``file://`` URL and in an e-mail zip), every
in-page anchor (``#id``) names an element of the page, and the page has the shared style and
the navigation bar (:mod:`assembly.app.report.page`). Parsed with :mod:`html.parser`.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

from .page import CSS


@dataclass
class PageFacts:
    """What a page holds: ``refs`` [(tag, attribute, value)] of every href and src, ``ids``,
    ``nav`` the hrefs inside ``<nav>``, ``styles`` the text of its ``<style>`` elements,
    ``scripts`` how many ``<script>`` elements it has."""
    refs: list = field(default_factory=list)
    ids: set = field(default_factory=set)
    nav: list = field(default_factory=list)
    styles: list = field(default_factory=list)
    scripts: int = 0


class _Reader(HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.facts = PageFacts()
        self._in_nav = 0
        self._in_style = False

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if a.get("id"):
            self.facts.ids.add(a["id"])
        for key in ("href", "src"):
            if a.get(key) is not None:
                self.facts.refs.append((tag, key, a[key]))
                if self._in_nav:
                    self.facts.nav.append(a[key])
        if tag == "nav":
            self._in_nav += 1
        elif tag == "style":
            self._in_style = True
            self.facts.styles.append("")
        elif tag == "script":
            self.facts.scripts += 1

    def handle_endtag(self, tag):
        if tag == "nav":
            self._in_nav -= 1
        elif tag == "style":
            self._in_style = False

    def handle_data(self, data):
        if self._in_style:
            self.facts.styles[-1] += data


def read_page(text: str) -> PageFacts:
    """The :class:`PageFacts` of an HTML text."""
    r = _Reader()
    r.feed(text)
    r.close()
    return r.facts


def page_problems(path) -> list[str]:
    """What is wrong with the page at ``path`` (empty when nothing): each a line naming the page
    and the reference."""
    path = Path(path)
    folder, facts = path.parent, read_page(path.read_text(encoding="utf-8"))
    out = []
    if CSS not in facts.styles:
        out.append(f"{path.name}: not the shared style sheet")
    if not facts.nav:
        out.append(f"{path.name}: no navigation bar")
    if facts.scripts:
        out.append(f"{path.name}: {facts.scripts} script(s)")
    for tag, key, ref in facts.refs:
        u = urlsplit(ref)
        if u.scheme or u.netloc:
            if u.scheme != "mailto":
                out.append(f"{path.name}: <{tag} {key}={ref!r}>: a remote or absolute resource")
            continue
        if not u.path:                                   # an anchor in this page
            if u.fragment not in facts.ids:
                out.append(f"{path.name}: <{tag} {key}={ref!r}>: no element has id {u.fragment!r}")
            continue
        name = unquote(u.path)
        if name.startswith("/") or ".." in Path(name).parts:
            out.append(f"{path.name}: <{tag} {key}={ref!r}>: outside the folder")
        elif not (folder / name).is_file():
            out.append(f"{path.name}: <{tag} {key}={ref!r}>: no such file in the folder")
        elif u.fragment and name.endswith(".html"):
            other = read_page((folder / name).read_text(encoding="utf-8"))
            if u.fragment not in other.ids:
                out.append(f"{path.name}: <{tag} {key}={ref!r}>: {name} has no id {u.fragment!r}")
    return out


def folder_problems(folder) -> list[str]:
    """:func:`page_problems` of every ``*.html`` page of ``folder`` (and its subfolders)."""
    return [p for page in sorted(Path(folder).rglob("*.html")) for p in page_problems(page)]
