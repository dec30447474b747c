"""DTTorDmp of the two-mass model (assembly.analysis.two_mass).

Chain of tests/analysis/test_drivetrain.py: rotor -- shaft k1 -- wheel (r_w) -- mesh k_m --
pinion (r_p) -- shaft k2 -- generator, N = r_w / r_p; on the low-speed side the springs are
in series, k = 1 / (1/k1 + 1/(k_m r_w^2) + 1/(k2 N^2)). The static condensation lets each
spring take the share k / k_j of the end-to-end twist (series springs carry one torque), so
a damper c_j beside spring j adds c_j (k / k_j)^2 (its dissipation c_j (share d')^2 at the
end-to-end twist rate d'), with k_j and c_j on the low-speed side (c2 N^2 for the
high-speed shaft's damper, as its stiffness k2 N^2): with k1 and k_m rigid, c2 N^2.
Modal ratio: the two-mass mode J_eq d'' + c d' + k d = 0 has zeta = c / (2 J_eq omega_1).
"""
from __future__ import annotations

import dataclasses
import math

import pytest

from assembly import Bearing, Body, Scene, Shaft
from assembly.analysis.two_mass import two_mass
from assembly.app.export.elastodyn import fragment_text
from assembly.scene.tables import Damping
from tests.analysis.test_drivetrain import K1, K2, KM, chain

INF = math.inf


def _damp_shaft(scene, i, c):
    shafts = list(scene.shafts)
    shafts[i] = dataclasses.replace(shafts[i], c_torsion=c)
    return Scene(**{**{f.name: getattr(scene, f.name) for f in dataclasses.fields(Scene)}, "shafts": tuple(shafts)})


def test_two_mass_chain_damper_is_dttordmp_exactly():
    c = 7.5e4
    bodies = (Body(name="rotor", mass=10.0, polar_inertia=1e3, role="rotor"),
              Body(name="gen", mass=10.0, polar_inertia=2.0, position=(0, 0, 1), role="generator"))
    sc = Scene(name="two", bodies=bodies, shafts=(Shaft(body1="rotor", body2="gen", k_torsion=1e7, c_torsion=c),),
               bearings=tuple(Bearing(body=b.name, k_radial=INF, k_axial=INF, k_tilt=INF) for b in bodies))
    tm = two_mass(sc)
    assert tm.damping == c
    assert f"{c:>11.10g}   DTTorDmp" in fragment_text(tm, sc.name)


def test_geared_chain_dampers_in_series():
    r_w, r_p, c1, c2 = 0.4, 0.1, 3.0e4, 2.0
    N = r_w / r_p
    k = 1 / (1 / K1 + 1 / (KM * r_w ** 2) + 1 / (K2 * N ** 2))
    tm = two_mass(_damp_shaft(_damp_shaft(chain(r_w, r_p), 0, c1), 1, c2))
    want = c1 * (k / K1) ** 2 + c2 * N ** 2 * (k / (K2 * N ** 2)) ** 2
    assert tm.damping == pytest.approx(want, rel=1e-9)
    # the high-speed damper alone: c2 N^2 times the square of its spring's twist share
    alone = two_mass(_damp_shaft(chain(r_w, r_p), 1, c2)).damping
    assert alone == pytest.approx(c2 * N ** 2 * (k / (K2 * N ** 2)) ** 2, rel=1e-9)


def test_no_damping_no_dttordmp():
    tm = two_mass(chain())
    assert tm.damping is None
    assert "DTTorDmp not derived" in fragment_text(tm, "chain")


def test_modal_ratio_dttordmp():
    zeta = 0.02
    sc = chain()
    tm = two_mass(Scene(**{**{f.name: getattr(sc, f.name) for f in dataclasses.fields(Scene)},
                                  "damping": Damping(modal_ratio=zeta)}))
    J_ls = tm.generator_inertia * tm.gear_ratio ** 2
    J_eq = tm.rotor_inertia * J_ls / (tm.rotor_inertia + J_ls)
    w1 = math.sqrt(tm.stiffness / J_eq)          # the two-mass free-free mode
    assert tm.damping == pytest.approx(2 * zeta * w1 * J_eq, rel=1e-12)


def test_bearing_dampers_without_torsion_give_no_dttordmp():
    # The 5 MW scene's bearings carry radial, axial and tilt dampers only (Nejad et al. 2016,
    # Wind Energy 19: c_x, c_y, c_z, c_beta, c_gamma; no c about the shaft): none of them
    # resists the torsional twist, so the two-mass damper is exactly zero (the torsional
    # model sees them only as round-off of the bearing frames), not a damper to the housing.
    from pathlib import Path

    from assembly.scene.schema import load_scene
    scene = load_scene(Path(__file__).resolve().parents[2] / "assembly" / "scenes" / "nrel5mw.toml")
    assert all(b.c_radial_x for b in scene.bearings)
    assert two_mass(scene).damping == 0.0
