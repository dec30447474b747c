"""Scene-level time-domain runs (:func:`assembly.dynamics.simulate.simulate`): start state,
loads from files, generator laws, gearbox efficiency, planet phasing, bad input, a run that
stops. The integrators' own theory is in test_integrators.py and test_transient_physics.py."""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.dynamics.simulate import simulate
from assembly.dynamics.transient import Diverged, Nonlinear, integrate
from assembly.errors import SceneError
from assembly.scene.schema import load_scene, scene_from_dict

# A torsional gear pair, 20/60 teeth-like radii (ratio 3): the rotor (gear 1) drives the
# generator (gear 2) through one mesh; inertias and stiffness round numbers.
R1, R2 = 0.05, 0.15                # m, base radii
J1, J2 = 2.0, 0.5                  # kg m^2
K_MESH = 1.0e8                     # N/m
RATIO = R2 / R1                    # generator turns at 1/3 of the rotor, the other way


# every run here on both steps, the compiled and the Python one (tests/dynamics/conftest.py)
pytestmark = pytest.mark.usefixtures("step_path")


def pair(simulation: dict, mesh: dict | None = None) -> dict:
    """Scene dict of the pair with ``simulation`` and extra ``mesh`` fields."""
    c = (R1 + R2) / math.cos(math.radians(20.0))
    return {"name": "pair", "bodies": [
        {"name": "rotor", "mass": 10.0, "polar_inertia": J1, "fidelity": "torsional", "role": "rotor"},
        {"name": "generator", "mass": 10.0, "polar_inertia": J2, "position": [c, 0.0, 0.0],
         "fidelity": "torsional", "role": "generator"}],
        "meshes": [{"name": "m", "gear1": "rotor", "gear2": "generator", "stiffness": K_MESH, "base_radius1": R1,
                    "base_radius2": R2, "pressure_angle_deg": 20.0, **(mesh or {})}],
        "simulation": simulation}


def test_balanced_start_is_static_equilibrium():
    # rotor torque T and generator torque T / RATIO balance (gear geometry), so the static start
    # has the mesh carrying F = T / r1 from t = 0 and nothing accelerates: every output constant.
    T = 1000.0
    s = scene_from_dict(pair({"speed": 10.0, "loads": [{"body": "rotor", "value": T}],
                              "generator": {"torque": T * RATIO}}))
    r = simulate(s, 0.01, 1e-4, ["force:m", "speed:rotor", "speed:generator"])
    np.testing.assert_allclose(r.outputs["force:m"], T / R1, rtol=1e-9)
    np.testing.assert_allclose(r.outputs["speed:rotor"], 10.0, rtol=1e-9)
    np.testing.assert_allclose(r.outputs["speed:generator"], -10.0 / RATIO, rtol=1e-9)


def test_unbalanced_load_accelerates_the_chain_by_inertia_relief():
    # a rotor torque T alone: the chain's rigid-body acceleration alpha = T / (J1 + J2 / RATIO^2)
    # (kinetic energy of the gear train at unit rotor speed), exactly, from the first step.
    T = 100.0
    s = scene_from_dict(pair({"speed": 0.0, "loads": [{"body": "rotor", "value": T}]}))
    r = simulate(s, 0.02, 1e-4, ["speed:rotor"])
    alpha = T / (J1 + J2 / RATIO ** 2)
    w = r.outputs["speed:rotor"]
    np.testing.assert_allclose(w[-1], alpha * r.time_s[-1], rtol=1e-9)


def test_gearbox_efficiency_needs_a_low_speed_shaft():
    # the friction's sign is the low-speed-shaft torque's: a chain without a shaft on the rotor
    # must name one
    s = scene_from_dict(pair({"speed": 10.0, "generator": {"torque": 300.0}, "gearbox_efficiency": 0.95}))
    with pytest.raises(SceneError, match="simulation.lss_shaft"):
        simulate(s, 0.01, 1e-4, ["speed:rotor"])


def _quill_pair(simulation: dict) -> dict:
    """The pair with the rotor on a torsional shaft from a hub (the low-speed shaft)."""
    d = pair(simulation)
    d["bodies"].insert(0, {"name": "hub", "mass": 100.0, "polar_inertia": 50.0, "fidelity": "torsional"})
    d["bodies"][1]["role"] = None
    d["bodies"][0]["role"] = "rotor"
    d["shafts"] = [{"name": "lss", "body1": "hub", "body2": "rotor", "k_torsion": 1.0e6}]
    return d


def test_gearbox_efficiency_friction_balances_the_lss_torque():
    # ElastoDyn's GBoxEff: the rotor must supply T_gen / (RATIO eta) (the generator turns RATIO
    # times slower than the rotor gear); with exactly that torque the chain keeps its speed.
    # Without the friction term the same torques would change it by T_gen (1/eta - 1) / RATIO /
    # J_eq per second, J_eq the chain's inertia at the hub: far more than the drift allowed here.
    eta, Tg, w0, t_end = 0.95, 300.0, 10.0, 0.2
    J_eq = 50.0 + J1 + J2 / RATIO ** 2
    d = _quill_pair({"speed": w0, "loads": [{"body": "hub", "value": Tg / (RATIO * eta)}],
                     "generator": {"torque": Tg}, "gearbox_efficiency": eta})
    d["bodies"] = [{k: v for k, v in b.items() if v is not None} for b in d["bodies"]]
    r = simulate(scene_from_dict(d), t_end, 1e-4, ["speed:hub", "torque:lss"])
    drift = abs(r.outputs["speed:hub"][-1] - w0)
    missing = Tg * (1 / eta - 1) / RATIO / J_eq * t_end          # speed change without the friction
    assert drift < 1e-2 * missing
    np.testing.assert_allclose(r.outputs["torque:lss"].mean(), Tg / (RATIO * eta), rtol=1e-3)


def test_pi_generator_settles_at_rated_speed_with_the_balancing_torque():
    # integral action: at steady state omega_gen = rated and T_gen = T_rotor x RATIO (the generator
    # turns RATIO times slower), so the mesh carries T_rotor / r1
    T = 900.0
    w_rated = 10.0 / RATIO
    s = scene_from_dict(pair({"speed": 9.0, "loads": [{"body": "rotor", "value": T}],
                              "generator": {"law": "pi", "torque": 2500.0, "rated_speed": w_rated, "kp": 2000.0,
                                            "ki": 20000.0, "max_torque": 4000.0}}))
    r = simulate(s, 3.0, 1e-3, ["speed:generator", "force:m"])
    np.testing.assert_allclose(abs(r.outputs["speed:generator"][-1]), w_rated, rtol=1e-4)
    np.testing.assert_allclose(r.outputs["force:m"][-1], T / R1, rtol=1e-4)


def test_rotor_torque_from_an_openfast_file_in_kilonewton_metres(tmp_path):
    # RotTorq in kN-m: the run applies 1000 x the file's value; balanced by the generator it is
    # the mesh force x r1 from the static start on (t = 0 row of the file).
    (tmp_path / "run.out").write_text(
        "Predictions were generated on 23-Nov-2026 using OpenFAST\n\n"
        "Time\tRotTorq\tRotSpeed\n(s)\t(kN-m)\t(rpm)\n"
        "0.0\t1.2\t95.5\n1.0\t1.2\t95.5\n", encoding="utf-8")
    s = scene_from_dict(pair({"speed": 10.0, "loads": [{"body": "rotor", "openfast": "run.out", "column": "RotTorq"}],
                              "generator": {"torque": 1200.0 * RATIO}}))
    r = simulate(s, 0.005, 1e-4, ["force:m"], base_dir=tmp_path)
    np.testing.assert_allclose(r.outputs["force:m"], 1200.0 / R1, rtol=1e-9)


def test_planet_meshes_are_phased_by_planet_angle():
    # Parker (2000): planet n's sun mesh lags planet 0's by z_s psi_n; equally spaced planets of
    # the 5 MW stage 1 (z_s = 19, N = 3): 19 x 2 pi / 3 -> phases 2 pi/3 x 19 (mod 2 pi).
    s = load_scene("nrel5mw").with_values({"stages[0].variation_sun": {"step": 0.5}})
    v = [m.variation for m in s.expanded().meshes if "sun-planet" in m.name and m.name.startswith("stage1")]
    for n, vn in enumerate(v):
        assert math.isclose(vn.phase, 19 * 2 * math.pi * n / 3, rel_tol=1e-12, abs_tol=1e-12)


BAD = [
    # k = k0 (1 - 1.2) < 0 at phi = pi; 1 + 0.6 cos(phi) + 0.6 cos(2 phi + pi) = 1.6 + 0.6 c - 1.2 c^2
    # (c = cos phi) is -0.2 at phi = pi: harmonics each below 1 that together make k negative
    ({"mesh": {"variation": {"amplitudes": [1.2], "teeth": 20}}}, "meshes[0].variation.amplitudes"),
    ({"mesh": {"variation": {"amplitudes": [0.6, 0.6], "phases": [0.0, math.pi], "teeth": 20}}},
     "meshes[0].variation.amplitudes"),
    ({"mesh": {"variation": {"step": 0.5, "teeth": 20}}}, "meshes[0].variation.contact_ratio"),  # no teeth: no c
    ({"mesh": {"variation": {"step": 0.5, "contact_ratio": 1.5, "harmonics": 3}}}, "meshes[0].variation.teeth"),
    ({"mesh": {"backlash": -1e-4}}, "meshes[0].backlash"),
    ({"mesh": {"variation": {"amplitudes": [0.1], "phases": [0.0, 1.0]}}}, "meshes[0].variation.phases"),
    ({"sim": {"loads": [{"body": "nobody", "value": 1.0}]}}, "simulation.loads[0].body"),
    ({"sim": {"loads": [{"body": "rotor", "value": 1.0, "end_value": 2.0}]}}, "simulation.loads[0].t_end"),
    ({"sim": {"loads": [{"body": "rotor", "table": "t.csv"}]}}, "simulation.loads[0].column"),
    ({"sim": {"generator": {"law": "pi", "torque": 1.0}}}, "simulation.generator.rated_speed"),
    ({"sim": {"gearbox_efficiency": 1.5}}, "simulation.gearbox_efficiency"),
    ({"sim": {"brake": {"torque": -5.0}}}, "simulation.brake.torque"),
]


@pytest.mark.parametrize("change, path", BAD, ids=[p for _, p in BAD])
def test_bad_time_domain_input_names_the_field(change, path):
    sim = {"speed": 1.0, **change.get("sim", {})}
    with pytest.raises(SceneError) as e:
        simulate(scene_from_dict(pair(sim, change.get("mesh"))), 0.001, 1e-4, ["force:m"])
    assert str(e.value).startswith(path), str(e.value)


@pytest.mark.parametrize("rows, what", [("0,1\n0.2,1\n0.1,2\n", "does not increase"),
                                        ("0,1\n0.1,2\n", "torque")], ids=["non-monotonic", "missing column"])
def test_bad_csv_load_names_the_field(tmp_path, rows, what):
    (tmp_path / "t.csv").write_text("time,Torque\n" + rows, encoding="utf-8")
    s = scene_from_dict(pair({"speed": 1.0, "loads": [{"body": "rotor", "table": "t.csv",
                                                       "column": "Torque" if "increase" in what else "torque"}]}))
    with pytest.raises(SceneError) as e:
        simulate(s, 0.001, 1e-4, [], base_dir=tmp_path)
    assert str(e.value).startswith("simulation.loads[0].table") and what in str(e.value)


class _Blowup(Nonlinear):
    """A softening spring -k x^3 on one coordinate: x'' = x^3 leaves every bound in finite time."""

    def __init__(self):
        self.U = np.ones((1, 1))

    def forces(self, t, x, xd):
        return -x ** 3, -3 * x ** 2, np.zeros(1)


def test_a_run_that_leaves_every_bound_stops_with_a_named_partial_result():
    # x'' = x^3 from x = 1, v = 1/sqrt(2)... grows without bound (energy v^2/2 - x^4/4 = 0 gives
    # x(t) = 1 / (1 - t / sqrt 2): blow-up at t = sqrt 2 s)
    with pytest.raises(Diverged) as e:
        integrate(np.eye(1), None, np.zeros((1, 1)), lambda t: np.zeros(1), [1.0], [1 / math.sqrt(2)], 1e-3, 3.0,
                  nonlinear=_Blowup(), dof_names=["x"])
    p = e.value.partial
    # every row keeps its own time (the steps'), and before the pole the rows follow the closed
    # form to the trapezoidal rule's O(dt^2) error, amplified by the growth
    assert len(p.time_s) == len(p.y) == len(p.iterations) > 1
    np.testing.assert_allclose(p.time_s, np.arange(len(p.time_s)) * 1e-3, rtol=0, atol=1e-12)
    early = p.time_s <= 1.0
    np.testing.assert_allclose(p.y[early, 0], 1 / (1 - p.time_s[early] / math.sqrt(2)), rtol=1e-3)
    assert p.time_s[-1] > 1.0
    assert not p.complete and np.all(np.isfinite(p.y))
    assert p.time_s[-1] < math.sqrt(2) + 0.05                 # stops at the blow-up, not at t_end
    assert "t = " in str(e.value) and ("x" in str(e.value) or "Newton" in str(e.value))


# ---------------------------------------------------------------- OpenFAST files in a run

def _gentq_file(tmp_path, gentq_knm, name="gen.outb", t_end=1.0, file_id=3):
    """An OpenFAST output (binary of ``file_id``, or text for a ``.out`` name) with a constant
    GenTq (kN-m), and RotTorq, GenPwr and RotSpeed beside it."""
    from tests.support.openfast_files import out_text, outb_bytes
    t = np.linspace(0.0, t_end, 11)
    data = np.column_stack([np.full(11, gentq_knm), np.full(11, 1.2), np.full(11, 5.0), np.full(11, 12.1)])
    names, units = ["Time", "GenTq", "RotTorq", "GenPwr", "RotSpeed"], ["(s)", "(kN-m)", "(kN-m)", "(kW)", "(rpm)"]
    if name.endswith(".out"):
        (tmp_path / name).write_text(out_text(names, units, np.column_stack([t, data]).tolist()), encoding="utf-8")
    else:
        (tmp_path / name).write_bytes(outb_bytes(names, units, t, data, file_id))
    return name


@pytest.mark.parametrize("file_id", [2, 3])
def test_recorded_generator_torque_balances_the_rotor_torque_times_the_ratio(tmp_path, file_id):
    # GenTq = T x RATIO (kN-m in the file) against a rotor torque T: the chain keeps its speed and
    # the mesh carries T / r1 (the closed form of the constant-law test above), from a binary file
    T = 1200.0
    name = _gentq_file(tmp_path, T * RATIO / 1e3, file_id=file_id)
    s = scene_from_dict(pair({"speed": 10.0, "loads": [{"body": "rotor", "value": T}],
                              "generator": {"law": "table", "openfast": name, "column": "GenTq"}}))
    r = simulate(s, 0.01, 1e-4, ["force:m", "speed:rotor", "speed:generator"], base_dir=tmp_path)
    # int16 packing (FileFmtID 2) of a constant channel is exact to its float32 offset's rounding
    rtol = 1e-9 if file_id == 3 else 3 * 2 ** -24
    np.testing.assert_allclose(r.outputs["force:m"], T / R1, rtol=rtol)
    np.testing.assert_allclose(r.outputs["speed:rotor"], 10.0, rtol=rtol)
    np.testing.assert_allclose(r.outputs["speed:generator"], -10.0 / RATIO, rtol=rtol)
    assert not [w for w in r.warnings if "time range" in w]               # the file covers the run


@pytest.mark.parametrize("speed", [10.0, 0.0], ids=["turning", "standstill"])
@pytest.mark.parametrize("gentq", [2.0, -1.5], ids=["generating", "motoring"])
def test_recorded_generator_torque_sign(tmp_path, speed, gentq):
    # OpenFAST's GenTq > 0 brakes the generator's positive rotation (ElastoDyn: the generator DOF
    # sees -(GenTrq + HSSBrTrq) |GBRatio|), < 0 drives it. Referred to the rotor, Tg / RATIO opposes
    # the rotor's rotation: alpha = (T - Tg / RATIO) / (J1 + J2 / RATIO^2) exactly (inertia relief).
    # From standstill the positive sense is the one a positive rotor speed gives the generator.
    T, Tg = 1000.0, gentq * 1e3
    name = _gentq_file(tmp_path, gentq)
    s = scene_from_dict(pair({"speed": speed, "loads": [{"body": "rotor", "value": T}],
                              "generator": {"law": "table", "openfast": name, "column": "GenTq"}}))
    r = simulate(s, 0.02, 1e-4, ["speed:rotor"], base_dir=tmp_path)
    alpha = (T - Tg / RATIO) / (J1 + J2 / RATIO ** 2)
    np.testing.assert_allclose(r.outputs["speed:rotor"][-1], speed + alpha * r.time_s[-1], rtol=1e-9)


def test_recorded_generator_torque_with_gearbox_friction(tmp_path):
    # the nonlinear path (gearbox efficiency): the rotor must supply T_gen / (RATIO eta), as the
    # constant-law test above, with T_gen read from a CSV table
    eta, Tg, w0, t_end = 0.95, 300.0, 10.0, 0.2
    (tmp_path / "gen.csv").write_text(f"time,GenTq_Nm\n0,{Tg}\n1,{Tg}\n", encoding="utf-8")
    J_eq = 50.0 + J1 + J2 / RATIO ** 2
    d = _quill_pair({"speed": w0, "loads": [{"body": "hub", "value": Tg / (RATIO * eta)}],
                     "generator": {"law": "table", "table": "gen.csv", "column": "GenTq_Nm"},
                     "gearbox_efficiency": eta})
    d["bodies"] = [{k: v for k, v in b.items() if v is not None} for b in d["bodies"]]
    r = simulate(scene_from_dict(d), t_end, 1e-4, ["speed:hub", "torque:lss"], base_dir=tmp_path)
    missing = Tg * (1 / eta - 1) / RATIO / J_eq * t_end
    assert abs(r.outputs["speed:hub"][-1] - w0) < 1e-2 * missing
    np.testing.assert_allclose(r.outputs["torque:lss"].mean(), Tg / (RATIO * eta), rtol=1e-3)


def test_run_longer_than_the_file_warns(tmp_path):
    # rows 0 .. 0.005 s, a run to 0.01 s: the last row is held for the second half, and said so
    T = 1200.0
    name = _gentq_file(tmp_path, 1.2, name="run.out", t_end=0.005)
    s = scene_from_dict(pair({"speed": 10.0, "loads": [{"body": "rotor", "openfast": name, "column": "RotTorq"}],
                              "generator": {"torque": T * RATIO}}))
    r = simulate(s, 0.01, 1e-4, ["force:m"], base_dir=tmp_path)
    assert ("simulation.loads[0] (run.out, channel RotTorq): the run (0 to 0.01 s) leaves the data's time range "
            "(0 to 0.005 s of run time); its last value is held from 0.005 to 0.01 s") in r.warnings
    np.testing.assert_allclose(r.outputs["force:m"], T / R1, rtol=1e-9)


def test_run_beyond_the_files_time_range_warns(tmp_path, caplog):
    # rows at file time 0 .. 1 s; time_offset 0.995 puts them at run time -0.995 .. 0.005 s
    T = 1200.0
    name = _gentq_file(tmp_path, T * RATIO / 1e3)
    s = scene_from_dict(pair({"speed": 10.0, "loads": [{"body": "rotor", "value": T}],
                              "generator": {"law": "table", "openfast": name, "column": "GenTq",
                                            "time_offset": 0.995}}))
    with caplog.at_level("WARNING"):
        r = simulate(s, 0.01, 1e-4, ["force:m"], base_dir=tmp_path)
    want = ("simulation.generator (gen.outb, channel GenTq, time_offset 0.995 s): the run (0 to 0.01 s) leaves the "
            "data's time range (-0.995 to 0.005 s of run time); its last value is held from 0.005 to 0.01 s")
    assert [w for w in r.warnings if "time range" in w] == [want]
    assert want in caplog.text
    np.testing.assert_allclose(r.outputs["force:m"], T / R1, rtol=1e-9)    # the held value is the same


@pytest.mark.parametrize("column, kind, words", [
    ("GenPwr", "torque", "simulation.loads[0].column = 'GenPwr': unit (kW) is a power, not a torque"),
    ("RotSpeed", "torque", "simulation.loads[0].column = 'RotSpeed': unit (rpm) is an angular speed, not a torque"),
    ("Time", "moment", "simulation.loads[0].column = 'Time': unit (s) is a time, not a torque"),
    ("RotTorq", "force", "simulation.loads[0].column = 'RotTorq': unit (kN-m) is a torque, not a force")])
def test_openfast_channel_of_another_kind_is_refused_in_a_run(tmp_path, column, kind, words):
    name = _gentq_file(tmp_path, 1.0, name="run.out")
    s = scene_from_dict(pair({"speed": 1.0, "loads": [{"body": "rotor", "openfast": name, "column": column,
                                                       "kind": kind, "direction": [1.0, 0.0, 0.0]}]}))
    with pytest.raises(SceneError) as e:
        simulate(s, 0.001, 1e-4, ["force:m"], base_dir=tmp_path)
    assert str(e.value) == words


FILE_BAD = [
    ({"generator": {"law": "table", "openfast": "gen.outb", "column": "GenTq", "torque": 5.0}},
     "simulation.generator.torque = 5.0: not used by law = 'table'"),
    ({"generator": {"law": "table"}}, "simulation.generator.openfast = None: missing"),
    ({"generator": {"torque": 5.0, "openfast": "gen.outb"}}, "simulation.generator.openfast = 'gen.outb': not used "
                                                             "by law = 'constant'"),
    ({"generator": {"law": "table", "openfast": "gen.outb", "column": "GenPwr"}},
     "simulation.generator.column = 'GenPwr': unit (kW) is a power, not a torque"),
    ({"loads": [{"body": "rotor", "value": 1.0, "time_offset": 2.0}]}, "simulation.loads[0].time_offset = 2.0"),
    ({"loads": [{"body": "rotor", "openfast": "gen.outb", "column": "GenTq", "time_window": [0.5]}]},
     "simulation.loads[0].time_window = [0.5]: must have exactly 2 entries"),
    ({"loads": [{"body": "rotor", "openfast": "gen.outb", "column": "GenTq", "time_window": [0.5, 3.0]}]},
     "simulation.loads[0].time_window = [0.5, 3.0]: reaches beyond the file's rows, which run from 0 to 1 s"),
]


@pytest.mark.parametrize("sim, words", FILE_BAD, ids=[w.split(":")[0] for _, w in FILE_BAD])
def test_bad_file_history_keys_name_the_field(tmp_path, sim, words):
    _gentq_file(tmp_path, 1.0)
    with pytest.raises(SceneError) as e:
        simulate(scene_from_dict(pair({"speed": 1.0, **sim})), 0.001, 1e-4, ["force:m"], base_dir=tmp_path)
    assert str(e.value).startswith(words), str(e.value)
