"""Elastic modes of flexible bodies and their nodal-diameter count.

Physics used:
- a mode of a body of revolution varies around the axis as cos(n theta + phi), n nodal
  diameters (Leissa 1969, Vibration of Plates, NASA SP-160, ch. 2);
- a structure of N identical sectors (a carrier with N posts and pins) has modes of
  harmonic n that are single for n = 0 and n = N/2, ... (n a multiple of N, here N = 3: n
  in {0, 3}) and otherwise come in pairs of equal frequency (Thomas 1979, "Dynamic of
  rotationally periodic structures", Int. J. Numer. Meth. Eng. 14, 81-102); the mesh is
  periodic only to mesh accuracy, so a pair is split by a fraction of a percent;
- the stage modes of a planetary stage with N = 3 equally spaced planets are rotational
  (single) or translational (pairs) (Lin & Parker 1999, J. Vib. Acoust. 121, 316-321);
  making the carrier flexible keeps those classes for the modes dominated by the rigid
  motion of the stage's members.
"""
import numpy as np
import pytest

from assembly import assemble, classify_modes, load_scene, solve_modes
from assembly.analysis.harmonics import cylindrical, dominant_harmonic, harmonic_power, rim_nodes


@pytest.mark.parametrize("n", range(0, 9))
def test_dominant_harmonic_of_cos_n_theta_on_uneven_ring(n):
    rng = np.random.default_rng(n)
    th = np.sort(rng.uniform(-np.pi, np.pi, 200))     # FE rim nodes are never evenly spaced
    v = np.cos(n * th + 0.7) + 0.05 * rng.standard_normal(th.size)
    assert dominant_harmonic(th, v) == n
    p = harmonic_power(th, v)
    # Mean square of A cos(n theta + phi) is A^2 / 2 for n > 0, A^2 for n = 0.
    assert p[n] == pytest.approx(0.5 if n else np.cos(0.7) ** 2, rel=0.05)


def test_nodal_diameters_from_3d_field_on_points():
    """A field cos(3 theta) in the axial direction plus a smaller uniform radial expansion
    (n = 0) on a ring of 3D points: n = 3 dominates in cylindrical components."""
    th = np.linspace(-np.pi, np.pi, 97, endpoint=False)
    P = np.column_stack([0.1 * np.cos(th), 0.1 * np.sin(th), np.zeros_like(th)])
    P = np.vstack([P, 0.05 * P])                               # an inner ring too
    idx = rim_nodes(P)
    assert set(idx) == set(range(97))
    t = np.arctan2(P[:, 1], P[:, 0])
    u = np.column_stack([0.3 * np.cos(t), 0.3 * np.sin(t), np.cos(3 * t)])[:, :, None]
    ang, uc = cylindrical(P[idx], u[idx])
    assert np.allclose(uc[:, 0, 0], 0.3)   # a uniform radial expansion: n = 0 in radial
    assert dominant_harmonic(ang, uc.reshape(len(idx), -1)) == 3


@pytest.fixture(scope="module")
def carrier():
    r = solve_modes(assemble(load_scene("planetary_flexible_carrier.toml")))
    return r, classify_modes(r)


def test_carrier_elastic_modes_and_stage_classes(carrier):
    r, infos = carrier
    assert len(infos) == len(r.frequencies_hz)
    # Lin & Parker (1999) for equally spaced planets: the in-plane stage modes are rotational
    # (single) or translational (pairs of equal frequency), so a classified translational mode
    # has exactly one translational twin and a rotational one none (twins within 1 %: the
    # flexible carrier's mesh is periodic only to mesh accuracy).
    stage = [mi for mi in infos if mi.mode_class in ("rotational", "translational")]
    assert {mi.mode_class for mi in stage} == {"rotational", "translational"}
    for mi in stage:
        twins = [o for o in stage if o.index != mi.index and abs(o.frequency_hz / mi.frequency_hz - 1) < 0.01]
        if mi.mode_class == "translational":
            assert [o.mode_class for o in twins] == ["translational"], (mi, twins)
        else:
            assert not twins, (mi, twins)
    # Carrier on its bearing, moving as a rigid body (below its first elastic mode): not elastic.
    assert all(mi.mode_class != "elastic" for mi in infos if mi.frequency_hz < 3000)
    # Modes in the carrier's elastic range (3-10 kHz) holding >= 80 % of the kinetic energy in
    # the carrier are its own elastic modes.
    own = [mi for mi in infos if 3000 < mi.frequency_hz < 10000
           and mi.dominant_bodies[0][0] == "stage.carrier" and mi.dominant_bodies[0][1] >= 0.8]
    assert len(own) >= 15
    for mi in own:
        assert mi.mode_class == "elastic" and mi.body == "stage.carrier", mi
        assert mi.label.startswith("elastic stage.carrier, ")
    # Modes led by the gears (sun, ring, planets) stay stage modes.
    for mi in infos:
        if mi.frequency_hz > 0 and mi.dominant_bodies[0][0] != "stage.carrier":
            assert mi.mode_class != "elastic", mi


def test_carrier_nodal_diameters_follow_cyclic_symmetry(carrier):
    """N = 3 sectors: harmonics n = 0, 3 single, all others in (nearly) equal pairs."""
    r, infos = carrier
    el = [mi for mi in infos if mi.mode_class == "elastic" and mi.frequency_hz < 12000]
    assert all(mi.nodal_diameters is not None for mi in el)
    f = {mi.index: mi for mi in el}
    for mi in el:
        twins = [f[j] for j in (mi.index - 1, mi.index + 1) if j in f
                 and f[j].nodal_diameters == mi.nodal_diameters
                 and abs(f[j].frequency_hz / mi.frequency_hz - 1) < 0.01]
        if mi.nodal_diameters % 3:
            assert len(twins) == 1, mi
        else:
            assert not twins, mi
