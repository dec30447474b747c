"""Superelement export (cms.export): the .npz and the Nastran DMIG text read back to the very
matrices, DOF map and node positions written; DMIG layout (symmetric IFO = 6, upper triangle
only, no zeros, 80-character lines); atomic writes.

Test model: a steel bar 0.5 x 0.1 x 0.1 m (scikit-fem P2 tetrahedra) with both end faces
tied by RBE2 to masters "a" and "b" at the face centres, reduced by Craig-Bampton with 5
fixed-interface modes and residual vectors. Tolerances: none -- the npz stores binary64 as is,
and the DMIG reals are Python's shortest round-trip representation (``repr``, <= 17
significant digits), which reads back to the same binary64 (IEEE 754 round-trip of 17
significant digits), so every comparison is exact equality.
"""
from __future__ import annotations

import dataclasses
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from cms.craig_bampton import CraigBamptonReductor
from cms.errors import CacheError, ReductionError
from cms.export import (
    FORMAT,
    LINE_WIDTH,
    dof_map,
    nastran_real,
    read_dmig,
    read_dmig_points,
    read_npz,
    write_dmig,
    write_npz,
)
from fe_components.coupling import couple_nodes
from tests.support.fe_models import box

A, B, C, RHO = 0.5, 0.1, 0.1, 7850.0          # m, m, m, kg/m^3
MASS = RHO * A * B * C                        # kg
COM = [A / 2, B / 2, C / 2]                   # m
INERTIA = np.diag([MASS / 12 * (B**2 + C**2), MASS / 12 * (A**2 + C**2), MASS / 12 * (A**2 + B**2)])  # kg m^2
ENDS = {"a": [0.0, B / 2, C / 2], "b": [A, B / 2, C / 2]}


@pytest.fixture(scope="module")
def se():
    m = box(lengths=(A, B, C), divisions=(4, 1, 1), rho=RHO)
    X = m.node_coords
    c = couple_nodes(m.K, m.M, X, {"a": (np.flatnonzero(np.isclose(X[:, 0], 0.0)), ENDS["a"], "rbe2"),
                                   "b": (np.flatnonzero(np.isclose(X[:, 0], A)), ENDS["b"], "rbe2")})
    return CraigBamptonReductor(c.K_c, c.M_c, c.boundary_dofs, n_modes=5, dof_layout=c.dof_layout(X),
                                dof_names=c.boundary_names, residual_vectors=True,
                                metadata={"mass": MASS, "center_of_mass": COM, "inertia": INERTIA.tolist()}).reduce()


def _in_order(matrix, keys, want):
    """``matrix`` (rows/columns ``keys``) permuted to the order ``want``."""
    idx = [keys.index(k) for k in want]
    return matrix[np.ix_(idx, idx)]


def test_npz_reads_back_bit_exact_with_its_dof_map(se, tmp_path):
    path = write_npz(tmp_path / "bar.npz", se)
    z = read_npz(path)
    assert z["format"] == FORMAT and z["version"] == "1" and "N m/rad" in z["units"]
    assert np.array_equal(z["K"], se.K) and np.array_equal(z["M"], se.M)
    nb, nm = se.n_boundary, se.n_modes
    assert list(z["dof_names"]) == se.boundary_names + [f"q{k}" for k in range(nm)]
    assert list(z["node_names"]) == ["a", "b"] and list(z["node_ids"]) == [1, 2]
    assert np.array_equal(z["node_positions"], [ENDS["a"], ENDS["b"]])
    assert list(z["dof_node"]) == [0] * 6 + [1] * 6 + [-1] * nm
    assert list(z["dof_component"]) == [1, 2, 3, 4, 5, 6] * 2 + [0] * nm
    assert z["n_boundary"] == nb and list(z["scalar_ids"]) == list(range(1001, 1001 + nm))
    assert np.array_equal(z["fixed_interface_frequencies_hz"], se.mode_frequencies_hz)
    assert z["n_residual_vectors"] == se.metadata["n_residual_vectors"] > 0
    assert z["mass"] == MASS and np.array_equal(z["center_of_mass"], COM) and np.array_equal(z["inertia"], INERTIA)
    # a plain file: every array loads without pickle, none is an object array
    with np.load(path, allow_pickle=False) as raw:
        assert all(raw[k].dtype != object for k in raw.files)
    assert sorted(os.listdir(tmp_path)) == ["bar.npz"]          # no temporary file left


def test_read_npz_refuses_a_file_of_another_format(se, tmp_path):
    se.save(tmp_path / "se.npz")                                 # cms's own cache format
    with pytest.raises(CacheError, match="format"):
        read_npz(tmp_path / "se.npz")
    (tmp_path / "text.npz").write_text("K = 1\n")
    with pytest.raises(CacheError, match="cannot read"):
        read_npz(tmp_path / "text.npz")


def test_dmig_reads_back_bit_exact(se, tmp_path):
    path = write_dmig(tmp_path / "bar.dmig", se)
    mats = read_dmig(path)
    assert sorted(mats) == ["KAAX", "MAAX"]
    want = dof_map(se).keys()
    assert want[:7] == [(1, 1), (1, 2), (1, 3), (1, 4), (1, 5), (1, 6), (2, 1)] and want[-1] == (1000 + se.n_modes, 0)
    for name, ref in (("KAAX", se.K), ("MAAX", se.M)):
        matrix, keys = mats[name]
        assert sorted(keys) == sorted(want)
        got = _in_order(matrix, keys, want)
        assert np.array_equal(got, ref) and np.array_equal(got, got.T), name
    grids, spoints = read_dmig_points(path)
    assert {g: p.tolist() for g, p in grids.items()} == {1: ENDS["a"], 2: ENDS["b"]}
    assert spoints == list(range(1001, 1001 + se.n_modes))


def _dmig_columns(text: str, name: str) -> list:
    """[(column key, [(row key, value)])] of the DMIG column cards of ``name`` (layout check)."""
    cols, ours = [], False
    for line in text.splitlines():
        f = line.split(",")
        if f[0] != "+":
            ours = f[0] == "DMIG" and f[1] == name and f[2] != "0"
            if ours:
                cols.append(((int(f[2]), int(f[3])), [((int(f[5]), int(f[6])), float(f[7]))]))
        elif ours:
            cols[-1][1].extend(((int(f[k]), int(f[k + 1])), float(f[k + 2])) for k in (1, 5) if len(f) > k)
    return cols


def test_dmig_layout_symmetric_upper_triangle_without_zeros(se, tmp_path):
    K = se.K.copy()
    K[0, 7] = K[7, 0] = K[3, 20] = K[20, 3] = 0.0                # exact zeros are dropped
    sez = dataclasses.replace(se, K=K)
    text = write_dmig(tmp_path / "z.dmig", sez, k_name="KSE", m_name="MSE").read_text()
    lines = text.splitlines()
    assert max(len(ln) for ln in lines) <= LINE_WIDTH
    assert "DMIG,KSE,0,6,2,0,0" in lines and "DMIG,MSE,0,6,2,0,0" in lines   # IFO 6, TIN 2, TOUT 0, POLAR 0
    assert "K2GG=KSE" in text and "M2GG=MSE" in text and "Units SI: m, kg, s, N" in text
    pos = {k: j for j, k in enumerate(dof_map(sez).keys())}
    for name, ref in (("KSE", K), ("MSE", se.M)):
        cols = _dmig_columns(text, name)
        terms = [(pos[r], pos[c], v) for c, rows in cols for r, v in rows]
        assert all(i <= j for i, j, _ in terms)                          # upper triangle only
        assert len({(i, j) for i, j, _ in terms}) == len(terms)          # each term once
        assert all(v != 0.0 for _, _, v in terms)
        assert len(terms) == np.count_nonzero(np.triu(ref))             # every non-zero term
        assert all(ref[i, j] == v for i, j, v in terms)
    matrix, keys = read_dmig(tmp_path / "z.dmig")["KSE"]
    assert np.array_equal(_in_order(matrix, keys, list(pos)), K)


def test_ids_are_the_callers(se, tmp_path):
    path = write_dmig(tmp_path / "ids.dmig", se, node_ids=[10, 20], first_scalar_id=500)
    grids, spoints = read_dmig_points(path)
    assert sorted(grids) == [10, 20] and spoints == list(range(500, 500 + se.n_modes))
    assert read_dmig(path)["KAAX"][1][0] == (10, 1)
    with pytest.raises(ReductionError, match="differ"):
        write_dmig(tmp_path / "clash.dmig", se, node_ids=[1, 2], first_scalar_id=2)
    with pytest.raises(ReductionError, match="one GRID id per interface node"):
        dof_map(se, node_ids=[1])
    assert not (tmp_path / "clash.dmig").exists()


def test_flexgear_body_superelement_maps_by_name_and_master_positions(se, tmp_path):
    """A flexible body's superelement has no kinds or points (a rigid-body basis was given):
    the names 'node:ux' and metadata['masters'] carry the map."""
    bare = dataclasses.replace(se, boundary_kinds=np.full(se.n_boundary, -1), boundary_points=np.zeros((0, 3)),
                               metadata={**se.metadata, "masters": {"a": [0.0, 0.0, -0.1], "b": [0.0, 0.0, 0.1]}})
    z = read_npz(write_npz(tmp_path / "bare.npz", bare))
    assert list(z["node_names"]) == ["a", "b"]
    assert np.array_equal(z["node_positions"], [[0.0, 0.0, -0.1], [0.0, 0.0, 0.1]])
    assert list(z["dof_component"][:12]) == [1, 2, 3, 4, 5, 6] * 2
    unnamed = dataclasses.replace(bare, boundary_names=[])
    with pytest.raises(ReductionError, match="boundary DOF 0"):
        write_npz(tmp_path / "unnamed.npz", unnamed)
    assert sorted(os.listdir(tmp_path)) == ["bare.npz"]


def test_a_non_symmetric_matrix_is_refused(se, tmp_path):
    K = se.K.copy()
    K[0, 1] *= 1.001
    with pytest.raises(ReductionError, match="not symmetric"):
        write_dmig(tmp_path / "x.dmig", dataclasses.replace(se, K=K))
    assert not (tmp_path / "x.dmig").exists()


@pytest.mark.parametrize("write", [write_npz, write_dmig])
def test_missing_folder_is_a_clear_error(se, tmp_path, write):
    with pytest.raises(FileNotFoundError, match="no such folder") as err:
        write(tmp_path / "missing" / "bar.out", se)
    assert err.value.filename == str(tmp_path / "missing")
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("write", [write_npz, write_dmig])
def test_a_failed_write_keeps_the_old_file_and_leaves_no_temporary(se, tmp_path, write, monkeypatch):
    out = tmp_path / "bar.out"
    out.write_text("old\n")

    def refuse(src, dst):
        raise OSError(28, os.strerror(28), str(dst))

    monkeypatch.setattr(os, "replace", refuse)
    with pytest.raises(OSError, match=os.strerror(28)):
        write(out, se)
    assert out.read_text() == "old\n" and os.listdir(tmp_path) == ["bar.out"]


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0, reason="root writes into read-only folders")
def test_read_only_folder_is_a_clear_error(se, tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        with pytest.raises(PermissionError, match="cannot write bar.dmig") as err:
            write_dmig(ro / "bar.dmig", se)
        assert err.value.filename == str(ro) and os.listdir(ro) == []
    finally:
        ro.chmod(0o755)


def test_unwritable_folder_is_a_clear_error(se, tmp_path, monkeypatch):
    """The folder refuses the temporary file (as a read-only folder does for a non-root user)."""
    import tempfile

    def refuse(**kwargs):
        raise PermissionError(13, os.strerror(13), os.path.join(kwargs["dir"], ".tmp"))

    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    with pytest.raises(PermissionError, match="cannot write bar.npz into this folder") as err:
        write_npz(tmp_path / "bar.npz", se)
    assert err.value.filename == str(tmp_path) and os.listdir(tmp_path) == []


@given(st.floats(allow_nan=False, allow_infinity=False))
def test_nastran_real_round_trips_every_double(x):
    s = nastran_real(x)
    assert float(s) == x and "." in s.partition("E")[0] and len(s) <= 24 and "e" not in s


@given(st.floats(1e-99, 9.999e99), st.booleans())
def test_nastran_real_in_16_characters_keeps_ten_digits(x, negative):
    """16 characters: sign, d.ddddddddd (10 significant digits), E-dd; round to nearest,
    so the relative error is at most half a unit of the 10th digit, 5e-10."""
    x = -x if negative else x
    s = nastran_real(x, 16)
    assert len(s) <= 16 and "." in s
    assert abs(float(s) - x) <= 5e-10 * abs(x)
    if len(nastran_real(x)) <= 16:
        assert float(s) == x                                     # repr fits: exact


def test_dmig_in_16_character_fields(se, tmp_path):
    path = write_dmig(tmp_path / "f16.dmig", se, field_width=16)
    text = path.read_text()
    for line in text.splitlines():
        if not line.startswith("$"):
            assert max(len(f) for f in line.split(",")) <= 16, line
    want = dof_map(se).keys()
    for name, ref in (("KAAX", se.K), ("MAAX", se.M)):
        matrix, keys = read_dmig(path)[name]
        got = _in_order(matrix, keys, want)
        assert np.all(np.abs(got - ref) <= 5e-10 * np.abs(ref)), name   # >= 10 significant digits


def test_nastran_real_needs_a_decimal_point_and_refuses_non_finite():
    assert nastran_real(1e-05) == "1.0E-05" and nastran_real(1e16) == "1.0E+16" and nastran_real(0.5) == "0.5"
    with pytest.raises(ReductionError, match="not finite"):
        nastran_real(float("inf"))


#: pyNastran 1.4.1 (the current release) pins numpy < 2 and calls np.in1d, gone in NumPy
#: 2.4, so it cannot run beside flexgear: it reads the file in an environment of its own,
#: made once (about 15 s with pip's cache, 60 s without) and kept in pytest's cache folder.
PYNASTRAN = ("pyNastran==1.4.1", "numpy<2", "scipy", "cpylog", "docopt-ng")
READ_WITH_PYNASTRAN = """
import json, sys
import numpy as np
from pyNastran.bdf.bdf import BDF
model = BDF(debug=None)
model.read_bdf(sys.argv[1], punch=True, xref=False)
out = {"matrices": {}, "nodes": {str(g): n.xyz.tolist() for g, n in model.nodes.items()},
       "spoints": sorted(int(s) for s in model.spoints)}
for name in ("KAAX", "MAAX"):
    matrix, rows, _ = model.dmig[name].get_matrix(is_sparse=False, apply_symmetry=True)[:3]
    out["matrices"][name] = {"keys": [[int(v) for v in rows[i]] for i in range(len(rows))],
                             "values": np.asarray(matrix, float).tolist()}
print(json.dumps(out))   # floats as repr: the shortest decimal that reads back to the same binary64
"""


def _pynastran_python(request, tmp_path_factory) -> Path:
    """The interpreter of a virtual environment holding PYNASTRAN (made if missing, with this
    environment's pip: ``pip --python``; the base interpreter's site-packages are visible,
    so a scipy there is not installed again)."""
    cache = getattr(request.config, "cache", None)
    root = cache.mkdir("pynastran-1.4.1") if cache is not None else tmp_path_factory.mktemp("pynastran")
    venv, done = root / "venv", root / "venv.ok"
    if not done.exists():
        shutil.rmtree(venv, ignore_errors=True)
        base = getattr(sys, "_base_executable", sys.executable)
        subprocess.run([base, "-m", "venv", "--without-pip", "--system-site-packages", str(venv)], check=True,
                       timeout=120)
        out = subprocess.run([sys.executable, "-m", "pip", "--python", str(venv / "bin" / "python"), "install",
                              "-q", "--no-deps", *PYNASTRAN], capture_output=True, text=True, timeout=600)
        assert out.returncode == 0, f"cannot install {PYNASTRAN}: {out.stderr[-2000:]}"
        done.write_text(" ".join(PYNASTRAN) + "\n")
    return venv / "bin" / "python"


@pytest.mark.slow   # the first run makes pyNastran's environment
def test_pynastran_reads_the_dmig_bit_exact(se, tmp_path, request, tmp_path_factory):
    """A Nastran-family reader (pyNastran's BDF, bulk data only) accepts the file and gets the
    same binary64 matrices, GRIDs and SPOINTs."""
    python = _pynastran_python(request, tmp_path_factory)
    path = write_dmig(tmp_path / "bar.dmig", se)
    out = subprocess.run([str(python), "-c", READ_WITH_PYNASTRAN, str(path)], capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    got = json.loads(out.stdout)
    want = dof_map(se).keys()
    for name, ref in (("KAAX", se.K), ("MAAX", se.M)):
        keys = [tuple(k) for k in got["matrices"][name]["keys"]]
        matrix = np.array(got["matrices"][name]["values"])
        assert np.array_equal(_in_order(matrix, keys, want), ref), name
    assert got["nodes"] == {"1": ENDS["a"], "2": ENDS["b"]}
    assert got["spoints"] == list(range(1001, 1001 + se.n_modes))


def test_is_export_knows_its_own_files_and_no_other(se, tmp_path):
    # the exports of any version are recognised by their format entry / DMIG header line; a user's
    # npz, Nastran file, zip or text is not, nor an npz of pickled objects
    import zipfile

    from cms.export import is_export
    ours = [write_npz(tmp_path / "a.npz", se), write_dmig(tmp_path / "a.dmig", se, title="a title " * 30),
            write_dmig(tmp_path / "b.dmig", se, field_width=16)]
    assert all(is_export(p) for p in ours)
    np.savez(tmp_path / "u.npz", K=np.eye(2), format=np.array("something else"))
    np.savez(tmp_path / "v.npz", format=np.array([{"a": 1}], dtype=object))
    with zipfile.ZipFile(tmp_path / "w.zip", "w") as z:
        z.writestr("readme.txt", "hi")
    (tmp_path / "x.dmig").write_text("$ my model\nDMIG,KAAX,0,6,2,0\n")
    (tmp_path / "y.dmig").write_text("$ " + "x" * 500 + "\n$ Nastran bulk data, free-field. Matrices\n")
    (tmp_path / "z.bin").write_bytes(b"PK\x03\x04 truncated")
    (tmp_path / "e.txt").write_text("")
    for name in ("u.npz", "v.npz", "w.zip", "x.dmig", "y.dmig", "z.bin", "e.txt"):
        assert not is_export(tmp_path / name), name
