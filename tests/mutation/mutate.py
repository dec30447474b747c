"""Mutation pass over the physics modules: does a small wrong change in the physics fail a test?

One mutant at a time, each a single edit of a physics line -- flip a sign (``+`` <-> ``-``,
drop a unary minus), change a numeric constant by 1 %, drop a term of a sum, swap a
constant index (0 <-> 1, k -> k - 1) -- is written into a private copy of the source tree,
and the quick tests that cover that module (``MODULES`` below; ``-x -q -m "not slow"``)
run against it. A mutant the tests fail on is killed; one they pass is a survivor, and a
survivor of a physics line needs a test that kills it or a written reason (an equivalent
mutant, or a change below what any physics can see) in ``accepted.toml`` beside this file.

Only the functions named in ``MODULES`` are mutated (the physics; not argument checks,
messages or logging), and within them no line of a ``raise``, an ``assert``, a logging
call or a string. ``--sample N`` draws N mutants per module (seeded: the same draw on
every machine); the default takes them all.

    make mutate                        # every module, every mutant
    python tests/mutation/mutate.py --module frf --sample 40 --list

The working tree is never touched: the copy lives in a temporary folder, and the tests
import it (it is first on ``sys.path``). Run it with ``nice``: it is CPU-heavy. Prints a
table (module, mutants, killed, survived, accepted, kill rate) and the survivors (file:line,
function, the edit); exits 1 when an unaccepted survivor remains.
"""
from __future__ import annotations

import argparse
import ast
import dataclasses
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
ACCEPTED = Path(__file__).with_name("accepted.toml")

#: module key -> (source files with their physics functions, the quick tests that cover them).
#: A test entry is a path or a path with ``-k`` selection after "::-k ".
MODULES = {
    "element": ({"assembly/mechanics/elements.py": ["Element.stiffness", "Element.damping", "_rank_one_sum",
                                          "relative_spring", "line_of_action", "gear_mesh"]},
                ["tests/mechanics/test_core_elements.py", "tests/analysis/test_helix_thrust.py",
                 "tests/mechanics/test_line_of_action.py",
                 "tests/analysis/test_static_forces.py", "tests/scene/test_core_validation.py",
                 "tests/model/test_bearing_directions.py", "tests/app/test_reference.py"]),
    "reduction": ({"cms/craig_bampton.py": ["CraigBamptonReductor.reduce", "CraigBamptonReductor.reconstruct",
                                            "CraigBamptonReductor._modes", "CraigBamptonReductor._reduced_matrices",
                                            "_augmentation"]},
                  ["tests/cms/test_cms_cutoff.py", "tests/cms/test_cms_rbe2.py", "tests/cms/test_cms_stress.py",
                   "tests/cms/test_cms_residual_contract.py",
                   "tests/cms/test_cms_reduction.py::-k not free_free and not eigen_methods"]),
    "frf": ({"assembly/dynamics/frf.py": ["low_accurate", "_rigid_free", "_modal", "_modal_outputs", "_residues",
                                          "_residual", "_state_modes", "_sum_poles", "_sum", "_direct",
                                          "cutoff_check", "_residual_bound", "undamped_warnings"],
             "assembly/dynamics/damping.py": ["scene_modal_damping", "section_factors", "damping_in_modes",
                                              "damping_on_q", "section_share"],
             "assembly/mechanics/nullity.py": ["_null_space"],
             "assembly/dynamics/run_outputs.py": ["scene_share"],
             "assembly/dynamics/run_checks.py": ["undamped_band"]},
            ["tests/dynamics/test_frf.py", "tests/dynamics/test_frf_residual_terms.py",
             "tests/dynamics/test_frf_truncation.py", "tests/dynamics/test_frf_phasing.py",
             "tests/dynamics/test_frf_edges.py", "tests/dynamics/test_section_loads.py",
             "tests/mechanics/test_rigid_body_modes.py"]),
    "mesh_variation": ({"assembly/dynamics/mesh_variation.py": ["rectangular_wave", "series", "Series.__init__",
                                                                "Series.__call__", "lowest_factor",
                                                                "DeadZone.__init__", "DeadZone.__call__"],
                        "assembly/dynamics/mesh_laws.py": ["mesh_law", "mesh_into"],
                        "assembly/scene/mesh_excitation.py": ["overlap_ratio", "stage_variations"]},
                       ["tests/dynamics/test_mesh_stiffness_wave.py", "tests/dynamics/test_simulate.py",
                        "tests/dynamics/test_transient_physics.py"]),
    "integrator": ({"assembly/dynamics/integrators.py": ["hht", "generalized_alpha", "newmark",
                                                         "integrate_linear", "effective_matrix", "_step",
                                                         "amplification"],
                    "assembly/dynamics/transient.py": ["_weighted", "integrate", "PythonSteps.run"],
                    "assembly/dynamics/step_kernel.py": ["newton_matrix", "lu_factor", "lu_solve", "settled", "run_stretch"]},
                   ["tests/dynamics/test_integrators.py", "tests/dynamics/test_simulate.py",
                    "tests/dynamics/test_transient_physics.py", "tests/dynamics/test_compiled_step.py"]),
    "reaction": ({"assembly/analysis/reactions.py": ["_shift", "element_wrenches", "static_report", "support_reactions",
                                            "equilibrium", "_torque_balance", "_mesh_row", "_constraint_reactions",
                                            "_add_rigid_directions", "_ratio_check"]},
                 ["tests/analysis/test_static_forces.py", "tests/analysis/test_static_loads.py",
                  "tests/analysis/test_helix_thrust.py", "tests/model/test_bearing_directions.py",
                  "tests/analysis/test_reaction_rows.py"]),
}


@dataclasses.dataclass(frozen=True)
class Mutant:
    file: str
    function: str
    line: int
    start: int          # character offsets of the replaced span in the file
    end: int
    original: str
    replacement: str
    kind: str
    mutated: str        # the mutated line(s), whitespace collapsed: names the mutant in accepted.toml

    @property
    def key(self) -> tuple:
        return (self.file, self.function, self.mutated)

    def describe(self) -> str:
        def short(t):
            t = " ".join(t.split())
            return t if len(t) <= 70 else t[:67] + "..."
        return f"{self.file}:{self.line} {self.function}: {self.kind}: {short(self.original)} -> {short(self.replacement)}"


# ------------------------------------------------------------------ finding mutants
def _functions(tree: ast.Module, names: list[str]):
    """(qualified name, node) of the listed functions (``Class.method`` for methods)."""
    want = set(names)
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name in want:
            yield node.name, node
        elif isinstance(node, ast.ClassDef):
            for sub in node.body:
                q = f"{node.name}.{sub.name}" if isinstance(sub, (ast.FunctionDef, ast.AsyncFunctionDef)) else None
                if q in want:
                    yield q, sub


def _excluded_lines(fn) -> set[int]:
    """Lines of raise / assert statements, logging calls, docstrings and strings."""
    out = set()
    for node in ast.walk(fn):
        skip = isinstance(node, (ast.Raise, ast.Assert, ast.JoinedStr))
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and \
                isinstance(node.func.value, ast.Name) and node.func.value.id in ("log", "logging", "warnings"):
            skip = True
        if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant) and isinstance(node.value.value, str):
            skip = True
        if skip:
            out.update(range(node.lineno, (node.end_lineno or node.lineno) + 1))
    return out


def _offsets(text: str) -> list[int]:
    starts, pos = [], 0
    for line in text.splitlines(keepends=True):
        starts.append(pos)
        pos += len(line)
    return starts


def _span(starts, node) -> tuple[int, int]:
    # ast columns are UTF-8 byte offsets; the physics modules are ASCII in code lines
    return starts[node.lineno - 1] + node.col_offset, starts[node.end_lineno - 1] + node.end_col_offset


def _bump(value):
    """A numeric constant changed by 1 %."""
    return repr(value * 1.01) if isinstance(value, float) else repr(round(value * 1.01, 6))


def mutants_of(path: str, functions: list[str]) -> list[Mutant]:
    text = (ROOT / path).read_text(encoding="utf-8")
    tree = ast.parse(text)
    starts = _offsets(text)
    out = []

    def add(fn_name, node, replacement, kind, span=None):
        a, b = span or _span(starts, node)
        original = text[a:b]
        if replacement != original:
            la = text.rfind("\n", 0, a) + 1
            lb = text.find("\n", b)
            lb = len(text) if lb < 0 else lb
            mutated = " ".join((text[la:a] + replacement + text[b:lb]).split())
            out.append(Mutant(path, fn_name, node.lineno, a, b, original, replacement, kind, mutated))

    def seg(node):
        a, b = _span(starts, node)
        return text[a:b]

    for fn_name, fn in _functions(tree, functions):
        skip = _excluded_lines(fn)
        body = fn.body[1:] if (fn.body and isinstance(fn.body[0], ast.Expr)
                               and isinstance(fn.body[0].value, ast.Constant)) else fn.body
        for stmt in body:
            for node in ast.walk(stmt):
                if not hasattr(node, "lineno") or node.lineno in skip:
                    continue
                if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub)):
                    flipped = "-" if isinstance(node.op, ast.Add) else "+"
                    left, right = seg(node.left), seg(node.right)
                    # flip the operator between the operands (keeps everything else as written)
                    a, _ = _span(starts, node.left)
                    _, b = _span(starts, node.right)
                    lend = _span(starts, node.left)[1]
                    rstart = _span(starts, node.right)[0]
                    between = text[lend:rstart]
                    op = "+" if isinstance(node.op, ast.Add) else "-"
                    if between.count(op) == 1:
                        add(fn_name, node, text[a:lend] + between.replace(op, flipped) + text[rstart:b], "flip sign",
                            (a, b))
                    add(fn_name, node, f"({left})", "drop term", (a, b))
                    if isinstance(node.op, ast.Add):
                        add(fn_name, node, f"({right})", "drop term", (a, b))
                elif isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub) \
                        and not isinstance(node.operand, ast.Constant):
                    add(fn_name, node, f"({seg(node.operand)})", "flip sign")
                if isinstance(node, ast.BinOp):
                    for side in (node.left, node.right):
                        if isinstance(side, ast.Constant) and isinstance(side.value, (int, float)) \
                                and not isinstance(side.value, bool) and side.value != 0:
                            add(fn_name, side, _bump(side.value), "constant +1 %")
                if isinstance(node, ast.Subscript):
                    idx = node.slice.elts if isinstance(node.slice, ast.Tuple) else [node.slice]
                    for e in idx:
                        if isinstance(e, ast.Constant) and isinstance(e.value, int) and not isinstance(e.value, bool):
                            k = e.value
                            add(fn_name, e, repr(1 if k == 0 else k - 1), "swap index")
    # one mutant per (span, replacement)
    seen, unique = set(), []
    for m in out:
        if (m.start, m.end, m.replacement) not in seen:
            seen.add((m.start, m.end, m.replacement))
            unique.append(m)
    return unique


# ------------------------------------------------------------------ running them
def _copy_tree(dest: Path) -> None:
    ignore = shutil.ignore_patterns(".venv", ".git", "__pycache__", "*.pyc", "*.egg-info", "build", ".pytest_cache",
                                    ".hypothesis", "results")
    shutil.copytree(ROOT, dest, ignore=ignore, symlinks=True)


def _pytest_args(tests: list[str], root: Path) -> list[list[str]]:
    """pytest arguments of each run: the plain files together, each ``-k`` selection alone;
    files the tree does not have (yet) are left out."""
    tests = [t for t in tests if (root / t.split("::", 1)[0]).exists()]
    plain = [t for t in tests if "::-k " not in t]
    runs = [plain] if plain else []
    for t in tests:
        if "::-k " in t:
            path, expr = t.split("::-k ", 1)
            runs.append([path, "-k", expr])
    return runs


def run_tests(copy: Path, tests: list[str], timeout: float, env: dict) -> tuple[str, float]:
    """'killed' (a test failed or errored, or timed out) or 'survived'; and the time taken."""
    t0 = time.perf_counter()
    for args in _pytest_args(tests, copy):
        cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-m", "not slow", "-p", "no:cacheprovider", *args]
        try:
            out = subprocess.run(cmd, cwd=copy, env=env, capture_output=True, text=True,
                                 timeout=max(1.0, timeout - (time.perf_counter() - t0)))
        except subprocess.TimeoutExpired:
            return "killed", time.perf_counter() - t0
        if out.returncode == 5:
            raise SystemExit(f"no test collected by {' '.join(args)}")
        if out.returncode != 0:
            return "killed", time.perf_counter() - t0
    return "survived", time.perf_counter() - t0


def load_accepted() -> dict:
    if not ACCEPTED.exists():
        return {}
    data = tomllib.loads(ACCEPTED.read_text(encoding="utf-8"))
    return {(a["file"], a["function"], " ".join(a["mutated"].split())): a["reason"]
            for a in data.get("accepted", [])}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--module", action="append", choices=sorted(MODULES),
                    help="module(s) to mutate (default: all)")
    ap.add_argument("--sample", type=int, default=0, help="at most N mutants per module, drawn with a fixed seed")
    ap.add_argument("--seed", type=int, default=26)
    ap.add_argument("--function", action="append", metavar="NAME",
                    help="mutate only these functions (e.g. after a change to them)")
    ap.add_argument("--list", action="store_true", help="list the mutants and stop")
    ap.add_argument("--json", type=Path, help="also write the results to this file")
    ap.add_argument("--rerun", type=Path, help="a --json file of an earlier run: run its survivors again (the "
                                               "tests only grew since, so its killed mutants stay killed)")
    args = ap.parse_args(argv)
    accepted = load_accepted()
    names = args.module or list(MODULES)
    plan = {}
    for name in names:
        files, tests = MODULES[name]
        ms = [m for path, fns in files.items() for m in mutants_of(path, fns)
              if not args.function or m.function in args.function]
        if args.sample and len(ms) > args.sample:
            ms = sorted(random.Random(f"{args.seed}:{name}").sample(ms, args.sample), key=lambda m: (m.file, m.start))
        plan[name] = (ms, tests)
    earlier = {}
    if args.rerun:
        for r in json.loads(args.rerun.read_text(encoding="utf-8"))["results"]:
            earlier[(r["file"], r["function"], r["mutated"])] = r["status"]
        plan = {name: ([m for m in ms if earlier.get(m.key) in ("survived", "accepted", None)], tests, ms)
                for name, (ms, tests) in plan.items()}
    else:
        plan = {name: (ms, tests, ms) for name, (ms, tests) in plan.items()}
    if args.list:
        for name, (ms, _, _) in plan.items():
            for m in ms:
                print(f"{name}: {m.describe()}")
        return 0
    rows, survivors, results = [], [], []
    with tempfile.TemporaryDirectory(prefix="flexgear-mutants-") as tmp:
        copy = Path(tmp) / "src"
        _copy_tree(copy)
        env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1", PYTHONPATH=str(copy),
                   FLEXGEAR_CACHE_DIR=os.environ.get("FLEXGEAR_CACHE_DIR") or str(Path(tmp) / "cache"))
        for name, (ms, tests, drawn) in plan.items():
            status, base = run_tests(copy, tests, 3600.0, env)
            if status != "survived":
                print(f"{name}: the tests fail on the unmutated code; skipped", file=sys.stderr)
                continue
            timeout = max(60.0, 3.0 * base)
            killed = len(drawn) - len(ms)                  # killed in the earlier run (--rerun)
            surv = acc = 0
            for i, m in enumerate(ms, 1):
                target = copy / m.file
                original = target.read_bytes()
                text = original.decode("utf-8")
                target.write_text(text[:m.start] + m.replacement + text[m.end:], encoding="utf-8")
                try:
                    status, dt = run_tests(copy, tests, timeout, env)
                finally:
                    target.write_bytes(original)
                if status == "killed":
                    killed += 1
                elif m.key in accepted:
                    acc += 1
                    status = "accepted"
                else:
                    surv += 1
                    survivors.append((name, m))
                results.append(dict(module=name, status=status, seconds=round(dt, 1), **dataclasses.asdict(m)))
                print(f"[{name} {i}/{len(ms)}] {status:8s} {dt:6.1f} s  {m.describe()}", flush=True)
            n = len(drawn)
            rate = (killed + acc) / n if n else 1.0
            rows.append((name, n, killed, surv, acc, rate))
    print()
    print(f"{'module':16s} {'mutants':>7s} {'killed':>7s} {'survived':>8s} {'accepted':>8s} {'kill rate':>9s}")
    for name, n, k, s, a, rate in rows:
        print(f"{name:16s} {n:7d} {k:7d} {s:8d} {a:8d} {rate:9.1%}")
    tot = [sum(r[i] for r in rows) for i in (1, 2, 3, 4)]
    if rows:
        print(f"{'all':16s} {tot[0]:7d} {tot[1]:7d} {tot[2]:8d} {tot[3]:8d} {(tot[1] + tot[3]) / max(tot[0], 1):9.1%}")
    if survivors:
        print("\nsurvivors (kill each with a test, or give a reason in tests/mutation/accepted.toml):")
        for name, m in survivors:
            print(f"  {m.describe()}\n      mutated = {json.dumps(m.mutated)}")
    if args.json:
        args.json.write_text(json.dumps({"rows": rows, "results": results}, indent=1), encoding="utf-8")
    return 1 if survivors else 0


if __name__ == "__main__":
    sys.exit(main())
