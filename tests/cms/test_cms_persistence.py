"""Superelement file format (atomic, versioned) and the reduction cache."""
import json
import logging
import os
import tempfile
import threading

import numpy as np
import pytest
from hypothesis import given, settings

from cms.cache import SuperelementCache, array_hash, cache_key
from cms.craig_bampton import CraigBamptonReductor
from cms.errors import CacheError
from cms.superelement import Superelement, read_sealed_npz, write_sealed_npz
from tests.support.corruption import CORRUPTIONS, corrupt
from tests.support.fe_models import box
from tests.support.fuzz import examples

MATERIAL = {"E": 210e9, "nu": 0.3, "rho": 7850.0}   # steel, SI


def _reduce(n_modes=3):
    m = box(lengths=(0.4, 0.1, 0.1), divisions=(3, 1, 1), **MATERIAL)
    b = m.dofs_where(lambda x: np.isclose(x[0], 0.0))
    names = [f"n{j // 3}:{'xyz'[j % 3]}" for j in range(m.n)]
    return m, b, CraigBamptonReductor(m.K, m.M, b, n_modes=n_modes, dof_names=names,
                                      node_coords=m.node_coords,
                                      metadata={"material": MATERIAL}).reduce()


def test_save_load_round_trip_is_exact(tmp_path):
    _, _, se = _reduce()
    p = tmp_path / "se.npz"
    se.save(p)
    assert os.listdir(tmp_path) == ["se.npz"]          # no temp file left behind
    back = Superelement.load(p)
    for k in ("K", "M", "Phi", "Psi", "boundary_dofs", "interior_dofs", "eigenvalues",
              "boundary_points", "boundary_kinds"):
        assert np.array_equal(getattr(back, k), getattr(se, k)), k
    assert back.boundary_names == se.boundary_names
    assert back.metadata["material"] == MATERIAL
    q = np.arange(se.K.shape[0], dtype=float)
    assert np.array_equal(back.reconstruct(q), se.reconstruct(q))


def test_failed_write_leaves_previous_file_intact(tmp_path, monkeypatch):
    _, _, se = _reduce()
    p = tmp_path / "se.npz"
    se.save(p)
    before = p.read_bytes()

    def boom(*a, **k):
        raise OSError("disk full")
    monkeypatch.setattr(np, "savez", boom)
    with pytest.raises(OSError):
        se.save(p)
    assert p.read_bytes() == before
    assert os.listdir(tmp_path) == ["se.npz"]


def test_unknown_version_and_garbage_raise_cache_error(tmp_path):
    _, _, se = _reduce()
    p = tmp_path / "se.npz"
    se.save(p)
    arrays = read_sealed_npz(p)
    meta = json.loads(str(arrays["metadata_json"]))
    meta["version"] = 999
    arrays["metadata_json"] = np.array(json.dumps(meta))
    write_sealed_npz(p, arrays)                    # a well-sealed file of an unknown version
    with pytest.raises(CacheError) as ei:
        Superelement.load(p)
    assert ei.value.value[1] == 999
    np.savez(p, **arrays)                          # unsealed, as version 1 wrote them
    with pytest.raises(CacheError, match="no content hash"):
        Superelement.load(p)
    (tmp_path / "bad.npz").write_bytes(b"not a zip")
    with pytest.raises(CacheError):
        Superelement.load(tmp_path / "bad.npz")


def test_cache_reduces_an_unchanged_component_once(tmp_path):
    m, b, _ = _reduce()
    calls = []

    def reduce():
        calls.append(1)
        return CraigBamptonReductor(m.K, m.M, b, n_modes=3, node_coords=m.node_coords).reduce()

    inputs = {"mesh_hash": array_hash(m.node_coords, m.basis.mesh.t), "material": MATERIAL,
              "interfaces": {"root": b.tolist()}, "mode_selection": {"n_modes": 3}}
    cache = SuperelementCache(tmp_path)
    se1 = cache.get_or_reduce(inputs, reduce)
    se2 = SuperelementCache(tmp_path).get_or_reduce(dict(inputs), reduce)   # fresh process
    assert len(calls) == 1
    assert np.array_equal(se1.K, se2.K)
    # any changed input is a different key
    for change in ({"material": {**MATERIAL, "E": 200e9}},
                   {"mode_selection": {"n_modes": 4}},
                   {"mesh_hash": array_hash(m.node_coords * 1.01, m.basis.mesh.t)}):
        assert cache_key(**{**inputs, **change}) != cache_key(**inputs)
    assert cache_key(**inputs) == cache_key(**dict(reversed(list(inputs.items()))))


# ---- integrity: sealed files, corrupt entries are misses, concurrent writers ----------------

def _sealed_sample(tmp_dir) -> bytes:
    _, _, se = _reduce()
    p = os.path.join(tmp_dir, "se.npz")
    se.save(p)
    with open(p, "rb") as fh:
        return fh.read()


@pytest.fixture(scope="module")
def sealed(tmp_path_factory):
    return _sealed_sample(tmp_path_factory.mktemp("sealed"))


@settings(max_examples=examples(150), deadline=None)
@given(how=CORRUPTIONS)
def test_any_change_to_a_superelement_file_is_a_cache_error(sealed, how):
    # The seal covers every byte (zip comment = SHA-256 of all bytes before the digits):
    # whatever the damage -- including bytes zip readers ignore (timestamps, attributes) --
    # load raises CacheError, never BadZipFile/EOFError/ValueError, never other numbers.
    bad = corrupt(sealed, how)
    assert bad != sealed
    with tempfile.TemporaryDirectory() as d:
        p = os.path.join(d, "se.npz")
        with open(p, "wb") as fh:
            fh.write(bad)
        with pytest.raises(CacheError):
            Superelement.load(p)


def test_corrupt_entry_is_moved_aside_and_reduced_again(tmp_path, caplog):
    m, b, clean = _reduce()
    calls = []

    def reduce():
        calls.append(1)
        return _reduce()[2]

    inputs = {"mesh_hash": array_hash(m.node_coords, m.basis.mesh.t), "n_modes": 3}
    cache = SuperelementCache(tmp_path)
    cache.get_or_reduce(inputs, reduce)
    p = cache.path(cache_key(**inputs))
    with open(p, "r+b") as fh:                      # one flipped bit in the middle
        fh.seek(os.path.getsize(p) // 2)
        byte = fh.read(1)
        fh.seek(-1, 1)
        fh.write(bytes([byte[0] ^ 1]))
    with caplog.at_level(logging.WARNING, logger="cms.cache"):
        se = SuperelementCache(tmp_path).get_or_reduce(inputs, reduce)
    # a second reduction of the same matrices: equal to round-off (BLAS summation order)
    assert len(calls) == 2 and np.allclose(se.K, clean.K, rtol=0, atol=1e-12 * np.abs(clean.K).max())
    assert [r.levelname for r in caplog.records] == ["WARNING"] and p in caplog.records[0].getMessage()
    aside = [f for f in os.listdir(tmp_path) if f.startswith(os.path.basename(p) + ".corrupt-")]
    assert len(aside) == 1
    caplog.clear()
    again = SuperelementCache(tmp_path)
    again.get_or_reduce(inputs, reduce)             # and the run after that is a hit
    assert (again.hits, len(calls), caplog.records) == (1, 2, [])


def test_entry_rejected_by_check_is_a_miss(tmp_path):
    # A readable entry that does not fit its inputs (the caller's check raises) is treated
    # like a corrupt one: moved aside, reduced again; a fresh reduction failing it raises.
    _, _, se = _reduce()
    inputs = {"n_modes": 3}
    cache = SuperelementCache(tmp_path)
    cache.put(cache_key(**inputs), se)

    def check(s):
        if s.metadata.get("built_from") != "mesh B":
            raise CacheError("built from another mesh", "built_from", s.metadata.get("built_from"))

    def reduce():
        s = _reduce()[2]
        s.metadata["built_from"] = "mesh B"
        return s

    out = cache.get_or_reduce(inputs, reduce, check=check)
    assert out.metadata["built_from"] == "mesh B" and cache.discarded == 1 and cache.misses == 1
    assert SuperelementCache(tmp_path).get(cache_key(**inputs), check) is not None
    with pytest.raises(CacheError, match="another mesh"):
        SuperelementCache(tmp_path / "empty").get_or_reduce(inputs, lambda: _reduce()[2], check=check)


def test_concurrent_writers_of_one_entry_each_publish_a_whole_file(tmp_path):
    # Eight threads store different contents under one name at once: each write goes to its
    # own mkstemp file and is os.replace'd, so the survivor is one writer's whole file.
    p = tmp_path / "se.npz"
    contents = [{"x": np.full(200_000, k, dtype=float)} for k in range(8)]
    start = threading.Barrier(8)

    def run(k):
        start.wait()
        write_sealed_npz(p, contents[k])

    threads = [threading.Thread(target=run, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    x = read_sealed_npz(p)["x"]
    assert np.all(x == x[0]) and x[0] in range(8)
    assert os.listdir(tmp_path) == ["se.npz"]


def _reduce_slowly_and_count(folder: str, counter: str, start) -> str:
    """A worker process: wait for the start signal, then get-or-reduce one entry with a
    reduction that takes 0.5 s and records (appends a line to ``counter``) that it ran."""
    import time as _time

    def reduce():
        with open(counter, "a") as fh:
            fh.write("reduced\n")
        _time.sleep(0.5)
        return _reduce()[2]
    start.wait()
    se = SuperelementCache(folder).get_or_reduce({"mesh": "shared-entry"}, reduce)
    return array_hash(se.K, se.M)


def test_two_processes_missing_one_entry_reduce_it_once(tmp_path):
    # Both processes miss the same key at the same moment: the build lock lets one reduce
    # while the other waits and then loads that entry (design studies run workers in parallel)
    import multiprocessing as mp
    ctx = mp.get_context("spawn")
    counter = tmp_path / "reductions.txt"
    with ctx.Manager() as manager, ctx.Pool(2) as pool:
        start = manager.Event()
        jobs = [pool.apply_async(_reduce_slowly_and_count, (str(tmp_path / "cache"), str(counter), start))
                for _ in range(2)]
        start.set()
        hashes = [j.get(timeout=120) for j in jobs]
    assert counter.read_text().count("reduced") == 1
    assert hashes[0] == hashes[1]
    assert [p.name for p in (tmp_path / "cache").iterdir() if p.name.startswith(".")] == []  # no lock left
