"""Every fenced ```toml and ```python block of README.md runs.

A TOML block is written to a file and loaded with ``load_scene``; a complete scene (one with
bodies or planetary stages) is also assembled and solved, and must give finite frequencies
with a small eigen-residual. A Python block is exec'd in a fresh namespace from an empty
temporary working directory. The README has no block that is not meant to run.
"""
from __future__ import annotations

import math
import re
import tomllib
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[2] / "README.md"
FENCE = re.compile(r"^```(toml|python)[ \t]*\n(.*?)^```[ \t]*$", re.MULTILINE | re.DOTALL)


def readme_blocks(kind: str) -> list[tuple[int, str]]:
    """(line number, source) of each ```kind block of README.md."""
    text = README.read_text(encoding="utf-8")
    return [(text.count("\n", 0, m.start()) + 1, m.group(2))
            for m in FENCE.finditer(text) if m.group(1) == kind]


def _params(kind: str):
    # the source is padded with blank lines so that line numbers in errors are README's
    return [pytest.param("\n" * line + src, id=f"README.md:{line}") for line, src in readme_blocks(kind)]


def test_readme_has_examples():
    # guards the extraction: an empty parameter list would let the tests below pass vacuously
    assert readme_blocks("toml"), "no ```toml block found in README.md"
    assert readme_blocks("python"), "no ```python block found in README.md"


@pytest.mark.parametrize("source", _params("toml"))
def test_readme_toml_block(source, tmp_path):
    from assembly import assemble, load_scene, solve_modes

    path = tmp_path / "readme_scene.toml"
    path.write_text(source, encoding="utf-8")
    scene = load_scene(path)
    data = tomllib.loads(source)
    if data.get("bodies") or data.get("stages"):
        res = solve_modes(assemble(scene))
        freqs = list(res.frequencies_hz)
        assert freqs and all(math.isfinite(f) for f in freqs)
        assert res.max_residual < 1e-8


@pytest.mark.parametrize("source", _params("python"))
def test_readme_python_block(source, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code = compile(source, "README.md", "exec")   # errors read README.md:<line>
    exec(code, {"__name__": "__readme__"})
