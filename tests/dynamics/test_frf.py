"""Frequency response functions (assembly.dynamics.frf).

Closed forms used below (M q'' + C q' + K q = f e^{i w t}, q = H f):

* two inertias J1, J2 on a torsional spring k with damper c, free otherwise, torque T on
  J1: with z = k + i w c,
  [[z - w^2 J1, -z], [-z, z - w^2 J2]] [th1, th2] = [T, 0], solved by Cramer's rule below;
  the shaft torque is z (th1 - th2). As w -> 0, th1 = -1/(J_tot w^2) (1 + O(w^2 J2^2 /
  (k J_tot))): the whole chain accelerates as one rigid body of J_tot = J1 + J2.
* the chain of two unit inertias, J1 grounded by k and J1-J2 joined by k:
  K = k [[2, -1], [-1, 1]], lambda = k (3 -+ sqrt 5) / 2, mode (1, 2 - lambda/k)
  (e.g. Inman, Engineering Vibration, ch. 4). With modal damping zeta the driving-point
  receptance at J2 is sum_r phi_r2^2 / (lambda_r - w^2 + 2 i zeta w sqrt(lambda_r)); at
  w = omega_1 the first term is phi_12^2 / (2 i zeta lambda_1), the second is bounded by
  phi_22^2 / (lambda_2 - lambda_1) (its damping only lowers it).
* Maxwell-Betti reciprocity: K, M, C symmetric, so H_ij = H_ji for an output that is the
  work-conjugate of an input (motion at its point, in its direction).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from assembly import Bearing, Body, Scene, SceneError, Shaft, assemble
from assembly.analysis.modal import solve_modes
from assembly.dynamics.frf import frequency_response
from assembly.scene.schema import load_scene
from assembly.scene.tables import Damping

INF = math.inf
J1, J2, K, C = 2.0, 3.0, 1.0e4, 30.0         # kg m^2, kg m^2, N m/rad, N m s/rad


def _held(name, pos, J, **bearing):
    """A body on a bearing rigid in every direction but its spin (about global z)."""
    return (Body(name=name, mass=10.0, polar_inertia=J, position=pos),
            Bearing(body=name, k_radial=INF, k_axial=INF, k_tilt=INF, **bearing))


def two_mass(c=C, damping=None, ground=None, j1=J1, j2=J2, k=K) -> Scene:
    (b1, br1), (b2, br2) = _held("a", (0, 0, 0), j1, **(ground or {})), _held("b", (0, 0, 1), j2)
    return Scene(name="two", bodies=(b1, b2), bearings=(br1, br2), damping=damping,
                 shafts=(Shaft(name="s", body1="a", body2="b", k_torsion=k, c_torsion=c),))


def _closed_two_mass(w):
    """(th1, th2) per unit torque on J1, by Cramer's rule on the 2x2 system above; its
    determinant a11 a22 - a12^2 expanded to w^2 (w^2 J1 J2 - z (J1 + J2)) (the z^2 terms
    cancel exactly, which in floating point would cost digits at low w)."""
    z = K + 1j * w * C
    det = w ** 2 * (w ** 2 * J1 * J2 - z * (J1 + J2))
    return (z - w ** 2 * J2) / det, z / det


@pytest.mark.parametrize("method", ["modal", "direct"])
def test_two_mass_shaft_torque_closed_form(method):
    f = np.concatenate([np.geomspace(0.01, 100.0, 60), [math.sqrt(K * (J1 + J2) / (J1 * J2)) / (2 * math.pi)]])
    r = frequency_response(assemble(two_mass()), "torque:a", ["torque:s", "motion:a:rz", "motion:b:spin"],
                           f, method=method)
    w = 2 * np.pi * f
    th1, th2 = _closed_two_mass(w)
    want = (K + 1j * w * C) * (th1 - th2)
    got = r.outputs["torque:s"]
    assert np.all(np.abs(np.abs(got) / np.abs(want) - 1) <= 1e-9)
    assert np.all(np.abs(np.angle(got / want)) <= 1e-9)                     # phase, rad
    assert np.all(np.abs(r.outputs["motion:a:rz"] - th1) <= 1e-9 * np.abs(th1))
    assert np.all(np.abs(r.outputs["motion:b:spin"] - th2) <= 1e-9 * np.abs(th2))
    assert r.units["torque:s"] == "N m/(N m)" and r.units["motion:a:rz"] == "rad/(N m)"


def test_free_free_chain_rigid_body_limit():
    model = assemble(two_mass())
    f = np.array([1e-3, 1e-2])                                               # Hz, far below 14.5 Hz
    w = 2 * np.pi * f
    jt = J1 + J2
    # the modal solve takes the rigid-body term exactly: 1e-9. The direct LU of K - w^2 M + i w C
    # is backward stable, its relative error bounded by a small multiple of eps x cond (Higham,
    # Accuracy and Stability of Numerical Algorithms, ch. 9); cond ~ 2 K / (w^2 J_tot) is 1e8 at 1e-3 Hz
    cond = 2 * K / (w ** 2 * jt)
    rtol = {"modal": np.full_like(w, 1e-9), "direct": np.maximum(1e-9, 10 * np.finfo(float).eps * cond)}
    for method in ("modal", "direct"):
        th = frequency_response(model, "torque:a", "motion:a:rz", f, method=method).outputs["motion:a:rz"]
        assert np.all(np.isfinite(th))
        assert np.all(np.abs(th * (-jt * w ** 2) - 1) <= 2 * w ** 2 * J2 ** 2 / (K * jt))
        assert np.all(np.abs(th - _closed_two_mass(w)[0]) <= rtol[method] * np.abs(th))
    with pytest.raises(SceneError, match="0 Hz"):
        frequency_response(model, "torque:a", "motion:a:rz", [0.0, 1.0])


def test_isolated_mode_peak_is_static_modal_gain_over_two_zeta():
    zeta, k = 2e-3, 4.0e4
    scene = two_mass(c=0.0, damping=Damping(modal_ratio=zeta), ground=dict(k_torsion=k), j1=1.0, j2=1.0, k=k)
    lam = k * (3 - math.sqrt(5)) / 2, k * (3 + math.sqrt(5)) / 2
    phi2 = [(2 - l / k) ** 2 / (1 + (2 - l / k) ** 2) for l in lam]         # phi_r2^2, mass-normalised
    peak = phi2[0] / (2 * zeta * lam[0])                                    # |first term| at omega_1
    eps = (phi2[1] / (lam[1] - lam[0])) / peak                              # neighbour / peak bound
    assert eps < 0.01
    model = assemble(scene)
    for method in ("modal", "direct"):
        h = frequency_response(model, "torque:b", "motion:b:rz", [math.sqrt(lam[0]) / (2 * math.pi)],
                               method=method).outputs["motion:b:rz"][0]
        assert abs(abs(h) / peak - 1) <= eps


def _damped_pair() -> Scene:
    """The Kahraman helical pair with a mesh damper and bearing dampers (non-proportional)."""
    sc = load_scene("kahraman_beta20")
    return dataclasses.replace(
        sc, meshes=tuple(dataclasses.replace(m, damping=2.0e3) for m in sc.meshes),
        bearings=tuple(dataclasses.replace(b, c_radial=5.0e2, c_tilt=2.0) for b in sc.bearings))


POINTS = ["force:pinion:x", "force:pinion:z", "moment:pinion:y", "torque:wheel", "force:wheel:y"]


def _conjugate(name: str) -> str:
    kind, body, *axis = name.split(":")
    if kind == "torque":
        return f"motion:{body}:spin"
    return f"motion:{body}:{'r' if kind == 'moment' else ''}{axis[0]}"


def test_reciprocity():
    model = assemble(_damped_pair())
    f = np.geomspace(10.0, 2.0e4, 200)
    H = np.array([[frequency_response(model, i, _conjugate(j), f).outputs[_conjugate(j)] for j in POINTS]
                  for i in POINTS])                                         # H[i, j]: input i, output at j
    scale = np.abs(H).max(axis=(0, 1))
    assert np.all(np.abs(H - H.transpose(1, 0, 2)) <= 1e-10 * scale)
    assert np.abs(H[0, 3]).max() > 1e-6 * np.abs(H[0, 0]).max()             # the pair is coupled


@pytest.mark.parametrize("damping", [None, Damping(modal_ratio=0.02), Damping(rayleigh_alpha=5.0, rayleigh_beta=1e-6)])
def test_superposition_matches_direct_away_from_resonance(damping):
    model = assemble(dataclasses.replace(_damped_pair(), damping=damping))
    res = solve_modes(model)
    outs = ["force:pinion-wheel", "motion:wheel:x", "force:" + model.elements[0].name + ":x", "motion:pinion:spin"]
    f = np.geomspace(1.0, 3.0e4, 400)
    fn = res.frequencies_hz[res.n_rigid:]
    f = f[np.min(np.abs(f[:, None] / fn[None, :] - 1), axis=1) > 0.02]      # >= 2 % from every mode
    modal = frequency_response(model, "torque:pinion", outs, f, result=res)
    direct = frequency_response(model, "torque:pinion", outs, f, method="direct", result=res)
    for name in modal.outputs:
        a, b = modal.outputs[name], direct.outputs[name]
        assert np.all(np.abs(a - b) <= 1e-6 * np.abs(b)), name


def test_modal_damping_without_dampers_is_diagonal_and_exact():
    # the two-mass chain with modal ratio only: both paths exact everywhere, resonance included
    zeta = 0.05
    model = assemble(two_mass(c=0.0, damping=Damping(modal_ratio=zeta)))
    wn = math.sqrt(K * (J1 + J2) / (J1 * J2))
    f = np.array([0.5, wn / (2 * math.pi), 40.0])
    a = frequency_response(model, "torque:a", "torque:s", f).outputs["torque:s"]
    b = frequency_response(model, "torque:a", "torque:s", f, method="direct").outputs["torque:s"]
    assert np.all(np.abs(a - b) <= 1e-9 * np.abs(b))
    # at resonance the shaft torque from J_eq d'' + c_eq d' + k d = (J2 / (J1 + J2)) T (d the
    # relative twist, c_eq = 2 zeta omega_n J_eq): the modal damping is the shaft's own in this
    # chain (the force-summation cut J2 th2'' = T_s), so T_s = (k + i w c_eq) d, and at w = omega_n
    # |T_s| = J2 / (J1 + J2) |k + i w c_eq| / (w c_eq) = J2 / (J1 + J2) sqrt(1 + 4 zeta^2) / (2 zeta)
    assert abs(a[1]) == pytest.approx(J2 / (J1 + J2) * math.sqrt(1 + 4 * zeta ** 2) / (2 * zeta), rel=1e-9)


@pytest.mark.parametrize("arg,name", [
    ("input", "torque:nobody"), ("input", "force:a:w"), ("input", "force:a"), ("input", "push:a"),
    ("input", "torque:a:nointerface"), ("input", "moment:zz:x"),
    ("output", "torque:nosuchshaft"), ("output", "force:nosuch"), ("output", "force:bearing[0]:a:q"),
    ("output", "force:bearing[0]:a:x"), ("output", "force:bearing[0]:a"), ("output", "motion:a:w"), ("output", "motion:nobody:x"),
    ("output", "torque:bearing[0]:a"), ("output", "speed:a"),
])
def test_bad_names_name_the_argument(arg, name):
    model = assemble(two_mass())
    ins, outs = ("torque:a", [name]) if arg == "output" else (name, ["torque:s"])
    with pytest.raises(SceneError) as exc:
        frequency_response(model, ins, outs, [1.0])
    assert exc.value.path == {"input": "input", "output": "outputs"}[arg] and exc.value.value == name


def test_bad_frequencies():
    model = assemble(two_mass())
    for f in ([], [-1.0], [math.nan], [math.inf]):
        with pytest.raises(SceneError) as err:
            frequency_response(model, "torque:a", "torque:s", f)
        assert err.value.path.startswith("frequency_hz")


def test_free_free_chain_with_non_proportional_dampers():
    # three inertias, shafts of different c/k: the state form with the undamped rigid-body
    # mode outside it. Low-frequency limit -1/(J_tot w^2), its relative deviation of order
    # (w / w_1)^2 <= w^2 J_tot / k_min (w_1^2 >= k_min / J_tot... bounded here by 10x that).
    bodies = [_held(n, (0, 0, z), J) for n, z, J in (("a", 0, 1.0), ("b", 1, 2.0), ("c", 2, 3.0))]
    scene = Scene(name="three", bodies=tuple(b for b, _ in bodies), bearings=tuple(br for _, br in bodies),
                  shafts=(Shaft(name="s1", body1="a", body2="b", k_torsion=1e4, c_torsion=30.0),
                          Shaft(name="s2", body1="b", body2="c", k_torsion=3e4, c_torsion=1.0)))
    model = assemble(scene)
    f = np.array([1e-3, 0.5, 3.0, 50.0, 200.0])
    a = frequency_response(model, "torque:a", ["motion:a:rz", "torque:s2"], f)
    b = frequency_response(model, "torque:a", ["motion:a:rz", "torque:s2"], f, method="direct")
    for name in a.outputs:
        assert np.all(np.abs(a.outputs[name] - b.outputs[name]) <= 1e-6 * np.abs(b.outputs[name])), name
    w = 2 * np.pi * f[0]
    assert abs(a.outputs["motion:a:rz"][0] * (-6.0 * w ** 2) - 1) <= 10 * w ** 2 * 6.0 / 1e4
