"""Fuzz through assembly and the eigen solve: shipped scenes with their numbers pushed over
many decades. Every draw ends in either one user-error line (exit-2 class, naming a field of
the scene) or modes that pass their own checks:

- the number of rigid-body (0 Hz) modes is a property of the scene's structure, not of its
  magnitudes: scaling positive stiffnesses, masses and inertias by positive finite factors
  leaves it unchanged (the null space of a sum of positive semi-definite springs does not
  depend on their positive weights);
- every frequency is finite, none negative, and the eigen residuals are at round-off.

Rigid-body scenes only (milliseconds per solve); flexible bodies are fuzzed before meshing
in test_fuzz_scenes.py and test_cache_integrity.py. ``make fuzz`` draws more (tests/support/fuzz.py;
CI draws the same examples every run).
"""
import copy
import tomllib

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from assembly.analysis.modal import solve_modes
from assembly.app.errors import user_errors
from assembly.model.assemble import assemble
from assembly.scene.schema import SCENE_DIR, scene_from_dict
from tests.support.fuzz import examples, number_paths

BASES = {name: tomllib.loads((SCENE_DIR / name).read_text())
         for name in ("kahraman_beta20.toml", "lin_parker_n3.toml", "peeters_parallel_torsional.toml")}
#: Fields that scale a physical magnitude (stiffness N/m or N m/rad, mass kg, inertia kg m^2);
#: geometry (radii, positions, angles) is left alone, so the scene stays a valid mechanism.
MAGNITUDES = ("mass", "polar_inertia", "transverse_inertia", "stiffness", "k_radial", "k_axial", "k_tilt",
              "k_torsion", "k_bending", "k_shear", "k_mesh_sun", "k_mesh_ring")
EXAMPLES = examples(120)


def _get(tree, path):
    for p in path:
        tree = tree[p]
    return tree


def _set(tree, path, value):
    _get(tree, path[:-1])[path[-1]] = value


def _reference_rigid_count(name):
    return solve_modes(assemble(scene_from_dict(copy.deepcopy(BASES[name])))).n_rigid


REF_RIGID = {name: _reference_rigid_count(name) for name in BASES}


@st.composite
def scaled_scene(draw):
    name = draw(st.sampled_from(sorted(BASES)))
    tree = copy.deepcopy(BASES[name])
    paths = sorted(number_paths(tree, MAGNITUDES))
    for path in draw(st.lists(st.sampled_from(paths), min_size=1, max_size=3, unique=True)):
        _set(tree, path, _get(tree, path) * 10.0 ** draw(st.integers(-40, 40)))
    return name, tree


@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(case=scaled_scene())
def test_scaled_magnitudes_give_checked_modes_or_one_named_error(case):
    name, tree = case
    try:
        res = solve_modes(assemble(scene_from_dict(tree)))
    except user_errors() as exc:
        msg = str(exc)
        assert "\n" not in msg and "=" in msg, msg      # "path = value: reason"
        return
    f = res.frequencies_hz
    assert np.all(np.isfinite(f)) and np.all(f >= 0)
    assert res.max_residual < 1e-8, res.max_residual
    assert res.n_rigid == REF_RIGID[name], (res.n_rigid, f[:REF_RIGID[name] + 2])
