"""Section loads (shaft torques, mesh and bearing forces, stresses) carry every damping force.

Theory (assembly.dynamics.damping, module notes): the scene's damping is
``C_s = beta K + M Phi_e diag(d_r) Phi_e' M`` (``d_r = alpha + 2 zeta_r omega_r``), and with
``K phi_r = lambda_r M phi_r`` it equals ``K G``, ``G = beta I + Phi_e diag(d_r / lambda_r)
Phi_e' M``. Element e carries ``k_e B_e G q'`` of it, so the section loads add up to the
damping force integrated and every body's own balance holds with them:

* a rigid body i: ``M_i q_i'' = f_i - sum_{e at i} B_ei' (section load of e)``; for the rotor
  of a two-inertia chain, ``J_R th_R'' = -T`` (the shaft torque T is positive when the rotor
  is twisted ahead, acting as -T on it), in the frequency domain ``-w^2 J_R th_R + T = 0``;
* in the time domain the generalized-alpha step balances at the intermediate instants
  (Chung & Hulbert 1993): ``(1 - a_m) J a_{n+1} + a_m J a_n + (1 - a_f) T_{n+1} + a_f T_n =
  f_R(t_{n+1-a_f})`` (Newmark: a_m = a_f = 0).

The balance is algebraic: it holds to round-off (1e-9 of the peak torque here, against
1e-16 measured), whatever the damping form. Rayleigh beta and an element damper c = beta k
on the same spring are the same matrix, so they give the same torque (to round-off).
The chain: Jonkman's NREL 5 MW two-mass drivetrain (NREL/TP-500-38060): rotor 38 759 236
kg m^2, generator 534.116 kg m^2 x 97^2 = 5 025 497 kg m^2 on the low-speed side, DTTorSpr
8.67637e8 N m/rad, DTTorDmp 6.215e6 N m s/rad (5 % critical; beta = c / k = 7.163133e-3 s).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from assembly import Bearing, Body, Scene, Shaft, assemble
from assembly.dynamics.damping import damping_on_q, every_mode, section_share
from assembly.dynamics.frf import frequency_response
from assembly.dynamics.run_model import scheme_of
from assembly.dynamics.simulate import simulate
from assembly.model.damping import damping_matrix
from assembly.scene.schema import load_scene
from assembly.scene.tables import Damping
from assembly.scene.time_domain import Simulation, TimeLoad

INF = math.inf
J_R, J_G, K_S = 38_759_236.0, 534.116 * 97 ** 2, 8.67637e8      # kg m^2, kg m^2, N m/rad [Jonkman 2009]
C_S = 6.215e6                                                      # N m s/rad, DTTorDmp [Jonkman 2009]
BETA = C_S / K_S                                                   # s: Rayleigh beta with beta k = c
W1 = math.sqrt(K_S * (J_R + J_G) / (J_R * J_G))                    # rad/s, the free-free mode (2.2227 Hz)

#: every damping form of a scene, each giving the torsional mode about 5 % of critical
FORMS = {
    "element": dict(c=C_S),
    "rayleigh_beta": dict(damping=Damping(rayleigh_beta=BETA)),
    "rayleigh_alpha": dict(damping=Damping(rayleigh_alpha=2 * 0.05 * W1)),
    "modal_ratio": dict(damping=Damping(modal_ratio=0.05)),
    "class_ratios": dict(damping=Damping(class_ratios={"rotational": 0.05})),
    "element_and_beta": dict(c=0.5 * C_S, damping=Damping(rayleigh_beta=0.5 * BETA)),
    "all_forms": dict(c=0.3 * C_S, damping=Damping(modal_ratio=0.01, rayleigh_alpha=0.05, rayleigh_beta=0.2 * BETA)),
}


def chain(c: float = 0.0, damping=None, simulation=None) -> Scene:
    """Rotor and generator held in every direction but their spin about z, one torsional shaft."""
    bodies = (Body(name="rotor", mass=1.1e5, polar_inertia=J_R, position=(0, 0, 0), role="rotor"),
              Body(name="generator", mass=1.9e3, polar_inertia=J_G, position=(0, 0, 3), role="generator"))
    bearings = tuple(Bearing(body=b.name, k_radial=INF, k_axial=INF, k_tilt=INF) for b in bodies)
    return Scene(name="two-mass", bodies=bodies, bearings=bearings, damping=damping, simulation=simulation,
                 shafts=(Shaft(name="shaft", body1="rotor", body2="generator", k_torsion=K_S, c_torsion=c),))


@pytest.mark.parametrize("form", FORMS)
@pytest.mark.parametrize("method", ["modal", "direct"])
def test_frf_rotor_balance_holds_with_every_damping_form(form, method):
    # -w^2 J_R th_R + T = 0 at every frequency, resonance included
    f = np.concatenate([np.geomspace(0.05, 50.0, 40), [W1 / (2 * math.pi)]])
    r = frequency_response(assemble(chain(**FORMS[form])), "torque:generator",
                           ["torque:shaft", "motion:rotor:spin", "acceleration:rotor:spin"], f, method=method)
    T, th, acc = (r.outputs[k] for k in ("torque:shaft", "motion:rotor:spin", "acceleration:rotor:spin"))
    w = 2 * np.pi * f
    peak = np.abs(T).max()
    assert np.abs(-w ** 2 * J_R * th + T).max() <= 1e-9 * peak
    assert np.abs(J_R * acc + T).max() <= 1e-9 * peak
    assert r.units["acceleration:rotor:spin"] == "rad/s^2/(N m)"


def test_frf_rayleigh_beta_and_its_element_damper_give_one_torque():
    f = np.geomspace(0.05, 50.0, 60)
    outs = ["torque:shaft", "motion:rotor:spin"]
    for method in ("modal", "direct"):
        a = frequency_response(assemble(chain(c=BETA * K_S)), "torque:generator", outs, f, method=method)
        b = frequency_response(assemble(chain(**FORMS["rayleigh_beta"])), "torque:generator", outs, f,
                               method=method)
        for k in outs:
            assert np.abs(a.outputs[k] - b.outputs[k]).max() <= 1e-12 * np.abs(a.outputs[k]).max(), (method, k)


def _run(scene: Scene, scheme: str):
    """0.6 s after a generator torque step of 1e6 N m held 50 ms (drives the 2.2 Hz mode)."""
    load = TimeLoad(body="generator", value=1.0e6, end_value=0.0, t_start=0.05, t_end=0.05 + 1e-3)
    sim = Simulation(scheme=scheme, loads=(load,), static_start=False)
    return simulate(dataclasses.replace(scene, simulation=sim), 0.6, 1e-3,
                    ["torque:shaft", "acceleration:rotor:spin"])


@pytest.mark.parametrize("form", FORMS)
@pytest.mark.parametrize("scheme", ["newmark", "hht", "generalized-alpha"])
def test_simulate_rotor_balance_holds_with_every_damping_form(form, scheme):
    scene = chain(**FORMS[form])
    r = _run(scene, scheme)
    s = scheme_of(Simulation(scheme=scheme))
    T, a = r.outputs["torque:shaft"], r.outputs["acceleration:rotor:spin"]
    balance = ((1 - s.alpha_m) * J_R * a[1:] + s.alpha_m * J_R * a[:-1]
               + (1 - s.alpha_f) * T[1:] + s.alpha_f * T[:-1])
    assert np.abs(T).max() > 1e5                                       # the step drives the shaft
    assert np.abs(balance).max() <= 1e-9 * np.abs(T).max()


def test_simulate_rayleigh_beta_and_its_element_damper_give_one_torque():
    a = _run(chain(c=BETA * K_S), "newmark").outputs["torque:shaft"]
    b = _run(chain(**FORMS["rayleigh_beta"]), "newmark").outputs["torque:shaft"]
    assert np.abs(a - b).max() <= 1e-10 * np.abs(a).max()


def test_section_shares_add_up_to_the_scene_damping():
    # K G = C_s exactly (every mode kept): the shares of all elements and flexible bodies add up
    # to the damping force integrated. On the 5 MW drivetrain (126 DOFs, 3 stages) with every form.
    scene = load_scene("nrel5mw").with_values({"damping": {
        "class_ratios": {"rotational": 0.05, "planet": 0.02}, "modal_ratio": 0.01, "rayleigh_alpha": 0.1,
        "rayleigh_beta": 1e-5}})
    model = assemble(scene)
    modes = every_mode(model)
    C_s = damping_on_q(model, modes) - damping_matrix(model).toarray()
    KG = model.K.toarray() @ section_share(model, modes)
    assert np.abs(KG - C_s).max() <= 1e-9 * np.abs(C_s).max()


def _geared(damping=None, mesh_c=0.0):
    """A torsional geared chain: rotor -shaft- pinion | mesh | wheel -shaft- generator."""
    rb1, rb2 = 0.1, 0.3                                               # m, base radii
    cd = (rb1 + rb2) / math.cos(math.radians(20.0))                   # m, centre distance
    bodies = tuple(Body(name=n, mass=m, polar_inertia=j, position=p, fidelity="torsional") for n, m, j, p in (
        ("rotor", 50.0, 4.0, (0, 0, -1)), ("pinion", 5.0, 0.02, (0, 0, 0)),
        ("wheel", 30.0, 1.1, (cd, 0, 0)), ("generator", 40.0, 2.5, (cd, 0, 1))))
    from assembly import GearMesh
    mesh = GearMesh(gear1="pinion", gear2="wheel", stiffness=5e8, base_radius1=rb1, base_radius2=rb2,
                    pressure_angle=math.radians(20.0), damping=mesh_c, name="mesh")
    shafts = (Shaft(name="s1", body1="rotor", body2="pinion", k_torsion=2e5, c_torsion=0.0),
              Shaft(name="s2", body1="wheel", body2="generator", k_torsion=8e5, c_torsion=0.0))
    bearings = tuple(Bearing(body=b.name, k_radial=INF, k_axial=INF, k_tilt=INF, c_torsion=3.0)
                     for b in bodies if b.name in ("pinion", "wheel"))
    return Scene(name="geared", bodies=bodies, bearings=bearings, meshes=(mesh,), shafts=shafts, damping=damping)


@pytest.mark.parametrize("damping", [Damping(modal_ratio=0.04), Damping(rayleigh_alpha=3.0, rayleigh_beta=2e-5)])
def test_frf_pinion_balance_through_shaft_mesh_and_bearing_damper(damping):
    # pinion: J_p th'' = T_s1 - r1 F_mesh + (bearing torque) [Peeters et al. 2006: torque on the
    # pinion -r1 k delta, delta = r1 th_p - r2 th_w, with drive_sign 1]; the bearing's damper to the
    # housing acts on the spin: its force:BEARING:rz output is the moment it exerts on the body.
    scene = _geared(damping, mesh_c=800.0)
    f = np.geomspace(1.0, 3000.0, 80)
    outs = ["torque:s1", "force:mesh", "force:bearing[0]:pinion:rz", "acceleration:pinion:spin"]
    for method in ("modal", "direct"):
        r = frequency_response(assemble(scene), "torque:rotor", outs, f, method=method)
        Ts, F, Tb, a = (r.outputs[k] for k in outs)
        lhs = 0.02 * a
        rhs = Ts - 0.1 * F + Tb
        assert np.abs(lhs - rhs).max() <= 1e-9 * np.abs(Ts).max(), method


def test_simulate_names_undamped_modes_in_band():
    # the chain's torsional mode (sqrt(k (J_R + J_G) / (J_R J_G)) / 2 pi = 2.2227 Hz) without any
    # damper rings without decay: the run says so; with any damping form it does not
    sim = Simulation(loads=(TimeLoad(body="generator", value=1.0e5),), static_start=False)
    r = simulate(dataclasses.replace(chain(), simulation=sim), 0.01, 1e-3, ["torque:shaft"])
    bad = [w for w in r.warnings if "no damping" in w]
    assert len(bad) == 1 and f"2 ({W1 / (2 * math.pi):.6g} Hz)" in bad[0]
    for form in FORMS.values():
        r = simulate(dataclasses.replace(chain(**form), simulation=sim), 0.01, 1e-3, ["torque:shaft"])
        assert not [w for w in r.warnings if "no damping" in w]
    # the band is the scene's band_hz: the mode 0.5 % above it is not named
    above = dataclasses.replace(chain(), simulation=sim, band_hz=W1 / (2 * math.pi) / 1.005)
    r = simulate(above, 0.01, 1e-3, ["torque:shaft"])
    assert not [w for w in r.warnings if "no damping" in w]


@pytest.mark.gmsh
@pytest.mark.slow
def test_stress_with_rayleigh_beta_is_the_kelvin_voigt_stress():
    # Rayleigh beta is a Kelvin-Voigt solid, sigma = D (eps + beta eps'): in the frequency domain
    # the stress is (1 + i w beta) D eps(u). Here D eps(u) is the full stress recovery of the
    # wheel (FlexibleBodyModel.stress, the images' path) from u of an independent dense solve of
    # (K - w^2 M + i w beta K) q = f, and the FRF's von Mises is the peak over one cycle of
    # Re((1 + i w beta) S e^{i w t}) (frf_channels.von_mises_peak), at the most stressed node.
    from assembly.dynamics.frf_channels import input_channel, von_mises_peak
    beta = 2e-5                                                       # s
    scene = load_scene("hs_parallel_stage.toml").with_values({"bearings[2].k_torsion": 1.0e7,
                                                             "damping": {"rayleigh_beta": beta}})
    model = assemble(scene)
    wheel = model.bodies["wheel"]
    iface = sorted(model.bodies["pinion"].masters)[0]
    src = f"torque:pinion:{iface}"
    K, M = model.K.toarray(), model.M.toarray()
    f_in = input_channel(model, src).k_row
    w = 2 * np.pi * 700.0                                             # rad/s, between modes
    q = np.linalg.solve(K - w * w * M + 1j * w * beta * K, f_in)
    zb = (model.T @ q)[model.body_slice("wheel")]
    re, im = wheel.stress(np.real(zb)), wheel.stress(np.imag(zb))
    node = int(np.argmax(re.von_mises + im.von_mises))
    voigt = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]
    S = np.array([re.sigma[node][i, j] + 1j * im.sigma[node][i, j] for i, j in voigt])
    want = von_mises_peak((1 + 1j * w * beta) * S)
    name = "stress:wheel:" + ",".join(f"{v:.17g}" for v in wheel.origin + wheel.axes @ re.points[node])
    for method in ("modal", "direct"):
        got = frequency_response(model, src, [name], [700.0], method=method, modes_hz=np.inf).outputs[name][0]
        assert abs(got.real / want - 1) <= 1e-8, method
    # without its share the stress would be off by |1 + i w beta| - 1 = 4e-3 here: the test can fail
    assert abs(abs(1 + 1j * w * beta) - 1) > 1e-3
