"""A planetary stage joined to a body by a shaft sits on that body's axis: placed there
exactly (``coaxial_with``), accepted when a typed centre is off by the coordinates'
rounding, refused naming the stage's centre, the body, the offset and the fix when the
offset is a lever arm the torsional model cannot turn, and refused as the shaft's alignment
(as a beam shaft's) beyond a microradian over the shaft -- a spring shaft included.

Before: one unit in the last digit of the typed centre made ``flexgear compare`` refuse the
scene naming a spring that had nothing to do with it (``shafts[0].k_shear = 12080000.0: 1.2e-02
x the median ...``): the structural count saw a lever arm of 5.6e-17 m, so no free rotation,
and the "elastic" mode it left (k delta^2) was lost in the solve's round-off. A spring shaft
5 mm off axis was accepted and made a 1.2 Hz mode of a drivetrain that turns freely.

The scenes are the shipped two-stage drive with the wheel a plain body (its component's
teeth, a steel disc's mass; no meshing), compared torsional and rigid (assembly.analysis.compare).
"""
from __future__ import annotations

import copy
import math
import random
import re
import tomllib

import numpy as np
import pytest

from assembly.analysis.compare import compare
from assembly.app.cli import main
from assembly.errors import SceneError
from assembly.scene.save import toml_text
from assembly.scene.schema import SCENE_DIR, scene_from_dict, to_dict
from assembly.scene.shafts import AXIS_TOLERANCE
from tests.support.fuzz import examples

#: Steel density (kg/m^3).
RHO = 7850.0


def plain_quill() -> dict:
    """two_stage_quill.toml with the wheel a plain steel disc of its tip diameter and face
    width (m = rho pi r^2 b, J = m r^2 / 2), the stage coaxial with it."""
    tree = tomllib.loads((SCENE_DIR / "two_stage_quill.toml").read_text())
    wheel = tree["bodies"][1]
    teeth = wheel.pop("component")["teeth"]
    wheel.pop("flex")
    r = 0.5 * 83 * 0.005 / math.cos(math.radians(12.0))       # pitch radius z m_n / (2 cos beta)
    m = RHO * math.pi * r * r * 0.06
    wheel.update(teeth=teeth, mass=m, polar_inertia=0.5 * m * r * r)
    tree["bearings"][1].pop("interface")
    tree["shafts"][0].pop("interface1")
    return tree


COAXIAL = plain_quill()
EXACT = scene_from_dict(copy.deepcopy(COAXIAL))
WHEEL_X = EXACT.body("wheel").position[0]


def typed(center) -> dict:
    """The plain quill with the stage centre typed instead of coaxial_with."""
    tree = copy.deepcopy(COAXIAL)
    st = tree["stages"][0]
    for key in ("coaxial_with", "axial_offset"):
        st.pop(key, None)
    st["center"] = [float(c) for c in center]
    return tree


def elastic(c) -> dict:
    """Sorted frequencies (Hz) per fidelity of a comparison."""
    return {k: np.sort(r.frequencies_hz) for k, r in c.results.items()}


REFERENCE = elastic(compare(EXACT))


def test_coaxial_with_places_the_stage_on_the_axis_exactly():
    st = EXACT.stages[0]
    assert st.center == (WHEEL_X, 0.0, 0.4) and st.axis == EXACT.body("wheel").axis
    # the same model as the centre typed to the last bit (the shipped scene before): bit for bit
    typed_exact = elastic(compare(scene_from_dict(typed((WHEEL_X, 0.0, 0.4)))))
    for fid, f in REFERENCE.items():
        np.testing.assert_array_equal(typed_exact[fid], f)
    # as given, it saves as written (coaxial_with, no centre) and reads back the same
    back = scene_from_dict(tomllib.loads(toml_text(to_dict(EXACT, defaults=False))))
    assert back == EXACT and back.as_given("stages")[0].coaxial_with == "wheel"


def test_coaxial_with_a_skew_axis_keeps_the_free_rotation():
    # the whole drive turned to the axis (1, 2, 2)/3: no coordinate of the stage centre is
    # exact, only the construction is; the torsional model still turns freely (1 rigid-body
    # mode) and its frequencies are the axis-aligned ones (a rotation of space changes none)
    tree = copy.deepcopy(COAXIAL)
    axis = [1.0, 2.0, 2.0]
    for b in tree["bodies"]:
        b["axis"] = axis
    tree["stages"][0]["axis"] = axis
    c = compare(scene_from_dict(tree))
    for fid, f in elastic(c).items():
        assert c.results[fid].n_rigid == 1
        np.testing.assert_allclose(f[1:], REFERENCE[fid][1:], rtol=1e-9)


@pytest.mark.parametrize("bad, path, words", [
    (dict(center=[0.0, 0.0, 0.0]), "stages[0].center", "leave center out"),
    (dict(coaxial_with="planetary.sun"), "stages[0].coaxial_with", "stage written before"),
    (dict(axis=[0.0, 1e-3, 1.0]), "stages[0].axis", "off the axis"),
])
def test_coaxial_with_refusals(bad, path, words):
    tree = copy.deepcopy(COAXIAL)
    tree["stages"][0].update(bad)
    with pytest.raises(SceneError) as e:
        scene_from_dict(tree)
    assert e.value.path == path and words in e.value.reason


def test_axial_offset_needs_coaxial_with():
    tree = typed((WHEEL_X, 0.0, 0.4))
    tree["stages"][0]["axial_offset"] = 0.4
    with pytest.raises(SceneError) as e:
        scene_from_dict(tree)
    assert e.value.path == "stages[0].axial_offset"


def _offset(rng: random.Random, size: str) -> np.ndarray:
    """A stage centre ``size`` off the exact one in a random direction: "ulp" moves x or y
    by one unit in the last place of x, otherwise a random unit vector times the size (m)."""
    c = np.array([WHEEL_X, 0.0, 0.4])
    if size == "ulp":   # x to its neighbour, or y (0) by the same step (its own ulp, 5e-324, is no length)
        k, sign = rng.choice((0, 1)), rng.choice((-1.0, 1.0))
        c[k] = math.nextafter(c[k], sign * math.inf) if k == 0 else sign * math.ulp(WHEEL_X)
        return c
    v = np.array([rng.gauss(0, 1) for _ in range(3)])
    return c + float(size) * v / np.linalg.norm(v)


SIZES = ("0", "ulp", "1e-12", "1e-9", "1e-6")
#: A lever arm below this many metres is the coordinates' rounding (1e-10 of the
#: coordinates' magnitude, 0.4 m: assembly.mechanics.nullity.DROP_RTOL): harmless, accepted.
ROUNDING = 1e-10 * 0.4


def _expect(center):
    """(transverse offset of the stage centre from the wheel's axis (m), outcome): accepted
    within the coordinates' rounding; refused naming the stage centre up to a microradian
    over the quill (from the wheel's point (x_w, 0, 0) to the sun's, the stage centre);
    beyond that refused as the quill's alignment."""
    off = float(np.hypot(center[0] - WHEEL_X, center[1]))
    p1, p2 = np.array([WHEEL_X, 0.0, 0.0]), np.asarray(center, float)
    limit = AXIS_TOLERANCE * max(np.linalg.norm(p2 - p1), np.abs(np.r_[p1, p2]).max())
    if off <= 0.5 * ROUNDING:
        return off, "accepted"
    if off > limit:
        return off, "shaft"
    if off > 2 * ROUNDING:
        return off, "centre"
    return off, "either"       # at the rounding threshold: accepted or refused, each checked as such


def _check(outcome: str, off: float, run):
    """Run ``run()`` (a comparison); check it against the outcome expected for ``off``."""
    try:
        c = run()
    except SceneError as exc:
        assert outcome != "accepted", str(exc)
        assert "\n" not in str(exc)
        if exc.path == "stages[0].center":
            assert outcome in ("centre", "either"), str(exc)
            m = re.search(r"sits ([0-9.e+-]+) m off the axis of 'wheel' \(bodies\[1\]\), to which shafts\[0\] "
                          r"\(quill\) joins 'planetary.sun'", exc.reason)
        else:
            assert exc.path == "shafts[0].body2" and outcome in ("shaft", "either"), str(exc)
            m = re.search(r"'planetary.sun' attaches ([0-9.e+-]+) m off the axis line of 'wheel'", exc.reason)
        assert m, str(exc)
        assert float(m.group(1)) == pytest.approx(off, rel=5e-3)
        assert 'coaxial_with = "wheel", axial_offset = ' in exc.reason
        return None
    assert outcome in ("accepted", "either"), f"offset {off:.3g} m accepted"
    for fid, f in elastic(c).items():
        assert c.results[fid].n_rigid == 1
        # a lever arm delta changes a frequency by (delta / 0.4 m)^2 at most: 1e-20 here
        np.testing.assert_allclose(f[1:], REFERENCE[fid][1:], rtol=1e-9)
    return c


N_FUZZ = examples(25)


@pytest.mark.parametrize("seed", range(N_FUZZ))
def test_stage_centre_offsets_api(seed):
    rng = random.Random(seed)
    size = SIZES[seed % len(SIZES)]
    center = _offset(rng, size)
    off, outcome = _expect(center)
    _check(outcome, off, lambda: compare(scene_from_dict(typed(center))))


@pytest.mark.parametrize("size", ["ulp", "1e-9", "1e-6"])
def test_stage_centre_offsets_cli(size, tmp_path, capsys):
    center = _offset(random.Random(7), size)
    off, outcome = _expect(center)
    f = tmp_path / "quill.toml"
    f.write_text(toml_text(typed(center)))
    code = main(["compare", str(f)])
    out, err = capsys.readouterr()
    if outcome == "accepted":
        assert code == 0 and "rigid-body" in out
        return
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("flexgear: error: ")
    assert 'coaxial_with = "wheel"' in lines[0] and f"{off:.3g} m off the axis" in lines[0]


def test_one_ulp_off_is_accepted_by_compare():
    # the shipped scene's stage centre one unit in the last place off the wheel's axis
    center = (math.nextafter(WHEEL_X, 1.0), 0.0, 0.4)
    _check("accepted", abs(center[0] - WHEEL_X), lambda: compare(scene_from_dict(typed(center))))


# ---------------------------------------------------------------- spring shafts off axis
def test_spring_shaft_5mm_off_axis_is_refused():
    # the case: the quill between the wheel and a sun 5 mm off the wheel's axis
    tree = typed((WHEEL_X, 0.005, 0.4))
    with pytest.raises(SceneError) as e:
        scene_from_dict(tree)
    r = e.value.reason
    assert e.value.path == "shafts[0].body2" and e.value.value == "planetary.sun"
    assert "spring shaft 'quill' from 'wheel'" in r and "to 'planetary.sun'" in r
    assert "attaches 0.005 m off the axis line of 'wheel'" in r


def two_discs(offset) -> dict:
    """Two steel discs on bearings joined by a spring shaft 0.5 m long, the second disc
    ``offset`` (m, in the plane normal to the axis) off the first one's axis."""
    disc = {"mass": 10.0, "polar_inertia": 0.05}
    return {"bodies": [dict(name="a", position=[0.0, 0.0, 0.0], **disc),
                       dict(name="b", position=[offset[0], offset[1], 0.5], **disc)],
            "bearings": [{"body": n, "k_radial": 1e9, "k_axial": 1e9, "k_tilt": 1e6} for n in "ab"],
            "shafts": [{"name": "s", "body1": "a", "body2": "b", "k_torsion": 1e5, "k_bending": 1e5,
                        "k_axial": 1e8, "k_shear": 1e7}]}


@pytest.mark.parametrize("seed", range(examples(20)))
def test_spring_shafts_off_axis_refused_as_beams(seed):
    # any offset beyond a microradian over the shaft's length: refused naming both bodies
    # and the offset, as a beam shaft is; within it: accepted
    rng = random.Random(seed)
    size = 10.0 ** rng.uniform(-6.0, -1.0)
    phi = rng.uniform(0.0, 2 * math.pi)
    off = (size * math.cos(phi), size * math.sin(phi))
    for beam in (False, True):
        tree = two_discs(off)
        if beam:
            sh = tree["shafts"][0]
            for k in ("k_torsion", "k_bending", "k_axial", "k_shear"):
                del sh[k]
            sh["diameter"] = 0.05
        length = math.sqrt(0.25 + size * size)
        if size <= 0.99 * AXIS_TOLERANCE * length:
            scene_from_dict(tree)
            continue
        with pytest.raises(SceneError) as e:
            scene_from_dict(tree)
        assert e.value.path == "shafts[0].body2" and e.value.value == "b"
        kind = "beam" if beam else "spring"
        m = re.search(rf"the {kind} shaft 's' from 'a' .* to 'b' .* 'b' attaches ([0-9.e+-]+) m off the axis line of "
                      rf"'a'", e.value.reason)
        assert m and float(m.group(1)) == pytest.approx(size, rel=5e-3), e.value.reason


def test_spring_shaft_off_axis_cli(tmp_path, capsys):
    f = tmp_path / "discs.toml"
    f.write_text(toml_text(two_discs((0.005, 0.0))))
    assert main(["modes", str(f)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("flexgear: error: shafts[0].body2 = 'b': the spring shaft 's' ")
    assert "attaches 0.005 m off the axis line of 'a'" in err[0]
