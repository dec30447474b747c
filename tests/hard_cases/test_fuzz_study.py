"""Fuzzing design studies: random study tables (real, misspelt and wildcard paths; values of
every TOML type; every design) through reading, expanding, running and writing. A study is
either refused with a SceneError naming a study field, or every variant becomes a row whose
status is "ok" or "error" (never an exception), and the table files hold every row."""
from __future__ import annotations

import csv
import json
import math

import pyarrow.parquet as pq
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from assembly.app.study.engine import run_study
from assembly.app.study.file import read_study
from assembly.app.study.out import write_table
from assembly.app.study.spec import scene_paths
from assembly.errors import SceneError
from assembly.scene.edit import value_kind
from assembly.scene.schema import load_scene
from tests.support.fuzz import at, examples

SCENE = "kahraman_beta20"     # rigid pair: a variant solves in milliseconds
PATHS = scene_paths(load_scene(SCENE))

path = st.one_of(st.sampled_from(PATHS),
                 st.sampled_from(PATHS).map(lambda p: p[:-1]),                   # misspelt
                 st.sampled_from(["bearings[*].k_radial", "meshes[*].stiffness", "bearings[*].nope",
                                  "bodies[*].mass", "meshes[7].stiffness", "", "a..b", "bearings[0]"]))
value = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10, 10 ** 12),
                  st.booleans(), st.text(max_size=5), st.just(0.0), st.just(-1.0))
values = st.one_of(st.fixed_dictionaries({"values": st.lists(value, min_size=0, max_size=3)}),
                   st.fixed_dictionaries({"range": st.lists(value, min_size=2, max_size=4)}),
                   st.fixed_dictionaries({"log_range": st.lists(value, min_size=2, max_size=4)}),
                   st.fixed_dictionaries({"bounds": st.lists(value, min_size=1, max_size=3)}))
anything = st.builds(lambda p, v, scale: {"path": p, **v, **({"scale": scale} if scale is not None else {})},
                     path, values, st.one_of(st.none(), st.booleans(), st.just("yes")))
# a number field with numbers of any size and sign: read, then each variant runs or is a row's error
NUMBERS = [p for p in PATHS if value_kind(load_scene(SCENE), p) in ("number", "int")]
numeric = st.builds(lambda p, v, scale: {"path": p, "values": v, "scale": scale}, st.sampled_from(NUMBERS),
                    st.lists(st.one_of(st.floats(1e-3, 1e12), st.sampled_from([0.0, -1.0, 1e300, 3])),
                             min_size=1, max_size=3), st.booleans())
parameter = st.one_of(numeric, numeric, anything)
design = st.one_of(st.just({}), st.fixed_dictionaries({"kind": st.sampled_from(["grid", "lhs", "random", "sobol"]),
                                                       "samples": st.one_of(st.integers(-1, 6), st.just(2.5)),
                                                       "seed": st.one_of(st.integers(-1, 99), st.just("x"))}))


def _toml(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") if math.isinf(v) else repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False).replace("\x7f", "\\u007f")   # JSON's escapes are TOML's;
        # TOML also refuses a raw DEL
    if isinstance(v, list):
        return "[" + ", ".join(_toml(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {_toml(x)}" for k, x in v.items()) + " }"
    return str(v)


def study_text(params, dsg) -> str:
    lines = [f'scene = "{SCENE}"', "[keep]", "modes = 3"]
    if dsg:
        lines += ["[design]", *(f"{k} = {_toml(v)}" for k, v in dsg.items())]
    for p in params:
        lines += ["[[parameters]]", *(f"{k} = {_toml(v)}" for k, v in p.items())]
    return "\n".join(lines) + "\n"


@settings(max_examples=examples(60), deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(params=st.lists(parameter, min_size=0, max_size=3), dsg=design)
def test_random_studies_are_refused_by_field_or_give_a_row_per_variant(tmp_path, params, dsg):
    f = tmp_path / "study.toml"
    f.write_text(study_text(params, dsg), encoding="utf-8")
    try:
        study = read_study(f)
    except SceneError as exc:
        msg = str(exc)
        assert "\n" not in msg and msg.split(" ", 1)[0].split("=")[0].strip(), msg
        assert msg.startswith(("parameters", "design")), msg
        return
    study.variants = study.variants[:6]       # the rows of a few variants are enough
    event(f"ran {len(study.variants)} variants")
    rows = run_study(study, "serial")
    assert [r["variant"] for r in rows] == list(range(len(rows)))
    for r in rows:
        assert r["status"] in ("ok", "error")
        assert (r["error"] == "") == (r["status"] == "ok")
        if r["status"] == "ok":
            assert all(math.isfinite(r[f"f{j}_hz"]) and r[f"f{j}_hz"] > 0 for j in (1, 2, 3))
        else:
            assert "\n" not in r["error"] and not r["error"].startswith(("TypeError", "ValueError", "KeyError")), \
                r["error"]
    out = tmp_path / "out"
    out.mkdir(exist_ok=True)
    write_table(rows, study.parameters, out)
    assert len(list(csv.DictReader(open(out / "study.csv")))) == len(rows) == pq.read_table(out / "study.parquet").num_rows


# ---- malformed study files: every table level, every key, every size ----
# A valid study per analysis (tests/app/test_study_read.py's BASES, on its torsional pair), then
# one to three of: an unknown key in any table (random or one letter off a known key), a value
# of any TOML type for any known key, a top-level key written below a table header, a huge
# range / sample count / step count. Each file is read by the Python API and is either a study
# of at most MAX_VARIANTS variants or a SceneError line naming a study field, within seconds.
import copy  # noqa: E402
import re  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import pytest  # noqa: E402

from assembly.app.study.spec import MAX_VARIANTS  # noqa: E402
from assembly.scene.save import toml_text  # noqa: E402
from tests.app.test_simulate_cli import pair_file  # noqa: E402
from tests.app.test_study_read import BASES  # noqa: E402

_KEY = r'(?:[A-Za-z0-9_-]+|"(?:[^"\\]|\\.)*")(?:\[\d+\])?'       # a bare or quoted key, an index
FIELD = re.compile(rf"^{_KEY}(?:\.{_KEY})* = ")                     # a study field as the file writes it
TOP_KEYS = ["name", "scene", "analysis", "keep", "frf", "simulate", "design"]
toml_value = st.recursive(
    st.one_of(st.booleans(), st.integers(-2, 10 ** 15), st.floats(allow_nan=True, allow_infinity=True),
              st.sampled_from(["", "false", "true", "1.0", "pair.toml", "frf", "lhs", "force:m", "peak"]),
              st.text(max_size=6)),
    lambda inner: st.one_of(st.lists(inner, max_size=3), st.dictionaries(st.sampled_from(["modes", "kind", "x"]),
                                                                         inner, max_size=2)),
    max_leaves=4)


def _tables(data: dict) -> list[tuple]:
    """The path (tuple of keys and indices) of every table of a study dict, the top one first."""
    out = [()]
    for k, v in data.items():
        if isinstance(v, dict):
            out.append((k,))
        elif k == "parameters" and isinstance(v, list) and all(isinstance(x, dict) for x in v):
            out += [(k, i) for i in range(len(v))]
    return out


@st.composite
def malformed(draw):
    """(study text, what was done): a valid base with one to three mutations."""
    data = copy.deepcopy(BASES[draw(st.sampled_from(sorted(BASES)))])
    below = []                   # lines written below the last table header
    done = []
    for _ in range(draw(st.integers(1, 3))):
        how = draw(st.sampled_from(["unknown", "type", "misplaced", "huge"]))
        if how == "unknown":
            table = at(data, draw(st.sampled_from(_tables(data))))
            known = draw(st.sampled_from(sorted(table) or ["x"]))
            i = draw(st.integers(0, max(len(known) - 1, 0)))
            key = draw(st.one_of(st.just(known[:i] + known[i + 1:] or "k"), st.just(known + "s"),
                                 st.from_regex(r"[a-z_]{1,8}", fullmatch=True), st.text(min_size=1, max_size=4)))
            if key not in table:
                table[key] = draw(toml_value)
                done.append(f"unknown {key}")
        elif how == "type":
            path = draw(st.sampled_from([(*t, k) for t in _tables(data) for k in at(data, t)]))
            at(data, path[:-1])[path[-1]] = draw(toml_value)
            done.append(f"type {path}")
        elif how == "misplaced":
            key = draw(st.sampled_from(TOP_KEYS))
            below.append(f"{key} = " + _toml(draw(st.one_of(st.just(data.get(key, "pair.toml")), toml_value))))
            done.append(f"misplaced {key}")
        else:
            big = 10 ** draw(st.integers(5, 15))
            what = draw(st.sampled_from(["range", "samples", "steps", "grid"]))
            if what == "range":
                data["parameters"] = [{"path": "meshes[0].stiffness", "range": [1e8, 4e8, big]}]
                data.pop("design", None)
            elif what == "samples":
                data["design"] = {"kind": "random", "samples": big}
                data["parameters"] = [{"path": "meshes[0].stiffness", "bounds": [1e8, 4e8]}]
            elif what == "steps" and isinstance(data.get("simulate"), dict):
                data["simulate"].update(t_end=big * 1e-3, dt=1e-3)
            else:
                data.pop("design", None)
                n = draw(st.integers(2, 400))
                data["parameters"] = [{"path": p, "range": [1.0, 2.0, n]} for p in
                                      ("meshes[0].stiffness", "meshes[0].base_radius1", "meshes[0].base_radius2")]
            done.append(f"huge {what} {big:.0e}")
    text = toml_text(data)
    return text + "".join(line + "\n" for line in below), done


@pytest.fixture(scope="module")
def pair_dir(tmp_path_factory):
    d = tmp_path_factory.mktemp("malformed")
    pair_file(d)
    return d


@pytest.mark.slow       # about 6-10 s on two busy cores
@settings(max_examples=examples(150), deadline=None)
@given(case=malformed())
def test_malformed_study_files_are_read_or_refused_by_field(pair_dir, case):
    text, done = case
    f = pair_dir / "study.toml"
    f.write_text(text, encoding="utf-8")
    t0 = time.perf_counter()
    try:
        study = read_study(f)
    except SceneError as exc:
        msg = str(exc)
        assert len(msg.splitlines()) == 1 and FIELD.match(msg), (msg, done, text)
        event("refused")
    else:
        assert 1 <= len(study.variants) <= MAX_VARIANTS, done
        event("accepted")
    assert time.perf_counter() - t0 < 10.0, (done, "read for too long")     # a variant takes ms here


MALFORMED_CLI = [
    ("modes", "\n[[parameters]]\npath = \"meshes[0].stiffness\"\nvalues = [1e8]\nscael = true\n", "parameters[1].scael"),
    ("lhs", "", "design.samples = 1000000000000"),
    ("frf", "analysis = \"frf\"\n", "parameters[0].analysis"),
    ("simulate", "", "simulate.unreduced = 'false'"),
]


@pytest.mark.parametrize("base, extra, where", MALFORMED_CLI, ids=[w for _, _, w in MALFORMED_CLI])
def test_malformed_study_files_through_the_command_line(pair_dir, tmp_path, base, extra, where):
    # a handful through the real command (a process each): exit 2, one line, nothing written
    data = copy.deepcopy(BASES[base])
    if base == "lhs":
        data["design"]["samples"] = 10 ** 12
    if base == "simulate":
        data["simulate"]["unreduced"] = "false"
    f = pair_dir / f"cli_{base}.toml"
    f.write_text(toml_text(data) + extra, encoding="utf-8")
    out = tmp_path / "out"
    p = subprocess.run([sys.executable, "-m", "assembly.app.cli", "study", str(f), "--out", str(out), "--serial",
                        "-q"], capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and p.stderr.startswith(f"flexgear: error: {where}") and p.stderr.count("\n") == 1, \
        p.stderr
    assert not out.exists()
