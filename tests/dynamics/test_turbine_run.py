"""The drivetrain in its turbine (``[turbine]``, assembly.dynamics.turbine_run), each run against an
answer computed here.

Theory.
* A gearbox 1000 times stiffer than the NREL 5 MW's turns as one rigid body: the rotor-generator
  one-mass model J Omega' = Q(V, Omega, beta) - N T_g, J = phi' M phi the model's inertia
  referred to the rotor (phi its rigid-body motion per unit rotor speed), N = omega_g / Omega,
  with the same surface and the same controller (its own instance) called at the same samples.
  Its elastic modes move up sqrt(1000) = 31.6 times and their quasi-static twist falls 1000
  times, so what separates the two runs is of order 1e-3 of the twist's share in the speeds:
  the issue asks 1e-3 RMS of each channel's mean.
* Aerodynamic damping. A two-mass drivetrain (rotor J_r, generator J_g N^2 on the low-speed
  side, shaft k: ElastoDyn's) above rated with a constant generator torque: the aerodynamic
  torque Q = q R Cq(lambda, beta) at a fixed wind and pitch is affine in Omega inside one cell of
  the bilinear surface (lambda = Omega R / V), so the coupled run is the linear two-mass model
  with the rotor damper d = -dQ/dOmega = -q R (R/V) dCq/dlambda, the slope read here from the
  table's own numbers; integrated here by the trapezoidal rule (what Newmark's average
  acceleration is on a linear model), the two agree to Newton's tolerance.
* Gravity: a shaft's bearings carry its weight by the lever rule, W (z_b - c)/L and W (c - z_a)/L
  (tilted by tau: W cos tau radially, W sin tau axially). A steady nacelle acceleration a along
  y loads the shaft with -m a, carried alike (Park et al.'s 6 250 N nacelle force).
* Unbalance: M x'' + c x' + k x = m e Omega^2 cos(Omega t): X = m e Omega^2 / (k - M Omega^2 + i c
  Omega); the trapezoidal rule's steady response is that with i Omega -> (2i/h) tan(Omega h/2).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from assembly.dynamics.discon import Discon
from assembly.dynamics.rosco_data import NREL5MW_SURFACE, rosco_file
from assembly.dynamics.rotor_surface import read_surface, rotor_loads
from assembly.dynamics.run_start import start_velocity
from assembly.dynamics.simulate import simulate
from assembly.dynamics.turbine_run import ROSCO_INPUT, ROSCO_LIBRARY
from assembly.errors import SceneError
from assembly.model.assemble import assemble
from assembly.scene.schema import load_scene, scene_from_dict
from tests.support.turbine_scenes import J_GEN, J_ROTOR, K_SHAFT, RADIUS, RATED_TQ, RATIO, RPM, two_mass

pytest.importorskip("rosco", reason="the rosco package (its NREL 5 MW surface) is not installed")

pytestmark = pytest.mark.usefixtures("step_path")

RHO = 1.225


def _surface():
    return read_surface(rosco_file(NREL5MW_SURFACE))


def _trim_pitch(wind: float, omega: float, torque: float) -> float:
    """The pitch (rad) at which the rotor's torque at ``wind``, ``omega`` is ``torque`` (the torque
    falls with pitch above rated: bisection)."""
    s = _surface()
    lo, hi = 0.0, math.radians(25.0)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if rotor_loads(s, RADIUS, RHO, wind, omega, mid).torque > torque:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


# ---- a stiff gearbox is the one-mass model ---------------------------------------------------

def _nrel_turbine(tmp_path, wind: str, pitch: float, period: float):
    f = tmp_path / "turbine.toml"
    f.write_text(f"""extends = "nrel5mw.toml"
name = "stiff turbine"
[set.damping]
class_ratios = {{ rotational = 0.05 }}
[set.simulation]
speed = 1.2671
[set.turbine]
surface = "rosco"
radius = {RADIUS}
pitch = {pitch!r}
wind = {wind}
controller = {{ kind = "rosco", period = {period} }}
""")
    return load_scene(f)


def _one_mass(J, N, sense, wind, pitch0, omega0, torque0, dt, t_end, period, eta=0.944):
    """The one-mass rotor-generator model, trapezoidal in Omega (the aerodynamic torque at the new
    step solved by Newton's method on the surface), with ROSCO called at every sample."""
    s = _surface()
    ctrl = Discon(rosco_file(ROSCO_LIBRARY), rosco_file(ROSCO_INPUT))
    every = round(period / dt)
    n = round(t_end / dt)
    om, tq, beta = omega0, torque0, pitch0
    out = np.zeros((n + 1, 4))
    try:
        for k in range(n + 1):
            t = k * dt
            if k % every == 0 and k < n:                # a sample: the demand from the state now
                o = ctrl.step(t, period, N * om, om, beta, tq, wind(t), power=eta * tq * N * om)
                tq, beta = o.generator_torque, o.pitch   # pitch_tau = 0: the demand itself
            out[k] = om, tq, beta, eta * tq * N * om
            if k == n:
                break
            q0 = rotor_loads(s, RADIUS, RHO, wind(t), om, beta).torque
            w1 = om
            for _ in range(30):                          # J (w1 - om)/dt = (Q(w1) + Q(om))/2 - N tq
                ld = rotor_loads(s, RADIUS, RHO, wind(t + dt), w1, beta)
                r = J * (w1 - om) / dt - 0.5 * (ld.torque + q0) + N * tq
                w1 -= r / (J / dt - 0.5 * ld.dq_domega)
                if abs(r) < 1e-12 * J * om / dt:
                    break
            om = w1
    finally:
        ctrl.close()
    return out


STIFF = {"period": 0.01, "dt": 0.01, "t_end": 30.0}


@pytest.fixture(scope="module")
def stiff_turbine(tmp_path_factory):
    """The stiff turbine's scene, model and one-mass reference run: none of them takes a time
    step of the integrator (the reference is its own Python loop), so they are built once for
    both steps of step_path, which only the run of the test itself takes."""
    period, dt, t_end = STIFF["period"], STIFF["dt"], STIFF["t_end"]
    tmp_path = tmp_path_factory.mktemp("stiff_turbine")
    pitch = _trim_pitch(16.0, 1.2671, RATED_TQ * 96.354)       # nrel5mw.toml's ratio (its teeth)
    scene = _nrel_turbine(tmp_path, "{ steps = [[0.0, 16.0], [10.0, 19.0]] }", pitch, period)
    model = assemble(scene)
    # the one-mass model of the same drivetrain: its inertia and ratio from the rigid-body motion
    phi = start_velocity(model, scene, scene.simulation, 1.0)[0]
    M = model.M.toarray()
    J = float(phi @ M @ phi)
    from assembly.model.probes import spin_row
    N = abs(float(spin_row(model, "generator") @ phi))
    wind = lambda t: 16.0 if t < 10.0 else 19.0                 # noqa: E731 (steps as the scene's)
    # the generator torque that balances the start (module notes of turbine_run)
    q0 = rotor_loads(_surface(), RADIUS, RHO, 16.0, 1.2671, pitch).torque
    ref = _one_mass(J, N, 1.0, wind, pitch, 1.2671, q0 / N, dt, t_end, period)
    return tmp_path, model, ref


def test_a_stiff_gearbox_turns_as_the_one_mass_rotor_generator_model(stiff_turbine):
    dt, t_end = STIFF["dt"], STIFF["t_end"]
    tmp_path, model, ref = stiff_turbine
    stiff = dataclasses.replace(model, K=model.K * 1e3)
    run = simulate(stiff, t_end, dt, base_dir=tmp_path)
    names = ("turbine:rotor_speed", "turbine:generator_torque", "turbine:pitch", "turbine:power")
    for j, name in enumerate(names):
        got, want = run.outputs[name], ref[:, j]
        rms = math.sqrt(np.mean((got - want) ** 2))
        assert rms <= 1e-3 * abs(np.mean(want)), (name, rms / abs(np.mean(want)))
    # the step in the wind moved the pitch: the controller worked, not just held
    assert ref[-1, 2] - ref[int(9.9 / dt), 2] > math.radians(2.0)


# ---- aerodynamic damping: the coupled run is the linearised two-mass model --------------------

def test_aerodynamic_damping_is_the_surface_slope_in_the_two_mass_model():
    wind, omega0, dt, t_end = 16.0, 12.1 * RPM, 2e-3, 4.0
    tq = RATED_TQ * RATIO
    pitch = _trim_pitch(wind, omega0, tq)
    pulse, t_pulse = 0.05 * tq, (0.2, 0.4)          # a torque pulse on the generator, along its turning
    scene = two_mass(omega0, pitch, wind, pulse, t_pulse, dt, tq)
    run = simulate(scene, t_end, dt, outputs=["torque:shaft", "speed:rotor", "turbine:aero_torque"])
    # the surface's slope in this cell, from the table's numbers
    s = _surface()
    lam = omega0 * RADIUS / wind
    i = int(np.searchsorted(s.tsr, lam)) - 1
    j = int(np.searchsorted(s.pitch, pitch)) - 1
    u = (pitch - s.pitch[j]) / (s.pitch[j + 1] - s.pitch[j])
    slope = ((1 - u) * (s.cq[i + 1, j] - s.cq[i, j]) + u * (s.cq[i + 1, j + 1] - s.cq[i, j + 1])) \
        / (s.tsr[i + 1] - s.tsr[i])
    qdyn = 0.5 * RHO * math.pi * RADIUS ** 2 * wind ** 2
    d = -qdyn * RADIUS * slope * RADIUS / wind                   # N m s/rad, > 0: damping
    q0 = rotor_loads(s, RADIUS, RHO, wind, omega0, pitch).torque
    # the run stayed in that cell (the premise of linearity)
    w = run.outputs["speed:rotor"]
    lams = w * RADIUS / wind
    assert s.tsr[i] < lams.min() and lams.max() < s.tsr[i + 1]
    # the linear model: x = (theta_r - theta_g, omega_r, omega_g), trapezoidal rule
    Jg = J_GEN * RATIO ** 2

    def rhs(t):                                                  # the doublet, as the loads' ramps
        f = np.clip((t - t_pulse[0]) / dt, 0, 1) - np.clip((t - t_pulse[1]) / dt, 0, 1)
        return np.array([0.0, (q0 + d * omega0) / J_ROTOR, (-tq + pulse * f) / Jg])   # a load drives

    A = np.array([[0.0, 1.0, -1.0], [-K_SHAFT / J_ROTOR, -d / J_ROTOR, 0.0], [K_SHAFT / Jg, 0.0, 0.0]])
    n = round(t_end / dt)
    x = np.array([q0 / K_SHAFT, omega0, omega0])                 # the static start's twist
    L, R = np.eye(3) - 0.5 * dt * A, np.eye(3) + 0.5 * dt * A
    ts = np.zeros(n + 1)
    ts[0] = K_SHAFT * x[0]
    for k in range(n):
        x = np.linalg.solve(L, R @ x + 0.5 * dt * (rhs(k * dt) + rhs((k + 1) * dt)))
        ts[k + 1] = K_SHAFT * x[0]
    got = run.outputs["torque:shaft"]
    got = got * np.sign(got[0])                                  # the output's sign: rotor driving +
    swing = np.max(np.abs(ts - ts[0]))
    # Newton's tolerance (1e-10 of the forces, ~q0) over the run's steps: 1e-7 of the swing
    assert np.max(np.abs(got - ts)) <= 1e-7 * swing
    # and the aerodynamic damper matters at that tolerance: without it the model misses by far more
    A0 = A.copy()
    A0[1, 1] = 0.0
    L0, R0 = np.eye(3) - 0.5 * dt * A0, np.eye(3) + 0.5 * dt * A0
    x, miss = np.array([q0 / K_SHAFT, omega0, omega0]), 0.0
    for k in range(n):
        b = rhs(k * dt) + rhs((k + 1) * dt)
        b[1] -= 2 * d * omega0 / J_ROTOR
        x = np.linalg.solve(L0, R0 @ x + 0.5 * dt * b)
        miss = max(miss, abs(K_SHAFT * x[0] - got[k + 1]))
    assert miss > 1e-3 * swing
    # the drivetrain mode's damping ratio from the linear model, > 0 from the surface alone
    ev = np.linalg.eigvals(A)
    osc = ev[np.argmax(ev.imag)]
    assert -osc.real / abs(osc) > 0.0
    # the controller was called at its sample times, every one
    times = run.info["_controller_times"]
    assert run.info["controller_calls"] == n and times == pytest.approx([k * dt for k in range(n)], abs=1e-12)


# ---- gravity, the nacelle's motion, an unbalance: the scene's loads on a shaft ---------------

M_S, ZC, ZA, ZB = 100.0, 0.4, 0.0, 1.0          # kg, m
KR, KA, KT = 1.0e8, 1.0e8, 1.0e6                 # N/m, N/m, N m/rad
G = 9.80665


def _shaft(**extra):
    return scene_from_dict({
        "name": "shaft on two bearings", "fidelity": "rigid",
        "bodies": [{"name": "shaft", "role": "rotor", "mass": M_S, "polar_inertia": 2.0, "position": [0.0, 0.0, ZC]}],
        "bearings": [{"body": "shaft", "position": [0.0, 0.0, z], "k_radial": KR, "k_axial": KA, "k_tilt": 0.0,
                      "k_torsion": KT} for z in (ZA, ZB)], **extra})


def _bearing_forces(z):
    """(y forces, z forces) of the two bearings on the shaft (spring force -k u at each)."""
    u, th = z[0:3], z[3:6]
    out = []
    for zp in (ZA, ZB):
        up = u + np.cross(th, np.array([0.0, 0.0, zp - ZC]))
        out.append((-KR * up[1], -KA * up[2]))
    return np.array(out)


@pytest.mark.parametrize("tilt_deg", [0.0, 5.0])
def test_gravity_in_a_static_case_is_carried_by_the_lever_rule(tilt_deg):
    from assembly.analysis.static import solve_static_cases
    from assembly.scene.tables import LoadCase
    scene = _shaft(turbine={"gravity": True, "tilt_deg": tilt_deg})
    st = solve_static_cases(assemble(scene), [("gravity", LoadCase(name="gravity"))])[0]
    F = _bearing_forces(st.z)
    W, t = M_S * G, math.radians(tilt_deg)
    lever = np.array([(ZB - ZC) / (ZB - ZA), (ZC - ZA) / (ZB - ZA)]) * W * math.cos(t)
    np.testing.assert_allclose(F[:, 0], lever, rtol=0, atol=1e-10 * W)
    assert F[:, 1].sum() == pytest.approx(W * math.sin(t), abs=1e-10 * W)


def test_a_steady_nacelle_acceleration_loads_the_bearings_by_the_lever_rule():
    # Park et al.: an inertia force of 6 250 N from the nacelle's motion; here a = 6250 / m along y
    a = 6250.0 / M_S
    scene = _shaft(simulation={"nacelle": [{"dof": "y", "amplitude": a, "phase_deg": 90.0}]})
    dofs = ("x", "y", "z", "rx", "ry", "rz")
    run = simulate(scene, 1e-3, 1e-4, outputs=[f"motion:shaft:{c}" for c in dofs])
    # the static start under the steady load: the state stays there (the run records it)
    z = np.array([run.outputs[f"motion:shaft:{c}"][-1] for c in dofs])
    F = _bearing_forces(z)
    lever = np.array([(ZB - ZC) / (ZB - ZA), (ZC - ZA) / (ZB - ZA)]) * 6250.0
    # the housing accelerates up: the shaft lags, the bearings push it up with m a
    np.testing.assert_allclose(F[:, 0], lever, rtol=1e-9)


def test_an_unbalance_on_a_turning_rotor_is_the_closed_form():
    mu, e, c = 0.02, 0.1, 2.0e3
    kx = 2 * KR
    omega = 0.8 * math.sqrt(kx / M_S)
    h = 2 * math.pi / omega / 100
    scene = scene_from_dict({
        "name": "rotor with an unbalance", "fidelity": "rigid",
        "bodies": [{"name": "shaft", "role": "rotor", "mass": M_S, "polar_inertia": 2.0,
                    "position": [0.0, 0.0, 0.5]}],
        "bearings": [{"body": "shaft", "position": [0.0, 0.0, z], "k_radial": KR, "k_axial": KA, "k_tilt": 0.0,
                      "c_radial": c / 2} for z in (0.0, 1.0)],
        "simulation": {"speed": omega, "unbalance": [{"body": "shaft", "mass": mu, "radius": e}]}})
    t_end = 20 * 2 * M_S / c      # e^-20 = 2e-9 of the start left (its swing at most ~2 X): below 1e-8 X
    run = simulate(scene, t_end, h, outputs=["motion:shaft:x", "motion:shaft:y"])
    t = run.time_s
    x, y = run.outputs["motion:shaft:x"], run.outputs["motion:shaft:y"]
    sd = 2j / h * math.tan(omega * h / 2)
    Xd = mu * e * omega ** 2 / (kx + M_S * sd ** 2 + c * sd)
    last = t >= t_end - 5 * 2 * math.pi / omega
    np.testing.assert_allclose(x[last], np.real(Xd * np.exp(1j * omega * t[last])), rtol=0, atol=1e-8 * abs(Xd))
    np.testing.assert_allclose(y[last], np.real(-1j * Xd * np.exp(1j * omega * t[last])), rtol=0,
                               atol=1e-8 * abs(Xd))


# ---- bad input: one line naming the field ----------------------------------------------------

@pytest.mark.parametrize("turbine, field", [
    ({"wind": {"table": "missing.csv", "column": "V"}}, "turbine.wind.table"),
    ({"wind": {"steps": [[0.0, 16.0]], "speed": 16.0}}, "turbine.wind.steps"),
    ({"wind": {}}, "turbine.wind.speed"),
    ({"controller": {"kind": "discon", "library": "nowhere.so", "input": "DISCON.IN"}}, "turbine.controller.library"),
    ({"controller": {"kind": "rosco", "input": "nowhere/DISCON.IN"}}, "turbine.controller.input"),
    ({"controller": {"kind": "simple", "period": 0.01}}, "turbine.controller.rated_speed"),
    ({"controller": {"kind": "baseline", "period": 0.015}}, "turbine.controller.period"),
    ({"surface": None}, "turbine.surface"),
    ({"radius": None}, "turbine.radius"),
    ({"wind": {"speed": 400.0}}, "turbine.surface"),
])
def test_bad_turbine_input_is_refused_naming_the_field(tmp_path, turbine, field):
    tb = {"surface": "rosco", "radius": RADIUS, "pitch_deg": 12.0, "wind": {"speed": 16.0},
          "controller": {"kind": "baseline", "period": 0.01}}
    tb.update(turbine)
    tb = {k: v for k, v in tb.items() if v is not None}
    scene = two_mass(12.1 * RPM, 0.2, 16.0, 0.0, (0.1, 0.2), 0.01, 1.0)
    scene = scene_from_dict({**_dict(scene), "turbine": tb})
    before = sorted(tmp_path.iterdir())
    with pytest.raises(SceneError) as exc:
        simulate(scene, 0.1, 0.01, base_dir=tmp_path)
    assert field in exc.value.path or field in str(exc.value)
    assert sorted(tmp_path.iterdir()) == before


def _dict(scene):
    from assembly.scene.schema import to_dict
    d = to_dict(scene, defaults=False)
    d.pop("turbine", None)
    return d


@pytest.mark.parametrize("table, field", [
    ({"radius": -63.0}, "turbine.radius"),
    ({"density": 0.0}, "turbine.density"),
    ({"wind": {"speed": -3.0}}, "turbine.wind.speed"),
    ({"wind": {"turbulence": "D", "speed": 10.0}}, "turbine.wind.turbulence"),
    ({"controller": {"kind": "bladed"}}, "turbine.controller.kind"),
    ({"controller": {"period": 0.0}}, "turbine.controller.period"),
    ({"tilt_deg": 60.0}, "turbine.tilt"),
])
def test_bad_turbine_numbers_are_refused_when_the_scene_is_read(table, field):
    with pytest.raises(SceneError) as exc:
        _shaft(turbine=table)
    assert exc.value.path.startswith(field)


def test_an_unbalance_needs_a_turning_body():
    # a cover on its own bearings, held against turning: nothing spins it
    d = _dict(_shaft())
    d["simulation"] = {"speed": 10.0, "unbalance": [{"body": "cover", "mass": 1.0, "radius": 0.1}]}
    for b in d["bearings"]:
        b["k_torsion"] = 0.0                                     # the shaft turns freely
    d["bodies"].append({"name": "cover", "mass": 10.0, "polar_inertia": 1.0, "position": [0.0, 0.0, 2.0]})
    d["bearings"].append({"body": "cover", "position": [0.0, 0.0, 2.0], "k_radial": KR, "k_axial": KA,
                          "k_tilt": KT, "k_torsion": KT})
    with pytest.raises(SceneError) as exc:
        simulate(scene_from_dict(d), 0.01, 1e-3)
    assert exc.value.path == "simulation.unbalance[0].body"


def test_a_turbine_output_needs_a_turbine():
    with pytest.raises(SceneError) as exc:
        simulate(_shaft(), 0.01, 1e-3, outputs=["turbine:wind"])
    assert exc.value.path == "outputs[0]"


def test_a_wind_table_is_read_as_given_and_must_cover_the_run(tmp_path):
    # a CSV wind series: the run's wind is it, linear between its rows
    (tmp_path / "wind.csv").write_text("time,V\n0.0,15.0\n0.05,17.0\n0.1,16.0\n")
    scene = two_mass(12.1 * RPM, 0.2, 16.0, 0.0, (0.02, 0.04), 0.01, RATED_TQ * RATIO)
    d = _dict(scene)
    d["turbine"] = {"surface": "rosco", "radius": RADIUS, "pitch": 0.2, "wind": {"table": "wind.csv", "column": "V"},
                    "controller": {"kind": "baseline", "period": 0.01}}
    run = simulate(scene_from_dict(d), 0.1, 0.01, outputs=["turbine:wind"], base_dir=tmp_path)
    np.testing.assert_allclose(run.outputs["turbine:wind"], np.interp(run.time_s, [0.0, 0.05, 0.1],
                                                                       [15.0, 17.0, 16.0]), rtol=1e-15)
    with pytest.raises(SceneError) as exc:
        simulate(scene_from_dict(d), 0.2, 0.01, base_dir=tmp_path)
    assert exc.value.path == "turbine.wind.table"


def test_the_command_line_refuses_a_bad_turbine_in_one_line(tmp_path, capsys):
    from assembly.app.cli import main
    f = tmp_path / "bad.toml"
    f.write_text('extends = "nrel5mw.toml"\nname = "bad"\n[set.turbine]\nradius = -63.0\nsurface = "rosco"\n'
                 'wind = { speed = 16.0 }\n')
    out = tmp_path / "out"
    assert main(["simulate", str(f), "--t-end", "0.1", "--dt", "0.01", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "turbine.radius" in err[0] and "-63" in err[0]
    assert not out.exists()


def test_a_wind_from_an_openfast_channel_is_that_channel_in_m_per_s():
    from assembly.dynamics.load_series import read_openfast_out
    from tests.support.openfast_files import DATA
    f = DATA / "FASTOutBin.outb"                     # SNL SWiFT, Wind1VelX in m/s, 0 .. 1 s every 5 ms
    want = read_openfast_out(f, "Wind1VelX", "test", expect="m/s")
    scene = two_mass(5.0 * RPM, 0.0, 7.2, 0.0, (0.5, 0.6), 0.005, RATED_TQ * RATIO)
    d = _dict(scene)
    d["turbine"] = {"surface": "rosco", "radius": RADIUS, "pitch": 0.0,
                    "wind": {"openfast": str(f), "column": "Wind1VelX"},
                    "controller": {"kind": "baseline", "period": 0.005}}
    run = simulate(scene_from_dict(d), 1.0, 0.005, outputs=["turbine:wind"])
    np.testing.assert_allclose(run.outputs["turbine:wind"], np.interp(run.time_s, want.time_s, want.values),
                               rtol=1e-14)
    # a channel that is not a speed is refused by its unit
    d["turbine"]["wind"]["column"] = "RotSpeed"
    with pytest.raises(SceneError) as exc:
        simulate(scene_from_dict(d), 1.0, 0.005)
    assert exc.value.path.startswith("turbine.wind")
