"""``flexgear bench part`` (assembly/app/bench/part.py) runs end to end at a coarse element
size: the table's rows and columns, not the timings."""
from __future__ import annotations

import pytest

from assembly.app.bench import part as bench_part


def _rows(out: str) -> list[dict]:
    """The Markdown table of the benchmark's stdout as dicts keyed by the column names."""
    lines = [ln for ln in out.splitlines() if ln.startswith("|")]
    head = [c.strip() for c in lines[0].strip("|").split("|")]
    assert set(lines[1].strip("|").split("|")) == {"---"}
    return [dict(zip(head, (c.strip() for c in ln.strip("|").split("|")), strict=True)) for ln in lines[2:]]


@pytest.mark.gmsh
@pytest.mark.slow
def test_quick_run_prints_both_carriers_cold_and_warm(capsys):
    assert bench_part.main(["--quick"]) == 0
    out = capsys.readouterr().out
    rows = _rows(out)
    assert list(rows[0]) == list(bench_part.COLUMNS)
    by = {r["component"]: r for r in rows}
    assert list(by) == [bench_part.LABELS[k] for k in ("step", "step-warm", "builtin")]
    step, warm, builtin = by.values()
    for r in rows:
        assert float(r["size [m]"]) == bench_part.QUICK_SIZE
        assert int(r["FE DOFs"]) > 0
        times = [float(r[c].split()[0]) for c in bench_part.COLUMNS[4:10]]
        assert all(t >= 0 for t in times) and times[-1] >= max(times[:-1])
        n_modes, plus, n_rv, rv = r["modes kept"].split()
        # 6 interfaces x 6 master DOFs: one residual vector each
        assert plus == "+" and rv == "rv" and int(n_rv) == 36 and int(n_modes) >= 0
        freqs = [float(f) for f in r["f1, f2, f3 fixed-interface [Hz]"].split(",")] if int(n_modes) else []
        assert len(freqs) == min(3, int(n_modes)) and freqs == sorted(freqs)
        assert all(0 < f < 4500 for f in freqs)   # kept: below the cutoff, 1.5 x band 3000 Hz
        assert float(r["peak RSS [MB]"]) > 0
    # the warm row reads the very mesh the cold row wrote
    assert warm["FE DOFs"] == step["FE DOFs"] and warm["mass [kg]"] == step["mass [kg]"]
    assert builtin["read/import [s]"].endswith("(a)") and "(a) The built-in carrier" in out
    # similar parts: the carrier with windows (CAD volume x 7850 kg/m^3: 17.9 kg) and the
    # built-in carrier with posts (15.8 kg)
    m_step, m_builtin = float(step["mass [kg]"]), float(builtin["mass [kg]"])
    assert abs(m_step - 17.9) < 0.2 and abs(m_builtin - 15.8) < 0.2
    assert abs(m_step / m_builtin - 1) < 0.2


def test_size_list_is_checked(capsys):
    assert bench_part.size_list("0.015, 0.012,0.008") == (0.015, 0.012, 0.008)
    for bad in ("abc", "0.01,-1", ","):
        with pytest.raises(SystemExit) as exc:
            bench_part.main(["--size", bad])
        assert exc.value.code == 2
    assert "element sizes" in capsys.readouterr().err
