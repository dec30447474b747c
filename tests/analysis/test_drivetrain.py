"""Kinematic chain and two-mass equivalent (assembly.analysis.drivetrain, assembly.mechanics.condensation).

Chain of the closed forms: rotor J_R -- torsional shaft k1 -- wheel (base radius r_w)
-- spur mesh k_m -- pinion (r_p) -- shaft k2 -- generator J_G, every body on rigid
bearings. In the torsional model each body turns by th about its own axis; the mesh
compression along the line of action is delta = r_w th_w + r_p th_p (a point of a base
circle moves r_b th along the line of action, which is tangent to both base circles;
for a spur mesh the line of action lies in the transverse plane), so the rank-one mesh
spring k_m delta^2 / 2 is k_m r_w^2 (th_w + th_p / (r_w/r_p))^2 / 2: a torsional spring
k_m r_w^2 on the wheel side. The rigid-body mode (delta = 0) turns the pinion at
-r_w/r_p times the wheel: GBRatio N = r_w / r_p. Seen from the rotor (low-speed) side the
three springs are in series, the high-speed shaft reflected by N^2 (equal strain energy
at equal rotor rotation): k = 1 / (1/k1 + 1/(k_m r_w^2) + 1/(k2 N^2)). Kinetic energy of
the rigid mode at unit rotor speed: J_R + J_w + N^2 (J_p + J_G); lumping all but the
rotor on the generator shaft: GenIner = J_G + J_p + J_w / N^2.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from assembly import (
    Bearing,
    Body,
    Fixed,
    GearMesh,
    MechanismError,
    Scene,
    SceneError,
    Shaft,
    assemble,
    solve_modes,
    with_fidelity,
)
from assembly.analysis.drivetrain import chain_ends, speed_ratios, two_mass_frequencies
from assembly.analysis.two_mass import two_mass
from assembly.mechanics.condensation import condense
from assembly.scene.schema import load_scene

INF = math.inf
ALPHA = math.radians(20.0)
J_R, J_W, J_P, J_G = 1.0e3, 5.0, 0.1, 2.0           # kg m^2
K1, KM, K2 = 1.0e7, 1.0e9, 1.0e5                    # N m/rad, N/m, N m/rad


def _body(name, J, pos, role=None):
    return Body(name=name, mass=10.0, polar_inertia=J, position=pos, role=role)


def _bearings(names):
    return tuple(Bearing(body=b, k_radial=INF, k_axial=INF, k_tilt=INF) for b in names)


def chain(r_w=0.4, r_p=0.1, k1=K1, km=KM, k2=K2, **changes) -> Scene:
    """The rotor -- k1 -- wheel -- mesh -- pinion -- k2 -- generator chain (module docstring);
    ``r_w < 0``: the wheel is an internal (ring) gear."""
    C = abs(r_w + r_p) / math.cos(ALPHA)
    bodies = (_body("rotor", J_R, (0.0, 0.0, -1.0), "rotor"), _body("wheel", J_W, (0.0, 0.0, 0.0)),
              _body("pinion", J_P, (C, 0.0, 0.0)), _body("generator", J_G, (C, 0.0, 1.0), "generator"))
    sc = dict(name="chain", bodies=bodies, bearings=_bearings(b.name for b in bodies),
              meshes=(GearMesh(gear1="wheel", gear2="pinion", stiffness=km, base_radius1=r_w, base_radius2=r_p,
                               pressure_angle=ALPHA),),
              shafts=(Shaft(body1="rotor", body2="wheel", k_torsion=k1),
                      Shaft(body1="pinion", body2="generator", k_torsion=k2)))
    sc.update(changes)
    return Scene(**sc)


def test_nrel_5mw_two_mass_frequencies():
    # Jonkman, Butterfield, Musial, Scott (2009), NREL/TP-500-38060, NREL 5 MW: rotor inertia
    # about the shaft 38 759 236 kg m^2, GenIner 534.116 kg m^2, GBRatio 97, DTTorSpr
    # 867 637 000 N m/rad; free-free sqrt(k (1/J_R + 1/(N^2 J_G)))/(2 pi) = 2.2227 Hz and
    # generator locked sqrt(k/J_R)/(2 pi) = 0.753 Hz, compared to half a unit of the last digit.
    free, locked = two_mass_frequencies(38_759_236.0, 534.116, 97.0, 867_637_000.0)
    assert abs(free - 2.2227) <= 0.5e-4
    assert abs(locked - 0.753) <= 0.5e-3


@pytest.mark.parametrize("bad", [0.0, -1.0, INF, math.nan])
@pytest.mark.parametrize("which", range(4))
def test_two_mass_frequencies_refuse_non_positive_or_non_finite(bad, which):
    args = [1.0, 1.0, 1.0, 1.0]
    args[which] = bad
    with pytest.raises(ValueError, match="finite number > 0"):
        two_mass_frequencies(*args)


@pytest.mark.parametrize("r_w, r_p, k1, km, k2", [
    (0.4, 0.1, K1, KM, K2),          # high-speed shaft dominates (k2 N^2 = 1.6e6)
    (0.4, 0.1, 1e12, 1e6, 1e12),     # mesh dominates (k_m r_w^2 = 1.6e5)
    (0.1, 0.3, 2e6, 3e8, 7e6),       # a speed-reducing pair: N = 1/3
    (-0.4, 0.1, K1, KM, K2),         # internal wheel (ring): same sense of rotation
])
def test_chain_two_mass_closed_form(r_w, r_p, k1, km, k2):
    tm = two_mass(chain(r_w, r_p, k1, km, k2))
    N = abs(r_w / r_p)
    assert tm.gear_ratio == pytest.approx(N, rel=1e-12)
    # external pair: the pinion turns against the wheel; internal: with it
    assert np.sign(tm.speed_ratio) == (-1.0 if r_w > 0 else 1.0)
    assert tm.stiffness == pytest.approx(1.0 / (1 / k1 + 1 / (km * r_w**2) + 1 / (k2 * N**2)), rel=1e-9)
    assert tm.rotor_inertia == pytest.approx(J_R, rel=1e-12)
    assert tm.generator_only_inertia == pytest.approx(J_G, rel=1e-12)
    assert tm.gearbox_inertia == pytest.approx(J_P + J_W / N**2, rel=1e-12)
    assert tm.generator_inertia == pytest.approx(J_G + J_P + J_W / N**2, rel=1e-12)


def test_speed_ratios_of_the_chain():
    model = assemble(with_fidelity(chain(), "torsional"))
    r = speed_ratios(model, "rotor")
    # the shafts turn their two bodies together; the mesh turns the pinion at -r_w/r_p = -4
    assert r == pytest.approx({"rotor": 1.0, "wheel": 1.0, "pinion": -4.0, "generator": -4.0}, rel=1e-12)


def _two_inertias(kind):
    """Chains with only the rotor and the generator as inertias."""
    if kind == "shaft":
        bodies = (_body("rotor", J_R, (0.0, 0.0, 0.0), "rotor"), _body("generator", J_G, (0.0, 0.0, 1.0), "generator"))
        return Scene(name="shaft", bodies=bodies, bearings=_bearings(["rotor", "generator"]),
                     shafts=(Shaft(body1="rotor", body2="generator", k_torsion=K1),))
    bodies = (_body("rotor", J_R, (0.0, 0.0, 0.0), "rotor"),
              _body("generator", J_G, (0.5 / math.cos(ALPHA), 0.0, 0.0), "generator"))
    return Scene(name="mesh", bodies=bodies, bearings=_bearings(["rotor", "generator"]),
                 meshes=(GearMesh(gear1="rotor", gear2="generator", stiffness=KM, base_radius1=0.4,
                                  base_radius2=0.1, pressure_angle=ALPHA),))


@pytest.mark.parametrize("kind", ["shaft", "mesh"])
def test_two_mass_frequencies_equal_the_torsional_modes_of_a_two_inertia_chain(kind):
    # With only the two inertias, the torsional model is the two-mass model itself: its one
    # elastic mode is the free-free frequency, and with the generator held (a [[fixed]] rz)
    # its only mode is the generator-locked one.
    sc = _two_inertias(kind)
    free, locked = two_mass(sc).frequencies_hz()
    res = solve_modes(assemble(with_fidelity(sc, "torsional")))
    assert res.n_rigid == 1
    assert res.frequencies_hz[1] == pytest.approx(free, rel=1e-9)
    held = dataclasses.replace(sc, fixed=(Fixed(body="generator", dofs=("rz",)),))
    res = solve_modes(assemble(with_fidelity(held, "torsional")))
    assert res.n_rigid == 0
    assert res.frequencies_hz[0] == pytest.approx(locked, rel=1e-9)


def test_planetary_stage_gear_ratio_is_willis():
    # Fixed ring, torque in at the carrier, out at the sun: omega_sun / omega_carrier =
    # 1 + r_ring / r_sun (Willis; base radii, both meshes at one pressure angle), and the
    # sun turns in the carrier's sense.
    sc = load_scene("lin_parker_n3.toml")
    st = sc.stages[0]
    free = lambda m: dataclasses.replace(m, bearing=dataclasses.replace(m.bearing, k_torsion=0.0))  # noqa: E731
    st = dataclasses.replace(st, ring=dataclasses.replace(st.ring, support="fixed", bearing=None),
                             sun=free(st.sun), carrier=free(st.carrier))
    ends = (_body("hub", 1e3, (0.0, 0.0, -1.0), "rotor"), _body("gen", 1.0, (0.0, 0.0, 1.0), "generator"))
    sc = Scene(name="turbine", stages=(st,), bodies=ends, bearings=_bearings(["hub", "gen"]),
               shafts=(Shaft(body1="hub", body2="stage.carrier", k_torsion=1e8),
                       Shaft(body1="stage.sun", body2="gen", k_torsion=1e6)))
    tm = two_mass(sc)
    assert tm.speed_ratio == pytest.approx(1 + st.ring.base_radius / st.sun.base_radius, rel=1e-12)
    assert 0 < tm.stiffness < 1e8           # the shafts in series with the stage: softer than either


# ---------------------------------------------------------------- bad input, each class
def _roles(sc, roles):
    return dataclasses.replace(sc, bodies=tuple(dataclasses.replace(b, role=r) for b, r in zip(sc.bodies, roles)))


@pytest.mark.parametrize("roles, kwargs, path, value", [
    ((None, None, None, "generator"), {}, "bodies.role", "None"),            # no rotor
    (("rotor", None, None, None), {}, "bodies.role", "None"),                # no generator
    (("rotor", "rotor", None, "generator"), {}, "bodies[1].role", "rotor"),  # two rotors
    (("rotor", None, "generator", "generator"), {}, "bodies[3].role", "generator"),
    (("rotor", None, None, "generator"), {"rotor": "nacelle"}, "rotor", "nacelle"),
    (("rotor", None, None, "generator"), {"generator": "rotor"}, "generator", "rotor"),  # one body, both ends
])
def test_chain_ends_missing_ambiguous_or_unknown(roles, kwargs, path, value):
    with pytest.raises(SceneError) as err:
        chain_ends(_roles(chain(), roles), **kwargs)
    assert err.value.path == path and str(err.value.value) == value


def test_no_single_rigid_body_mode_is_refused_with_the_reason():
    # a torsional spring to the housing: no rigid-body mode
    sc = chain()
    held = dataclasses.replace(sc, bearings=sc.bearings[:1] + (dataclasses.replace(sc.bearings[1], k_torsion=1e3),)
                               + sc.bearings[2:])
    with pytest.raises(MechanismError, match="no rigid-body mode"):
        two_mass(held)
    # a free sub-chain: the mesh gone, wheel side and pinion side turn independently
    with pytest.raises(MechanismError, match="2 rigid-body modes"):
        two_mass(dataclasses.replace(sc, meshes=()))


def test_condense_series_springs_and_singular_interior():
    # three springs k_a, k_b, k_c in series between coordinates 0 and 3 (1, 2 interior):
    # K_cc = k_s [[1, -1], [-1, 1]], k_s = 1 / (1/k_a + 1/k_b + 1/k_c)
    ka, kb, kc = 2.0, 3.0, 5.0
    K = np.zeros((4, 4))
    for (i, j), k in zip([(0, 1), (1, 2), (2, 3)], (ka, kb, kc)):
        K[np.ix_([i, j], [i, j])] += k * np.array([[1, -1], [-1, 1]])
    ks = 1 / (1 / ka + 1 / kb + 1 / kc)
    np.testing.assert_allclose(condense(K, [0, 3]), ks * np.array([[1, -1], [-1, 1]]), rtol=1e-14)
    # an interior coordinate no spring reaches: K_ii singular
    K5 = np.zeros((5, 5))
    K5[:4, :4] = K
    with pytest.raises(MechanismError, match="singular"):
        condense(K5, [0, 3])
