"""Extreme magnitudes: rigid-body modes from structure, unresolvable spectra refused with
the field named, soft meshes that keep their bearing modes.

Class of scenes: the Kahraman pairs (spur and helical, 12 DOFs) and Lin & Parker N = 3
(planetary stage, 18 DOFs) with mesh stiffness, bearing stiffness, one body's mass and
its inertias each scaled over many decades. Every outcome must be either a SceneError
naming a field that exists in the scene (with its value), or frequencies that match an
60-digit solve (mpmath) of the same model with every bearing kept elastic, to the
documented bound. Rules: assembly/analysis/resolution.py, assembly/model/constraints.py, assembly/mechanics/nullity.py.
"""
import copy
import dataclasses
import math
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import mpmath as mp
import numpy as np
import pytest
from hypothesis import event, given, settings
from hypothesis import strategies as st

import assembly.analysis.modal as am
import assembly.model.constraints as ac
from assembly import assemble, solve_modes
from assembly.analysis.resolution import EPS, FREQ_RTOL, ROUNDOFF, WARN_RTOL
from assembly.errors import SceneError
from assembly.scene.schema import SCENE_DIR, scene_from_dict
from assembly.scene.tables import DEFAULT_BAND_HZ, DOF_NAMES, derive
from tests.support.fuzz import examples

ROOT = Path(__file__).resolve().parents[2]
TREES = {n: tomllib.loads((SCENE_DIR / n).read_text())
         for n in ("kahraman_beta0.toml", "kahraman_beta20.toml", "lin_parker_n3.toml")}
BEARING_FIELDS = ("k_radial", "k_axial", "k_tilt")


def exact_eigen(K, M, dps=60, add_diagonal=None) -> tuple:
    """Generalized eigenvalues (ascending) of the float64 matrices K, M taken as exact,
    computed with ``dps`` decimal digits -- the reference the double solve is judged by --
    and the round-off weight of each mode, ``(lambda_max + |lambda_i|) ||B||_1 ||x_i||^2``
    (x_i: the mode of the problem scaled to unit mass diagonal B, B-normalised; see
    assembly/analysis/resolution.py). ``add_diagonal`` {index: value} is added to K in extended precision."""
    with mp.workdps(dps):
        Km = mp.matrix(K.tolist())
        for i, v in (add_diagonal or {}).items():
            Km[i, i] += mp.mpf(v)
        L = mp.cholesky(mp.matrix(M.tolist()))
        Li = mp.inverse(L)
        C = Li * Km * Li.T
        ev, Q = mp.eigsy((C + C.T) / 2)
        X = mp.diag([mp.sqrt(M[i, i]) for i in range(len(M))]) * Li.T * Q
        lam = np.array([float(x) for x in ev])
        norms = np.array([float(sum(X[r, c] ** 2 for r in range(X.rows))) for c in range(X.cols)])
    order = np.argsort(lam)
    u = 1.0 / np.sqrt(np.diag(M))
    B_norm = np.abs(u[:, None] * M * u[None, :]).sum(axis=0).max()
    lam, norms = lam[order], norms[order]
    return lam, (lam[-1] + np.abs(lam)) * B_norm * norms


def exact_eigenvalues(K, M, dps=60, add_diagonal=None) -> np.ndarray:
    return exact_eigen(K, M, dps, add_diagonal)[0]


def _bearing_tables(tree):
    """Every bearing table of a scene tree (top-level and stage members/planets)."""
    out = list(tree.get("bearings", []))
    for stg in tree.get("stages", []):
        out += [stg[m]["bearing"] for m in ("sun", "ring", "carrier", "planets") if "bearing" in stg[m]]
    return out


def _body_tables(tree):
    out = list(tree.get("bodies", []))
    for stg in tree.get("stages", []):
        out += [stg[m] for m in ("sun", "ring", "carrier", "planets")]
    return out


def scaled_tree(name, mesh, bearing, body, mass, inertia):
    """Scene tree with every mesh stiffness x ``mesh``, every finite bearing stiffness of
    BEARING_FIELDS x ``bearing``, and body table ``body`` (index into :func:`_body_tables`)
    with its mass x ``mass`` and inertias x ``inertia``."""
    tree = copy.deepcopy(TREES[name])
    for m in tree.get("meshes", []):
        m["stiffness"] *= mesh
    for stg in tree.get("stages", []):
        stg["k_mesh_sun"] *= mesh
        stg["k_mesh_ring"] *= mesh
    for b in _bearing_tables(tree):
        for f in BEARING_FIELDS:
            b[f] = b[f] * bearing if math.isfinite(b[f]) else b[f]
    bodies = _body_tables(tree)
    b = bodies[body % len(bodies)]
    b["mass"] *= mass
    for f in ("polar_inertia", "transverse_inertia"):
        if f in b:
            b[f] *= inertia
    return tree


def field_at(tree, path):
    """The value at a scene path such as ``stages[0].planets.bearing.k_radial``."""
    node = tree
    for part in path.split("."):
        m = re.fullmatch(r"(\w+)(?:\[(\d+)\])?", part)
        assert m, path
        node = node[m.group(1)]
        if m.group(2) is not None:
            node = node[int(m.group(2))]
    return node


def without_candidates(sc):
    """The expanded scene ``sc`` with every candidate bearing stiffness
    (:func:`assembly.model.constraints.candidates`) set to 0: its K is the coupling stiffness
    K' the candidates are judged against."""
    new = list(sc.bearings)
    for i, f in ac.candidates(sc):
        new[i] = dataclasses.replace(new[i], **{f: 0.0})
    return derive(sc, bearings=tuple(new))


def all_elastic_eigenvalues(scene) -> tuple:
    """(exact eigenvalues, round-off of the part assembled in double, DOFs) of ``scene``
    with every bearing kept a spring. The candidate bearing springs act on one independent
    coordinate each (a plain body, at its own position, to its own frame), so they are
    added to the diagonal of the model assembled without them, in extended precision:
    assembling them in double would bury a planet's coordinates under the round-off of
    1e20 N/m springs seen through the carrier's frame."""
    sc = scene.expanded()
    probe = assemble(without_candidates(sc))
    index = {n: i for i, n in enumerate(probe.dof_names)}
    add = {}
    for i, f in ac.candidates(sc):
        br = sc.bearings[i]
        for d, g in zip(DOF_NAMES, br.diagonal_fields()):
            if g == f and f"{br.body}.{d}" in index:
                j = index[f"{br.body}.{d}"]
                add[j] = add.get(j, 0.0) + getattr(br, f)
    K, M = probe.K.toarray(), probe.M.toarray()
    probe_round = ROUNDOFF * EPS * exact_eigen(K, M)[1]
    return exact_eigenvalues(K, M, add_diagonal=add), probe_round, K.shape[0]


def roundoff_rtol(lam, weight) -> np.ndarray:
    """Relative frequency error bound of each elastic mode of an exact spectrum ``lam``
    with one rigid-body mode: 0.5 ROUNDOFF eps weight_i / lambda_i."""
    with np.errstate(divide="ignore"):
        return np.where(lam[1:] > 0, 0.5 * ROUNDOFF * EPS * weight[1:] / lam[1:], np.inf)


def _check_refusal(tree, exc):
    # One line naming a field the user wrote, with the value written there.
    assert "\n" not in str(exc)
    assert field_at(tree, exc.path) == exc.value, (exc.path, exc.value)


@settings(max_examples=examples(50), deadline=None)
@given(name=st.sampled_from(sorted(TREES)), mesh=st.integers(-8, 12), bearing=st.integers(-3, 12),
       body=st.integers(0, 5), mass=st.integers(-15, 15), inertia=st.integers(-15, 15))
def test_extreme_magnitudes_refused_or_accurate(name, mesh, bearing, body, mass, inertia):
    tree = scaled_tree(name, 10.0 ** mesh, 10.0 ** bearing, body, 10.0 ** mass, 10.0 ** inertia)
    scene = scene_from_dict(tree)
    model = assemble(scene)
    # The model actually solved, in extended precision: is it resolvable in double?
    exact, weight = exact_eigen(model.K.toarray(), model.M.toarray())
    bound = roundoff_rtol(exact, weight)
    try:
        r = solve_modes(model)
    except SceneError as exc:
        event("refused")
        _check_refusal(tree, exc)
        # refused only when the round-off bound (computed from the exact spectrum) really
        # exceeds the documented accuracy; a factor 2 for the computed vs exact spectrum
        assert bound[0] > FREQ_RTOL / 2, bound[0]
        return
    event("accepted, constraints" if model.rigidified else "accepted, all elastic")
    assert bound[0] <= 2 * FREQ_RTOL
    # Structure: every bearing and mesh stiffness is > 0, so the only free motion is the
    # spin of the gear train (sun and carrier / both gears turn freely): exactly one
    # rigid-body mode, whatever the magnitudes -- and no elastic mode reported as rigid.
    assert r.n_rigid == 1
    # The solve: every elastic frequency within its own round-off bound of the exact one
    # (at most FREQ_RTOL for the lowest).
    assert r.info["frequency_rtol"] <= FREQ_RTOL
    f_exact = np.sqrt(exact[1:]) / (2 * math.pi)
    assert np.all(np.abs(r.frequencies_hz[1:] / f_exact - 1) <= bound)
    # Count: every DOF of the model gives a mode; the constraints removed exactly the
    # directions of the bearing fields they replaced (k_radial, k_tilt: two DOFs each).
    lam_ref, probe_round, n_ref = all_elastic_eigenvalues(scene)
    n_held = sum(1 if f in ("k_axial", "k_torsion") else 2 for _, f, _ in model.rigidified)
    assert len(r.frequencies_hz) == model.K.shape[0] == n_ref - n_held
    # The constraints: in-band modes match the all-elastic model within the solve's bound,
    # CONSTRAINT_RTOL per held DOF, and the round-off of the part assembled in double
    # (the largest round-off of its modes, relative to each mode).
    assert lam_ref[0] < 1e-6 * lam_ref[1]         # one rigid-body mode there too
    band = scene.band_hz or DEFAULT_BAND_HZ
    f_ref = np.sqrt(lam_ref[1:]) / (2 * math.pi)
    k = int(np.sum(f_ref <= band))
    tol = r.info["frequency_rtol"] + n_held * ac.CONSTRAINT_RTOL + 0.5 * probe_round.max() / lam_ref[1:1 + k]
    err = np.abs(r.frequencies_hz[1:1 + k] / f_ref[:k] - 1)
    assert np.all(err <= tol), (err, tol)


@pytest.mark.parametrize("name", sorted(TREES))
@pytest.mark.parametrize("bearing", [1e6, 1e8, 1e10, 1e12])
def test_constraint_decision_is_judged_without_candidate_springs(name, bearing):
    # assemble judges the candidates on the diagonal of its own assembly with their bearing
    # elements left out; that must be the diagonal of the scene with the candidate
    # stiffnesses set to 0 (the definition of K' in assembly.model.constraints.constraint_shift),
    # so the same directions become constraints. Bearings x1e6 ... 1e12 turn none, some
    # and most of the candidates into constraints.
    scene = scene_from_dict(scaled_tree(name, 1.0, bearing, 0, 1.0, 1.0))
    sc = scene.expanded()
    probe = assemble(without_candidates(sc))
    diagonal = dict(zip(probe.dof_names, zip(probe.K.diagonal(), probe.M.diagonal())))
    _, expected = ac.rigidify(sc, diagonal, sc.band_hz or DEFAULT_BAND_HZ)
    assert assemble(scene).rigidified == expected


def test_soft_mesh_keeps_bearing_modes(caplog):
    # Kahraman pair (spur) with a mesh of 1 N/m: the gears are almost decoupled, so the
    # 12 modes are the free spin, the mesh torsion mode sqrt(k (r1^2/J1 + r2^2/J2))/2pi and
    # each gear's bearing modes: radial sqrt(k_r/m) twice, axial sqrt(k_a/m), tilt
    # sqrt(k_t/I) twice. The mesh couples them by ~k_mesh/k_bearing = 1e-8 relative.
    tree = scaled_tree("kahraman_beta0.toml", 1.0 / 2e8, 1.0, 0, 1.0, 1.0)
    with caplog.at_level("WARNING", logger="assembly.analysis.resolution"):
        r = solve_modes(assemble(scene_from_dict(tree)))
    # the spread (2.2 kHz / 0.21 Hz)^2 = 1.1e8 costs accuracy: 0.5 ROUNDOFF eps 1.1e8 = 1.2e-7
    # relative on the 0.21 Hz mode, above WARN_RTOL = 1e-8 (within FREQ_RTOL): a warning
    # names the soft mesh
    assert WARN_RTOL < r.info["frequency_rtol"] <= FREQ_RTOL
    assert any("meshes[0].stiffness = 1.0" in rec.getMessage() for rec in caplog.records), caplog.text
    b, g, mesh = tree["bodies"][0], tree["bearings"][0], tree["meshes"][0]
    two_pi = 2 * math.pi
    f_torsion = math.sqrt(mesh["stiffness"] * 2 * mesh["base_radius1"] ** 2 / b["polar_inertia"]) / two_pi
    per_gear = [math.sqrt(g["k_axial"] / b["mass"])] + [math.sqrt(g["k_radial"] / b["mass"])] * 2 \
        + [math.sqrt(g["k_tilt"] / b["transverse_inertia"])] * 2
    expected = np.sort([f_torsion] + [w / two_pi for w in per_gear * 2])
    assert r.n_rigid == 1 and len(r.frequencies_hz) == 12
    np.testing.assert_allclose(r.frequencies_hz[1:], expected, rtol=1e-6)


@pytest.mark.parametrize("name, path, value", [
    ("kahraman_beta0.toml", "meshes[0].stiffness", 1e20),
    ("kahraman_beta0.toml", "meshes[0].stiffness", 1e300),
    ("kahraman_beta0.toml", "meshes[0].stiffness", 1e-6),
    ("kahraman_beta0.toml", "bodies[1].polar_inertia", 1e-300),
    ("kahraman_beta0.toml", "bodies[0].mass", 1e-300),
    ("kahraman_beta0.toml", "bodies[0].mass", 1e300),
    ("kahraman_beta20.toml", "bearings[1].k_torsion", 1e-300),
    ("kahraman_beta20.toml", "bearings[0].k_tilt", 1e-300),
    ("lin_parker_n3.toml", "stages[0].k_mesh_ring", 1e20),
    ("lin_parker_n3.toml", "stages[0].carrier.mass", 1e-300),
    ("lin_parker_n3.toml", "stages[0].planets.mass", 1e-30),
])
def test_absurd_value_is_named(name, path, value):
    # One field set to a value whose spread (or singular mass matrix) no double solve can
    # resolve: the error names exactly that field and its value.
    tree = copy.deepcopy(TREES[name])
    *head, last = path.split(".")
    field_at(tree, ".".join(head))[last] = value
    with pytest.raises(SceneError) as exc:
        solve_modes(assemble(scene_from_dict(tree)))
    assert (exc.value.path, exc.value.value) == (path, value)


def test_unchecked_solve_records_the_refusal_instead_of_raising():
    # check=False (a benchmark's reference solve): the same verdict, as text in info, and
    # the modes are returned; the check is not skipped silently.
    tree = copy.deepcopy(TREES["kahraman_beta0.toml"])
    tree["meshes"][0]["stiffness"] = 1e20
    model = assemble(scene_from_dict(tree))
    with pytest.raises(SceneError) as exc:
        solve_modes(model)
    r = solve_modes(model, check=False)
    assert r.info["resolution"] == str(exc.value) and math.isnan(r.info["frequency_rtol"])
    assert len(r.frequencies_hz) == model.K.shape[0]


def test_sparse_path_counts_and_checks_alike(monkeypatch):
    # The sparse (large-model) path on a small model: the same structural count and the
    # same frequencies as the dense path (its eigen-residual tolerance, 1e-10, bounds the
    # difference), and the same refusal of an unresolvable mesh.
    scene = scene_from_dict(TREES["kahraman_beta20.toml"])
    dense = solve_modes(assemble(scene))
    monkeypatch.setattr(am, "DENSE_MAX", 4)
    sparse = solve_modes(assemble(scene), n_modes=8)
    assert sparse.n_rigid == dense.n_rigid == 1
    np.testing.assert_allclose(sparse.frequencies_hz[1:], dense.frequencies_hz[1:8], rtol=1e-8)
    tree = scaled_tree("kahraman_beta20.toml", 1e12, 1.0, 0, 1.0, 1.0)
    with pytest.raises(SceneError) as exc:
        solve_modes(assemble(scene_from_dict(tree)), n_modes=8)
    assert exc.value.path == "meshes[0].stiffness"


def test_cli_refuses_stiff_mesh_in_one_line(tmp_path):
    # `modes` on a scene with a 1e20 N/m mesh: exit code 2, one stderr line naming the field.
    text = (SCENE_DIR / "kahraman_beta0.toml").read_text()
    text, n = re.subn(r"(?m)^stiffness = .*$", "stiffness = 1e20", text)
    assert n == 1
    path = tmp_path / "stiff.toml"
    path.write_text(text)
    p = subprocess.run([sys.executable, "-m", "assembly.app.cli", "modes", str(path)], cwd=ROOT,
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "meshes[0].stiffness = 1e+20" in lines[0], p.stderr
    assert p.stdout == ""
