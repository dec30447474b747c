"""Beam shafts: Timoshenko elements between a shaft's end bodies and its stations.

Closed forms are derived in the comments; textbook matrices name their source."""
import dataclasses
import math
import tomllib

import numpy as np
import pytest

from assembly.analysis.energy import element_strain_energy, kinetic_by_element, kinetic_energy_by_body
from assembly.analysis.modal import solve_modes
from assembly.errors import SceneError
from assembly.mechanics.beam import cowper_kappa, section, timoshenko_element
from assembly.model.assemble import assemble
from assembly.scene.save import scene_to_toml
from assembly.scene.schema import scene_from_dict
from assembly.scene.tables import Bearing, Body, Fixed, Scene, Shaft, Station, with_fidelity
from fe_components.material import STEEL, Material

E, NU, RHO = STEEL.E, STEEL.nu, STEEL.rho
G = STEEL.G


def _przemieniecki(L, A, Iy, Iz, J, kappa):
    """12 x 12 Timoshenko beam stiffness, beam along x, DOFs per node [u, v, w, th_x, th_y,
    th_z]: Przemieniecki (1968), Theory of Matrix Structural Analysis, eq. 5.116, with
    Phi_y = 12 E I_z / (kappa G A L^2), Phi_z = 12 E I_y / (kappa G A L^2)."""
    py = 12 * E * Iz / (kappa * G * A * L ** 2)
    pz = 12 * E * Iy / (kappa * G * A * L ** 2)
    K = np.zeros((12, 12))
    a = E * A / L
    t = G * J / L
    by = E * Iz / ((1 + py) * L ** 3)
    bz = E * Iy / ((1 + pz) * L ** 3)
    up = {(0, 0): a, (0, 6): -a, (6, 6): a,
          (3, 3): t, (3, 9): -t, (9, 9): t,
          # v - th_z plane
          (1, 1): 12 * by, (1, 5): 6 * L * by, (1, 7): -12 * by, (1, 11): 6 * L * by,
          (5, 5): (4 + py) * L ** 2 * by, (5, 7): -6 * L * by, (5, 11): (2 - py) * L ** 2 * by,
          (7, 7): 12 * by, (7, 11): -6 * L * by, (11, 11): (4 + py) * L ** 2 * by,
          # w - th_y plane
          (2, 2): 12 * bz, (2, 4): -6 * L * bz, (2, 8): -12 * bz, (2, 10): -6 * L * bz,
          (4, 4): (4 + pz) * L ** 2 * bz, (4, 8): 6 * L * bz, (4, 10): (2 - pz) * L ** 2 * bz,
          (8, 8): 12 * bz, (8, 10): 6 * L * bz, (10, 10): (4 + pz) * L ** 2 * bz}
    for (i, j), v in up.items():
        K[i, j] = K[j, i] = v
    return K


@pytest.mark.parametrize("bore", [0.0, 0.05])
@pytest.mark.parametrize("L", [0.25, 1.5])   # stocky (Phi ~ 0.3) and slender
def test_element_is_przemieniecki_timoshenko(bore, L):
    d = 0.12
    sec = section(d, bore, NU)
    p_a = np.array([0.3, -0.2, 0.1])
    el = timoshenko_element("e", "a", "b", p_a, p_a + [L, 0.0, 0.0], sec, STEEL)
    # both bodies' motions are taken at p_a: w_b(p_a) maps to the motion at p_b by the rigid
    # arm, so undo it to compare with the textbook matrix on the two node motions
    arm = np.eye(12)
    arm[6:9, 9:12] = np.array([[0, 0, 0], [0, 0, L], [0, -L, 0]])   # u(p_b) = u(p_a) + th x (L e_x)
    K_nodes = np.linalg.inv(arm).T @ el.stiffness() @ np.linalg.inv(arm)
    K_ref = _przemieniecki(L, sec.A, sec.I, sec.I, sec.J_p, sec.kappa)
    assert np.allclose(K_nodes, K_ref, rtol=1e-12, atol=1e-12 * np.abs(K_ref).max())


def test_cowper_kappa_limits():
    # Cowper (1966), Table 1: solid circle 6 (1 + nu) / (7 + 6 nu); thin-walled tube (m -> 1)
    # 2 (1 + nu) / (4 + 3 nu)
    assert cowper_kappa(0.3, 0.0) == pytest.approx(6 * 1.3 / (7 + 1.8), rel=1e-15)
    assert cowper_kappa(0.3, 1.0) == pytest.approx(2 * 1.3 / (4 + 0.9), rel=1e-15)


def _cantilever(L, d, stations=(), fidelity=None):
    bodies = (Body("root", mass=1.0, polar_inertia=0.1, position=(0.0, 0.0, 0.0)),
              Body("tip", mass=1.0, polar_inertia=0.1, position=(0.0, 0.0, L)))
    st = tuple(Station(f"s{i}", a) for i, a in enumerate(stations))
    return Scene(bodies=bodies, fixed=(Fixed("root"),), fidelity=fidelity,
                 shafts=(Shaft("root", "tip", diameter=d, name="shaft", stations=st),))


@pytest.mark.parametrize("stations", [(), (0.3, 0.9, 0.55)])   # unsorted on purpose
def test_cantilever_tip_deflection_timoshenko(stations):
    L, d, P = 1.2, 0.2, 1.0e5
    m = assemble(_cantilever(L, d, stations))
    f = np.zeros(m.n_abs)
    f[m.offsets["tip"] + 0] = P           # force along global x at the tip body's centre
    q = np.linalg.solve(m.K.toarray(), m.T.T @ f)
    z = m.T @ q
    sec = section(d, 0.0, NU)
    # Timoshenko cantilever under a tip force: bending P L^3 / (3 E I) plus shear P L / (kappa G A);
    # the two-node element with Phi = 12 E I / (kappa G A L^2) is exact at its nodes for it
    want = P * L ** 3 / (3 * E * sec.I) + P * L / (sec.kappa * G * sec.A)
    assert z[m.offsets["tip"]] == pytest.approx(want, rel=1e-9)
    # tip slope (rotation about y, which turns z into x): P L^2 / (2 E I), no shear part
    assert z[m.offsets["tip"] + 4] == pytest.approx(P * L ** 2 / (2 * E * sec.I), rel=1e-9)


def test_two_discs_on_a_shaft_torsion():
    L, d, J1, J2 = 0.8, 0.05, 0.4, 1.1
    sc = Scene(fidelity="torsional",
               bodies=(Body("a", mass=10.0, polar_inertia=J1, position=(0.0, 0.0, 0.0)),
                       Body("b", mass=10.0, polar_inertia=J2, position=(0.0, 0.0, L))),
               shafts=(Shaft("a", "b", diameter=d),))
    r = solve_modes(assemble(sc))
    sec = section(d, 0.0, NU)
    k = G * sec.J_p / L
    # the element lumps half the shaft's polar inertia rho J_p L at each disc
    half = RHO * sec.J_p * L / 2
    # two inertias on a torsional spring: omega^2 = k (1/J1 + 1/J2)
    want = math.sqrt(k * (1 / (J1 + half) + 1 / (J2 + half))) / (2 * math.pi)
    assert r.frequencies_hz[0] == pytest.approx(0.0, abs=1e-6 * want)
    assert r.frequencies_hz[1] == pytest.approx(want, rel=1e-10)


def _free_shaft(n_elements, L=2.0, d=0.02):
    """A uniform free-free shaft of n_elements equal elements; its end bodies carry 1e-9 of
    the shaft's mass and inertia (so they shift frequencies by ~1e-9, below every tolerance)."""
    m_s = RHO * math.pi * d ** 2 / 4 * L
    tiny = dict(mass=1e-9 * m_s, polar_inertia=1e-9 * m_s * d ** 2 / 8)
    st = tuple(Station(f"s{i}", L * i / n_elements) for i in range(1, n_elements))
    return Scene(bodies=(Body("a", position=(0.0, 0.0, 0.0), **tiny), Body("b", position=(0.0, 0.0, L), **tiny)),
                 shafts=(Shaft("a", "b", diameter=d, name="shaft", stations=st),))


def _first_bending_error(n):
    L, d = 2.0, 0.02
    r = solve_modes(assemble(_free_shaft(n, L, d)))
    sec = section(d, 0.0, NU)
    # Euler-Bernoulli free-free beam: (beta L)^2 = 22.373 (Blevins 1979, Formulas for natural
    # frequency and mode shape, Table 8-1), f = 22.373 sqrt(E I / (m L^4)) / (2 pi), m = rho A
    f_eb = 22.373 * math.sqrt(E * sec.I / (RHO * sec.A * L ** 4)) / (2 * math.pi)
    f = r.frequencies_hz[r.frequencies_hz > 1e-3 * f_eb]
    assert f[0] == pytest.approx(f[1], rel=1e-9)       # the two bending planes
    return f[0] / f_eb - 1


def test_free_free_bending_converges_to_euler_bernoulli():
    # Lumped masses make the first bending mode low by ~c/n^2 (n elements): halving the
    # elements divides the error by ~4. Measured: -4.6e-2 (n = 8), -1.22e-2 (16), -3.27e-3 (32),
    # so at 32 stations the lumped shaft is 0.33 % low: tolerance 0.4 %. Beneath it lies the
    # Timoshenko shaft's own lowering by shear and rotary inertia, estimated as for a simply
    # supported beam (Timoshenko 1921) -(lambda r_g / L)^2 (1 + E / (kappa G)) / 2 with
    # lambda = 4.730, r_g / L = 2.5e-3: -2.7e-4. Richardson's extrapolation of the last two
    # (the 1/n^2 term removed) must land on that floor, not on a discretisation error.
    errs = [_first_bending_error(n) for n in (8, 16, 32)]
    assert all(e < 0 for e in errs)
    assert 3.3 < errs[0] / errs[1] < 4.0 and 3.3 < errs[1] / errs[2] < 4.0
    assert -4e-3 < errs[2] < 0
    floor = -(4.730 * 0.005 / 2.0) ** 2 * (1 + E / (cowper_kappa(NU, 0.0) * G)) / 2
    assert (4 * errs[2] - errs[1]) / 3 == pytest.approx(floor, rel=0.2)


def test_mode_energies_add_up():
    # Bearings on the stations, one rigid end on the shaft's end: every strain energy is in
    # an element, every kinetic energy in a body or in an element's end masses.
    sc = Scene(bodies=(Body("hub", mass=500.0, polar_inertia=80.0, position=(0.0, 0.0, 0.0)),
                       Body("carrier", mass=300.0, polar_inertia=40.0, position=(0.0, 0.0, 2.0))),
               bearings=(Bearing("main.inp_a", k_radial=2e9, k_axial=5e8, k_tilt=0.0),
                         Bearing("main.inp_b", k_radial=2e9, k_axial=0.0, k_tilt=0.0)),
               shafts=(Shaft("hub", "carrier", diameter=0.7, bore_diameter=0.2, name="main",
                             stations=(Station("inp_a", 0.333), Station("inp_b", 1.166))),))
    r = solve_modes(assemble(sc))
    m, Z = r.model, r.abs_shapes
    strain = sum(element_strain_energy(m, el, Z) for el in m.elements)
    total = 0.5 * np.einsum("im,im->m", Z, m.K_abs @ Z)
    assert np.allclose(strain, total, rtol=1e-9, atol=1e-9 * total.max())
    kinetic = kinetic_energy_by_body(r).sum(axis=1) + kinetic_by_element(r).sum(axis=1)
    assert np.allclose(kinetic, 1.0, rtol=1e-9)              # mass-normalised modes: z' M z = 1
    assert kinetic_by_element(r)[:, 1:4].any()   # the shaft's elements carry the ends' half masses


def test_station_bodies_mass_and_place():
    sc = Scene(bodies=(Body("hub", mass=1.0, polar_inertia=1.0, position=(1.0, 0.0, 0.0), axis=(1.0, 0.0, 0.0)),
                       Body("carrier", mass=1.0, polar_inertia=1.0, position=(3.0, 0.0, 0.0), axis=(1.0, 0.0, 0.0))),
               bearings=(Bearing("main.b", k_radial=1e9, k_axial=1e9, k_tilt=0.0),),
               shafts=(Shaft("hub", "carrier", diameter=0.7, name="main", stage="lss",
                             stations=(Station("b", 1.5), Station("a", 0.5))),))
    b = sc.body("main.a")
    A = math.pi * 0.7 ** 2 / 4
    # station a at 0.5 m: half of its 0.5 m and of its 1.0 m neighbouring elements
    assert b.mass == pytest.approx(RHO * A * 0.75, rel=1e-14)
    assert b.polar_inertia == pytest.approx(RHO * math.pi * 0.7 ** 4 / 32 * 0.75, rel=1e-14)
    assert b.position == pytest.approx((1.5, 0.0, 0.0)) and b.stage == "lss"
    assert b.fidelity == "rigid"


def _nrel_scene(**shaft):
    base = dict(body1="hub", body2="carrier", diameter=0.7, name="main_shaft",
                stations=(Station("inp_a", 0.333), Station("inp_b", 1.166)))
    base.update(shaft)
    # the main bearings at the stations the shaft has (a bearing naming no body is refused first)
    seats = {st.name for st in base.get("stations", ())}
    bearings = tuple(Bearing(f"main_shaft.{name}", k_radial=3e9, k_axial=k_ax, k_tilt=0.0)
                     for name, k_ax in (("inp_a", 1e9), ("inp_b", 0.0)) if name in seats)
    return Scene(name="nrel5mw main shaft",
                 bodies=(Body("hub", mass=5.6e4, polar_inertia=1.2e5, position=(0.0, 0.0, 0.0)),
                         Body("carrier", mass=1.2e4, polar_inertia=4.0e3, position=(0.0, 0.0, 2.0))),
                 bearings=bearings, shafts=(Shaft(**base),))


def test_toml_round_trip_with_stations():
    sc = _nrel_scene(bore_diameter=0.1, stage="lss", material=Material(E=2.0e11, nu=0.29, rho=7800.0))
    back = scene_from_dict(tomllib.loads(scene_to_toml(sc)))
    assert back == sc
    assert [b.name for b in back.expanded().bodies] == ["hub", "carrier", "main_shaft.inp_a", "main_shaft.inp_b"]


def test_existing_spring_shaft_unchanged():
    s = Shaft("a", "b", 1e6, k_bending=2e5)
    assert not s.is_beam and s.diagonal().tolist() == [0.0, 0.0, 0.0, 2e5, 2e5, 1e6]


_BAD = [
    # station outside (0, L): at the start, at the end, beyond, before
    # (the bearings name both stations: a scene without one is refused for that name first)
    (dict(stations=(Station("inp_a", 0.0), Station("inp_b", 1.166))), "shafts[0].stations[0].at", 0.0, "L = 2 m"),
    (dict(stations=(Station("inp_a", 0.3), Station("inp_b", 2.0))), "shafts[0].stations[1].at", 2.0, "L = 2 m"),
    (dict(stations=(Station("inp_a", 2.55), Station("inp_b", 1.166))), "shafts[0].stations[0].at", 2.55,
     "shorter than its bearing span"),
    (dict(stations=(Station("inp_a", -0.1), Station("inp_b", 1.166))), "shafts[0].stations[0].at", -0.1, "L = 2 m"),
    # duplicates
    (dict(stations=(Station("inp_a", 0.3), Station("inp_b", 0.3))), "shafts[0].stations[1].at", 0.3, "same place"),
    (dict(stations=(Station("inp_a", 0.3), Station("inp_a", 1.1), Station("inp_b", 1.166))),
     "shafts[0].stations[1].name", "inp_a",
     "duplicate"),
    # section
    (dict(bore_diameter=0.7), "shafts[0].bore_diameter", 0.7, "less than diameter"),
    (dict(bore_diameter=0.9), "shafts[0].bore_diameter", 0.9, "less than diameter"),
    # derived fields given
    (dict(k_torsion=1e9), "shafts[0].k_torsion", 1e9, "leave this out"),
    (dict(k_bending=1e9), "shafts[0].k_bending", 1e9, "leave this out"),
    (dict(position=(0.0, 0.0, 1.0)), "shafts[0].position", (0.0, 0.0, 1.0), "leave this out"),
    # names
    (dict(name=None), "shafts[0].name", None, "needs a name"),
    (dict(stations=(Station("in.a", 0.3), Station("inp_a", 0.5), Station("inp_b", 1.166))),
     "shafts[0].stations[0].name", "in.a", "without '.'"),
    # spring shaft: stations need a diameter, k_torsion stays required
    (dict(diameter=None, k_torsion=1e9), "shafts[0].stations", ["inp_a", "inp_b"], "give its diameter"),
    (dict(diameter=None, stations=()), "shafts[0].k_torsion", None, "missing required field"),
]


@pytest.mark.parametrize("change, path, value, words", _BAD)
def test_bad_beam_shafts_refused(change, path, value, words):
    with pytest.raises(SceneError) as e:
        _nrel_scene(**change)
    assert (e.value.path, e.value.value) == (path, value)
    assert words in e.value.reason


def test_shaft_off_body1_axis_refused():
    sc = _nrel_scene()
    carrier = dataclasses.replace(sc.bodies[1], position=(0.01, 0.0, 2.0))
    with pytest.raises(SceneError) as e:
        dataclasses.replace(sc, bodies=(sc.bodies[0], carrier))
    assert e.value.path == "shafts[0].body2" and "off body1's axis" in e.value.reason


def test_station_name_taken_by_a_body_refused():
    sc = _nrel_scene()
    twin = Body("main_shaft.inp_b", mass=1.0, polar_inertia=1.0, position=(0.0, 0.0, 1.0))
    with pytest.raises(SceneError) as e:
        dataclasses.replace(sc, bodies=sc.bodies + (twin,))
    assert (e.value.path, e.value.value) == ("shafts[0].stations[1].name", "inp_b")


def test_station_fidelity_follows_the_scene_default_never_flexible():
    sc = _nrel_scene()
    tors = with_fidelity(sc, "torsional").expanded()
    assert {b.fidelity for b in tors.bodies} == {"torsional"}
    ends = tuple(dataclasses.replace(b, fidelity="rigid") for b in sc.bodies)
    flex_default = dataclasses.replace(sc, bodies=ends, fidelity="flexible")
    assert flex_default.body("main_shaft.inp_a").fidelity == "rigid"
