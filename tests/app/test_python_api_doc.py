"""Every ```python block of docs/python_api.md runs, in order, in one namespace, from an
empty temporary working directory (the page builds its example step by step)."""
import re
from pathlib import Path

DOC = Path(__file__).resolve().parents[2] / "docs" / "python_api.md"
FENCE = re.compile(r"^```python[ \t]*\n(.*?)^```[ \t]*$", re.MULTILINE | re.DOTALL)


def test_python_api_doc_runs(tmp_path, monkeypatch):
    text = DOC.read_text(encoding="utf-8")
    blocks = [(text.count("\n", 0, m.start()) + 1, m.group(1)) for m in FENCE.finditer(text)]
    assert len(blocks) >= 5   # guards the extraction
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for line, src in blocks:
        exec(compile("\n" * line + src, str(DOC), "exec"), namespace)   # line numbers are the page's
    assert (tmp_path / "helix30.toml").exists() and (tmp_path / "results_stiffer" / "index.html").exists()
