"""The mass-property cache (assembly.model.mass_cache): a warm rigid load of a component body reads
no mesh, a hit gives the very numbers the integration gave, a damaged or stale entry is a
miss (moved aside with a warning when damaged), and concurrent writers publish whole files.

Component: a coarse steel cylinder (L = 0.2 m, D = 0.04 m, P2 mesh 0.02 m): meshed in ~0.1 s.
"""
from __future__ import annotations

import json
import logging
import os
import shutil
import tempfile
import threading
from types import SimpleNamespace

import numpy as np
import pytest

import assembly.model.components as components
import fe_components.meshing as meshing
from assembly.model import mass_cache
from assembly.model.components import CacheDirs, build_fe, forget_fe_models, local_mass_properties, mesh_entry
from assembly.scene.tables import FlexOptions
from fe_components.meshing import MeshOptions, ensure_mesh
from fe_components.params import CylinderParams
from tests.support.corruption import sweep
from tests.support.shaft_scene import shaft_scene

pytestmark = pytest.mark.gmsh

PARAMS = CylinderParams(length=0.2, diameter=0.04)
OPTIONS = FlexOptions(mesh_size=0.02)


def _fail(*a, **k):
    raise AssertionError("a mesh was read where the mass-property cache should have answered")


def _no_mesh_reads(monkeypatch):
    for name in ("read_mesh", "mesh_content_hash", "generate_mesh"):
        monkeypatch.setattr(meshing, name, _fail)
    monkeypatch.setattr(components, "build_fe", _fail)


def _same(p, fe):
    """Bitwise equality with the FE model's integrated properties (JSON floats round-trip)."""
    assert p.mass == fe.mass
    assert np.array_equal(p.center_of_mass, fe.center_of_mass) and np.array_equal(p.inertia, fe.inertia)
    assert p.mesh_sha256 == fe.mesh_sha256


@pytest.fixture(scope="module")
def clean(tmp_path_factory):
    root = tmp_path_factory.mktemp("clean")
    caches = CacheDirs(root, root / "cms")
    forget_fe_models()
    p = local_mass_properties(PARAMS, OPTIONS, caches)
    (entry,) = root.glob("*.mass-*.json")
    return SimpleNamespace(root=root, fe=build_fe(PARAMS, OPTIONS, caches), props=p, entry=entry)


@pytest.fixture
def cache(clean, tmp_path):
    shutil.copytree(clean.root, tmp_path / "c")      # copy2: the mesh keeps its size and mtime
    return CacheDirs(tmp_path / "c", tmp_path / "c" / "cms")


def test_miss_stores_the_integrated_numbers_and_a_hit_returns_them_without_reading_a_mesh(clean, cache,
                                                                                         monkeypatch, caplog):
    _same(clean.props, clean.fe)
    forget_fe_models()
    _no_mesh_reads(monkeypatch)
    with caplog.at_level(logging.WARNING):
        hit = local_mass_properties(PARAMS, OPTIONS, cache)
    _same(hit, clean.fe)
    assert not caplog.records


def test_density_is_part_of_the_key(clean, cache):
    # mass, first and second moments all scale with rho: twice the density, twice each
    from fe_components.material import Material
    heavy = FlexOptions(mesh_size=0.02, material=Material(rho=2 * OPTIONS.material.rho))
    p = local_mass_properties(PARAMS, heavy, cache)
    assert len(list(cache.meshes.glob("*.mass-*.json"))) == 2
    assert np.isclose(p.mass, 2 * clean.props.mass, rtol=1e-12)
    assert np.allclose(p.inertia, 2 * clean.props.inertia, rtol=1e-12, atol=1e-12 * clean.props.inertia.max())


def _wrong_seal(d: bytes) -> bytes:
    rec = json.loads(d)
    rec["sha256"] = rec["sha256"][::-1]
    return json.dumps(rec).encode()


def _other_mass(d: bytes) -> bytes:
    rec = json.loads(d)
    rec["mass"] *= 1.01                                # a changed number under the old seal
    return json.dumps(rec).encode()


def _other_density(d: bytes) -> bytes:
    rec = json.loads(d)
    rec["rho"] = 1.0                                   # sealed, but not the density of its key
    rec.pop("sha256")
    rec["sha256"] = mass_cache.seal(rec)
    return json.dumps(rec).encode()


CASES = {**sweep(), "wrong-seal": _wrong_seal, "changed-number": _other_mass, "other-density": _other_density}


@pytest.mark.parametrize("name", list(CASES))
def test_damaged_entry_is_moved_aside_integrated_again_and_then_hit(clean, cache, name, monkeypatch, caplog):
    target = cache.meshes / clean.entry.name
    good = target.read_bytes()
    bad = CASES[name](good)
    assert bad != good
    target.write_bytes(bad)
    forget_fe_models()
    with caplog.at_level(logging.WARNING):
        p = local_mass_properties(PARAMS, OPTIONS, cache)
    _same(p, clean.fe)
    warnings = [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING]
    assert len(warnings) == 1 and str(target) in warnings[0], warnings
    (aside,) = target.parent.glob(target.name + ".corrupt-*")
    assert aside.read_bytes() == bad
    caplog.clear()
    forget_fe_models()
    _no_mesh_reads(monkeypatch)
    with caplog.at_level(logging.WARNING):
        _same(local_mass_properties(PARAMS, OPTIONS, cache), clean.fe)
    assert not caplog.records


def test_replaced_mesh_makes_the_entry_stale_not_corrupt(clean, cache, caplog):
    # A different valid mesh (the cylinder meshed at 0.019 m) under the entry's mesh name: the
    # stored numbers belong to the old mesh, so they are integrated again from the new one,
    # quietly (nothing is damaged), and the entry now records the new mesh.
    other = ensure_mesh(PARAMS, MeshOptions(size=0.019), cache.meshes / "other")
    target = mesh_entry(PARAMS, OPTIONS, cache).path
    shutil.copyfile(other, target)
    forget_fe_models()
    with caplog.at_level(logging.WARNING):
        p = local_mass_properties(PARAMS, OPTIONS, cache)
    assert not caplog.records
    fe = build_fe(PARAMS, OPTIONS, cache)
    assert fe.mesh_sha256 != clean.fe.mesh_sha256 and p.mass != clean.props.mass
    _same(p, fe)
    assert json.loads((cache.meshes / clean.entry.name).read_text())["mesh_sha256"] == fe.mesh_sha256
    assert not list(cache.meshes.glob("*.corrupt-*"))


def test_concurrent_writers_of_one_entry_each_publish_a_whole_file(clean, tmp_path):
    # Eight threads store different numbers under one name at once: each writes its own
    # temporary file and os.replace's it, so the survivor is one writer's whole, sealed entry.
    mesh = mesh_entry(PARAMS, OPTIONS, CacheDirs(clean.root)).path
    path = mass_cache.entry_path(mesh, 7850.0, tmp_path)
    start = threading.Barrier(8)
    props = [mass_cache.MassProperties(1.0 + k, np.full(3, k, float), np.eye(3) * (k + 1), "x")
             for k in range(8)]

    def run(k):
        start.wait()
        mass_cache.store(path, props[k], mesh, 7850.0)

    threads = [threading.Thread(target=run, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    got = mass_cache.load(path, mesh, 7850.0)
    k = int(got.mass) - 1
    assert k in range(8) and np.array_equal(got.inertia, props[k].inertia)
    assert os.listdir(tmp_path) == [path.name]


@pytest.mark.parametrize("errno_", [13, 28, 30])   # EACCES, ENOSPC, EROFS
def test_a_folder_that_cannot_take_the_entry_costs_only_its_reuse(clean, tmp_path, monkeypatch, caplog, errno_):
    caches = CacheDirs(tmp_path, tmp_path / "cms")
    shutil.copy2(mesh_entry(PARAMS, OPTIONS, CacheDirs(clean.root)).path, tmp_path)   # mesh cached

    def refuse(*a, **k):
        raise OSError(errno_, os.strerror(errno_))

    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    forget_fe_models()
    with caplog.at_level(logging.WARNING):
        p = local_mass_properties(PARAMS, OPTIONS, caches)
    _same(p, clean.fe)
    assert any("cannot store mass properties" in r.getMessage() and os.strerror(errno_) in r.getMessage()
               for r in caplog.records)
    assert not list(tmp_path.glob("*.json"))


def test_warm_rigid_scene_assembles_the_same_model_without_reading_a_mesh(clean, cache, tmp_path, monkeypatch):
    from assembly.model.assemble import assemble
    from assembly.scene.schema import load_scene
    path = tmp_path / "shaft.toml"
    path.write_text(shaft_scene("rigid"))
    scene = load_scene(path)
    forget_fe_models()
    cold = assemble(scene, caches=CacheDirs(tmp_path / "cold", tmp_path / "cold" / "cms"))
    forget_fe_models()
    _no_mesh_reads(monkeypatch)
    warm = assemble(scene, caches=cache)
    assert (cold.K != warm.K).nnz == 0 and (cold.M != warm.M).nnz == 0
