"""Caches that are verified and heal themselves (fe_components.meshing, cms.cache,
assembly.model.flexible): a damaged cache entry is a miss, never a crash or a silent wrong number.

Component: a coarse free steel shaft (cylinder L = 0.2 m, D = 0.04 m, P2 mesh 0.02 m,
1530 DOFs, 6 fixed-interface modes + residual vectors): meshes in ~0.1 s, reduces in ~0.2 s.
Each case starts from a copy of one clean cache, damages the mesh or the superelement file,
builds the flexible body again and checks: the numbers of the clean build, one warning
naming the file, the file moved aside, and the run after that a pure cache hit.
"""
from __future__ import annotations

import io
import json
import logging
import os
import shutil
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import scipy.linalg as sl

import assembly.model.flexible as flexible
import fe_components.geometry as geometry
import fe_components.meshing as meshing
from assembly.model.components import CacheDirs, forget_fe_models
from assembly.model.flexible import flexible_body
from assembly.scene.tables import Body, FlexOptions
from cms.errors import CacheError
from fe_components.errors import MeshingError
from fe_components.meshing import MeshOptions, ensure_mesh, mesh_path
from fe_components.params import CylinderParams
from tests.support.corruption import corrupt, sweep
from tests.support.shaft_scene import shaft_scene

pytestmark = pytest.mark.gmsh

REPO = Path(__file__).resolve().parents[2]
PARAMS = CylinderParams(length=0.2, diameter=0.04)
OPTIONS = FlexOptions(mesh_size=0.02, n_modes=6)
BODY = Body("shaft", fidelity="flexible", component=PARAMS, flex=OPTIONS)
BAND_HZ = 3000.0
#: Two Craig-Bampton reductions of bitwise-identical FE matrices differ only by round-off
#: (BLAS summation order, eigen-solver start vectors): measured 1.7e-14 relative on the
#: fixed-interface eigenvalues and the reduced K, 7e-14 of f_max^2 on the body's
#: eigenvalues. 1e-10 is 1000x that, and 100x below the reduction's own eigen-residual
#: tolerance (1e-8), so any change of the mesh or of the reduction inputs would show.
RTOL = 1e-10


def _caches(root: Path) -> CacheDirs:
    return CacheDirs(root / "meshes", root / "meshes" / "cms")


def _build(caches: CacheDirs):
    forget_fe_models()              # a new process: nothing memoised
    return flexible_body(BODY, OPTIONS, BAND_HZ, caches=caches)


def _numbers(body, stress: bool = True) -> SimpleNamespace:
    """Free-free eigenvalues of the body ((rad/s)^2), its reduced K, the fixed-interface
    eigenvalues, and the von Mises field (Pa, back-expanded to the mesh) of a unit motion of
    the first master node along x (a physical coordinate: its meaning does not depend on
    the reduction, unlike a modal coordinate's sign)."""
    lam = sl.eigh(body.K, body.M, eigvals_only=True)
    zb = np.zeros(body.ndof)
    zb[0] = 1e-6                     # m
    return SimpleNamespace(lam=lam, K=body.K, ev=body.superelement.eigenvalues,
                           von_mises=body.stress(zb).von_mises if stress else None)


def _assert_same(body, clean, stress: bool = True):
    now = _numbers(body, stress)
    assert np.all(np.abs(now.lam - clean.lam) <= RTOL * clean.lam.max())
    assert np.all(np.abs(now.ev - clean.ev) <= RTOL * clean.ev.max())
    assert np.all(np.abs(now.K - clean.K) <= RTOL * np.abs(clean.K).max())
    if stress:
        assert np.all(np.abs(now.von_mises - clean.von_mises) <= RTOL * clean.von_mises.max())


@pytest.fixture(scope="module")
def clean(tmp_path_factory):
    root = tmp_path_factory.mktemp("clean")
    body = _build(_caches(root))
    assert body.info["cache_hits"] == 0
    (npz,) = (root / "meshes" / "cms").glob("*.npz")
    mesh = mesh_path(PARAMS, MeshOptions(size=OPTIONS.mesh_size), root / "meshes")
    return SimpleNamespace(root=root, numbers=_numbers(body), npz=npz, mesh=mesh,
                           mesh_sha256=body.superelement.metadata["mesh_sha256"])


@pytest.fixture
def cache(clean, tmp_path):
    shutil.copytree(clean.root, tmp_path / "c")
    return tmp_path / "c"


def _mesh_no_hash(d: bytes) -> bytes:
    return d[:d.rindex(b"$FlexgearContentHash")]                         # as version 1 wrote it


def _mesh_wrong_hash(d: bytes) -> bytes:
    i = d.rindex(b"sha256 ") + len(b"sha256 ")
    return d[:i] + bytes(reversed(d[i:i + 64])) + d[i + 64:]            # a valid-looking other hash


def _npz_no_hash(d: bytes) -> bytes:
    buf = io.BytesIO()
    with np.load(io.BytesIO(d)) as z:
        np.savez(buf, **{k: z[k] for k in z.files})                     # as version 1 wrote it
    return buf.getvalue()


def _npz_wrong_hash(d: bytes) -> bytes:
    return d[:-64] + bytes(reversed(d[-64:]))


def _cases(kind: str) -> dict:
    cases = sweep()
    if kind == "mesh":
        cases.update({"no-hash-section": _mesh_no_hash, "wrong-hash": _mesh_wrong_hash})
    else:
        cases.update({"no-hash-comment": _npz_no_hash, "wrong-hash": _npz_wrong_hash})
    return cases


CASES = [(kind, name) for kind in ("mesh", "superelement") for name in _cases(kind)]


@pytest.mark.parametrize("kind,name", CASES, ids=[f"{k}-{n}" for k, n in CASES])
def test_damaged_entry_is_moved_aside_rebuilt_and_then_hit(clean, cache, kind, name, caplog, monkeypatch):
    target = cache / (clean.mesh if kind == "mesh" else clean.npz).relative_to(clean.root)
    good = target.read_bytes()
    bad = _cases(kind)[name](good)
    assert bad != good
    target.write_bytes(bad)
    with caplog.at_level(logging.WARNING):
        body = _build(_caches(cache))
    warnings = [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING]
    assert len(warnings) == 1 and str(target) in warnings[0], warnings
    (aside,) = target.parent.glob(target.name + ".corrupt-*")
    assert aside.read_bytes() == bad
    _assert_same(body, clean.numbers)
    # gmsh is deterministic: the healed mesh is the clean one, so its reduction is reused
    assert body.superelement.metadata["mesh_sha256"] == clean.mesh_sha256
    assert body.info["cache_hits"] == (1 if kind == "mesh" else 0)
    # the run after that: a pure hit (no gmsh, no reduction, no warning)
    caplog.clear()
    monkeypatch.setattr(meshing, "generate_mesh", _fail)
    monkeypatch.setattr(flexible, "_reduce", _fail)
    with caplog.at_level(logging.WARNING):
        again = _build(_caches(cache))
    assert again.info["cache_hits"] == 1 and not caplog.records
    _assert_same(again, clean.numbers, stress=False)


def _fail(*a, **k):
    raise AssertionError("cache miss where a hit was expected")


def test_replaced_mesh_is_reduced_again_never_paired_with_the_old_reduction(clean, cache, monkeypatch):
    # The reduction is cached; the mesh file is then replaced by a DIFFERENT valid mesh
    # (sealed, so no corruption to detect: the shaft meshed at 0.019 m stands in for a
    # regenerated mesh that came out different). The superelement key is the mesh content
    # hash, so the next build reduces the new mesh rather than reuse the old reduction, and
    # modes and stresses come from one mesh.
    caches = _caches(cache)
    other = ensure_mesh(PARAMS, MeshOptions(size=0.019), caches.meshes)
    target = cache / clean.mesh.relative_to(clean.root)
    shutil.copyfile(other, target)
    body = _build(caches)
    assert body.info["cache_hits"] == 0                     # not the old reduction
    new_sha = body.superelement.metadata["mesh_sha256"]
    assert new_sha != clean.mesh_sha256 and body.coupled()[0].mesh_sha256 == new_sha
    assert not np.allclose(_numbers(body).lam[6:], clean.numbers.lam[6:], rtol=1e-6)


def test_mesh_changed_during_a_run_is_refused_at_back_expansion(clean, cache):
    # Modes come from the cached reduction (no FE model built); the mesh file then changes
    # under the run. Back-expansion must not read the new mesh with the old modes.
    caches = _caches(cache)
    body = _build(caches)
    assert body.info["cache_hits"] == 1
    other = ensure_mesh(PARAMS, MeshOptions(size=0.019), cache / "other")
    shutil.copyfile(other, cache / clean.mesh.relative_to(clean.root))
    forget_fe_models()
    zb = np.zeros(body.ndof)
    zb[0] = 1e-6
    with pytest.raises(CacheError, match="not the one this body's reduction was built from"):
        body.stress(zb)


def test_memoised_model_of_the_reduction_mesh_is_used_for_back_expansion(clean, cache):
    # Same change under the run, but this process still holds the FE model the reduction
    # was built from: back-expansion uses it (same content hash) and gives the clean stresses.
    caches = _caches(cache)
    (cache / clean.npz.relative_to(clean.root)).unlink()      # force a reduction: FE memoised
    body = _build(caches)
    other = ensure_mesh(PARAMS, MeshOptions(size=0.019), cache / "other")
    shutil.copyfile(other, cache / clean.mesh.relative_to(clean.root))
    _assert_same(body, clean.numbers)


def test_superelement_of_another_mesh_under_this_key_is_rebuilt(clean, cache, caplog):
    # An entry whose recorded mesh hash is not the key's (e.g. copied by hand, or written by
    # a racing process from another mesh) is rejected by the body's check and rebuilt.
    caches = _caches(cache)
    foreign = _caches(cache / "foreign")
    shutil.copytree(caches.meshes, foreign.meshes, ignore=shutil.ignore_patterns("cms"))
    shutil.copyfile(ensure_mesh(PARAMS, MeshOptions(size=0.019), cache / "other"),
                    foreign.meshes / clean.mesh.name)
    _build(foreign)
    (foreign_npz,) = foreign.superelements.glob("*.npz")
    target = cache / clean.npz.relative_to(clean.root)
    shutil.copyfile(foreign_npz, target)
    with caplog.at_level(logging.WARNING):
        body = _build(caches)
    assert any(str(target) in r.getMessage() and "another mesh" in r.getMessage() for r in caplog.records)
    _assert_same(body, clean.numbers)


def test_gmsh_failure_after_a_corrupt_entry_is_a_meshing_error(clean, cache, monkeypatch, caplog):
    # The cached mesh is corrupt (warning, moved aside) and gmsh then fails: the error is
    # gmsh's MeshingError with the parameters, not a cache error about the old file.
    target = cache / clean.mesh.relative_to(clean.root)
    target.write_bytes(target.read_bytes()[:100])

    def broken_solid(occ, params, *a):
        return [(3, occ.addCylinder(0, 0, 0, 0, 0, params.length, 0.0))]   # zero radius: OCC refuses

    monkeypatch.setattr(geometry, "build_solid", broken_solid)  # meshing imports it when it meshes
    with caplog.at_level(logging.WARNING), pytest.raises(MeshingError, match="gmsh failed") as e:
        _build(_caches(cache))
    assert e.value.params["length"] == PARAMS.length and "hash" not in str(e.value)
    assert any(str(target) in r.getMessage() for r in caplog.records)


def _cli_modes(scene: Path, cache: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "FLEXGEAR_CACHE_DIR": str(cache), "PYTHONPATH": str(REPO)}
    return subprocess.run([sys.executable, "-m", "assembly.app.cli", "modes", str(scene), "--json"],
                          cwd=REPO, env=env, capture_output=True, text=True, timeout=300)


def _elastic(stdout: str):
    """(elastic frequencies in Hz, number of rigid-body modes) of ``modes --json``."""
    out = json.loads(stdout)
    n = out["n_rigid_body_modes"]
    return np.array(out["frequencies_hz"][n:]), n


def test_cli_heals_a_corrupt_cache_and_prints_the_same_modes(tmp_path):
    scene = tmp_path / "shaft.toml"
    scene.write_text(shaft_scene("flexible"))
    cache = tmp_path / "cache"
    first = _cli_modes(scene, cache)
    assert first.returncode == 0, first.stderr
    freqs, n_rigid = _elastic(first.stdout)
    (npz,) = (cache / "cms").glob("*.npz")
    (msh,) = cache.glob("*.msh")
    for target in (npz, msh):
        data = target.read_bytes()
        target.write_bytes(corrupt(data, ("flip", len(data) // 2, 1)))
        run = _cli_modes(scene, cache)
        assert run.returncode == 0, run.stderr
        assert "Traceback" not in run.stderr and str(target) in run.stderr
        again, rigid_again = _elastic(run.stdout)
        # elastic frequencies of a re-reduction agree to round-off (see RTOL), of f_max; the
        # one free spin is a zero mode either way (its printed value is round-off noise)
        assert rigid_again == n_rigid == 1
        assert np.all(np.abs(again - freqs) <= RTOL * freqs.max())
        assert len(list(target.parent.glob(target.name + ".corrupt-*"))) == 1


@pytest.mark.parametrize("errno_", [13, 28, 30])   # EACCES, ENOSPC, EROFS
def test_a_cache_folder_that_cannot_take_files(clean, tmp_path, monkeypatch, caplog, errno_):
    """A superelement that cannot be stored costs only its reuse (warning, same numbers); a
    mesh that cannot be written is one MeshCacheError line naming the folder (we run as root
    in CI, so the OS error is injected where the cache creates its temporary file)."""
    import tempfile

    from fe_components.errors import MeshCacheError

    def refuse(*a, **k):
        raise OSError(errno_, os.strerror(errno_))

    caches = _caches(tmp_path)
    mesh_path(PARAMS, MeshOptions(size=0.02, order=2), caches.meshes).parent.mkdir(parents=True)
    shutil.copy(clean.mesh, caches.meshes)                      # the mesh is cached, the reduction not
    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    with caplog.at_level(logging.WARNING):
        body = _build(caches)
    _assert_same(body, clean.numbers, stress=False)
    assert any("cannot store superelement" in r.getMessage() and os.strerror(errno_) in r.getMessage()
               for r in caplog.records)
    shutil.rmtree(caches.meshes)
    forget_fe_models()
    with pytest.raises(MeshCacheError, match=os.strerror(errno_)) as err:
        _build(caches)
    assert "\n" not in str(err.value) and "FLEXGEAR_CACHE_DIR" in str(err.value)
