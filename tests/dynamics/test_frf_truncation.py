"""Modal truncation with the residual correction (assembly.dynamics.frf, ``modes_hz``).

The NREL 5 MW drivetrain (rigid gearbox bodies, 126 DOFs, modes up to 6.7 kHz) carries
Nejad et al.'s (2016) bearing dampers: its damping is not proportional, so the kept and
truncated modes are coupled by damping as well as by their static flexibility. Modes up to
30 x 50 Hz (the default cutoff, 96 of the 126) are superposed; the 30 above answer
quasi-statically. The error of that correction is of order (f / f_r)^4 of the truncated
modes' share and (w C_kt / lambda_t)^2 of the damping coupling, both below 1e-6 here,
against the direct solve of the whole model (whose own error, eps x cond, is ~1e-8 at
0.5 Hz). Plain truncation misses the static flexibility of 30 modes: a visible error.
"""
from __future__ import annotations

import numpy as np
import pytest

from assembly import SceneError, assemble
from assembly.analysis.modal import solve_modes
from assembly.dynamics.frf import frequency_response
from assembly.scene.schema import load_scene

FMAX = 50.0                                                             # Hz


@pytest.fixture(scope="module")
def drivetrain():
    model = assemble(load_scene("nrel5mw.toml"))
    return model, solve_modes(model)


def _outputs(model):
    return (["torque:" + e.name for e in model.elements if e.kind == "shaft"]
            + ["force:" + e.name for e in model.elements if e.kind == "mesh"])


def _scaled_error(r, ref):
    """Largest |H - H_ref| over the band, per output relative to that output's peak |H_ref|."""
    return max(np.max(np.abs(r.outputs[k] - ref.outputs[k])) / np.max(np.abs(ref.outputs[k])) for k in ref.outputs)


def test_residual_correction_against_direct_solve(drivetrain):
    model, res = drivetrain
    f = np.geomspace(FMAX / 100, FMAX, 300)
    nat = res.frequencies_hz[res.n_rigid:]
    kept = int(np.searchsorted(res.frequencies_hz, 30 * FMAX, side="right"))
    assert 0 < kept < len(res.frequencies_hz)                             # modes are truncated
    ref = frequency_response(model, "torque:generator", _outputs(model), f, method="direct", result=res)
    got = frequency_response(model, "torque:generator", _outputs(model), f, result=res)
    plain = frequency_response(model, "torque:generator", _outputs(model), f, result=res, residual=False)
    assert _scaled_error(got, ref) <= 1e-6
    assert _scaled_error(plain, ref) >= 1e-5                              # the correction is what holds it
    # pointwise, away from resonances (5 %) and from anti-resonances (|H| > 1 % of its peak)
    away = np.array([np.min(np.abs(nat / x - 1)) > 0.05 for x in f])
    for k, h in ref.outputs.items():
        ok = away & (np.abs(h) > 0.01 * np.abs(h).max())
        assert np.all(np.abs(got.outputs[k][ok] - h[ok]) <= 1e-6 * np.abs(h[ok])), k


def test_every_mode_kept_is_the_full_superposition(drivetrain):
    model, res = drivetrain
    f = np.geomspace(1.0, 20.0, 50)
    a = frequency_response(model, "torque:generator", _outputs(model), f, result=res, modes_hz=np.inf)
    b = frequency_response(model, "torque:generator", _outputs(model), f, result=res,
                           modes_hz=2 * res.frequencies_hz[-1])
    assert all(np.array_equal(a.outputs[k], b.outputs[k]) for k in a.outputs)


@pytest.mark.parametrize("bad", [0.0, -10.0, float("nan")])
def test_bad_cutoff_names_it(drivetrain, bad):
    model, res = drivetrain
    with pytest.raises(SceneError) as err:
        frequency_response(model, "torque:generator", ["torque:" + _outputs(model)[0].split(":", 1)[1]], [1.0],
                           result=res, modes_hz=bad)
    assert err.value.path == "modes_hz"
