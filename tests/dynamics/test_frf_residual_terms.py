"""The residual correction of a truncated modal FRF where its inertia, damping and coupling
terms matter (assembly.dynamics.frf, ``_residual`` and the coupling terms of ``_modal``).

A torsional chain, ground -k0- a -k1- b -k2- c, with a light body c on k2: two modes in
the band (22.5 and 45 Hz) and one mode of c against b at f_t = 357 Hz, truncated by the
cutoff ``modes_hz`` = 300 Hz; the band reaches 60 Hz, so f / f_t <= 0.17 there (the
default cutoff, 30 x the band, leaves these terms below what any test sees).

Closed form of what is neglected (module notes of frf.py): a truncated mode r answers with
1 / (lambda_r - w^2 + i w c_r) = (1 / lambda_r) (1 + x_r + x_r^2 / (1 - x_r)), x_r = (w^2 - i
w c_r) / lambda_r; the correction keeps 1 + x_r, whose x_r part is the inertia term w^2 /
lambda_r^2 and the damping term -i w c_r / lambda_r^2. With a diagonal modal damping (modal
ratios, Rayleigh) the modes do not couple, and the error is exactly the sum over the
truncated modes of g_r x_r^2 / ((1 - x_r) lambda_r), g_r = (out phi_r)(phi_r' in): bounded by
sum |g_r| |x_r|^2 / ((1 - |x_r|) lambda_r), of order (f / f_t)^4 for the inertia part.
The tests hold the modal FRF to that bound against the direct solve, and check that the
term under test is at least 5 x the bound, so that a missing or sign-flipped term fails.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.linalg as sla

from assembly import Bearing, Body, Scene, Shaft, assemble
from assembly.analysis.modal import solve_modes
from assembly.dynamics.frf import frequency_response
from assembly.scene.tables import Damping

INF = math.inf
FMAX = 60.0                                   # Hz, top of the band
CUTOFF = 5 * FMAX                             # Hz: between the 45 Hz and the 357 Hz mode
F = np.linspace(0.2, 1.0, 17) * FMAX
OUTS = ["motion:c:spin", "motion:a:spin"]


def _held(name, z, J, **bearing):
    return (Body(name=name, mass=10.0, polar_inertia=J, position=(0, 0, z)),
            Bearing(body=name, k_radial=INF, k_axial=INF, k_tilt=INF, **bearing))


def chain(damping=None, c0=0.0, c1=0.0, c2=0.0, k2=1.0e4) -> Scene:
    (a, ba), (b, bb), (c, bc) = (_held("a", 0, 1.0, k_torsion=4.0e4, c_torsion=c0), _held("b", 1, 0.5),
                                 _held("c", 2, 2.0e-3))
    return Scene(name="chain", bodies=(a, b, c), bearings=(ba, bb, bc), damping=damping,
                 shafts=(Shaft(name="s1", body1="a", body2="b", k_torsion=2.0e4, c_torsion=c1),
                         Shaft(name="s2", body1="b", body2="c", k_torsion=k2, c_torsion=c2)))


def _modes(model):
    """Eigenvalues (rad/s)^2 and mass-normalised shapes of the model's q (scipy, not flexgear)."""
    lam, phi = sla.eigh(model.K.toarray(), model.M.toarray())
    return lam, phi


def _truncation_bound(model, modal_c):
    """Per output: (bound on the error of the first-order residual, the inertia term, the
    damping term), each (n_f,), from the closed form of the module notes; ``modal_c(lam)``
    the diagonal modal damping c_r (1/s) of the modes."""
    lam, phi = _modes(model)
    names = model.dof_names
    t = np.sqrt(lam) / (2 * np.pi) > CUTOFF                      # the truncated modes
    w = 2 * np.pi * F[:, None]
    lt, ct = lam[t][None, :], modal_c(lam)[t][None, :]
    x = (w ** 2 - 1j * w * ct) / lt
    out = {}
    for name in OUTS:
        body = name.split(":")[1]
        g = phi[names.index(f"{body}.rz"), t] * phi[names.index("c.rz"), t]     # input: torque on c
        bound = (np.abs(g) * np.abs(x) ** 2 / ((1 - np.abs(x)) * lt)).sum(axis=1)
        inertia = np.abs((g * w ** 2 / lt ** 2).sum(axis=1))
        damping = np.abs((g * w * ct / lt ** 2).sum(axis=1))
        out[name] = bound, inertia, damping
    return out


def _errors(model, modes_hz=CUTOFF, freqs=F, outs=OUTS):
    res = solve_modes(model)
    ref = frequency_response(model, "torque:c", outs, freqs, method="direct", result=res)
    got = frequency_response(model, "torque:c", outs, freqs, result=res, modes_hz=modes_hz)
    return ({k: np.abs(got.outputs[k] - ref.outputs[k]) for k in outs},
            {k: np.abs(ref.outputs[k]) for k in outs}, res)


def test_the_mode_set_truncates_one_mode_near_the_band():
    lam, _ = _modes(assemble(chain()))
    f = np.sqrt(lam) / (2 * np.pi)
    assert f[1] < CUTOFF < f[2] and 0.15 < FMAX / f[2] < 0.2


def test_inertia_term_of_the_residual():
    """Light modal damping (zeta = 0.01): the inertia term w^2 / lambda^2 is the correction;
    the error left is the closed-form remainder, of order (f / f_t)^4."""
    zeta = 0.01
    model = assemble(chain(Damping(modal_ratio=zeta)))
    err, ref, _ = _errors(model)
    for name, (bound, inertia, _) in _truncation_bound(model, lambda lam: 2 * zeta * np.sqrt(lam)).items():
        # round-off of the direct solve: a few eps x cond (cond ~ lambda_max / w^2 < 1e4 here)
        assert np.all(err[name] <= bound * (1 + 1e-6) + 1e-12 * ref[name]), name
        assert np.all(inertia >= 5 * bound), name                   # the term is what holds it


def test_damping_term_of_the_residual():
    """Rayleigh damping beta K (c_r = beta lambda_r: the truncated mode as damped, relative
    to its stiffness, as the kept ones): beta w = 0.05 at the top of the band, so the
    damping term -i w c_r / lambda_r^2 outweighs the inertia term there and the remainder."""
    beta = 0.05 / (2 * np.pi * FMAX)
    model = assemble(chain(Damping(rayleigh_beta=beta)))
    err, ref, _ = _errors(model)
    for name, (bound, _, damping) in _truncation_bound(model, lambda lam: beta * lam).items():
        assert np.all(err[name] <= bound * (1 + 1e-6) + 1e-12 * ref[name]), name
        assert np.all(damping >= 5 * bound), name


def test_damping_coupling_terms_leave_an_error_of_second_order():
    """Dampers on the ground bearing and both shafts (not proportional): the kept and the
    truncated modes couple through the damping, to first order in eps = (w^2 + w |C|) /
    lambda_t, which the correction carries (module notes); what it leaves is of order eps^2.
    Stiffening k2 nine-fold raises lambda_t nine-fold (the light body c barely moves the kept
    modes) and divides eps by 9: an error of second order falls by 81 or more, one of first
    order -- a coupling term missing or of the wrong sign -- by about 9. Required: 27 =
    9^1.5, pointwise over the band, for motions and for the internal load of the damped
    shaft (whose damper part enters the outputs)."""
    outs = ["motion:c:spin", "motion:a:spin", "torque:s2", "torque:s1"]
    soft, _, _ = _errors(assemble(chain(None, 50.0, 20.0, 2.0)), outs=outs)
    stiff, _, _ = _errors(assemble(chain(None, 50.0, 20.0, 2.0, k2=9.0e4)), outs=outs)
    for name in outs:
        assert np.all(soft[name] >= 27 * stiff[name]), (name, np.min(soft[name] / stiff[name]))


def test_damping_coupling_at_a_kept_resonance():
    """One damper, on k2 only: its rank-one modal damping C = c v v' couples the kept and
    truncated modes fully (C_kt^2 = c_kk c_tt), and at a kept resonance the coupling's share
    of the kept modes' damping, w C_kt^2 / (lambda_t c_kk) = w c_tt / lambda_t = eps_d, is
    first order: the correction's kept-mode term (the mass change w^2 C_kt C_tk / lambda_t)
    must be there, and the error left is of order eps^2 of the resonant response."""
    model = assemble(chain(None, 0.0, 0.0, 5.0))
    lam, phi = _modes(model)
    names = model.dof_names
    d = phi[names.index("b.rz")] - phi[names.index("c.rz")]          # the damper's modal row
    c_tt = 5.0 * d[2] ** 2
    fn = np.sqrt(lam[:2]) / (2 * np.pi)                              # the kept resonances
    w = 2 * np.pi * fn
    eps = w * c_tt / lam[2]
    assert np.all((eps > 0.05) & (eps < 0.2))                       # first order visible, series converges
    err, ref, _ = _errors(model, freqs=fn, outs=["motion:c:spin", "motion:b:spin", "torque:s2"])
    for name in err:
        assert np.all(err[name] <= eps ** 2 / (1 - eps) * ref[name]), (name, err[name] / ref[name], eps)


def test_a_long_frequency_list_gives_each_frequency_its_own_answer():
    """The superposition runs in blocks of frequencies (frf.BLOCK); the answer at a frequency
    does not depend on which others are asked for: 2.5 blocks of frequencies at once equal
    each frequency alone, for the diagonal and the state-space (dampers) paths."""
    from assembly.dynamics.frf import BLOCK
    f = np.linspace(1.0, FMAX, int(2.5 * BLOCK))
    pick = np.array([0, BLOCK - 1, BLOCK, BLOCK + 7, 2 * BLOCK + 3, len(f) - 1])
    for scene in (chain(Damping(modal_ratio=0.02)), chain(None, 50.0, 20.0, 2.0)):
        model = assemble(scene)
        res = solve_modes(model)
        every = frequency_response(model, "torque:c", OUTS, f, result=res, modes_hz=CUTOFF)
        alone = frequency_response(model, "torque:c", OUTS, f[pick], result=res, modes_hz=CUTOFF)
        for name in OUTS:
            np.testing.assert_allclose(every.outputs[name][pick], alone.outputs[name], rtol=1e-12)


def test_the_frf_reports_the_models_natural_frequencies():
    """FRF.natural_hz: the undamped elastic natural frequencies, sqrt(lambda) / (2 pi) of the
    model's own eigenproblem K phi = lambda M phi (scipy here), as the FRF's modal cutoff
    counts them."""
    model = assemble(chain(Damping(modal_ratio=0.01)))
    lam, _ = _modes(model)
    r = frequency_response(model, "torque:c", OUTS, F, modes_hz=CUTOFF)
    np.testing.assert_allclose(r.natural_hz, np.sqrt(lam) / (2 * np.pi), rtol=1e-10)
