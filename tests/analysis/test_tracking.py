"""Mode tracking along a parameter change (assembly.analysis.tracking): branches follow shapes,
not the frequency order."""
import math

import numpy as np
import pytest

from assembly import Bearing, Body, Scene, assemble, load_scene, solve_modes
from assembly.analysis.tracking import track_modes


def _two_oscillators(k_a: float) -> Scene:
    """Two torsional bodies, each on its own torsion spring to the housing, not joined:
    two decoupled oscillators f = sqrt(k / J) / 2 pi (Rao, Mechanical Vibrations, sec. 2.2)."""
    return Scene(name="two oscillators", bodies=(
        Body("a", mass=1.0, polar_inertia=1e-3, fidelity="torsional"),
        Body("b", mass=1.0, polar_inertia=2e-3, position=(1.0, 0.0, 0.0), fidelity="torsional")),
        bearings=(Bearing("a", 1e8, 1e8, 1e5, k_torsion=k_a), Bearing("b", 1e8, 1e8, 1e5, k_torsion=2e4)))


def test_branches_follow_shapes_through_a_crossing():
    # k_a from 5e3 to 2e4 N m/rad: f_a = sqrt(k_a / 1e-3) / 2pi rises through f_b =
    # sqrt(2e4 / 2e-3) / 2pi = 503.3 Hz, reached exactly at k_a = 1e4 (a repeated frequency).
    ks = np.linspace(5e3, 2e4, 7)   # includes 1e4: the two frequencies are equal there
    branches = track_modes([solve_modes(assemble(_two_oscillators(k))) for k in ks])
    assert len(branches) == 2
    f_a = np.sqrt(ks / 1e-3) / (2 * np.pi)
    f_b = np.full_like(ks, math.sqrt(2e4 / 2e-3) / (2 * np.pi))
    a, b = sorted(branches, key=lambda br: br.frequencies_hz[0])   # a starts below b
    assert a.frequencies_hz == pytest.approx(f_a, rel=1e-9)   # follows body a past the crossing
    assert b.frequencies_hz == pytest.approx(f_b, rel=1e-9)
    assert np.all(a.mac[1:] > 0.999) and np.all(b.mac[1:] > 0.999)
    # frequency order alone would have swapped them: the lower mode is b's after the crossing
    lowest = [min(x, y) for x, y in zip(f_a, f_b)]
    assert not np.allclose(a.frequencies_hz, lowest)
    after = int(np.argmax(ks > 1e4))   # the first step past the crossing
    assert "crossing" in a.flags[after] and "crossing" in b.flags[after]
    assert not any(a.flags[:after]) and all("low-mac" not in f for f in a.flags)


def test_helix_angle_sweep_branches_are_continuous():
    # Kahraman's pair (Peeters et al., Wind Energy 9, 2006, Table I and Fig. 7) with the
    # helix angle from 0 to 30 deg in 2-deg steps: at 0 deg the in-plane and the
    # axial/tilt motions decouple; the helix couples them and several modes move (the
    # gear-mesh mode, the highest, rises 3972 -> 4333 Hz; tilt modes fall). Every branch
    # keeps its shape from step to step (MAC >= 0.8, no flag).
    base = load_scene("kahraman_beta0.toml")
    betas = np.arange(0.0, 30.1, 2.0)
    results = [solve_modes(assemble(base.with_value("meshes[0].helix_angle_deg", float(b)))) for b in betas]
    branches = track_modes(results)
    moving = [br for br in branches[results[0].n_rigid:]
              if abs(br.frequencies_hz[-1] / br.frequencies_hz[0] - 1) > 0.01]
    assert len(moving) >= 3
    for br in branches[results[0].n_rigid:]:
        assert np.all(br.mac[1:] >= 0.8) and not br.flagged, (br.frequencies_hz, br.mac, br.flags)
    mesh_mode = max(branches, key=lambda br: br.frequencies_hz[0])
    assert np.all(np.diff(mesh_mode.frequencies_hz) > 0)   # rises at every step
    # at 20 deg every tracked frequency is one of the shipped 20-deg scene's (published table)
    ref = solve_modes(assemble(load_scene("kahraman_beta20.toml"))).frequencies_hz
    k20 = int(np.flatnonzero(betas == 20.0)[0])
    for br in moving:
        assert np.min(np.abs(ref - br.frequencies_hz[k20])) <= 1e-9 * br.frequencies_hz[k20]


def test_mismatched_steps_refused():
    r1 = solve_modes(assemble(_two_oscillators(1e4)))
    r2 = solve_modes(assemble(load_scene("kahraman_beta0.toml")))
    with pytest.raises(ValueError):
        track_modes([r1, r2])
    assert track_modes([]) == []
