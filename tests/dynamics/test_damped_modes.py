"""Damping in the scene and damped modes (assembly.dynamics).

Closed forms used below:

* single DOF m x'' + c x' + k x = 0: s = -zeta w +- i w sqrt(1 - zeta^2), w = sqrt(k/m),
  zeta = c / (2 sqrt(k m)) (any vibration text, e.g. Inman, Engineering Vibration, ch. 1).
* two inertias J1, J2 joined by a torsional spring k and damper c, free otherwise: with
  relative twist d = th1 - th2, J1 th1'' = -(k d + c d'), J2 th2'' = +(k d + c d'), so
  d'' = -(1/J1 + 1/J2)(k d + c d'): J_eq d'' + c d' + k d = 0, J_eq = J1 J2 / (J1 + J2).
  The elastic root is s = -c/(2 J_eq) + i sqrt(k/J_eq - (c/(2 J_eq))^2); the common
  rotation (d = 0) strains neither spring nor damper: s = 0.
* Rayleigh C = alpha M + beta K: phi_i' C phi_i = alpha + beta w_i^2 = 2 zeta_i w_i, so
  zeta_i = alpha / (2 w_i) + beta w_i / 2.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly import Bearing, Body, Scene, SceneError, Shaft, assemble, solve_modes
from assembly.dynamics.damped_modes import damped_modes
from assembly.model.damping import damping_matrix, has_damping
from assembly.scene.tables import Damping, GearMesh

INF = math.inf
J1, J2, K = 2.0, 3.0, 1.0e4          # kg m^2, kg m^2, N m/rad


def _held(name, pos, J, **bearing):
    """A torsional body on a bearing rigid in every direction but its spin."""
    b = Bearing(body=name, k_radial=INF, k_axial=INF, k_tilt=INF, **bearing)
    return Body(name=name, mass=10.0, polar_inertia=J, position=pos), b


def two_mass(c=0.0, damping=None, ground=None) -> Scene:
    (b1, br1), (b2, br2) = _held("a", (0, 0, 0), J1), _held("b", (0, 0, 1), J2)
    if ground is not None:   # torsional spring k and damper c_torsion of body a to the housing
        br1 = Bearing(body="a", k_radial=INF, k_axial=INF, k_tilt=INF, **ground)
    return Scene(name="two", bodies=(b1, b2), bearings=(br1, br2), damping=damping,
                 shafts=(Shaft(body1="a", body2="b", k_torsion=K, c_torsion=c),))


def _solve(scene):
    res = solve_modes(assemble(scene))
    return res, damped_modes(res)


def test_single_dof_roots():
    m_J, k, c = 2.0, 8.0e3, 12.0
    body, br = _held("a", (0, 0, 0), m_J, k_torsion=k, c_torsion=c)
    res, dm = _solve(Scene(name="one", bodies=(body,), bearings=(br,)))
    w = math.sqrt(k / m_J)
    zeta = c / (2 * math.sqrt(k * m_J))
    want = complex(-zeta * w, w * math.sqrt(1 - zeta ** 2))
    assert abs(dm.s[0] - want) <= 1e-12 * abs(want)
    assert dm.ratios[0] == pytest.approx(zeta, rel=1e-12)
    assert dm.damped_hz[0] == pytest.approx(want.imag / (2 * math.pi), rel=1e-12)
    assert dm.undamped_hz[0] == pytest.approx(w / (2 * math.pi), rel=1e-12)


def test_two_mass_damped_shaft_closed_form():
    c = 30.0
    res, dm = _solve(two_mass(c))
    J = J1 * J2 / (J1 + J2)
    want = complex(-c / (2 * J), math.sqrt(K / J - (c / (2 * J)) ** 2))
    assert res.n_rigid == 1
    assert dm.s[0] == 0.0                      # the common rotation stays undamped
    assert abs(dm.s[1] - want) <= 1e-9 * abs(want)
    assert dm.mac[1] == pytest.approx(1.0, abs=1e-12)


def test_damping_matrix_is_the_shaft_damper():
    # on q = (th_a, th_b): C = c [[1, -1], [-1, 1]], as K = k [[1, -1], [-1, 1]]
    c = 30.0
    model = assemble(two_mass(c))
    C = damping_matrix(model).toarray()
    assert np.allclose(C, c / K * model.K.toarray(), rtol=0, atol=1e-12 * c)
    assert np.array_equal(C, C.T)


def test_damper_without_spring_damps_a_free_rotation():
    # a torsional damper c from body a to the housing, no spring there:
    # det [[J1 s^2 + c s + K, -K], [-K, J2 s^2 + K]] = s (J1 J2 s^3 + c J2 s^2 + K (J1 + J2) s + c K),
    # so a root s = 0 remains (det K = 0), the cubic gives a real decay and a damped pair
    c = 5.0
    res, dm = _solve(two_mass(0.0, ground={"c_torsion": c}))
    assert res.n_rigid == 1                   # a damper is no spring: the structure stays free
    cubic = np.roots([J1 * J2, c * J2, K * (J1 + J2), c * K])
    pair = cubic[np.argmax(cubic.imag)]
    real = cubic[np.argmin(abs(cubic.imag))].real
    assert abs(dm.s[1] - pair) <= 1e-9 * abs(pair)
    assert dm.s[0] == 0.0 or abs(dm.s[0] - real) <= 1e-9 * abs(real)


def test_rayleigh_ratios_and_rigid_mode():
    alpha, beta = 3.0, 2.0e-4
    chain = two_mass(damping=Damping(rayleigh_alpha=alpha, rayleigh_beta=beta))
    res, dm = _solve(chain)
    w = math.sqrt(res.eigenvalues[1])
    assert dm.s[0] == 0.0                     # alpha M projected out: the free spin stays free
    assert dm.ratios[1] == pytest.approx(alpha / (2 * w) + beta * w / 2, rel=1e-12)
    # a grounded three-mode chain: every mode gets its own ratio
    grounded = two_mass(damping=Damping(rayleigh_alpha=alpha, rayleigh_beta=beta), ground={"k_torsion": 2 * K})
    res, dm = _solve(grounded)
    w = np.sqrt(res.eigenvalues)
    assert np.allclose(dm.ratios, alpha / (2 * w) + beta * w / 2, rtol=1e-12, atol=0)


def test_modal_and_class_ratios_land_on_their_modes():
    res, dm = _solve(two_mass(damping=Damping(modal_ratio=0.02)))
    w = math.sqrt(res.eigenvalues[1])
    assert dm.s[0] == 0.0 and dm.ratios[1] == pytest.approx(0.02, rel=1e-14)
    assert dm.damped_hz[1] == pytest.approx(w * math.sqrt(1 - 0.02 ** 2) / (2 * math.pi), rel=1e-14)
    # the two-mass elastic mode is a spin mode: class "rotational"; an unnamed class keeps modal_ratio
    res, dm = _solve(two_mass(damping=Damping(modal_ratio=0.02, class_ratios={"rotational": 0.05})))
    assert dm.ratios[1] == pytest.approx(0.05, rel=1e-14)
    res, dm = _solve(two_mass(damping=Damping(modal_ratio=0.02, class_ratios={"translational": 0.05})))
    assert dm.ratios[1] == pytest.approx(0.02, rel=1e-14)


def test_modal_ratio_with_element_damper_adds_in_modal_coordinates():
    # one elastic mode: 2 zeta w + c / J_eq is its modal damping, ratio zeta + c / (2 J_eq w)
    c, zeta = 30.0, 0.01
    res, dm = _solve(two_mass(c, damping=Damping(modal_ratio=zeta)))
    J = J1 * J2 / (J1 + J2)
    w = math.sqrt(K / J)
    assert dm.ratios[1] == pytest.approx(zeta + c / (2 * J * w), rel=1e-12)


def test_beam_beta_is_stiffness_proportional():
    # C_e = beta K_e for every element of a beam shaft: with the shaft the only spring,
    # C = beta K on q
    bodies = (Body(name="a", mass=10.0, polar_inertia=J1, position=(0, 0, 0)),
              Body(name="b", mass=10.0, polar_inertia=J2, position=(0, 0, 1)))
    bearings = tuple(Bearing(body=n, k_radial=INF, k_axial=INF, k_tilt=INF) for n in ("a", "b"))
    sc = Scene(name="beam", bodies=bodies, bearings=bearings, fidelity="torsional",
               shafts=(Shaft(body1="a", body2="b", diameter=0.05, beta=1e-4),))
    model = assemble(sc)
    assert np.allclose(damping_matrix(model).toarray(), 1e-4 * model.K.toarray(), rtol=1e-14, atol=0)


def test_mesh_damper_along_line_of_action():
    # a spur mesh between gears of base radii r1, r2 held but for their spins: the mesh
    # compression is r1 th1 + r2 th2 (tests/analysis/test_drivetrain.py), so
    # C = c [r1, r2]' [r1, r2] on q, exactly as K = k [r1, r2]' [r1, r2]
    r1, r2, alpha, c, k = 0.2, 0.1, math.radians(20), 50.0, 1e8
    C_d = (r1 + r2) / math.cos(alpha)
    (g1, b1), (g2, b2) = _held("g1", (0, 0, 0), J1), _held("g2", (C_d, 0, 0), J2)
    sc = Scene(name="mesh", bodies=(g1, g2), bearings=(b1, b2),
               meshes=(GearMesh(gear1="g1", gear2="g2", stiffness=k, base_radius1=r1, base_radius2=r2,
                                pressure_angle=alpha, damping=c),))
    model = assemble(sc)
    g = np.array([r1, r2])
    assert np.allclose(damping_matrix(model).toarray(), c * np.outer(g, g), rtol=1e-12, atol=1e-12 * c)


def test_has_damping():
    assert not has_damping(two_mass())
    assert has_damping(two_mass(1.0))
    assert has_damping(two_mass(damping=Damping(rayleigh_beta=1e-5)))
    assert not has_damping(two_mass(damping=Damping(modal_ratio=0.0)))


# ---------------------------------------------------------------- scene tables
# the shipped scene has Nejad's split radial dampers on its planet bearings: unset them to give one c_radial
DAMPED = {"stages[0].c_mesh_sun": 1.0e3, "stages[0].c_mesh_ring": 2.0e3,
          "stages[0].planets.bearing.c_radial_x": None, "stages[0].planets.bearing.c_radial_y": None,
          "stages[0].planets.bearing.c_radial": 4.0e2, "stages[0].planets.bearing.c_axial": 6.0, "stages[0].planets.bearing.c_tilt_x": 3.0,
          "stages[0].planets.bearing.c_tilt_y": 4.0, "stages[0].planets.bearing.c_torsion": 5.0,
          "bearings[0].c_radial_x": 4.2e4, "bearings[0].c_radial_y": 3.06e4, "bearings[0].c_axial": 453.0,
          "damping": {"modal_ratio": 0.01, "class_ratios": {"rotational": 0.05, "out-of-plane": 0.02},
                      "rayleigh_alpha": 0.1, "rayleigh_beta": 1e-6}}


def test_damping_fields_round_trip_through_toml():
    import tomllib

    from assembly.scene.save import scene_to_toml
    from assembly.scene.schema import load_scene, scene_from_dict
    scene = load_scene("nrel5mw.toml").with_values(DAMPED)
    back = scene_from_dict(tomllib.loads(scene_to_toml(scene)))
    assert back == scene
    assert back.damping.class_ratios["out-of-plane"] == 0.02
    planet = next(b for b in back.expanded().bearings if b.body == "stage1.planet0")
    # planets' dampers reach every planet bearing: x, y radial, axial, the two tilts, torsion
    assert list(planet.damping_diagonal()) == [4.0e2, 4.0e2, 6.0, 3.0, 4.0, 5.0]
    assert all(m.damping in (1.0e3, 2.0e3) for m in back.expanded().meshes if m.name.startswith("stage1"))


BAD = [  # (field path to set, value, path the error names)
    ("damping", {"modal_ratio": 1.0}, "damping.modal_ratio"),
    ("damping", {"modal_ratio": -0.1}, "damping.modal_ratio"),
    ("damping", {"class_ratios": {"rotational": 1.5}}, "damping.class_ratios.rotational"),
    ("damping", {"class_ratios": {"out-of-plane": -0.5}}, "damping.class_ratios['out-of-plane']"),
    ("damping", {"class_ratios": {"rotational": "0.1"}}, "damping.class_ratios.rotational"),
    ("damping", {"class_ratios": {"torsional": 0.1}}, "damping.class_ratios"),
    ("damping", {"rayleigh_alpha": -1.0}, "damping.rayleigh_alpha"),
    ("damping", {"rayleigh_beta": -1e-6}, "damping.rayleigh_beta"),
    ("bearings[0].c_axial", -1.0, "bearings[0].c_axial"),
    ("bearings[0].c_torsion", math.inf, "bearings[0].c_torsion"),
    ("bearings[0].c_radial_y", None, "bearings[0].c_radial_y"),         # one of a split pair left
    ("stages[0].planets.bearing.c_tilt_x", None, "stages[0].planets.bearing.c_tilt_x"),
    ("stages[0].c_mesh_sun", -5.0, "stages[0].c_mesh_sun"),
]


@pytest.mark.parametrize("path,value,named", BAD, ids=[b[2] + "=" + repr(b[1]) for b in BAD])
def test_bad_damping_names_its_field(path, value, named):
    from assembly.scene.schema import load_scene
    with pytest.raises(SceneError) as err:
        load_scene("nrel5mw.toml").with_values({path: value})
    assert err.value.path == named


def test_split_damper_given_both_ways_is_refused():
    with pytest.raises(SceneError) as err:
        two_mass(ground={"c_radial": 1.0, "c_radial_x": 2.0, "c_radial_y": 2.0})
    assert err.value.path.endswith("c_radial_x")


def test_beam_and_spring_shaft_dampers_are_not_mixed():
    with pytest.raises(SceneError) as err:
        Scene(name="s", bodies=two_mass().bodies, bearings=two_mass().bearings,
              shafts=(Shaft(body1="a", body2="b", k_torsion=K, beta=1e-4),))
    assert err.value.path == "shafts[0].beta"
    with pytest.raises(SceneError) as err:
        Scene(name="s", bodies=two_mass().bodies, bearings=two_mass().bearings,
              shafts=(Shaft(body1="a", body2="b", diameter=0.05, c_torsion=1.0),))
    assert err.value.path == "shafts[0].c_torsion"
