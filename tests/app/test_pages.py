"""One page style for every HTML page (:mod:`assembly.app.report.page`) and the folder check
(:mod:`assembly.app.report.links`) the command tests run over what they write (run, frf,
campbell, simulate, runup, study and coupling: in their own tests).

The checker is shown to find each fault it is for, so a clean folder means something."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from assembly.app.report.links import folder_problems, page_problems, read_page
from assembly.app.report.page import CSS, Section, figure, page, table

ROOT = Path(__file__).resolve().parents[2]


def _page(sections, **kw) -> str:
    return page("t", sections, command="flexgear x", scene="pair", **kw)


def test_the_navigation_names_every_section_and_the_sibling_pages():
    text = _page([Section("Natural frequencies", "<p>a</p>", "Modes"), Section("Files", "<p>b</p>")],
                 pages=[("index.html", "The run"), ("orders.html", "Orders")], here="orders.html")
    facts = read_page(text)
    assert facts.nav == ["index.html", "#s-modes", "#s-files"]          # this page (orders.html) unlinked
    assert {"s-modes", "s-files"} <= facts.ids
    assert facts.styles == [CSS] and facts.scripts == 0
    assert "<code>flexgear x</code> &middot; scene <b>pair</b>" in text


def test_a_folder_of_one_page_lists_no_pages():
    assert read_page(_page([Section("Files", "")], pages=[("index.html", "The run")])).nav == ["#s-files"]


def test_sections_with_one_anchor_get_their_own():
    # two load cases named "Rated torque" and "rated-torque" (valid: names are only unique)
    # make one slug: the second and third get -2, -3, each navigation link finds its section
    text = _page([Section("Static load case 'Rated torque'", "a", "Rated torque"),
                  Section("Static load case 'rated-torque'", "b", "rated-torque"),
                  Section("Static load case 'rated torque'", "c", "rated torque")])
    ids = re.findall(r'<h2 id="([^"]+)"', text)
    assert ids == ["s-rated-torque", "s-rated-torque-2", "s-rated-torque-3"]
    assert read_page(text).nav == [f"#{i}" for i in ids]


def test_text_columns_left_numbers_right():
    text = table(["output", "f [Hz]", "share", "note"],
                 [["force:m", "342.3", "12 %", "-"], ["speed:rotor", 1.5e-3, "-", "clipped"], ["x", "-1e-3", "3", ""]])
    head = text.splitlines()[1]
    assert head == ('<tr><th class="l">output</th><th>f [Hz]</th><th>share</th><th class="l">note</th></tr>')
    assert "<td>0.0015</td>" in text and "<td>-</td>" in text
    assert table(["a", "b"], [["1", "2"]], left=(1,)).splitlines()[1] == '<tr><th>a</th><th class="l">b</th></tr>'


def _write(folder: Path, body: str, name: str = "index.html") -> Path:
    (folder / "a.png").write_bytes(b"\x89PNG")
    p = folder / name
    p.write_text(_page([Section("Plots", body)]), encoding="utf-8")
    return p


@pytest.mark.parametrize("body, fault", [
    (figure("a.png", "a"), None),
    (figure("b.png", "b"), "'b.png'>: no such file in the folder"),
    ('<a href="#nowhere">x</a>', "no element has id 'nowhere'"),
    ('<img src="https://example.org/a.png">', "a remote or absolute resource"),
    ('<a href="../a.png">x</a>', "outside the folder"),
    ('<a href="/tmp/a.png">x</a>', "outside the folder"),
    ('<a href="other.html#s-plots">x</a>', "'other.html#s-plots'>: no such file in the folder"),
    ('<script>alert(1)</script>', "1 script(s)"),
])
def test_the_checker_finds_each_fault(tmp_path, body, fault):
    p = _write(tmp_path, body)
    problems = page_problems(p)
    if fault is None:
        assert problems == []
    else:
        assert problems and all(fault in x for x in problems), problems      # a figure: its link and its picture


def test_the_checker_wants_the_style_the_navigation_and_anchors_of_the_other_page(tmp_path):
    (tmp_path / "index.html").write_text("<!DOCTYPE html><html><body><p>bare</p></body></html>", encoding="utf-8")
    _write(tmp_path, '<a href="index.html#s-plots">back</a>', "orders.html")
    assert folder_problems(tmp_path) == ["index.html: not the shared style sheet", "index.html: no navigation bar",
                                         "orders.html: <a href='index.html#s-plots'>: index.html has no id 's-plots'"]


@pytest.mark.parametrize("tag", ["<!DOCTYPE", "<table", "<img", "<figure", "<nav", "<style"])
def test_every_page_table_and_picture_is_built_by_the_one_page_builder(tag):
    writers = [p.relative_to(ROOT).as_posix() for p in (ROOT / "assembly").rglob("*.py")
               if tag in p.read_text(encoding="utf-8").replace("``" + tag, "")]      # not a docstring's ``<nav>``
    assert writers == ["assembly/app/report/page.py"]
