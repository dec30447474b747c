"""General static loads: point forces and moments at any body point or flexible interface,
per-case supports of chosen DOFs, their reactions and the equilibrium check -- against
rigid-body statics (lever rule, spring deflections) and beam theory."""
import dataclasses
import math
import tomllib

import numpy as np
import pytest

from assembly import Bearing, Body, FlexOptions, LoadCase, PointLoad, Scene, Support, load_scene
from assembly.analysis.reactions import static_report
from assembly.analysis.static import solve_static, solve_static_cases
from assembly.errors import MechanismError, SceneError
from assembly.mechanics.kinematics import unit
from assembly.scene.save import scene_to_toml
from assembly.scene.schema import scene_from_dict, shipped_scenes
from fe_components.material import STEEL
from fe_components.params import CylinderParams

K, KA = 1.0e8, 2.0e8            # N/m: radial and axial stiffness of each bearing (no tilt, no torsion)
A, B = 0.10, 0.20               # m: bearing A at -A, bearing B at +B along the axis (asymmetric)
F = 1000.0                      # N


def shaft(forces, supports=(Support(body="shaft", dofs=("rz",)),), axis=(0.0, 0.0, 1.0)):
    """A rigid shaft on two radial/axial spring bearings (no tilt stiffness: statically
    determinate), free to turn unless a support holds it."""
    e = unit(axis)
    lc = LoadCase(name="case", forces=tuple(forces), supports=tuple(supports))
    return Scene(name="shaft", bodies=(Body(name="shaft", mass=5.0, polar_inertia=1e-3, axis=tuple(e)),),
                 bearings=tuple(Bearing(body="shaft", name=n, position=tuple(s * e), k_radial=K, k_axial=KA,
                                        k_tilt=0.0) for n, s in (("A", -A), ("B", B))),
                 load=lc)


def solved(sc):
    st = solve_static(sc, sc.load)
    return st, static_report(st)


def test_radial_force_between_bearings_lever_rule_and_deflection():
    # Free body of the shaft (bearings at z = -A and +B, span L = A + B, force F along x at
    # z = c): moments about each bearing give the lever rule R_A = -F (B - c) / L,
    # R_B = -F (A + c) / L (force each bearing exerts on the shaft). Each bearing deflects
    # by -R / K, and the shaft is straight between them, so at the load point
    # u(c) = F ((B - c)^2 + (A + c)^2) / (K L^2).
    c, L = 0.05, A + B
    st, r = solved(shaft([PointLoad(body="shaft", point=(0.0, 0.0, c), force=(F, 0.0, 0.0))]))
    ra, rb = r.bearings
    assert ra["Fx_N"] == pytest.approx(-F * (B - c) / L, rel=1e-12)
    assert rb["Fx_N"] == pytest.approx(-F * (A + c) / L, rel=1e-12)
    for row in (ra, rb):
        assert row["Fy_N"] == pytest.approx(0.0, abs=1e-9 * F) and row["Fz_N"] == pytest.approx(0.0, abs=1e-9 * F)
    bm = st.model.bodies["shaft"]
    u = bm.motion_at((0.0, 0.0, c)) @ st.body_dofs("shaft")
    assert u[0] == pytest.approx(F * ((B - c) ** 2 + (A + c) ** 2) / (K * L * L), rel=1e-12)
    assert r.supports[0]["Mz_Nm"] == pytest.approx(0.0, abs=1e-9 * F * L)   # a radial force through the axis
    assert r.equilibrium["relative_error"] < 1e-12
    assert r.torque_Nm is None and r.balance == {} and r.ratio == {}


def test_support_of_chosen_dofs_takes_exactly_those_directions():
    # Force (0, Fy, Fz) at radius r0 off the axis, z = c; the support holds z and rz only.
    # Held axially, the bearings' axial springs do not deflect: the support takes -Fz. It
    # takes the torque of Fy about the axis, -r0 Fy. The moment of Fz about y (-r0 Fz) is a
    # couple of the radial bearing forces along x: R_Ax = -r0 Fz / L = -R_Bx; Fy goes by the
    # lever rule as in the test above.
    r0, c, L, fy, fz = 0.03, -0.04, A + B, 400.0, 700.0
    sc = shaft([PointLoad(body="shaft", point=(r0, 0.0, c), force=(0.0, fy, fz))],
               supports=[Support(body="shaft", dofs=("z", "rz"))])
    st, r = solved(sc)
    (sup,) = r.supports
    assert sup["Fz_N"] == pytest.approx(-fz, rel=1e-12)
    assert sup["Mz_Nm"] == pytest.approx(-r0 * fy, rel=1e-12)
    assert sup["Fx_N"] == sup["Fy_N"] == sup["Mx_Nm"] == sup["My_Nm"] == 0.0      # not held: no reaction
    ra, rb = r.bearings
    assert ra["Fz_N"] == pytest.approx(0.0, abs=1e-9 * fz) and rb["Fz_N"] == pytest.approx(0.0, abs=1e-9 * fz)
    assert ra["Fx_N"] == pytest.approx(-r0 * fz / L, rel=1e-12) and rb["Fx_N"] == pytest.approx(r0 * fz / L, rel=1e-12)
    assert ra["Fy_N"] == pytest.approx(-fy * (B - c) / L, rel=1e-12)
    assert rb["Fy_N"] == pytest.approx(-fy * (A + c) / L, rel=1e-12)
    q = dict(zip(st.model.dof_names, st.q))
    assert q["shaft.z"] == 0.0 and q["shaft.rz"] == 0.0
    assert r.equilibrium["relative_error"] < 1e-12


@pytest.mark.parametrize("axis, axes, moment", [
    ((0.0, 0.0, 1.0), "global", (0.0, 1.0, 0.0)),        # body axes = global axes
    ((1.0, 0.0, 0.0), "body", (0.0, 1.0, 0.0)),          # shaft along x, moment given about its local y
    ((1.0, 0.0, 0.0), "global", (0.0, 0.0, 1.0)),        # the same moment in global axes (local y = global z)
])
def test_moment_load_tilts_the_shaft_by_two_M_over_k_L_squared(axis, axes, moment):
    # A pure moment M about the shaft's local y: the bearings form a couple, R_A = M / L,
    # R_B = -M / L along local x (moments about either bearing), deflecting by -R / K, so the
    # tilt is (u_B - u_A) / L = 2 M / (K L^2) whatever the orientation of the shaft.
    M, L = 50.0, A + B
    st, r = solved(shaft([PointLoad(body="shaft", moment=tuple(M * np.array(moment)), axes=axes)], axis=axis))
    q = dict(zip(st.model.dof_names, st.q))
    assert q["shaft.ry"] == pytest.approx(2 * M / (K * L * L), rel=1e-12)
    ra, rb = r.bearings
    assert ra["Fx_N"] == pytest.approx(M / L, rel=1e-12) and rb["Fx_N"] == pytest.approx(-M / L, rel=1e-12)
    assert r.equilibrium["relative_error"] < 1e-12


# ---------------------------------------------------------------- flexible cantilever
LB, DB = 0.5, 0.05           # m: the fe_components validation cylinder, L/D = 10, mesh 12.5 mm


@pytest.fixture(scope="module")
def cantilever():
    """The cylinder clamped at end_a (a support on its rigid end face) with tip loads at end_b:
    a force, a bending moment and a torque, three cases on one factorisation."""
    clamp = (Support(body="beam", interface="end_a"),)
    tip = dict(body="beam", interface="end_b")
    cases = (LoadCase(name="force", forces=(PointLoad(**tip, force=(F, 0.0, 0.0)),), supports=clamp),
             LoadCase(name="moment", forces=(PointLoad(**tip, moment=(0.0, 100.0, 0.0)),), supports=clamp),
             LoadCase(name="torque", forces=(PointLoad(**tip, moment=(0.0, 0.0, 100.0)),), supports=clamp))
    sc = Scene(name="cantilever", loads=cases,
               bodies=(Body(name="beam", component=CylinderParams(length=LB, diameter=DB), fidelity="flexible",
                            flex=FlexOptions(mesh_size=0.0125, couplings={"end_a": "rbe2", "end_b": "rbe2"})),),
               bearings=(Bearing(body="beam", interface="end_a", k_radial=0.0, k_axial=0.0, k_tilt=0.0),))
    res = solve_static_cases(sc)
    return {st.load.name: st for st in res}


def _tip(st):
    return st.body_dofs("beam")[st.model.bodies["beam"].masters["end_b"][1]]


def test_cantilever_tip_force_and_moment_against_beam_theory(cantilever):
    # Timoshenko cantilever: tip deflection F L^3 / (3 E I) + F L / (kappa G A), with the
    # shear coefficient of a solid circle kappa = 6 (1 + nu) / (7 + 6 nu) (Cowper 1966,
    # J. Appl. Mech. 33); a tip moment M turns the tip by M L / (E I). Tolerance 1 %: the
    # rigid (RBE2) end faces also stop the Poisson contraction and warping of the root
    # section, a stiffening confined to about one diameter (D / L = 0.1), and P2 tetrahedra
    # at four elements per diameter -- the same mesh as the 1 % free-free bending frequency
    # check of the validation cylinder (tests/fe_components/test_fe_validation.py).
    E, G, nu = STEEL.E, STEEL.G, STEEL.nu
    I, area = math.pi * DB ** 4 / 64, math.pi * DB ** 2 / 4
    kappa = 6 * (1 + nu) / (7 + 6 * nu)
    assert _tip(cantilever["force"])[0] == pytest.approx(F * LB ** 3 / (3 * E * I) + F * LB / (kappa * G * area),
                                                         rel=0.01)
    assert _tip(cantilever["moment"])[4] == pytest.approx(100.0 * LB / (E * I), rel=0.01)
    # and the clamp reacts the tip load exactly: -F and the root moment -F L (statics)
    (sup,) = static_report(cantilever["force"]).supports
    assert sup["Fx_N"] == pytest.approx(-F, rel=1e-10) and sup["My_Nm"] == pytest.approx(-F * LB, rel=1e-10)


def test_cantilever_torque_against_saint_venant(cantilever):
    # A circular shaft twists without warping: theta = T L / (G J), J = pi D^4 / 32, exact
    # in elasticity even with rigid end faces; 1e-3 is the P2 discretisation (torsion
    # frequency of the same mesh: within 1 %, test_fe_validation).
    J = math.pi * DB ** 4 / 32
    assert _tip(cantilever["torque"])[5] == pytest.approx(100.0 * LB / (STEEL.G * J), rel=1e-3)
    (sup,) = static_report(cantilever["torque"]).supports
    assert sup["Mz_Nm"] == pytest.approx(-100.0, rel=1e-10)


def test_cantilever_reactions_balance(cantilever):
    for st in cantilever.values():
        assert static_report(st).equilibrium["relative_error"] < 1e-9, st.load.name


# ---------------------------------------------------------------- every shipped scene
@pytest.mark.parametrize("path", [p for p in shipped_scenes() if load_scene(p).load_cases()], ids=lambda p: p.name)
def test_shipped_scene_cases_are_in_equilibrium(path):
    # Sum of applied loads and every reaction from the housing is zero (statics), force and
    # moment, to the round-off of the solve (documented check: relative 1e-9).
    for st in solve_static_cases(load_scene(path)):
        r = static_report(st)
        assert r.equilibrium["relative_error"] < 1e-9, st.path
        if st.load.torque is not None:             # the torque balance of a torque case
            assert r.balance["relative_error"] < 1e-9, st.path


def test_torque_case_with_point_load_and_support_on_a_flexible_body():
    # The HS stage's rated torque plus a radial force at the flexible pinion's gear and a
    # support clamping the output shaft axially: statics closes, and the ratio check (valid
    # for a torque alone) says it does not apply.
    sc = load_scene("hs_parallel_stage.toml")
    lc = dataclasses.replace(sc.load, forces=(PointLoad(body="pinion", interface="gear_mesh", force=(0.0, 500.0, 0.0)),),
                             supports=(Support(body="output_shaft", dofs=("z",)),))
    st = solve_static(sc, lc)
    r = static_report(st)
    assert r.equilibrium["relative_error"] < 1e-9 and r.balance["relative_error"] < 1e-9
    assert r.ratio["relative_error"] is None and "not applicable" in r.ratio["note"]
    assert r.supports[0]["dofs"] == ["z"]


# ---------------------------------------------------------------- TOML and bad input
TOML = """
name = "shaft"
[[bodies]]
name = "shaft"
mass = 5.0
polar_inertia = 1e-3
[[bearings]]
body = "shaft"
position = [0.0, 0.0, -0.1]
k_radial = 1e8
k_axial = 2e8
k_tilt = 0.0
[[bearings]]
body = "shaft"
position = [0.0, 0.0, 0.2]
k_radial = 1e8
k_axial = 2e8
k_tilt = 0.0
[[loads]]
name = "radial"
[[loads.forces]]
body = "shaft"
point = [0.0, 0.0, 0.05]
force = [1000.0, 0.0, 0.0]
[[loads.forces]]
body = "shaft"
moment = [0.0, 5.0, 0.0]
axes = "body"
[[loads.supports]]
body = "shaft"
dofs = ["rz"]
"""


def test_toml_forces_and_supports_read_and_round_trip():
    sc = scene_from_dict(tomllib.loads(TOML))
    (lc,) = sc.loads
    assert lc.forces[0] == PointLoad(body="shaft", point=(0.0, 0.0, 0.05), force=(F, 0.0, 0.0))
    assert lc.forces[1].axes == "body" and lc.supports == (Support(body="shaft", dofs=("rz",)),)
    assert lc.input is None and lc.torque is None
    assert scene_from_dict(tomllib.loads(scene_to_toml(sc))) == sc


GOOD = PointLoad(body="shaft", force=(F, 0.0, 0.0))


@pytest.mark.parametrize("case, path", [
    (dict(forces=(dataclasses.replace(GOOD, body="nothing"),)), r"load\.forces\[0\]\.body = 'nothing': no body"),
    (dict(supports=(Support(body="nothing"),)), r"load\.supports\[0\]\.body = 'nothing': no body"),
    (dict(forces=(dataclasses.replace(GOOD, interface="bore"),)), r"load\.forces\[0\]\.interface = 'bore': .*no component"),
    (dict(supports=(Support(body="shaft", interface="end_a"),)), r"load\.supports\[0\]\.interface = 'end_a'"),
    (dict(forces=(dataclasses.replace(GOOD, interface="bore", point=(0.0, 0.0, 0.0)),)),
     r"load\.forces\[0\]\.point = \[0\.0, 0\.0, 0\.0\]: give either point or interface"),
    (dict(forces=(PointLoad(body="shaft"),)), r"load\.forces\[0\]\.force = \[0\.0, 0\.0, 0\.0\]: force and moment"),
    (dict(forces=()), r"load\.forces = \[\]: the case applies nothing"),
    (dict(supports=(Support(body="shaft", dofs=("rz", "w")),)), r"load\.supports\[0\]\.dofs\[1\] = 'w'"),
    (dict(supports=(Support(body="shaft", dofs=("rz", "rz")),)), r"load\.supports\[0\]\.dofs\[1\] = 'rz': given twice"),
    (dict(supports=(Support(body="shaft", dofs=()),)), r"load\.supports\[0\]\.dofs = \[\]"),
    (dict(input="shaft"), r"load\.output = None: a torque case needs input, output and torque"),
    (dict(torque=10.0), r"load\.input = None: a torque case needs"),
    (dict(input_interface="bore"), r"load\.input_interface = 'bore': no input body"),
    (dict(forces=(dataclasses.replace(GOOD, axes="local"),)), r"load\.forces\[0\]\.axes = 'local'"),
])
def test_bad_load_input_is_refused_naming_the_field(case, path):
    sc = shaft([GOOD])
    with pytest.raises(SceneError, match=path):
        dataclasses.replace(sc, load=dataclasses.replace(sc.load, **case))


def test_component_body_needs_an_interface_not_a_point():
    for pl, msg in ((PointLoad(body="pinion", force=(F, 0.0, 0.0)), r"forces\[0\]\.interface = None: pinion is a component"),
                    (PointLoad(body="pinion", point=(0.0, 0.0, 0.0), force=(F, 0.0, 0.0)),
                     r"forces\[0\]\.point = \[0\.0, 0\.0, 0\.0\]: pinion is a component")):
        sc = load_scene("hs_parallel_stage.toml")
        with pytest.raises(SceneError, match=msg):
            dataclasses.replace(sc, load=dataclasses.replace(sc.load, forces=(pl,)))


def test_a_case_that_leaves_a_mechanism_is_refused_before_solving():
    # no support: the shaft's bearings have no torsion stiffness, so it turns freely
    sc = shaft([GOOD], supports=())
    with pytest.raises(MechanismError, match=r"load \('case'\): with nothing held .*shaft\.rz"):
        solve_static(sc, sc.load)


def test_holding_a_direction_twice_is_refused():
    # two supports on one rigid body both holding its rotation about the axis: dependent holds
    sc = shaft([GOOD], supports=(Support(body="shaft", dofs=("rz",)), Support(body="shaft", dofs=("z", "rz"))))
    with pytest.raises(SceneError, match=r"load\.supports\[1\]\.dofs = 'rz': holds a direction"):
        solve_static(sc, sc.load)
