"""Static load cases: mesh forces, bearing reactions, output torque and checks against
statics of rigid gears (free-body equilibrium), at every fidelity."""
import dataclasses
import math

import numpy as np
import pytest

from assembly import Bearing, Body, GearMesh, LoadCase, Scene, load_scene, with_fidelity
from assembly.analysis.reactions import static_report
from assembly.analysis.static import solve_static, solve_static_cases
from assembly.errors import MechanismError, SceneError

R_B, ALPHA = 0.05, math.radians(20.0)   # Peeters et al. (2006) test pair: r_b 50 mm, 20 deg
T = 100.0                               # N m


def pair(fidelity="rigid", beta=0.0, **load):
    """The README's spur/helical pair (Peeters et al. 2006 data) with a torque into the pinion."""
    return Scene(
        name="pair",
        bodies=(Body(name="pinion", mass=2.0, polar_inertia=2.9e-3, fidelity=fidelity),
                Body(name="wheel", mass=2.0, polar_inertia=2.9e-3, fidelity=fidelity,
                     position=(2 * R_B / math.cos(ALPHA), 0.0, 0.0))),
        bearings=tuple(Bearing(body=b, k_radial=3.5e8, k_axial=1.0e8, k_tilt=2.775e5) for b in ("pinion", "wheel")),
        meshes=(GearMesh(gear1="pinion", gear2="wheel", stiffness=2.0e8, base_radius1=R_B, base_radius2=R_B,
                         pressure_angle=ALPHA, helix_angle=beta),),
        load=LoadCase(**{"input": "pinion", "output": "wheel", "torque": T, **load}))


def report(scene, load=None):
    return static_report(solve_static(scene, load or scene.load))


def test_spur_pair_mesh_force_is_torque_over_base_radius_and_bearings_carry_it():
    # Free body of the pinion: T = F r_b (the mesh force's arm about the axis is the base
    # radius); the bearing alone balances the mesh force (Peeters et al. 2006 geometry).
    r = report(pair())
    (m,) = r.meshes
    assert m["force_N"] == pytest.approx(T / R_B, rel=1e-12)
    assert m["drive_flank"] and m["axial_N"] == pytest.approx(0.0, abs=1e-9)
    F = np.array(m["force_on_gear2_N"])
    # line of action: sin(alpha) along the centre line (separating), cos(alpha) across it
    np.testing.assert_allclose(np.abs(F), T / R_B * np.array([math.sin(ALPHA), math.cos(ALPHA), 0.0]), rtol=1e-12)
    pin, whl = r.bearings
    np.testing.assert_allclose([pin["Fx_N"], pin["Fy_N"], pin["Fz_N"]], F, rtol=1e-12, atol=1e-9)   # pushed back
    np.testing.assert_allclose([whl["Fx_N"], whl["Fy_N"], whl["Fz_N"]], -F, rtol=1e-12, atol=1e-9)
    # equal gears: the output is held with T (speed ratio -1); the offset bearing forces
    # take the rest: T_in + T_out + F_radial x centre distance = 0
    assert r.output_torque_Nm == pytest.approx(T, rel=1e-12)
    assert r.balance["housing_Nm"] == pytest.approx(-2 * T, rel=1e-12)
    assert r.balance["relative_error"] < 1e-12
    assert r.ratio["speed_ratio"] == pytest.approx(-1.0, rel=1e-12)
    assert r.ratio["relative_error"] < 1e-12


def test_helical_pair_axial_force_is_transverse_force_times_tan_beta():
    # Kahraman (1994), helical mesh along the base helix: F_axial = F_bt tan(beta_b), F_bt = T / r_b
    # (the kahraman_beta20 scene, 20 deg helix).
    sc = load_scene("kahraman_beta20.toml")
    lc = LoadCase(input=sc.meshes[0].gear1, output=sc.meshes[0].gear2, torque=T)
    r = report(sc, lc)
    (m,) = r.meshes
    rb, beta = sc.meshes[0].base_radius1, sc.meshes[0].helix_angle
    assert m["transverse_N"] == pytest.approx(T / rb, rel=1e-12)
    assert abs(m["axial_N"]) == pytest.approx(T / rb * math.tan(beta), rel=1e-12)
    assert m["force_N"] == pytest.approx(T / (rb * math.cos(beta)), rel=1e-12)
    assert r.ratio["relative_error"] < 1e-12 and r.balance["relative_error"] < 1e-12


@pytest.fixture(scope="module")
def fixed_ring_stage():
    """Lin & Parker (1999) N = 3 stage, ring fixed, torque into the sun, carrier held."""
    sc = load_scene("lin_parker_n3.toml")
    st = sc.stages[0]
    st = dataclasses.replace(st, ring=dataclasses.replace(st.ring, support="fixed", bearing=None))
    return dataclasses.replace(sc, stages=(st,), load=LoadCase(input="stage.sun", output="stage.carrier", torque=T))


@pytest.mark.parametrize("fidelity", ["torsional", "rigid"])
def test_planetary_fixed_ring_equal_sharing_and_carrier_torque(fixed_ring_stage, fidelity):
    # Equally spaced planets share equally (symmetry): sun-planet force T_s / (N r_s);
    # planet free body: ring-planet force = sun-planet force; carrier torque from the
    # kinematics of a fixed-ring stage: T_c = T_s (1 + r_r / r_s) (base radii, same pressure angle)
    sc = with_fidelity(fixed_ring_stage, fidelity)
    st = sc.stages[0]
    r_s, r_r, n = st.sun.base_radius, st.ring.base_radius, st.planets.count
    r = report(sc)
    forces = [m["force_N"] for m in r.meshes]
    np.testing.assert_allclose(forces, T / (n * r_s), rtol=1e-12)
    assert r.output_torque_Nm == pytest.approx(-T * (1 + r_r / r_s), rel=1e-12)
    assert r.ratio["speed_ratio"] == pytest.approx(1 + r_r / r_s, rel=1e-12)
    ring = [c for c in r.constraints if c["body"] == "stage.ring" and c["dof"] == "rz"]
    assert ring[0]["value"] == pytest.approx(T * r_r / r_s, rel=1e-12) and ring[0]["source"] == "fixed"
    assert r.balance["relative_error"] < 1e-12


def test_fidelities_give_the_same_mesh_forces_hs_stage():
    # The input body's free body about its axis holds only the mesh force (bearings carry no
    # torsion), so F = T / (r_b cos beta) at every fidelity: agreement to the solve's
    # round-off, bounded by cond(K) eps ~ 1e-10 here.
    sc = load_scene("hs_parallel_stage.toml")
    m0 = sc.meshes[0]
    expect = sc.load.torque / (m0.base_radius1 * math.cos(m0.helix_angle))
    for fid in ("torsional", "rigid", "flexible"):
        r = report(sc if fid == "flexible" else with_fidelity(sc, fid))
        assert r.meshes[0]["force_N"] == pytest.approx(expect, rel=1e-10), fid
        assert r.shafts[0]["torque_Nm"] == pytest.approx(-r.output_torque_Nm, rel=1e-10), fid
        assert r.balance["relative_error"] < 1e-10 and r.ratio["relative_error"] < 1e-10, fid


def test_fidelities_give_the_same_mesh_forces_flexible_carrier():
    # Carrier input, sun held: sum of sun-planet forces x r_s = sun torque exactly at every
    # fidelity; each planet's share is 1/N by symmetry at torsional/rigid fidelity, and the
    # flexible carrier's mesh is not exactly 3-fold symmetric (measured spread 1.2e-5), so
    # its shares agree to 1e-4.
    sc = load_scene("planetary_flexible_carrier.toml")
    r_s, n = sc.stages[0].sun.base_radius, sc.stages[0].planets.count
    ref = None
    for fid in ("torsional", "rigid", "flexible"):
        r = report(sc if fid == "flexible" else with_fidelity(sc, fid))
        sun = [m["force_N"] for m in r.meshes if m["gear1"] == "stage.sun"]
        assert sum(sun) * r_s == pytest.approx(r.output_torque_Nm, rel=1e-10), fid
        ref = ref or sun
        np.testing.assert_allclose(sun, ref, rtol=1e-4 if fid == "flexible" else 1e-10)
        assert r.balance["relative_error"] < 1e-10 and r.ratio["relative_error"] < 1e-10, fid


def test_flexible_body_as_the_reacting_body():
    # Reversed power flow in the HS stage: torque into the rigid output shaft, the flexible
    # pinion held at its coupling seat. Pinion free body: F r_b1 cos(beta) = -T_out; ratio
    # from the teeth: T_out / T_in = -omega_in / omega_out = r_b1 / r_b2 (external pair).
    sc = load_scene("hs_parallel_stage.toml")
    m0 = sc.meshes[0]
    lc = LoadCase(input="output_shaft", output="pinion", output_interface="bearing_a", torque=1000.0)
    sc2 = dataclasses.replace(sc, load=lc)
    r = report(sc2)
    assert r.output_torque_Nm == pytest.approx(1000.0 * m0.base_radius1 / m0.base_radius2, rel=1e-10)
    assert abs(r.meshes[0]["force_N"]) * m0.base_radius1 * math.cos(m0.helix_angle) == pytest.approx(
        abs(r.output_torque_Nm), rel=1e-10)
    assert r.balance["relative_error"] < 1e-10 and r.ratio["relative_error"] < 1e-10


def test_several_load_cases_share_one_model_and_scale_linearly():
    sc = dataclasses.replace(pair(), load=None, loads=(LoadCase(input="pinion", output="wheel", torque=T, name="a"),
                                                       LoadCase(input="pinion", output="wheel", torque=-3 * T,
                                                                name="b")))
    a, b = solve_static_cases(sc)
    assert a.model is b.model and (a.path, b.path) == ("loads[0]", "loads[1]")
    np.testing.assert_allclose(b.z, -3 * a.z, rtol=1e-12, atol=1e-18)   # linear statics
    assert not static_report(b).meshes[0]["drive_flank"]


def test_held_assembly_that_still_moves_is_refused():
    # a wheel that meshes with nothing else: holding the pinion's mate leaves nothing free,
    # but a third, unconnected gear on a torsion-free bearing turns freely
    sc = pair()
    third = Body(name="idler", mass=1.0, polar_inertia=1e-3, position=(0.0, 0.5, 0.0))
    sc3 = Scene(name="free", bodies=sc.bodies + (third,),
                bearings=sc.bearings + (Bearing(body="idler", k_radial=1e8, k_axial=1e8, k_tilt=1e5),),
                meshes=sc.meshes, load=sc.load)
    with pytest.raises(MechanismError, match=r"load .*idler\.rz"):
        solve_static(sc3, sc3.load)


@pytest.mark.parametrize("change, path", [
    (dict(output="nothing"), r"loads\[1\]\.output = 'nothing'"),
    (dict(input="nothing"), r"loads\[1\]\.input = 'nothing'"),
    (dict(output="pinion"), r"loads\[1\]\.output = 'pinion': input and output must differ"),
    (dict(torque=0.0), r"loads\[1\]\.torque = 0\.0"),
    (dict(output_interface="bore"), r"loads\[1\]\.output_interface = 'bore'"),
    (dict(name="a"), r"loads\[1\]\.name = 'a': duplicate"),
])
def test_load_case_refusals_name_the_field(change, path):
    good = LoadCase(input="pinion", output="wheel", torque=T, name="a")
    bad = dataclasses.replace(good, **{"name": "b", **change})
    with pytest.raises(SceneError, match=path):
        dataclasses.replace(pair(), load=None, loads=(good, bad))


def test_load_and_loads_together_are_refused():
    sc = pair()
    with pytest.raises(SceneError, match=r"^loads = \['b'\]: give either"):
        dataclasses.replace(sc, loads=(dataclasses.replace(sc.load, name="b"),))


def test_interface_not_on_the_flexible_output_is_refused():
    sc = load_scene("hs_parallel_stage.toml")
    for iface, msg in ((None, r"load\.output_interface = None: pinion is a component"),
                       ("nowhere", r"load\.output_interface = 'nowhere': no such interface")):
        lc = LoadCase(input="output_shaft", output="pinion", output_interface=iface, torque=1.0)
        with pytest.raises(SceneError, match=msg):
            dataclasses.replace(sc, load=lc)
