"""``flexgear bench quick`` (assembly/app/bench/quick.py) prints its table: the timings are
not tested (they are the machine's), the table's arithmetic and what it names are."""
import io

import pytest

from assembly.app.bench.quick import COMMANDS, main
from assembly.app.cli import BENCHMARKS


def test_bench_quick_is_registered():
    assert BENCHMARKS["quick"] == "assembly.app.bench.quick"


def test_modes_row_gives_median_within_range_ratio_to_goal_and_load():
    buf = io.StringIO()
    assert main(["--only", "modes", "--repeat", "3"], out=buf) == 0
    lines = buf.getvalue().splitlines()
    assert " cores, load average " in lines[2] and "bytecode caches" in lines[2]
    head = next(k for k, ln in enumerate(lines) if ln.startswith("| command |"))
    rows = [ln for ln in lines[head + 2:] if ln.startswith("|")]
    assert len(rows) == 1
    cmd, runs, med, lo, hi, cpu, goal, ratio, load = [c.strip() for c in rows[0].strip("|").split("|")]
    assert cmd == "flexgear modes kahraman_beta20" and runs == "3"
    assert float(lo) <= float(med) <= float(hi) and float(cpu) > 0
    assert float(goal) == dict((n, g) for n, _, g in COMMANDS)["modes"] == 0.3
    # the ratio is the printed median over the goal, to the printed rounding (0.005 / 0.3)
    assert float(ratio) == pytest.approx(float(med) / float(goal), abs=0.005 / 0.3 + 0.005)
    float(load)  # a number (the 1-minute load average after the runs)


def test_repeat_below_one_is_refused():
    with pytest.raises(SystemExit) as exc:
        main(["--only", "modes", "--repeat", "0"], out=io.StringIO())
    assert exc.value.code == 2
