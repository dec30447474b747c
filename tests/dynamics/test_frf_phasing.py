"""Parker's mesh-phasing rule reproduced by the frequency response of a planetary stage.

Lin & Parker's stage with N = 5 equally spaced planets (the shipped ``lin_parker_n5``, 2 %
modal damping added) is driven at harmonic h of the sun mesh: planet n's sun-mesh force
(``mesh:stage.sun-planetN``, a transmission-error force pair) lags by h Z_s psi_n, psi_n the
planet's angle. The response is the phased sum of the five single-mesh FRFs. Parker (2000,
J. Sound Vib. 236(4), 561-573): with m = h Z_s mod N, the central members feel a net torque
only (m = 0: rotational modes), a net force only (m = +-1: translational modes) or nothing
(otherwise: planet modes). So the sun's rotation (only in rotational modes) is zero unless
m = 0, its translation zero unless m = +-1, and for m = 2, 3 sun and carrier stay at rest:
no rotational or translational peak at all, while the planets move. "Zero" is relative to the
same output under the in-phase excitation (round-off of a sum of 5 terms, ~1e-15; bound 1e-10).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly import assemble
from assembly.analysis.classify import classify_modes
from assembly.analysis.modal import solve_modes
from assembly.dynamics.frf import frequency_response
from assembly.dynamics.phasing import excited_class
from assembly.scene.schema import load_scene

N, Z_SUN = 5, 23                        # planets; sun teeth (any Z_s: only h Z_s mod N matters)
SUN = ("motion:stage.sun:rz", "motion:stage.sun:x", "motion:stage.sun:y")
CARRIER = ("motion:stage.carrier:rz", "motion:stage.carrier:x")
PLANET = ("motion:stage.planet0:rz",)


@pytest.fixture(scope="module")
def stage():
    model = assemble(load_scene("lin_parker_n5.toml").with_values({"damping": {"modal_ratio": 0.02}}))
    res = solve_modes(model)
    classes = {c.index: c.mode_class for c in classify_modes(res, nodal_diameters=False)}
    rot = [res.frequencies_hz[i] for i, c in classes.items() if c == "rotational" and i >= res.n_rigid]
    # every rotational mode hit, with points 10 % either side (the half-power band at 2 % is +-2 %)
    f = np.unique(np.concatenate([np.geomspace(50.0, 5000.0, 200), rot, 0.9 * np.array(rot), 1.1 * np.array(rot)]))
    psi = [math.atan2(*model.bodies[f"stage.planet{n}"].position[1::-1]) for n in range(N)]
    single = [frequency_response(model, f"mesh:stage.sun-planet{n}", SUN + CARRIER + PLANET, f, result=res)
              for n in range(N)]
    return f, rot, psi, single


def _phased(stage, h):
    f, rot, psi, single = stage
    w = [np.exp(-1j * h * Z_SUN * p) for p in psi]
    return {k: sum(wn * r.outputs[k] for wn, r in zip(w, single)) for k in single[0].outputs}


HARMONICS = range(1, 2 * N + 1)


@pytest.fixture(scope="module")
def scale(stage):
    """Per output, the largest response over every harmonic: the size "zero" is judged by."""
    peaks = [{k: np.max(np.abs(v)) for k, v in _phased(stage, h).items()} for h in HARMONICS]
    return {k: max(p[k] for p in peaks) for k in peaks[0]}


def test_in_phase_harmonic_peaks_at_every_rotational_mode(stage):
    """The positive half: a harmonic allowed to reach the rotational modes peaks at each."""
    f, rot, _, _ = stage
    h = N                                                               # h Z_s = 0 mod N
    assert excited_class(h, Z_SUN, N) == "rotational"
    # the carrier's rotation (the sun, driven at its own mesh, shows anti-resonances beside its peaks)
    spin = np.abs(_phased(stage, h)["motion:stage.carrier:rz"])
    at = lambda x: spin[np.argmin(np.abs(f - x))]
    assert len(rot) >= 2
    assert all(at(fr) > max(at(0.9 * fr), at(1.1 * fr)) for fr in rot)    # a local peak at each


@pytest.mark.parametrize("h", HARMONICS)
def test_phasing_rule_by_frf(stage, scale, h):
    H = _phased(stage, h)
    zero = {k: np.max(np.abs(v)) <= 1e-10 * scale[k] for k, v in H.items()}
    cls = excited_class(h, Z_SUN, N)
    assert zero["motion:stage.sun:rz"] == zero["motion:stage.carrier:rz"] == (cls != "rotational")
    assert zero["motion:stage.sun:x"] == zero["motion:stage.sun:y"] == (cls != "translational")
    assert zero["motion:stage.carrier:x"] == (cls != "translational")
    assert not zero["motion:stage.planet0:rz"]                         # the planets always move

