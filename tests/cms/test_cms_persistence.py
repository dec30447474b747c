"""Superelement file format (atomic, versioned) and the reduction cache."""
import json
import os

import numpy as np
import pytest

from cms.cache import SuperelementCache, array_hash, cache_key
from cms.craig_bampton import CraigBamptonReductor
from cms.errors import CacheError
from cms.superelement import Superelement, read_sealed_npz, write_sealed_npz

from tests.support.fe_models import box

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
