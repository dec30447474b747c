"""The package layout holds: floors that only import downward, no import cycle hidden inside a
function, no private name borrowed from another module, plotting, progress bars, Dask and the
command line kept to the application floor, tests that mirror the floors.

The floors of ``assembly`` (docs/architecture.md), lowest first:

    base (errors, atomic_file, arguments) < mechanics < scene < model < analysis < dynamics < app

A module may import its own floor or a lower one, at module level or inside a function.
``cms`` and ``fe_components`` are libraries: they import nothing of flexgear.
"""
import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("assembly", "cms", "fe_components")
#: floor name -> (rank, module prefixes): a module's floor is the one of its longest prefix
FLOORS = {"base": (0, ("assembly", "assembly.errors", "assembly.atomic_file", "assembly.arguments")),
          "mechanics": (1, ("assembly.mechanics",)),
          "scene": (2, ("assembly.scene",)),
          "model": (3, ("assembly.model",)),
          "analysis": (4, ("assembly.analysis",)),
          "dynamics": (5, ("assembly.dynamics",)),
          "app": (6, ("assembly.app",))}
#: import cycles allowed, each named and why: the scene resolves itself -- building a Scene
#: derives its gear numbers, expands its stages and shafts and validates the result, all on
#: the scene floor, and those steps build scenes (derive) in turn.
CYCLE_ALLOWLIST = {"the scene resolving itself": "assembly.scene."}
APP_ONLY = ("pyvista", "matplotlib", "tqdm", "dask", "distributed", "argparse")
TEST_FOLDERS = {"mechanics", "scene", "model", "analysis", "dynamics", "app", "cms", "fe_components",
                "hard_cases", "support", "mutation"}
#: a command-line flag in a string: --word-word (not a number, not a rule of dashes)
FLAG = re.compile(r"(?<![\w-])--[a-z][a-z0-9]*(?:-[a-z0-9]+)*")


def _modules():
    """(dotted name, path) of every module of the three packages, sorted by name."""
    out = []
    for pkg in PACKAGES:
        for path in sorted((ROOT / pkg).rglob("*.py")):
            if "scenes" in path.relative_to(ROOT / pkg).parts:       # shipped data and its scripts
                continue
            parts = path.relative_to(ROOT).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            out.append((name, path))
    return sorted(out)


MODULES = _modules()
NAMES = {n for n, _ in MODULES}


def _resolve(name: str, path: Path, node: ast.ImportFrom) -> str:
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    base = node.module or ""
    if node.level:
        anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
        base = ".".join(anchor + ([base] if base else []))
    return base


def _imports(name: str, path: Path, top_level_only: bool):
    """Absolute names a module imports (relative imports resolved)."""
    tree = ast.parse(path.read_text(), str(path))
    nodes = tree.body if top_level_only else ast.walk(tree)
    for node in nodes:
        if isinstance(node, ast.Import):
            yield from (a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = _resolve(name, path, node)
            subs = [f"{base}.{a.name}" for a in node.names]
            yield from (m for m in subs if m in NAMES)
            if not all(m in NAMES for m in subs):       # names from a module (not submodules)
                yield base


def floor(name: str):
    """(floor name, rank) of a module of assembly."""
    best = max(((f, r, p) for f, (r, ps) in FLOORS.items() for p in ps
                if name == p or name.startswith(p + ".")), key=lambda t: len(t[2]))
    return best[0], best[1]


def _graph(top_level_only: bool) -> dict:
    return {n: {i for i in _imports(n, p, top_level_only) if i in NAMES and i != n} for n, p in MODULES}


def test_every_package_module_is_found():
    # a miscount here would make the checks below pass vacuously
    assert {"assembly.scene.tables", "assembly.app.cli", "cms.craig_bampton", "fe_components.coupling"} <= NAMES


CORE = [(n, p) for n, p in MODULES if n.split(".")[0] == "assembly"]


@pytest.mark.parametrize("name,path", CORE, ids=[n for n, _ in CORE])
def test_a_module_imports_its_own_floor_or_lower(name, path):
    mine, rank = floor(name)
    up = sorted({i for i in _imports(name, path, top_level_only=False) if i.startswith("assembly")
                 and i in NAMES and floor(i)[1] > rank})
    assert not up, f"{name} ({mine}) imports a higher floor: {[(i, floor(i)[0]) for i in up]}"


@pytest.mark.parametrize("lib", ["cms", "fe_components"])
def test_libraries_import_nothing_of_flexgear(lib):
    others = {p for p in PACKAGES if p != lib}
    for name, path in MODULES:
        if name.split(".")[0] != lib:
            continue
        bad = sorted({i for i in _imports(name, path, top_level_only=False) if i.split(".")[0] in others})
        assert not bad, f"{name} imports {bad}"


def _cycle(graph: dict):
    """One cycle of ``graph`` as a list of modules, or None."""
    state = {}

    def visit(n, stack):
        if state.get(n) == "done":
            return None
        if state.get(n) == "active":
            return stack[stack.index(n):] + [n]
        state[n] = "active"
        for m in sorted(graph[n]):
            found = visit(m, stack + [n])
            if found:
                return found
        state[n] = "done"
        return None

    for n in sorted(graph):
        found = visit(n, [])
        if found:
            return found
    return None


def test_no_import_cycle_at_module_level():
    cycle = _cycle(_graph(top_level_only=True))
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


def test_no_cycle_hidden_in_a_function():
    """Every import hoisted to module level still forms a DAG: an import inside a function is
    there for its cost (gmsh, scikit-fem, start-up), never to break a cycle. The allowlist's
    cycles are collapsed first, each to one node."""
    graph = _graph(top_level_only=False)
    for why, prefix in CYCLE_ALLOWLIST.items():
        members = {n for n in graph if n.startswith(prefix)}
        node = prefix.rstrip(".") + " (" + why + ")"
        merged = {node: set().union(*(graph.pop(n) for n in members)) - members}
        for n, deps in graph.items():
            if deps & members:
                graph[n] = (deps - members) | {node}
        graph.update(merged)
        for n in graph:
            graph[n] = {node if d in members else d for d in graph[n]}
    cycle = _cycle(graph)
    assert cycle is None, "an import inside a function closes a cycle: " + " -> ".join(cycle)


def _test_modules():
    return sorted((ROOT / "tests").rglob("*.py"))


def _private_uses(path: Path, name: str):
    """(line, text) of every private name of another flexgear module used by ``path``:
    ``from m import _x`` and ``m._x`` on a module imported by name."""
    tree = ast.parse(path.read_text(), str(path))
    modules = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = _resolve(name, path, node)
            if base.split(".")[0] not in PACKAGES:
                continue
            for a in node.names:
                if a.name.startswith("_") and not a.name.startswith("__"):
                    yield node.lineno, f"from {base} import {a.name}"
                if f"{base}.{a.name}" in NAMES:
                    modules[a.asname or a.name] = f"{base}.{a.name}"
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] in PACKAGES:
                    modules[a.asname or a.name.split(".")[0]] = a.name
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and node.attr.startswith("_") and not node.attr.startswith("__"):
            v = node.value
            dotted = []
            while isinstance(v, ast.Attribute):
                dotted.append(v.attr)
                v = v.value
            if isinstance(v, ast.Name) and v.id in modules:
                yield node.lineno, f"{'.'.join([modules[v.id], *reversed(dotted)])}.{node.attr}"
        elif isinstance(node, ast.Constant) and isinstance(node.value, str):
            m = re.fullmatch(r"((?:assembly|cms|fe_components)(?:\.\w+)+)\.(_[a-z]\w*)", node.value)
            if m:                                     # monkeypatch.setattr("pkg.mod._name", ...)
                yield node.lineno, node.value


def test_no_private_name_crosses_a_module():
    found = []
    for name, path in MODULES + [(str(p.relative_to(ROOT).with_suffix("")).replace("/", "."), p)
                                 for p in _test_modules()]:
        found += [f"{path.relative_to(ROOT)}:{line}: {text}" for line, text in _private_uses(path, name)]
    assert not found, "\n".join(found)


def _docstring_nodes(tree) -> set:
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                out.add(id(first.value))
    return out


@pytest.mark.parametrize("name,path", [(n, p) for n, p in CORE if floor(n)[0] != "app"],
                         ids=[n for n, _ in CORE if floor(n)[0] != "app"])
def test_only_the_app_imports_plotting_progress_dask_argparse_or_names_a_flag(name, path):
    bad = sorted({i for i in _imports(name, path, top_level_only=False) for lib in APP_ONLY
                  if i == lib or i.startswith(lib + ".")})
    assert not bad, f"{name} imports {bad}"
    tree = ast.parse(path.read_text(), str(path))
    docs = _docstring_nodes(tree)
    flags = sorted({m.group(0) for node in ast.walk(tree) if isinstance(node, ast.Constant)
                    and isinstance(node.value, str) and id(node) not in docs
                    for m in FLAG.finditer(node.value)})
    assert not flags, f"{name} names command-line flags {flags}: the core names a scene path or a parameter"


def test_tests_mirror_the_floors():
    folders = {p.relative_to(ROOT / "tests").parts[0] for p in _test_modules()
               if len(p.relative_to(ROOT / "tests").parts) > 1}
    loose = sorted(p.name for p in _test_modules() if len(p.relative_to(ROOT / "tests").parts) == 1
                   and p.name not in ("__init__.py", "conftest.py", "test_architecture.py"))
    assert folders <= TEST_FOLDERS and not loose, (sorted(folders - TEST_FOLDERS), loose)
    assert {"mechanics", "scene", "model", "analysis", "dynamics", "app"} <= folders


def test_import_assembly_loads_no_model_floor():
    """``import assembly`` loads the scene language at most (the public names are lazy): the
    command line starts without the model, analysis or dynamics floors."""
    code = ("import sys, assembly\n"
            "mods = sorted(m for m in sys.modules if m == 'assembly' or m.startswith('assembly.'))\n"
            "print('\\n'.join(mods))\n")
    r = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
    loaded = r.stdout.split()
    above = [m for m in loaded if floor(m)[1] >= FLOORS["model"][0]]
    assert not above, above
    assert len(loaded) <= 12, loaded


def test_every_module_imports_in_sorted_order():
    """One fresh interpreter imports every module in alphabetical order, the order an import
    sorter gives: fails on a module that cannot be imported or needs another loaded first."""
    code = "import importlib, sys\nfor m in sys.argv[1:]:\n    importlib.import_module(m)\n"
    names = [n for n, _ in MODULES]
    r = subprocess.run([sys.executable, "-c", code, *sorted(names)],
                       cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]


#: the one module that imports gmsh (a session, or the module alone: gmsh_module)
GMSH_IMPORTERS = {"fe_components.gmsh_session"}


def test_gmsh_opens_only_in_its_session_module():
    importers = {n for n, p in MODULES if any(i == "gmsh" or i.startswith("gmsh.") for i in _imports(n, p, False))}
    assert importers <= GMSH_IMPORTERS, sorted(importers - GMSH_IMPORTERS)
    opened = sorted(n for n, p in MODULES if n != "fe_components.gmsh_session"
                    and re.search(r"\bgmsh\.(initialize|finalize)\(", p.read_text()))
    assert not opened, opened
