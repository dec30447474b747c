"""Direction of a helical mesh's axial force and of each bearing's thrust, for both helix
hands, both senses of the driving torque, external and internal pairs, both contact-point
conventions, against the flank geometry.

Expected direction, from the tooth flank (as in any machine-design text: Budynas & Nisbett,
Shigley's Mechanical Engineering Design, ch. 13, force analysis of helical gears; Niemann &
Winter, Maschinenelemente II, forces on helical spur gears -- the thrust on a driver follows
the right-hand rule for a right-hand driver, the left-hand rule for a left-hand one):

A flank of a helical gear of hand h (+1 right, -1 left; right = the tooth at height z is
turned by +z tan(beta) / r_p about +z, fe_components.params.GearTeeth) is the surface
theta = s f(r) + h z tan|beta| / r_p; s = +1 for the flank facing +theta. Its outward
normal is along s grad(theta - h z tan|beta| / r_p - s f(r)), whose tangential and axial
parts at the pitch radius are s / r_p and -s h tan|beta| / r_p. The mating flank pushes on
it with F_c = -F n_out (F > 0, contact): tangential -s F, axial +s h F tan|beta|. The
moment of F_c about the gear's axis is M = -s F r_p, so s = -sign(M) and

    F_axial = -h M tan|beta| / r_p           (M: moment of the mesh force on this gear)

for every gear of a pair, external or internal (only its own flank entered). The axial
part is the same at any radius of the helicoid: tan(beta_r) / r is constant (constant
lead), so r_p is the reference pitch radius and F_axial = -h M tan|beta_b| / r_b alike.
A driver held by a torque T about +z has M = -T: F_axial = h T tan|beta| / r_p, the hand
rule above (right-hand driver, torque along +z: thrust on the driver along +z). A bearing
that holds the gear axially reacts with -F_axial (docs/static.md: a bearing's reaction
is the force it exerts on its body).
"""
from __future__ import annotations

import math

import pytest

from assembly.analysis.reactions import static_report
from assembly.analysis.static import solve_static
from assembly.scene.schema import scene_from_dict

M_N, ALPHA_N, BETA, WIDTH = 0.004, 20.0, 15.0, 0.04      # m, deg, deg, m
T = 200.0                                                  # N m, into gear 1


def _body(name, z, hand, internal=False):
    return {"name": name, "mass": 3.0, "polar_inertia": 5e-3, "internal": internal,
            "teeth": {"n_teeth": z, "normal_module": M_N, "pressure_angle_deg": ALPHA_N,
                      "helix_angle_deg": hand * BETA, "face_width": WIDTH}}


def _pair(hand1, sense, internal, contact):
    """Gear 1 (23 teeth, hand ``hand1``) driven by ``sense * T``; gear 2 external (61 teeth,
    opposite hand) or internal (71 teeth, same hand: ISO 21771), held against rotation;
    both on bearings stiff axially, free to turn. The mesh's flank: the one the torque
    loads (``drive_sign = sense``)."""
    hand2 = hand1 if internal else -hand1
    bearing = {"k_radial": 1e9, "k_axial": 2e8, "k_tilt": 1e6}
    return scene_from_dict({
        "name": "helix thrust",
        "bodies": [_body("pinion", 23, hand1), _body("gear", 71 if internal else 61, hand2, internal)],
        "bearings": [{"body": "pinion", **bearing}, {"body": "gear", **bearing}],
        "meshes": [{"gear1": "pinion", "gear2": "gear", "stiffness": 5e8, "place": "gear2",
                    "drive_sign": sense, "contact_point": contact}],
        "load": {"input": "pinion", "output": "gear", "torque": sense * T},
    })


CASES = [(h, s, i, c) for h in (1, -1) for s in (1, -1) for i in (False, True) for c in ("pitch", "tangent")]


@pytest.mark.parametrize("hand1,sense,internal,contact", CASES,
                         ids=[f"{'RH' if h > 0 else 'LH'}-{'pos' if s > 0 else 'neg'}-{'int' if i else 'ext'}-{c}"
                              for h, s, i, c in CASES])
def test_axial_force_and_bearing_thrust_follow_the_flank(hand1, sense, internal, contact):
    sc = _pair(hand1, sense, internal, contact)
    r = static_report(solve_static(sc, sc.load))
    (m,) = r.meshes
    assert m["drive_flank"]                              # the torque loads the flank the scene names
    teeth = sc.bodies[0].teeth
    r_p = teeth.n_teeth * M_N / (2 * math.cos(math.radians(BETA)))      # gear 1's reference pitch radius
    # gear 1 (driver, M = -T): F_axial = h T tan|beta| / r_p (module notes)
    expect_on_1 = hand1 * sense * T * math.tan(math.radians(BETA)) / r_p
    on_gear2 = m["force_on_gear2_N"][2]                  # global z = both gears' axes
    assert on_gear2 == pytest.approx(-expect_on_1, rel=1e-9)          # Newton: gear 2 gets the opposite
    # the gear-2 rule on its own flank gives the same: F_axial,2 = -h2 M2 tan|beta| / r_p2,
    # M2 the mesh's moment on gear 2, which its hold (the output reaction) balances
    hand2 = hand1 if internal else -hand1
    r_p2 = abs(sc.bodies[1].teeth.n_teeth) * M_N / (2 * math.cos(math.radians(BETA)))
    M2 = -r.output_torque_Nm
    assert on_gear2 == pytest.approx(-hand2 * M2 * math.tan(math.radians(BETA)) / r_p2, rel=1e-9)
    # each bearing holds its gear axially against the mesh: thrust = -(axial mesh force on it)
    pin, gear = (next(b for b in r.bearings if b["body"] == name) for name in ("pinion", "gear"))
    assert pin["Fz_N"] == pytest.approx(-expect_on_1, rel=1e-9)
    assert gear["Fz_N"] == pytest.approx(expect_on_1, rel=1e-9)
    # the mesh row's axial component (along gear 1's axis, on gear 2) says the same
    assert m["axial_N"] == pytest.approx(-expect_on_1, rel=1e-9)


def test_right_hand_driver_thrust_by_the_hand_rule():
    """The textbook picture, spelt out: a right-hand pinion driven counter-clockwise seen
    from +z (torque along +z) is pushed along +z by its mate, so its bearing pushes it
    back along -z; a left-hand pinion in the same sense is pushed along -z."""
    for hand1, sign in ((1, 1.0), (-1, -1.0)):
        sc = _pair(hand1, 1, False, "pitch")
        r = static_report(solve_static(sc, sc.load))
        pin = next(b for b in r.bearings if b["body"] == "pinion")
        assert math.copysign(1.0, -pin["Fz_N"]) == sign
