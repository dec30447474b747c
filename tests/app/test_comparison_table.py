"""Fidelity comparison table (text and HTML cells): weak MACs flagged, shifts without a
meaningful partner hidden, Rayleigh-Ritz note, columns as wide as their content.

The rows are made up: the rules concern the table, not the physics of any scene.
MAC thresholds: 0.8 for a weak pairing, 0.5 for no partner (Allemang 2003, "The modal
assurance criterion - twenty years of use and abuse", Sound and Vibration 37(8): values
above 0.8-0.9 count as consistent shapes, low values as different shapes).
"""
from types import SimpleNamespace

from assembly.app.report.tables import comparison_cells, comparison_table, text_table

FIDS = ["torsional", "rigid", "flexible"]


def _row(mode, t, r, f, mac_t, mac_r, cls="translational", dom="stage.ring"):
    return {"mode": mode, "class": cls, "dominant_body": dom, "flexible": f, "rigid": r, "torsional": t,
            "mac_rigid": mac_r, "mac_torsional": mac_t}


ROWS = [_row(2, 1100.0, 1000.0, 990.0, 0.95, 0.99),        # good pair: both shifts shown
        _row(3, 1500.0, 1200.0, 1250.0, 0.40, 0.70),        # weak flex-rigid, no partner to torsional
        _row(4, None, 1800.0, 1700.0, None, 0.30),          # no meaningful partner at all
        _row(5, None, None, 3000.0, None, None, "elastic", "stage.carrier")]


def test_cells_flags_and_hidden_shifts():
    c = comparison_cells(ROWS, FIDS)
    h = c["header"]
    rows = {r[0]: dict(zip(h, r)) for r in c["rows"]}
    assert rows["2"]["shift vs rigid [%]"] == "-1.00" and rows["2"]["shift vs torsional [%]"] == "-10.00"
    assert rows["2"]["MAC flex-rigid"] == "0.99"
    # A shift upwards is shown when the pair is meaningful (the ordering holds for the k-th
    # frequency, not per pair); the weak MAC is starred.
    assert rows["3"]["shift vs rigid [%]"] == "+4.17" and rows["3"]["MAC flex-rigid"] == "0.70*"
    assert rows["3"]["shift vs torsional [%]"] == "--" and rows["3"]["MAC rigid-tors"] == "0.40*"
    assert rows["4"]["shift vs rigid [%]"] == "--"
    assert rows["5"]["shift vs rigid [%]"] == "-" and rows["5"]["class"] == "elastic"
    assert c["row_classes"] == ["", "weak", "weak", "unpaired"]
    notes = " ".join(c["notes"])
    assert "MAC < 0.8" in notes and "MAC < 0.5" in notes and "no meaningful partner" in notes
    assert "k-th frequency" in notes and "flexible <= rigid <= torsional" in notes
    # Footnotes only for what occurs.
    clean = comparison_cells(ROWS[:1], FIDS)
    assert not any(n.startswith(("*", "--")) for n in clean["notes"])


def test_text_table_columns_fit_their_content():
    t = text_table(["a", "long header"], [["wide cell value", "1"], ["x", "22"]], left={0})
    lines = t.splitlines()
    assert lines[0].startswith("a" + " " * 14 + "  long header")
    assert lines[1] == "wide cell value            1"
    c = SimpleNamespace(results=dict.fromkeys(FIDS), rows=ROWS,
                        timings={"rigid": {"n_dofs": 21, "total_s": 0.01}})
    text = comparison_table(c)
    head = text.splitlines()[0]
    for name in comparison_cells(ROWS, FIDS)["header"]:
        assert name in head          # no truncated column names
    assert text.count("Rayleigh-Ritz") == 1
