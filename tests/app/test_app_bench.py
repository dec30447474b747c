"""The FE-component benchmark (``flexgear bench fe``, assembly/app/bench_fe.py) runs end to end."""
from __future__ import annotations

import pytest

pytestmark = pytest.mark.gmsh


@pytest.mark.slow
def test_bench_fe_main_prints_table(capsys):
    from assembly.app.bench_fe import main

    assert main(["--components", "carrier", "--target-dofs", "20000", "--levels", "1", "--modes", "6"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    assert out[0].startswith("| component |") and len(out) == 3
    cells = [x.strip() for x in out[2].strip("|").split("|")]
    assert cells[0] == "carrier" and int(cells[3]) > 0
    freqs = [float(f) for f in cells[-1].split(",")]
    assert len(freqs) == 6 and all(f > 0 for f in freqs) and freqs == sorted(freqs)
