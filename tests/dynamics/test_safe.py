"""Interference (SAFE) diagram of a planetary stage (assembly.dynamics.safe).

Closed forms used below:

* Parker (2000), J. Sound Vib. 236(4), 561-573; Parker & Lin (2004), J. Mech. Des. 126,
  365-370: with N equally spaced planets (psi_n = 2 pi n / N) and Z_s sun teeth, harmonic l of
  planet n's mesh force lags planet 0's by l Z_s psi_n: a wave of phase index
  k_l = (l Z_s) mod N. k = 0 excites rotational modes only, k = +-1 translational only, any
  other index planet modes only (Lin & Parker 1999, J. Vib. Acoust. 121, 316-321).
* N equally spaced point loads of index k load the circumferential waves n = k (mod N) of a
  ring: an n-nodal-diameter mode sits at k = +-(n mod N).
* A constant natural frequency f_0 meets the order line f = a n at n = f_0 / a.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly import SceneError
from assembly.analysis.classify import ModeInfo
from assembly.dynamics.campbell import NEGLIGIBLE, campbell
from assembly.dynamics.phasing import excited_class
from assembly.dynamics.safe import (
    INTERFERENCE,
    class_indices,
    folded,
    judge,
    mode_indices,
    phase_index,
    safe_diagrams,
    stage_diagram,
    zigzag,
)
from assembly.scene.edit import with_values
from assembly.scene.schema import load_scene
from tests.support.campbell_scene import campbell_scene

N4 = 4
# (l Z_s) mod 4 by hand for l = 1, 2, 3:
#   Z_s = 31: 31, 62, 93 -> 3, 2, 1      Z_s = 30: 30, 60, 90 -> 2, 0, 2
#   Z_s = 29: 29, 58, 87 -> 1, 2, 3      Z_s = 28: 28, 56, 84 -> 0, 0, 0 (Z_s / N = 7: in phase)
BY_HAND = {31: (3, 2, 1), 30: (2, 0, 2), 29: (1, 2, 3), 28: (0, 0, 0)}
CLASS_AT = {0: "rotational", 1: "translational", 3: "translational", 2: "planet"}      # N = 4


def lin_parker_n4(sun_teeth: int):
    """Lin & Parker's N = 4 stage (shipped scene, base radii only) with the sun's teeth counted
    by a stiffness variation (a time-domain field: the modes do not change)."""
    return with_values(load_scene("lin_parker_n4"),
                       {"stages.stage.variation_sun": {"amplitudes": [0.1], "teeth": sun_teeth}})


@pytest.fixture(scope="module", params=sorted(BY_HAND))
def lp4(request):
    zs = request.param
    c = campbell(lin_parker_n4(zs), (0.0, 3000.0), reference="stage.sun")
    return zs, c, stage_diagram(c, "stage")


def test_lin_parker_harmonic_index_is_l_zs_mod_n(lp4):
    zs, c, d = lp4
    assert (d.n_planets, d.sun_teeth, d.equally_spaced) == (N4, zs, True)
    assert tuple(e.index for e in d.excitations) == BY_HAND[zs]
    assert tuple(e.harmonic for e in d.excitations) == (1, 2, 3)
    assert all(e.excites == CLASS_AT[e.index] for e in d.excitations)


def test_lin_parker_classes_meet_only_their_indices(lp4):
    # rotational modes at k = 0 only, translational at k = 1 and 3 (= -1), the planet modes at k = 2
    zs, c, d = lp4
    want = {"rotational": (0,), "translational": (1, 3), "planet": (2,)}
    assert {m.label for m in d.modes} == set(want)
    assert all(m.indices == want[m.label] for m in d.modes)
    hits = d.interferences
    assert all(CLASS_AT[r.index] == r.mode_class for r in hits)
    # every crossing of a harmonic with a mode of another index is ruled out
    assert all(r.verdict == "ruled out" for r in d.rows if r.index not in r.mode_indices)
    # the mode classes reached are those of the harmonics' indices, and only those
    assert {r.mode_class for r in hits} == {CLASS_AT[k] for k in BY_HAND[zs]}


def test_lin_parker_interference_speed_and_frequency(lp4):
    # the modes do not depend on speed: harmonic l meets mode f_0 at n = f_0 / (l a_1)
    zs, c, d = lp4
    freq = {m.mode: m.frequency_hz for m in d.modes}
    for r in d.interferences:
        assert r.frequency_hz == freq[r.mode]
        assert r.speed_rpm == pytest.approx(freq[r.mode] / (r.harmonic * d.mesh_hz_per_rpm), rel=1e-12)
        assert 0.0 <= r.speed_rpm <= 3000.0


def _agrees_with_campbell(c):
    diagrams = safe_diagrams(c)
    assert diagrams
    for d in diagrams:
        orders = {e.order for e in d.excitations}
        crossings = [x for x in c.crossings if x.order in orders]
        assert len(crossings) == len(d.rows)
        hit = {(r.order, r.mode) for r in d.interferences}
        # an interference is exactly a crossing the Campbell ranks as drivable with a share, and
        # of a rigid-member class exactly one whose phasing verdict is True; the Campbell leaves
        # elastic modes undecided, the index decides them
        assert hit <= {(x.order, x.mode) for x in c.ranked() if x.excitable is not False and x.share >= NEGLIGIBLE}
        rigid = {(x.order, x.mode) for x in crossings if x.excitable is True and x.share >= NEGLIGIBLE}
        assert {(r.order, r.mode) for r in d.interferences if r.mode_class != "elastic"} == rigid
        # what SAFE rules out, the Campbell rules out (elastic modes: undecided there)
        assert all(r.excitable is False or (r.mode_class == "elastic" and r.excitable is None)
                   for r in d.rows if r.verdict == "ruled out")
    return diagrams


def test_lin_parker_interferences_are_the_campbells_drivable_crossings(lp4):
    zs, c, d = lp4
    assert len(_agrees_with_campbell(c)) == 1 and d.interferences


def test_nrel5mw_stages_agree_with_the_campbell():
    # N = 3 stages (Z_s = 19: indices 1, 2, 0; Z_s = 18: in phase), helical stage 3 and
    # out-of-plane modes that get no index
    c = campbell(load_scene("nrel5mw"), (0.0, 15.0))
    d1, d2 = _agrees_with_campbell(c)
    assert (d1.stage, d1.sun_teeth, d1.n_planets) == ("stage1", 19, 3)
    assert tuple(e.index for e in d1.excitations) == (19 % 3, 38 % 3, 57 % 3) == (1, 2, 0)
    assert tuple(e.index for e in d2.excitations) == (0, 0, 0)          # 18 / 3 = 6
    assert any(r.verdict == "no index" for r in d1.rows)


def test_in_phase_stage_puts_every_harmonic_at_zero(tmp_path):
    # Z_s = 20, N = 4 (tests/support/campbell_scene.py): 20 l / 4 an integer for every l
    c = campbell(_scene(tmp_path, campbell_scene()), (0.0, 3000.0), harmonics=5)
    (d,) = safe_diagrams(c)
    assert (d.sun_teeth, d.n_planets) == (20, 4)
    assert [e.index for e in d.excitations] == [0] * 5
    assert d.interferences and all(r.mode_class == "rotational" for r in d.interferences)
    _agrees_with_campbell(c)


def _scene(tmp_path, text):
    p = tmp_path / "scene.toml"
    p.write_text(text)
    return load_scene(str(p))


def test_unequal_planets_get_no_index(tmp_path):
    # 86.4 and 266.4 deg: multiples of 360 / (20 + 80) = 3.6 deg, so the planets assemble
    c = campbell(_scene(tmp_path, campbell_scene((0.0, 86.4, 180.0, 266.4))), (0.0, 3000.0))
    (d,) = safe_diagrams(c)
    assert not d.equally_spaced and d.rows and not d.interferences
    assert all(r.verdict == "no index" and not r.mode_indices for r in d.rows)
    assert any("not equally spaced" in n for n in d.notes)


@pytest.mark.parametrize("n", range(1, 9))
def test_class_indices_are_parkers_rule(n):
    # r = (h Z_s) mod N excites class c exactly when r is one of c's indices; h = 1, Z_s = r + N
    for r in range(n):
        got = excited_class(1, r + n, n)
        assert phase_index(1, r + n, n) == r
        assert [c for c in ("rotational", "translational", "planet") if r in class_indices(c, n)] == [got]


def _elastic(body, nd):
    return ModeInfo(9, 100.0, 1, "elastic", "stage", (), body=body, nodal_diameters=nd, scope="stage")


@pytest.mark.parametrize("nd, n, want", [(0, 4, (0,)), (4, 4, (0,)), (1, 4, (1, 3)), (5, 4, (1, 3)), (2, 4, (2,)),
                                         (6, 4, (2,)), (3, 5, (2, 3)), (7, 3, (1, 2))])
def test_elastic_ring_mode_sits_at_its_nodal_diameters_mod_n(nd, n, want):
    assert mode_indices(_elastic("stage.ring", nd), "stage", n) == want
    assert mode_indices(_elastic("stage.carrier", nd), "stage", n) == want
    assert mode_indices(_elastic("stage.planet1", nd), "stage", n) == ()      # not a central member
    assert mode_indices(_elastic("other.ring", nd), "stage", n) == ()
    assert mode_indices(_elastic("stage.ring", None), "stage", n) == ()


@pytest.mark.parametrize("zs, n", [(19, 3), (31, 4), (23, 5), (25, 6)])
def test_zigzag_passes_through_every_harmonic(zs, n):
    # the folded order line is piecewise linear between its turns at multiples of N / 2: at
    # order nu = l Z_s it is at |k_l|
    nu, x = zigzag(5 * zs, n)
    assert np.all(np.diff(nu) > 0) and np.all((x >= 0) & (x <= n / 2))
    turns = nu[1:-1]
    assert np.allclose(turns / (n / 2), np.round(turns / (n / 2)), rtol=0, atol=1e-12)
    for lh in range(1, 6):
        assert np.interp(lh * zs, nu, x) == pytest.approx(folded(phase_index(lh, zs, n), n), abs=1e-9)
    assert folded(3, 4) == 1 and folded(2, 4) == 2 and math.isclose(folded(4.5, 3), 1.5)


def test_a_matching_index_without_a_modal_force_is_ruled_out():
    # the index is necessary, not sufficient: meshes holding none of the mode's strain energy
    # put no modal force into it (assembly.dynamics.participation); the Campbell rules it out too
    assert judge(0, (0,), 0.5 * NEGLIGIBLE, True)[0] == "ruled out"
    assert judge(0, (0,), NEGLIGIBLE, True)[0] == INTERFERENCE
    assert judge(2, (1, 3), 0.5, True)[0] == "ruled out"
    assert judge(0, (0,), 0.5, False)[0] == "no index"
    assert judge(0, (), 0.5, True, stage_planet_mode=True)[0] == "ruled out"
    assert judge(0, (), 0.5, True)[0] == "no index"


@pytest.mark.slow
def test_flexible_carrier_modes_sit_at_their_nodal_diameters():
    # N = 3, Z_s = 31 (counted by a stiffness variation: the modes do not change): harmonics at
    # 31, 62, 93 mod 3 = 1, 2, 0; the carrier's n-ND modes at +-(n mod 3)
    s = with_values(load_scene("planetary_flexible_carrier"),
                    {"stages.stage.variation_sun": {"amplitudes": [0.1], "teeth": 31}})
    c = campbell(s, (0.0, 3000.0), reference="stage.sun")
    (d,) = _agrees_with_campbell(c)
    assert [e.index for e in d.excitations] == [1, 2, 0]
    nds = {m.index + 1: m.nodal_diameters for m in c.modes}
    elastic = [(m, nds[m.mode]) for m in d.modes if m.label.startswith("elastic stage.carrier")]
    assert {nd % 3 for _, nd in elastic} == {0, 1, 2}
    assert all(m.indices == ((0,) if nd % 3 == 0 else (1, 2)) for m, nd in elastic)
    assert any(r.mode_class == "elastic" for r in d.rows)


@pytest.mark.parametrize("bad", [None, 5, "campbell", [], object()])
def test_a_campbell_is_required(bad):
    with pytest.raises(SceneError) as err:
        safe_diagrams(bad)
    assert err.value.path == "campbell"


def test_unknown_stage_is_named(lp4):
    zs, c, d = lp4
    for bad in ("stag", "", 5, None):
        with pytest.raises(SceneError) as err:
            stage_diagram(c, bad)
        assert err.value.path == "stage"


def test_stage_names_that_make_one_file_name_get_their_own_pictures():
    """'a b' and 'a/b' both make safe_a_b.png: the second gets _2 (one picture each, none
    overwritten)."""
    from types import SimpleNamespace

    from assembly.app.report.safe import png_names

    names = png_names([SimpleNamespace(stage=s) for s in ("a b", "a/b", "a_b", "c")])
    assert names == {"a b": "safe_a_b.png", "a/b": "safe_a_b_2.png", "a_b": "safe_a_b_3.png", "c": "safe_c.png"}
