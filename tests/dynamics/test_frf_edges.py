"""The FRF at its edges: no wrong number without a word.

* **Free drivetrains at low frequency.** A section load (shaft torque, mesh and bearing force,
  stress) of a free drivetrain tends, as w -> 0, to its inertia-relief static value: the load
  ``f`` minus the rigid-body acceleration it gives, ``K q = f - M Phi_r Phi_r' f``,
  ``Phi_r' M q = 0`` (``Phi_r`` the mass-normalised rigid-body modes), with the dynamic part
  ``O(w^2 / w_1^2)`` (2.5e-9 at 1e-4 Hz beside the 5 MW model's 1.8 Hz mode). It is solved
  here by the bordered static system, a path independent of either FRF method, and the FRF is
  held to 1e-8 of it down to 1e-6 Hz.
* **A damped rigid-body mode** (a damper c_g to the housing on the generator of a free
  two-inertia chain, torque 1 on J1): by Cramer's rule on
  ``[[k - w^2 J1, -k], [-k, k - w^2 J2 + i w c_g]]`` the shaft torque is
  ``T_s = k (i c_g - w J2) / (i c_g k - w k (J1 + J2) + w^3 J1 J2 - i w^2 J1 c_g)`` (one factor
  w cancelled by hand: the form has no cancellation as w -> 0, where T_s -> 1 - O(w)).
* **The modal cutoff.** Two unit inertias, J1 grounded by k and joined to J2 by k:
  ``lambda = k (3 -+ sqrt 5) / 2``, modes ``(1, 2 - lambda/k)`` normalised (Inman, Engineering
  Vibration, ch. 4). The residual term of an undamped mode left out is
  ``phi phi' / lambda (1 + x)`` for the exact ``phi phi' / (lambda (1 - x))``, ``x = (w/w_r)^2``:
  its error is ``x^2 / (1 - x)`` of the mode's static share ``phi phi' / lambda``, which
  diverges as w reaches w_r. A cutoff below 2 x fmax is refused (8.3 % at a mode just above
  it); one leaving the residual term a bound above 1e-3 is accepted with a warning.
"""
from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest
import scipy.linalg as sla
from hypothesis import given, settings
from hypothesis import strategies as st

from assembly import Bearing, Body, Scene, SceneError, Shaft, assemble
from assembly.dynamics.frf import frequency_response
from assembly.dynamics.frf_channels import input_channel, output_channels, output_rows
from assembly.scene.schema import load_scene
from assembly.scene.tables import Damping
from tests.support.fuzz import examples

INF = math.inf


def _inertia_relief(model, inp: str, outs: list) -> np.ndarray:
    """Static section loads of a free model under the unit input ``inp``: the bordered solve of
    the module notes, with the rigid-body modes of a dense eigen solve (M-orthonormal)."""
    K, M = model.K.toarray(), model.M.toarray()
    lam, V = sla.eigh(K, M)
    r = int(np.sum(lam < 1e-8 * lam[-1]))
    Pr = V[:, :r]
    f = input_channel(model, inp).k_row
    MP = M @ Pr
    n = K.shape[0]
    B = np.block([[K, MP], [MP.T, np.zeros((r, r))]])
    q = np.linalg.solve(B, np.concatenate([f - MP @ (Pr.T @ f), np.zeros(r)]))[:n]
    Ok, _ = output_rows([c for o in outs for c in output_channels(model, o)])
    return Ok @ q


@pytest.fixture(scope="module")
def nrel5mw():
    return assemble(load_scene("nrel5mw"))


@pytest.mark.parametrize("method", ["modal", "direct"])
def test_free_drivetrain_section_loads_reach_the_static_limit(nrel5mw, method):
    outs = ["torque:ls_shaft", "force:stage3", "torque:hss", "force:stage1.sun-planet0"]
    want = _inertia_relief(nrel5mw, "torque:generator", outs)
    f = np.array([1e-6, 1e-5, 1e-4])
    r = frequency_response(nrel5mw, "torque:generator", outs, f, method=method)
    assert r.warnings == ()
    for o, s in zip(outs, want):
        assert abs(s) > 0.1                                               # a real load, N or N m per N m
        assert np.all(np.abs(r.outputs[o] - s) <= 1e-8 * abs(s)), (o, np.abs(r.outputs[o] / s - 1))


@pytest.mark.gmsh
@pytest.mark.parametrize("method", ["modal", "direct"])
def test_free_flexible_stage_stress_reaches_the_static_limit(method):
    # hs_parallel_stage is free (its output shaft turns): the wheel's largest von Mises stress
    model = assemble(load_scene("hs_parallel_stage.toml"))
    iface = sorted(model.bodies["pinion"].masters)[0]
    src = f"torque:pinion:{iface}"
    K, M = model.K.toarray(), model.M.toarray()
    lam, V = sla.eigh(K, M)
    Pr = V[:, :1]
    f = input_channel(model, src).k_row
    MP = M @ Pr
    q = np.linalg.solve(np.block([[K, MP], [MP.T, np.zeros((1, 1))]]),
                        np.concatenate([f - MP @ (Pr.T @ f), [0.0]]))[:K.shape[0]]
    wheel = model.bodies["wheel"]
    static = wheel.stress((model.T @ q)[model.body_slice("wheel")])
    node = int(np.argmax(static.von_mises))
    name = "stress:wheel:" + ",".join(f"{v:.17g}" for v in wheel.origin + wheel.axes @ static.points[node])
    r = frequency_response(model, src, [name], [1e-6, 1e-4, 1e-3], method=method)
    assert np.all(np.abs(r.outputs[name].real / static.von_mises[node] - 1) <= 1e-8)


def _chain(c_g=0.0, c=0.0, damping=None, k=1.0e4, J1=2.0, J2=3.0, ground_k=0.0) -> Scene:
    bodies = (Body(name="a", mass=10.0, polar_inertia=J1, position=(0, 0, 0)),
              Body(name="b", mass=10.0, polar_inertia=J2, position=(0, 0, 1)))
    bearings = (Bearing(body="a", k_radial=INF, k_axial=INF, k_tilt=INF, k_torsion=ground_k),
                Bearing(body="b", k_radial=INF, k_axial=INF, k_tilt=INF, c_torsion=c_g))
    return Scene(name="chain", bodies=bodies, bearings=bearings, damping=damping,
                 shafts=(Shaft(name="s", body1="a", body2="b", k_torsion=k, c_torsion=c),))


def test_damped_rigid_body_mode_closed_form_down_to_1e_7_hz():
    k, J1, J2, cg = 1.0e4, 2.0, 3.0, 5.0
    f = np.array([1e-7, 1e-5, 1e-3, 0.1, 10.0])
    w = 2 * np.pi * f
    want = k * (1j * cg - w * J2) / (1j * cg * k - w * k * (J1 + J2) + w ** 3 * J1 * J2 - 1j * w ** 2 * J1 * cg)
    model = assemble(_chain(c_g=cg))
    modal = frequency_response(model, "torque:a", "torque:s", f).outputs["torque:s"]
    assert np.all(np.abs(modal - want) <= 1e-12 * np.abs(want))
    r = frequency_response(model, "torque:a", "torque:s", f, method="direct")
    # the plain solve (a damper acts on the rigid-body mode): its round-off bound is reported,
    # eps lambda_max / (w c_r) with lambda_max = k (1/J1 + 1/J2) + ... and c_r = c_g / (J1 + J2)
    bound = float(r.warnings[0].split("up to ")[1].split(" ")[0])
    assert 1e-7 < bound < 1e-4
    assert np.all(np.abs(r.outputs["torque:s"] - want) <= bound * np.abs(want))


@pytest.mark.parametrize("method", ["modal", "direct"])
def test_zero_hz_on_a_free_model_is_refused_and_on_a_held_one_answered(method):
    with pytest.raises(SceneError, match="0 Hz"):
        frequency_response(assemble(_chain(c=30.0)), "torque:a", "torque:s", [0.0, 1.0], method=method)
    with pytest.raises(SceneError, match="0 Hz"):
        frequency_response(assemble(_chain(c_g=5.0)), "torque:a", "torque:s", [0.0, 1.0], method=method)
    # held by a torsion spring k_g on J1: at 0 Hz the shaft carries nothing (the torque on J1
    # goes straight to the housing), and J1 turns 1/k_g
    r = frequency_response(assemble(_chain(c=30.0, ground_k=2.0e4)), "torque:a", ["torque:s", "motion:a:spin"],
                           [0.0], method=method)
    assert abs(r.outputs["torque:s"][0]) <= 1e-12
    assert r.outputs["motion:a:spin"][0] == pytest.approx(1 / 2.0e4, rel=1e-12)


@pytest.mark.parametrize("method", ["modal", "direct"])
def test_overflowing_frequency_is_refused(method):
    for fmax in (1e308, 1e160):
        with pytest.raises(SceneError, match="overflows|not physical"):
            frequency_response(assemble(_chain(c=30.0)), "torque:a", "torque:s", [1.0, fmax], method=method)


@pytest.mark.parametrize("method", ["modal", "direct"])
def test_undamped_modes_in_band_are_named(method):
    model = assemble(_chain())
    wn = math.sqrt(1e4 * 5.0 / 6.0) / (2 * math.pi)                     # Hz, 14.53
    r = frequency_response(model, "torque:a", "torque:s", np.linspace(1.0, 30.0, 31), method=method)
    assert len(r.warnings) == 1 and "no damping" in r.warnings[0] and f"2 ({wn:.6g} Hz)" in r.warnings[0]
    # below the mode, or damped: no warning
    assert frequency_response(model, "torque:a", "torque:s", [1.0, 10.0], method=method).warnings == ()
    for damped in (_chain(c=30.0), _chain(damping=Damping(modal_ratio=0.02)), _chain(c_g=5.0, c=1.0)):
        assert frequency_response(assemble(damped), "torque:a", "torque:s", [1.0, 30.0], method=method).warnings == ()
    # exactly at it: refused, naming the mode (or, where the grid's w^2 misses lambda by an ulp,
    # the warning above stands beside a finite number)
    try:
        hit = frequency_response(model, "torque:a", "torque:s", [wn], method=method)
    except SceneError as exc:
        assert "mode 2" in str(exc) and "no damping" in str(exc)
    else:
        assert np.all(np.isfinite(hit.outputs["torque:s"])) and "no damping" in hit.warnings[0]


def _grounded_pair(k=4.0e4):
    """Two unit inertias, J1 grounded by k, J1-J2 joined by k (module notes)."""
    return _chain(k=k, J1=1.0, J2=1.0, ground_k=k)


def test_cutoff_below_twice_fmax_is_refused():
    model = assemble(_grounded_pair())
    f2 = math.sqrt(4.0e4 * (3 + math.sqrt(5)) / 2) / (2 * math.pi)       # Hz, the second mode (51.5)
    for modes_hz in (0.5 * f2, 0.99 * f2, 1.5 * 40.0, 79.0):
        with pytest.raises(SceneError, match="modes_hz"):
            frequency_response(model, "torque:b", "motion:b:spin", np.linspace(1.0, 40.0, 9), modes_hz=modes_hz)


def test_cutoff_error_is_within_its_stated_bound_and_warned():
    k = 4.0e4
    model = assemble(_grounded_pair(k))
    lam = np.array([k * (3 - math.sqrt(5)) / 2, k * (3 + math.sqrt(5)) / 2])
    phi2 = np.array([(2 - l / k) for l in lam]) / np.sqrt(1 + np.array([(2 - l / k) ** 2 for l in lam]))
    f2 = math.sqrt(lam[1]) / (2 * math.pi)
    fmax = f2 / 2.2                                                      # the mode left out at 2.2 x fmax
    f = np.linspace(0.5, fmax, 40)
    w2 = (2 * np.pi * f) ** 2
    exact = phi2[0] ** 2 / (lam[0] - w2) + phi2[1] ** 2 / (lam[1] - w2)
    r = frequency_response(model, "torque:b", "motion:b:spin", f, modes_hz=2.05 * fmax)   # keeps mode 1 only
    x = w2 / lam[1]
    share = phi2[1] ** 2 / lam[1]
    err = np.abs(r.outputs["motion:b:spin"] - exact)
    assert np.all(err <= (x * x / (1 - x)) * share * (1 + 1e-6) + 1e-12 * np.abs(exact))
    assert err[-1] >= 0.5 * (x[-1] ** 2 / (1 - x[-1])) * share            # the bound is the error's size
    assert [w.split(":")[0] for w in r.warnings] == [f"modal cutoff {2.05 * fmax:.6g} Hz",
                                                     "1 mode(s) in the band asked have no damping"]
    # the default cutoff (30 x fmax keeps the mode): exact, no cutoff warning (the undamped mode's stays)
    r = frequency_response(model, "torque:b", "motion:b:spin", f)
    assert np.all(np.abs(r.outputs["motion:b:spin"] - exact) <= 1e-10 * np.abs(exact))
    assert len(r.warnings) == 1 and "no damping" in r.warnings[0]


def test_direct_solve_emits_no_python_warnings(nrel5mw):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        frequency_response(nrel5mw, "torque:generator", "torque:ls_shaft", [1e-6, 1e-3, 1.0], method="direct")


@settings(max_examples=examples(60), deadline=None)
@given(fmin=st.floats(0.0, 1e4), span=st.floats(1e-6, 1e300), points=st.integers(1, 40), log=st.booleans(),
       method=st.sampled_from(["modal", "direct"]), scene=st.sampled_from(["undamped", "damped", "ground_damped",
                                                                            "held"]))
def test_fuzzed_grids_give_a_finite_answer_or_one_error(fmin, span, points, log, method, scene):
    model = FUZZ_MODELS[scene]
    fmax = fmin + span
    f = np.geomspace(max(fmin, 1e-9), fmax, points) if log else np.linspace(fmin, fmax, points)
    try:
        r = frequency_response(model, "torque:a", ["torque:s", "motion:b:spin", "force:bearing[1]:b:rz"]
                               if scene == "ground_damped" else ["torque:s", "motion:b:spin"], f, method=method)
    except SceneError as exc:
        assert "\n" not in str(exc)
        return
    for h in r.outputs.values():
        assert np.all(np.isfinite(h))
    json.dumps({k: np.abs(h).tolist() for k, h in r.outputs.items()}, allow_nan=False)


FUZZ_MODELS = {"undamped": assemble(_chain()), "damped": assemble(_chain(c=30.0)),
               "ground_damped": assemble(_chain(c_g=5.0, c=3.0)), "held": assemble(_chain(c=3.0, ground_k=1e4))}


def _three(c_ac=5.0) -> Scene:
    """Three unit inertias a-b-c on two shafts k = 1e4 N m/rad, free to spin, and a torsional
    damper c_ac between a and c: modes 0, sqrt(k) (a and c opposite, b still: damped) and
    sqrt(3 k) (a and c alike, b opposite: the damper between a and c does not move)."""
    bodies = tuple(Body(name=n, mass=10.0, polar_inertia=1.0, position=(0, 0, z)) for n, z in zip("abc", (0, 1, 2)))
    bearings = tuple(Bearing(body=n, k_radial=INF, k_axial=INF, k_tilt=INF) for n in "abc") + (
        Bearing(body="a", frame="c", k_radial=0.0, k_axial=0.0, k_tilt=0.0, c_torsion=c_ac),)
    return Scene(name="three", bodies=bodies, bearings=bearings,
                 shafts=(Shaft(name="s1", body1="a", body2="b", k_torsion=1e4),
                         Shaft(name="s2", body1="b", body2="c", k_torsion=1e4)))


@pytest.mark.parametrize("method", ["modal", "direct"])
def test_the_undamped_mode_named_is_the_one_no_damper_moves(method):
    # mode 2 (15.9 Hz) is damped by the a-c damper, mode 3 (27.6 Hz) is not: only mode 3 is named;
    # a band that ends 0.5 % below mode 3 names nothing (the band is the frequencies asked)
    f_a, f_s = math.sqrt(1e4) / (2 * math.pi), math.sqrt(3e4) / (2 * math.pi)
    model = assemble(_three())
    r = frequency_response(model, "torque:a", "torque:s1", np.linspace(1.0, 2 * f_s, 40), method=method)
    assert len(r.warnings) == 1 and r.warnings[0].startswith(f"1 mode(s) in the band asked have no damping: "
                                                             f"3 ({f_s:.6g} Hz)")
    r = frequency_response(model, "torque:a", "torque:s1", np.linspace(1.0, f_s / 1.005, 40), method=method)
    assert r.warnings == ()
    assert f_a < f_s / 1.005


def test_the_cutoff_warning_states_the_residual_terms_error():
    # the warning's bound is the exact error of an undamped left-out mode's residual term at fmax,
    # x^2 / (1 - x) of its static share with x = (fmax / f_mode)^2 (module notes)
    k = 4.0e4
    model = assemble(_grounded_pair(k))
    f2 = math.sqrt(k * (3 + math.sqrt(5)) / 2) / (2 * math.pi)
    fmax = f2 / 2.2
    x = (fmax / f2) ** 2
    r = frequency_response(model, "torque:b", "motion:b:spin", np.linspace(0.5, fmax, 5), modes_hz=2.05 * fmax)
    said = float(r.warnings[0].split("error up to ")[1].split(" ")[0])
    assert said == float(f"{x * x / (1 - x):.2g}")


def test_undamped_modes_named_in_a_planetary_stage_are_those_no_damper_moves():
    # Lin & Parker's N = 4 stage with one damper, on the ring's torsion: its rotational and
    # translational modes move the ring, its planet modes (sun, ring and carrier at rest) do
    # not. The modes named must be exactly those with phi' C phi = 0, computed here from the
    # undamped modes and the damping matrix, and no others, wherever the band starts.
    scene = load_scene("lin_parker_n4").with_values({"stages[0].ring.bearing.c_torsion": 50.0})
    model = assemble(scene)
    from assembly.analysis.modal import solve_modes
    from assembly.model.damping import damping_matrix
    res = solve_modes(model)
    C = damping_matrix(model).toarray()
    fr = res.frequencies_hz
    zeta = np.einsum("ij,ij->j", res.shapes, C @ res.shapes) / (4 * np.pi * np.maximum(fr, 1e-300))
    elastic = np.arange(res.n_rigid, len(fr))
    assert 0 < np.sum(zeta[elastic] < 1e-9) < len(elastic)           # some modes damped, some not
    gaps = [math.sqrt(a * b) for a, b in zip(fr[elastic][:-1], fr[elastic][1:]) if b > a * (1 + 1e-3)]
    for lo, hi in ((1.0, fr[-1] * 1.1), (gaps[1], fr[-1] * 1.1), (1.0, gaps[len(gaps) // 2]), (gaps[2], gaps[-2])):
        inside = [i for i in elastic if lo <= fr[i] <= hi]           # band edges between the modes
        want = [i + 1 for i in inside if zeta[i] < 1e-9]
        r = frequency_response(model, "torque:stage.sun", "motion:stage.sun:spin", np.linspace(lo, hi, 7))
        named = [w for w in r.warnings if "no damping" in w]
        if not want:
            assert not named
            continue
        assert named and named[0].startswith(f"{len(want)} mode(s)"), named
        got = [int(t.split(" (")[0]) for t in named[0].split(": ", 1)[1].split("; ")[0].split(", ")]
        assert got == want[:8]
