"""``flexgear static`` and the run step for load cases: tables, JSON, files, one-line errors."""
import csv
import json
import math

import pytest

from assembly.app.cli import main
from assembly.app.report.pipeline import DEFAULT_STEPS, RunOptions, run_pipeline
from tests.app.test_core_cli import BASE

# The Peeters et al. (2006) spur pair (r_b 50 mm, 20 deg) of the CLI tests, two load cases.
PAIR = BASE + """
[[loads]]
name = "rated"
input = "pinion"
output = "wheel"
torque = 100.0
[[loads]]
name = "reverse"
input = "pinion"
output = "wheel"
torque = -50.0
"""


@pytest.fixture
def pair_file(tmp_path):
    p = tmp_path / "pair.toml"
    p.write_text(PAIR)
    return p


def test_static_json_gives_mesh_force_T_over_rb_per_case(pair_file, capsys):
    assert main(["static", str(pair_file), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    cases = out["load_cases"]
    assert [c["path"] for c in cases] == ["loads[0]", "loads[1]"]
    for c, torque in zip(cases, (100.0, -50.0)):       # free body of the pinion: F = T / r_b
        assert c["meshes"][0]["force_N"] == pytest.approx(torque / 0.05, rel=1e-12)
        assert c["torque_balance"]["relative_error"] < 1e-12
        assert c["ratio_check"]["relative_error"] < 1e-12


def test_static_text_tables(pair_file, capsys):
    assert main(["static", str(pair_file)]) == 0
    out = capsys.readouterr().out
    for word in ("gear meshes", "bearing reactions", "checks", "'reverse'", "opposite", "2000"):
        assert word in out


def test_static_refusals_are_one_line(pair_file, capsys, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(PAIR.replace('output = "wheel"\ntorque = -50.0', 'output = "nothing"\ntorque = -50.0'))
    assert main(["static", str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("flexgear: error: loads[1].output = 'nothing': no body of that name")
    assert main(["static", "lin_parker_n3.toml"]) == 2
    assert "no load case" in capsys.readouterr().err


def test_run_writes_static_files_and_section(pair_file, tmp_path):
    steps = [s for s in DEFAULT_STEPS if s.name not in ("fidelity comparison", "mode-shape images", "plots")]
    ctx = run_pipeline(pair_file, tmp_path / "out", RunOptions(images=False, compare=False), steps=steps)
    out = tmp_path / "out"
    data = json.loads((out / "static.json").read_text())
    assert len(data["load_cases"]) == 2 and len(ctx.statics) == 2
    rows = list(csv.DictReader(open(out / "static.csv")))
    force = [float(r["value"]) for r in rows if r["kind"] == "mesh" and r["quantity"] == "force"]
    assert force == pytest.approx([100.0 / 0.05, -50.0 / 0.05], rel=1e-12)
    html = (out / "index.html").read_text()
    assert "Static load case &#x27;rated&#x27;" in html and "bearing reactions" in html
    assert math.isfinite(ctx.static_reports[0].output_torque_Nm)


def test_static_point_loads_and_supports_in_json_text_and_csv(tmp_path, capsys):
    # The two-bearing shaft of tests/analysis/test_static_loads.py (bearings at z = -0.1 and
    # +0.2 m, 1000 N along x at z = 0.05 m, 5 N m about the body's y, the axis held by a
    # support): lever rule plus the couple of the moment, R_A = -1000 (0.2 - 0.05) / 0.3
    # + 5 / 0.3; nothing turns the shaft about its axis, so the support takes no torque.
    from tests.analysis.test_static_loads import TOML
    p = tmp_path / "shaft.toml"
    p.write_text(TOML)
    assert main(["static", str(p), "--json"]) == 0
    (case,) = json.loads(capsys.readouterr().out)["load_cases"]
    assert case["input"] is None and case["torque_balance"] == {} and case["ratio_check"] == {}
    assert case["bearings"][0]["Fx_N"] == pytest.approx(-1000.0 * 0.15 / 0.3 + 5.0 / 0.3, rel=1e-12)
    assert case["supports"][0]["dofs"] == ["rz"] and case["supports"][0]["Mz_Nm"] == pytest.approx(0.0, abs=1e-9)
    assert case["equilibrium"]["relative_error"] < 1e-12 and len(case["applied_loads"]) == 2
    assert main(["static", str(p)]) == 0
    out = capsys.readouterr().out
    for words in ("2 point load(s); 1 support(s)", "applied loads", "support reactions", "equilibrium"):
        assert words in out


def test_round_off_prints_as_zero_in_the_tables(capsys):
    # the quill drive's torque case: its tables print no load below 1e-10 of the case's largest
    # (the solve's round-off); the checks keep their residuals, the JSON every digit
    import re
    assert main(["static", "two_stage_quill"]) == 0
    text = capsys.readouterr().out
    tables = text.split("checks")[0]
    numbers = [float(x) for x in re.findall(r"(?<![\w.])-?\d+(?:\.\d+)?(?:e[-+]\d+)?(?![\w.])", tables)]
    top = max(abs(x) for x in numbers)
    assert all(x == 0.0 or abs(x) > 1e-10 * top for x in numbers)


def test_verbose_shows_progress_not_every_fe_form(capsys):
    # -v: flexgear's progress at INFO; scikit-fem's per-form assembly lines only with -vv
    import logging
    try:
        assert main(["-v", "modes", "kahraman_beta20", "--json"]) == 0
        assert logging.getLogger("skfem").getEffectiveLevel() == logging.WARNING
        assert main(["-vv", "modes", "kahraman_beta20", "--json"]) == 0
        assert logging.getLogger("skfem").getEffectiveLevel() == logging.DEBUG
    finally:
        logging.getLogger("skfem").setLevel(logging.NOTSET)
        logging.getLogger().setLevel(logging.WARNING)
