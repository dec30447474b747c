"""``flexgear export superelement``: the flexible carrier of the shipped planetary scene written
as .npz and Nastran DMIG in its local axes, read back equal to the body's superelement (the
same reduction: the cache of the test session); one-line errors for bodies without one.

The DMIG reals are shortest round-trip decimals (cms.export.nastran_real), so both files must
read back bit-exact: every comparison is exact equality."""
from __future__ import annotations

import os

import numpy as np
import pytest

from assembly.app.cli import main
from assembly.model.assemble import assemble
from assembly.scene.schema import load_scene
from cms.export import dof_map, read_dmig, read_dmig_points, read_npz

SCENE = "planetary_flexible_carrier.toml"
BODY = "stage.carrier"                          # the carrier of stage "stage"


@pytest.fixture(scope="module")
def carrier():
    return assemble(load_scene(SCENE)).bodies[BODY]


def test_exports_the_flexible_carrier_in_local_axes(carrier, tmp_path, capsys):
    out = tmp_path / "se"                                         # created by the command
    assert main(["export", "superelement", SCENE, "--body", BODY, "--out", str(out), "-q"]) == 0
    stdout = capsys.readouterr().out
    assert len(stdout.splitlines()) == 1 and f"{BODY}.npz" in stdout and f"{BODY}.dmig" in stdout
    assert sorted(os.listdir(out)) == [f"{BODY}.dmig", f"{BODY}.npz"]
    se = carrier.superelement
    z = read_npz(out / f"{BODY}.npz")
    assert np.array_equal(z["K"], se.K) and np.array_equal(z["M"], se.M)
    assert "local component axes" in z["frame"] and BODY in z["frame"]
    assert np.array_equal(z["frame_origin"], carrier.origin) and np.array_equal(z["frame_axes"], carrier.axes)
    # interface nodes: the body's masters, at their local positions (global = origin + R local)
    names = list(z["node_names"])
    assert sorted(names) == sorted(carrier.masters)
    for k, nm in enumerate(names):
        pos, idx = carrier.masters[nm]
        assert np.allclose(carrier.origin + carrier.axes @ z["node_positions"][k], pos, rtol=0, atol=1e-15)
        assert list(np.flatnonzero(z["dof_node"] == k)) == list(idx)          # the body's DOF indices
    assert list(z["dof_names"][:se.n_boundary]) == se.boundary_names
    assert z["mesh_sha256"] == se.metadata["mesh_sha256"]
    mats = read_dmig(out / f"{BODY}.dmig")
    want = dof_map(se).keys()
    for name, ref in (("KAAX", se.K), ("MAAX", se.M)):
        matrix, keys = mats[name]
        idx = [keys.index(k) for k in want]
        assert np.array_equal(matrix[np.ix_(idx, idx)], ref), name
    grids, spoints = read_dmig_points(out / f"{BODY}.dmig")
    assert np.array_equal(np.array([grids[g] for g in z["node_ids"]]), z["node_positions"])
    assert spoints == list(z["scalar_ids"])
    assert "local component axes" in (out / f"{BODY}.dmig").read_text().split("GRID,")[0]


def test_format_option_writes_only_the_named_file(tmp_path, capsys):
    assert main(["export", "superelement", SCENE, "--body", BODY, "--out", str(tmp_path), "--format", "dmig",
                 "-q"]) == 0
    assert os.listdir(tmp_path) == [f"{BODY}.dmig"]
    assert main(["export", "superelement", SCENE, "--body", BODY, "--out", str(tmp_path), "--format", "npz,step",
                 "-q"]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "--format" in err and "npz,step" in err


@pytest.mark.parametrize("body,reason", [("stage.sun", "is not a flexible body"), ("nope", "no such body")])
def test_a_body_without_superelement_is_a_one_line_error(tmp_path, capsys, body, reason):
    assert main(["export", "superelement", SCENE, "--body", body, "--out", str(tmp_path / "x"), "-q"]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and reason in err and BODY in err      # names the flexible bodies
    assert not (tmp_path / "x").exists()


# --out DIR: <body>.npz and <body>.dmig replace only flexgear's own earlier exports (cms.export.is_export),
# never a user's file of that name or a symbolic link; both are checked before either is written.
# The body: tests/support/tiny_runs.tiny_body (a 14-DOF bar superelement, named "bar").
@pytest.fixture(scope="module")
def bar():
    from tests.support.tiny_runs import tiny_body
    return tiny_body()


def _export(bar, out, monkeypatch, api: bool = False):
    from assembly.app.export import superelement as export_superelement
    if api:
        return export_superelement.write_body(bar, "scene", out)
    monkeypatch.setattr(export_superelement, "reduced_body", lambda scene, name: bar)
    return main(["export", "superelement", SCENE, "--body", "bar", "--out", str(out), "-q"])


USER_FILES = {"a user's npz": ("bar.npz", lambda p: np.savez(p, K=np.eye(2))),
              "a user's DMIG": ("bar.dmig", lambda p: p.write_text("$ my model\nDMIG,KAAX,0,6,2,0\n")),
              "a zip header, not a zip": ("bar.npz", lambda p: p.write_bytes(b"PK\x03\x04 not a zip"))}


@pytest.mark.parametrize("api", [False, True], ids=["cli", "api"])
@pytest.mark.parametrize("user", list(USER_FILES))
def test_a_users_file_of_the_name_is_never_replaced(bar, tmp_path, capsys, monkeypatch, user, api):
    from assembly.app.output import OutputDirError

    name, make = USER_FILES[user]
    path = tmp_path / name
    make(path)
    before = path.read_bytes()
    if api:
        with pytest.raises(OutputDirError, match="flexgear replaces only files it wrote"):
            _export(bar, tmp_path, monkeypatch, api=True)
    else:
        assert _export(bar, tmp_path, monkeypatch) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and f"--out {tmp_path}" in err[0] and str(path) in err[0], err
    assert path.read_bytes() == before
    assert os.listdir(tmp_path) == [path.name]         # neither file written: both checked first


def test_an_earlier_export_is_replaced_and_other_files_stay(bar, tmp_path, capsys, monkeypatch):
    assert _export(bar, tmp_path, monkeypatch) == 0
    (tmp_path / "notes.txt").write_text("mine")
    dmig = (tmp_path / "bar.dmig").read_text().replace("KAAX", "KOLD")          # an edited earlier export
    (tmp_path / "bar.dmig").write_text(dmig)
    assert _export(bar, tmp_path, monkeypatch) == 0
    assert "KAAX" in (tmp_path / "bar.dmig").read_text() and (tmp_path / "notes.txt").read_text() == "mine"
    assert sorted(os.listdir(tmp_path)) == ["bar.dmig", "bar.npz", "notes.txt"]


@pytest.mark.parametrize("name", ["bar.npz", "bar.dmig"])
def test_a_symbolic_link_of_the_name_is_refused(bar, tmp_path, capsys, monkeypatch, name):
    (tmp_path / "out").mkdir()
    _export(bar, tmp_path / "theirs", monkeypatch, api=True)            # flexgear's own file, even so
    (tmp_path / "out" / name).symlink_to(tmp_path / "theirs" / name)
    before = (tmp_path / "theirs" / name).read_bytes()
    assert _export(bar, tmp_path / "out", monkeypatch) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "symbolic link" in err[0]
    assert os.listdir(tmp_path / "out") == [name] and (tmp_path / "theirs" / name).read_bytes() == before


def test_out_may_be_a_link_to_a_folder(bar, tmp_path, capsys, monkeypatch):
    # the rule is on the files: a linked folder is written into, its other files untouched
    (tmp_path / "real").mkdir()
    (tmp_path / "real" / "notes.txt").write_text("mine")
    (tmp_path / "se").symlink_to(tmp_path / "real", target_is_directory=True)
    assert _export(bar, tmp_path / "se", monkeypatch) == 0
    assert sorted(os.listdir(tmp_path / "real")) == ["bar.dmig", "bar.npz", "notes.txt"]
