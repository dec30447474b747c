"""docs/python_api.md is one script: every ```python block runs, in order, in one namespace,
from an empty temporary working directory (the page builds its example step by step), and
together they use every public name of ``assembly`` (``fg.NAME``)."""
import re
from pathlib import Path

import pytest

import assembly

DOC = Path(__file__).resolve().parents[2] / "docs" / "python_api.md"
FENCE = re.compile(r"^```python[ \t]*\n(.*?)^```[ \t]*$", re.MULTILINE | re.DOTALL)


def _blocks():
    text = DOC.read_text(encoding="utf-8")
    return [(text.count("\n", 0, m.start()) + 1, m.group(1)) for m in FENCE.finditer(text)]


def test_the_script_uses_every_public_name():
    code = "\n".join(src for _, src in _blocks())
    used = set(re.findall(r"\bfg\.(\w+)", code))
    assert not sorted(set(assembly.__all__) - used), "docs/python_api.md leaves out public names"
    assert not sorted(used - set(assembly.__all__) - {"__all__"}), "docs/python_api.md uses names that are not public"


@pytest.mark.slow
def test_python_api_doc_runs(tmp_path, monkeypatch):
    blocks = _blocks()
    assert len(blocks) >= 10   # guards the extraction
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for line, src in blocks:
        exec(compile("\n" * line + src, str(DOC), "exec"), namespace)   # line numbers are the page's
    assert (tmp_path / "helix30.toml").exists() and (tmp_path / "results_stiffer" / "index.html").exists()
