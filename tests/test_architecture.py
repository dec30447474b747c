"""The package layout holds: the model core never reaches into the application layer or a
plotting library, and no two modules import each other at import time (a cycle), so an
import sorter may reorder any module's imports."""
import ast
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("assembly", "cms", "fe_components")
APP = "assembly.app"
FORBIDDEN_OUTSIDE_APP = ("assembly.app", "pyvista", "matplotlib")


def _modules():
    """(dotted name, path) of every module of the three packages, sorted by name."""
    out = []
    for pkg in PACKAGES:
        for path in sorted((ROOT / pkg).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            out.append((name, path))
    return sorted(out)


def _imports(name: str, path: Path, top_level_only: bool):
    """Absolute names a module imports (relative imports resolved)."""
    tree = ast.parse(path.read_text(), str(path))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    nodes = tree.body if top_level_only else ast.walk(tree)
    for node in nodes:
        if isinstance(node, ast.Import):
            yield from (a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            subs = [f"{base}.{a.name}" for a in node.names]
            yield from subs
            if not all(m in NAMES for m in subs):  # `from . import rigid` loads only cms.rigid
                yield base


MODULES = _modules()
NAMES = {n for n, _ in MODULES}


def test_every_package_module_is_found():
    # a miscount here would make the two checks below pass vacuously
    assert {"assembly.scene.tables", "assembly.app.cli", "cms.craig_bampton", "fe_components.coupling"} <= NAMES


@pytest.mark.parametrize("name,path", [(n, p) for n, p in MODULES if not n.startswith(APP)],
                         ids=[n for n, _ in MODULES if not n.startswith(APP)])
def test_core_does_not_import_app_or_plotting(name, path):
    bad = sorted({imp for imp in _imports(name, path, top_level_only=False)
                  for f in FORBIDDEN_OUTSIDE_APP if imp == f or imp.startswith(f + ".")})
    assert not bad, f"{name} imports {bad}"


@pytest.mark.parametrize("lib", ["cms", "fe_components"])
def test_libraries_import_nothing_of_flexgear(lib):
    others = {p for p in PACKAGES if p != lib}
    for name, path in MODULES:
        if name.split(".")[0] != lib:
            continue
        bad = sorted({i for i in _imports(name, path, top_level_only=False) if i.split(".")[0] in others})
        assert not bad, f"{name} imports {bad}"


def test_no_import_cycle_at_module_level():
    """Module-level imports form a DAG (function-level imports are deliberate and lazy)."""
    graph = {n: {i for i in _imports(n, p, top_level_only=True) if i in NAMES and i != n} for n, p in MODULES}
    state = {}

    def visit(n, stack):
        if state.get(n) == "done":
            return
        assert state.get(n) != "active", "import cycle: " + " -> ".join(stack + [n])
        state[n] = "active"
        for m in sorted(graph[n]):
            visit(m, stack + [n])
        state[n] = "done"

    for n in sorted(graph):
        visit(n, [])


def test_every_module_imports_in_sorted_order():
    """One fresh interpreter imports every module in alphabetical order, the order an import
    sorter gives: fails on a module that cannot be imported or needs another loaded first."""
    code = "import importlib, sys\nfor m in sys.argv[1:]:\n    importlib.import_module(m)\n"
    names = [n for n, _ in MODULES]
    r = subprocess.run([sys.executable, "-c", code, *sorted(names)],
                       cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
