"""The rectangular-wave mesh stiffness (assembly.dynamics.mesh_variation) against its Fourier
series, computed here by quadrature of the wave itself.

Tooth-pair alternation with profile contact ratio c in (1, 2): over one mesh period (2 pi in
the mesh angle phi) two pairs are in contact for a fraction c - 1 of the period, one pair
for the rest (e.g. Niemann & Winter, Maschinenelemente II; Parker, Vijayakar & Imajo 2000,
J. Sound Vib. 237). With the double contact centred on phi = 0 and the stiffness step dk
between them, k(phi) / k0 - 1 is dk / k0 times (1 on |phi| < pi (c - 1), 0 elsewhere) minus
its mean; its cosine coefficients a_h = (1 / pi) int_{-pi}^{pi} (k / k0 - 1) cos(h phi) dphi
are 2 (dk / k0) sin(h pi (c - 1)) / (h pi). A helical contact line sweeping eps_beta mesh
periods across the face averages the wave over a window of 2 pi eps_beta, which multiplies
harmonic h by sin(h pi eps_beta) / (h pi eps_beta). Both are computed below by adaptive
quadrature of the wave (scipy.integrate.quad, the jumps given as break points), not from
the closed form, to 1e-10.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from assembly.dynamics.mesh_variation import Series, rectangular_wave, series


def _pulse(phi, c):
    """1 where two tooth pairs are in contact (|phi| < pi (c - 1), phi wrapped to (-pi, pi])."""
    phi = (phi + math.pi) % (2 * math.pi) - math.pi
    return 1.0 if abs(phi) < math.pi * (c - 1) else 0.0


def _coefficient(h, c, step, overlap=0.0):
    """a_h of the wave averaged over the helical window, by quadrature (module notes)."""
    half = math.pi * (c - 1)

    def wave(phi):
        if overlap == 0.0:
            return step * _pulse(phi, c)
        # mean of the pulse over phi + s, |s| < pi eps: the overlap of two intervals, exact
        lo, hi = phi - math.pi * overlap, phi + math.pi * overlap
        total = 0.0
        for k in range(-int(overlap) - 2, int(overlap) + 3):        # the pulse's periodic copies
            a, b = -half + 2 * math.pi * k, half + 2 * math.pi * k
            total += max(0.0, min(hi, b) - max(lo, a))
        return step * total / (2 * math.pi * overlap)

    # break points: the jumps of the pulse, or the kinks of its window average
    kinks = [sx * half + sw * math.pi * overlap + 2 * math.pi * k
             for sx in (-1, 1) for sw in (-1, 1) for k in range(-int(overlap) - 2, int(overlap) + 3)]
    points = sorted({x for x in kinks if -math.pi < x < math.pi})
    val, abserr = quad(lambda p: wave(p) * math.cos(h * p), -math.pi, math.pi, points=points, limit=400,
                       epsabs=1e-13, epsrel=1e-12)
    return val / math.pi


@pytest.mark.parametrize("c", [1.05, 1.3, 1.55, 1.62, 1.9])
@pytest.mark.parametrize("step", [0.1, 0.45])
def test_spur_amplitudes_are_the_waves_fourier_coefficients(c, step):
    a = rectangular_wave(step, c, 12)
    want = np.array([_coefficient(h, c, step) for h in range(1, 13)])
    np.testing.assert_allclose(a, want, rtol=0, atol=1e-10 * step)
    # and the closed form of the module notes, 2 dk sin(h pi (c - 1)) / (h pi)
    h = np.arange(1, 13)
    np.testing.assert_allclose(a, 2 * step * np.sin(h * np.pi * (c - 1)) / (h * np.pi), rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("c,overlap", [(1.55, 0.3), (1.62, 1.0), (1.4, 1.7)])
def test_helical_window_multiplies_by_sinc(c, overlap):
    step = 0.3
    a = rectangular_wave(step, c, 8, overlap)
    want = np.array([_coefficient(h, c, step, overlap) for h in range(1, 9)])
    np.testing.assert_allclose(a, want, rtol=0, atol=1e-9 * step)


def test_a_whole_number_overlap_removes_every_harmonic():
    # eps_beta = 1: the contact line spans exactly one base pitch, the total contact length
    # is constant and the mesh stiffness does not vary (sinc(h) = 0 for every integer h)
    np.testing.assert_allclose(rectangular_wave(0.4, 1.6, 10, 1.0), 0.0, atol=1e-16)


def test_series_value_and_derivatives():
    """f = 1 + sum a_h cos(h phi + p_h) and its first two derivatives in phi (the angle
    force of the mesh potential uses f'), against central differences of f."""
    A = np.array([[0.2, -0.05, 0.01], [0.1, 0.0, -0.03]])
    P = np.array([[0.3, -1.0, 2.0], [0.0, 0.5, 0.1]])
    s = Series(A, P)
    phi = np.array([0.4, -2.1])
    f, d1, d2 = s(phi, second=True)
    h = np.arange(1, 4)
    want = 1 + (A * np.cos(np.outer(phi, np.ones(3)) * h + P)).sum(axis=1)
    np.testing.assert_allclose(f, want, rtol=1e-14)
    e = 1e-4
    fp, fm = s(phi + e)[0], s(phi - e)[0]
    np.testing.assert_allclose(d1, (fp - fm) / (2 * e), rtol=1e-7, atol=1e-10)      # O(e^2) = 1e-8
    np.testing.assert_allclose(d2, (fp - 2 * f + fm) / e ** 2, rtol=1e-5, atol=1e-6)


def test_a_scene_mesh_takes_the_wave_of_its_teeth():
    """A spur pair with teeth and `variation = {step}`: the contact ratio comes from the
    teeth (ISO 21771 path of contact / base pitch), the amplitudes are the wave's."""
    from assembly.scene.schema import scene_from_dict
    from fe_components.gear_pair import pair_geometry

    def body(name, z, beta):
        return {"name": name, "mass": 2.0, "polar_inertia": 3e-3,
                "teeth": {"n_teeth": z, "normal_module": 0.004, "pressure_angle_deg": 20.0,
                          "helix_angle_deg": beta, "face_width": 0.03}}

    for beta in (0.0, 12.0):
        sc = scene_from_dict({
            "name": "wave",
            "bodies": [body("p", 23, beta), body("w", 51, -beta)],
            "bearings": [{"body": "p", "k_radial": 1e9, "k_axial": 1e9, "k_tilt": 1e7},
                         {"body": "w", "k_radial": 1e9, "k_axial": 1e9, "k_tilt": 1e7}],
            "meshes": [{"gear1": "p", "gear2": "w", "stiffness": 4e8, "place": "gear2",
                        "variation": {"step": 0.35, "harmonics": 6}}]})
        v = sc.meshes[0].variation
        t1, t2 = sc.bodies[0].teeth, sc.bodies[1].teeth
        c = pair_geometry(t1, t2).contact_ratio
        eps_b = 0.03 * abs(math.sin(math.radians(beta))) / (math.pi * 0.004)
        assert v.contact_ratio == pytest.approx(c, rel=1e-12) and 1 < c < 2
        assert v.face_contact_ratio == pytest.approx(eps_b, rel=1e-12, abs=1e-15)
        a, p = series(v)
        want = [_coefficient(h, c, 0.35, eps_b) for h in range(1, 7)]
        np.testing.assert_allclose(a, want, rtol=0, atol=1e-9)
        assert np.all(p == 0.0)


def test_stage_meshes_take_their_own_pairs_contact_ratio_and_planet_phase():
    """A stage with teeth and both variations given as steps (the 5 MW transient scene's
    first stage): each sun-planet mesh takes the sun-planet pair's contact ratio, each
    planet-ring mesh the planet-ring pair's (1.115 and 1.278 for stage 1: they differ), and
    planet n's meshes are phased by z psi_n with z the counting gear's teeth (Parker 2000,
    J. Sound Vib. 236: the mesh of planet n lags planet 0's by z_s psi_n / z_r psi_n)."""
    from assembly.scene.gears import stage_contact_ratios
    from assembly.scene.planetary import expand_stages
    from assembly.scene.schema import load_scene

    sc = load_scene("nrel5mw_transient.toml")
    (i, st), = [(i, s) for i, s in enumerate(sc.stages) if s.variation_sun and s.variation_ring][:1]
    eps_sun, eps_ring = stage_contact_ratios(st)
    assert abs(eps_sun - eps_ring) > 0.01
    meshes = {m.name: m for m in expand_stages(sc)["meshes"]}
    for n, psi in enumerate(st.planet_angles()):
        sun, ring = meshes[f"{st.name}.sun-planet{n}"].variation, meshes[f"{st.name}.planet{n}-ring"].variation
        assert sun.contact_ratio == pytest.approx(eps_sun, rel=1e-12)
        assert ring.contact_ratio == pytest.approx(eps_ring, rel=1e-12)
        assert sun.phase == pytest.approx(st.variation_sun.phase + st.sun.teeth * psi, rel=1e-12, abs=1e-12)
        assert ring.phase == pytest.approx(st.variation_ring.phase + st.ring.teeth * psi, rel=1e-12, abs=1e-12)
