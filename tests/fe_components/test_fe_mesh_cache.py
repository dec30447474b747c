"""Mesh cache integrity without gmsh: the content-hash section, the committed reference
meshes, unique temporary files (healing with gmsh: tests/hard_cases/test_cache_integrity.py)."""
from __future__ import annotations

import logging
import tempfile
import threading
from pathlib import Path

import pytest
from hypothesis import given, settings

import fe_components.meshing as meshing
from fe_components.errors import MeshCacheError, MeshingError
from fe_components.meshing import cached_mesh, mesh_content_hash, mesh_path, read_mesh
from fe_components.reference import CASES, REF_DIR
from tests.support.corruption import CORRUPTIONS, corrupt
from tests.support.fuzz import examples

#: The smallest committed mesh (annulus, ~245 kB), the sample for byte-level corruption.
ANNULUS = mesh_path(*CASES["annulus"], REF_DIR)
CLEAN = ANNULUS.read_bytes()


def test_every_committed_reference_mesh_verifies():
    # the committed files carry the section and it matches their bytes
    for name, (params, options) in CASES.items():
        path = mesh_path(params, options, REF_DIR)
        assert len(mesh_content_hash(path)) == 64, name
    raw = read_mesh(ANNULUS)
    assert raw.content_hash == mesh_content_hash(ANNULUS) and raw.cell_type == "tetra10"


@settings(max_examples=examples(150), deadline=None)
@given(how=CORRUPTIONS)
def test_any_change_to_a_mesh_file_is_a_mesh_cache_error(how):
    # Every byte is covered by the hash (or is the hash), so every truncation, flipped
    # bit, inserted byte or foreign content is caught, always as MeshCacheError (never
    # meshio's or numpy's own exceptions, never a silently different mesh).
    bad = corrupt(CLEAN, how)
    assert bad != CLEAN
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / ANNULUS.name
        p.write_bytes(bad)
        for reader in (mesh_content_hash, read_mesh):
            with pytest.raises(MeshCacheError) as e:
                reader(p)
            assert e.value.path == str(p)


def test_unsealed_file_from_an_older_version_is_refused(tmp_path):
    p = tmp_path / ANNULUS.name
    p.write_bytes(CLEAN[:CLEAN.rindex(b"$FlexgearContentHash")])    # exactly what version 1 wrote
    with pytest.raises(MeshCacheError, match="no content-hash section"):
        read_mesh(p)


def test_committed_reference_mesh_is_never_rewritten(tmp_path, monkeypatch):
    # REFERENCE_DIR stands for meshes/ref here: a corrupt committed file raises and stays put
    monkeypatch.setattr(meshing, "REFERENCE_DIR", tmp_path)
    params, options = CASES["annulus"]
    p = mesh_path(params, options, tmp_path)
    bad = corrupt(CLEAN, ("flip", len(CLEAN) // 2, 1))
    p.write_bytes(bad)
    monkeypatch.setattr(meshing, "generate_mesh", _no_gmsh)
    with pytest.raises(MeshCacheError, match="git checkout") as e:
        cached_mesh(params, options, tmp_path)
    assert e.value.path == str(p) and "content hash mismatch" in e.value.reason
    assert sorted(tmp_path.iterdir()) == [p] and p.read_bytes() == bad


def test_corrupt_reference_mesh_falls_back_to_the_cache_in_a_scene(tmp_path, monkeypatch, caplog):
    # flexgear's mesh_entry: a corrupt committed mesh is left alone (warning naming it) and the
    # mesh is generated in the cache folder (here by a stand-in for gmsh writing the clean bytes)
    import fe_components.reference as reference
    from assembly.model.components import CacheDirs, mesh_entry
    from assembly.scene.tables import FlexOptions
    ref = tmp_path / "ref"
    ref.mkdir()
    params, options = CASES["annulus"]
    bad = CLEAN[:-1]
    (ref / ANNULUS.name).write_bytes(bad)
    monkeypatch.setattr(reference, "REF_DIR", ref)
    monkeypatch.setattr(meshing, "REFERENCE_DIR", ref)
    monkeypatch.setattr(meshing, "generate_mesh",
                        lambda p, o, path: Path(path).write_bytes(CLEAN[:CLEAN.rindex(b"$Flexgear")]))
    caches = CacheDirs(tmp_path / "cache", tmp_path / "cache" / "cms")
    flex = FlexOptions(mesh_size=options.size, order=options.order)
    with caplog.at_level(logging.WARNING):
        entry = mesh_entry(params, flex, caches)
    assert entry.path == caches.meshes / ANNULUS.name and entry.sha256 == mesh_content_hash(ANNULUS)
    assert any(str(ref / ANNULUS.name) in r.getMessage() for r in caplog.records)
    assert sorted(ref.iterdir()) == [ref / ANNULUS.name] and (ref / ANNULUS.name).read_bytes() == bad
    (ref / ANNULUS.name).write_bytes(CLEAN)
    assert mesh_entry(params, flex, caches).path == ref / ANNULUS.name


def _no_gmsh(*a, **k):
    raise AssertionError("gmsh called")


def test_concurrent_writers_of_one_entry_each_publish_a_whole_file(tmp_path, monkeypatch):
    # Eight threads miss the same entry at once and "mesh" it (a stand-in writing the
    # reference bytes slowly, in chunks): unique temporary names, sealed, os.replace'd;
    # every writer returns the same content hash, the final file verifies, no temp left.
    body = CLEAN[:CLEAN.rindex(b"$FlexgearContentHash")]
    params, options = CASES["annulus"]
    start = threading.Barrier(8)

    def slow_copy(params, options, path):
        with open(path, "wb") as fh:
            for k in range(0, len(body), 8192):
                fh.write(body[k:k + 8192])

    monkeypatch.setattr(meshing, "generate_mesh", slow_copy)
    out = []

    def run():
        start.wait()
        out.append(meshing.generate_entry(params, options, mesh_path(params, options, tmp_path)))

    threads = [threading.Thread(target=run) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(out) == 8 and set(out) == {mesh_content_hash(ANNULUS)}
    assert [p.name for p in tmp_path.iterdir()] == [ANNULUS.name]
    assert mesh_path(params, options, tmp_path).read_bytes() == CLEAN


def test_unreadable_fresh_mesh_is_a_meshing_error(tmp_path, monkeypatch):
    # gmsh "succeeds" but writes a file without tetrahedra: that is a meshing failure
    # reported as MeshingError (with the parameters), not a cache error
    from fe_components.meshing import load_mesh

    def empty_mesh(params, options, path):
        Path(path).write_bytes(b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n")

    monkeypatch.setattr(meshing, "generate_mesh", empty_mesh)
    params, options = CASES["annulus"]
    with pytest.raises(MeshingError, match="cannot be read back") as e:
        load_mesh(params, options, tmp_path)
    assert not isinstance(e.value, MeshCacheError) and e.value.params["length"] == params.length
