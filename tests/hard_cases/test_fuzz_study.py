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

from assembly.app.study_engine import run_study
from assembly.app.study_file import read_study
from assembly.app.study_out import write_table
from assembly.app.study_spec import scene_paths
from assembly.edit import value_kind
from assembly.errors import SceneError
from assembly.schema import load_scene
from tests.support.fuzz import examples

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
        return json.dumps(v, ensure_ascii=False)   # JSON escapes control characters as TOML does
    if isinstance(v, list):
        return "[" + ", ".join(_toml(x) for x in v) + "]"
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
