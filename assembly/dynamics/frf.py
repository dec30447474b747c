"""Frequency response functions of an assembled model with its damping.

The model ``M q'' + C q' + K q = f e^{i omega t}`` (``C`` the element dampers plus the
scene's Rayleigh and modal ratios, :mod:`assembly.dynamics.damping`) answers with
``q = H(omega) f``; inputs and outputs are the channels of
:mod:`assembly.dynamics.frf_channels` (outputs ``(r_k + i omega r_c) q``: section loads
from the springs and dampers, with each element's share of the scene's damping,
:mod:`assembly.dynamics.damping`).

``method="modal"`` (default): superposition over the modes of the model. In the
undamped modal coordinates ``q = Phi y`` (``Phi' M Phi = I``, ``Phi' K Phi = Lambda``) the
problem is ``(Lambda - omega^2 I + i omega C_m) y = Phi' f``:

* a diagonal ``C_m`` (modal ratios, Rayleigh, proportional dampers): every mode on its own,
  ``y_r = phi_r' f / (lambda_r - omega^2 + i omega c_r)``;
* otherwise the complex modes of the first-order (state) form, its state scaled as
  ``u = [Omega y; y']`` (entries of the size omega, not omega^2):
  ``A = [[0, Omega], [-Omega, -C_m]]`` (:func:`assembly.dynamics.damped_modes.state_form`),
  and by the partial fractions of the symmetric quadratic pencil ``H(omega) = sum_r (out y_r)
  (y_r' in) / (a_r (i omega - s_r))``, ``a_r = y_r' (C_m + 2 s_r I) y_r``, vectorised over
  frequencies.

Rigid-body modes (s = 0) that no damper acts on (``C_m`` rows at round-off, as
:mod:`assembly.dynamics.damped_modes` decides) stay out of the state form: their term is
exactly ``-1/omega^2 (out phi_r)(phi_r' in)``, finite for omega > 0, so a free-free
drivetrain has a finite response; no pseudo-inverse, no zeroed matrix. A section load
vanishes in every rigid-body mode (no spring is strained: ``phi_r' K phi_r = sum_e k_e
(B_e phi_r)^2 = 0``, and a flexible body moves rigidly), so its rigid-body residue is zero
by structure and is set so: computed, it is round-off that the ``1/omega^2`` would blow up
(a section load of a free drivetrain at 1e-5 Hz was 1 % off). Section loads at low
frequency are thus the elastic modes' quasi-static sum, the inertia-relief static load.

Modal truncation (``modes_hz``): only the modes up to ``modes_hz`` enter the sums above;
the modes left out (set T) answer quasi-statically, by the residual-flexibility term with
its first inertia and damping correction (the expansion of ``1/(lambda_r - omega^2 + i
omega c_r)`` to first order in ``(omega^2 - i omega c_r) / lambda_r``):

    q_T(omega) = sum_{r in T} phi_r (phi_r' f) [1/lambda_r + (omega^2 - i omega c_r) / lambda_r^2]

(``c_r`` the diagonal of ``C_m``; the damping coupling between kept and truncated modes is
taken to first order, :func:`_modal`). For an undamped mode at ``omega_r`` the term's
error is ``x^2 / (1 - x)`` of that mode's static share, ``x = (omega/omega_r)^2``: with
the default cutoff, :data:`MODAL_CUTOFF_FACTOR` x the highest frequency asked, below 1.3e-6;
it diverges as ``omega`` reaches ``omega_r``. A cutoff below :data:`MIN_CUTOFF_RATIO` x
the highest frequency asked (a mode just above it would be off by more than 8 % of its
static share, or diverge) is refused; one whose lowest left-out mode gives a bound above
:data:`CUTOFF_WARN` draws a warning with it. ``modes_hz=inf`` keeps every mode
(exact). Models above :data:`assembly.analysis.modal.DENSE_MAX` DOFs have no full modal basis: use
``method="direct"``.

``method="direct"``: the reference, ``(K - omega^2 M + i omega C) q = f`` solved per
frequency (dense LU on the mass-diagonal-scaled matrix), ``C`` on q including the Rayleigh
part ``alpha (M - M Phi_r Phi_r' M) + beta K`` and the modal ratios
``M Phi diag(2 zeta omega) Phi' M`` (exact for a model holding every mode). Its round-off
is about eps x cond; for a free drivetrain cond grows as ``lambda_max / omega^2`` at low
frequency, so a bound above :data:`DIRECT_RTOL` draws a warning naming the frequency below
which the modal method should be used.

No wrong number without a word: 0 Hz on a model with a rigid-body mode is refused (either
method); a response that is not finite (an undamped mode hit exactly, a frequency whose
square overflows) is refused naming the frequency; elastic modes inside the frequencies
asked that no damper or ratio damps are named in a warning (``FRF.warnings``), as are the
cutoff and round-off bounds above.
"""
from __future__ import annotations

import dataclasses
import logging
import time
import warnings
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
from threadpoolctl import threadpool_limits

from ..analysis.modal import SMALL_DENSE, modes_argument
from ..errors import SceneError, SolverError
from ..mechanics.nullity import rigid_body_count, rigid_body_modes
from ..model.assemble import model_argument, sparse_model
from .damped_modes import RIGID_RTOL, state_form
from .damping import damping_in_modes, damping_on_q, needs_modes, section_factors, section_share
from .frf_channels import Channel, input_channel, output_channels, output_rows, von_mises_peak
from .modal_ratios import mode_ratios

log = logging.getLogger(__name__)

METHODS = ("modal", "direct")
#: Frequencies per block of the vectorised superposition (bounds the n_f x 2n work array).
BLOCK = 2048
#: Default modal cutoff: modes up to this multiple of the highest frequency asked are
#: superposed, the rest enter by their residual flexibility (module notes).
MODAL_CUTOFF_FACTOR = 30.0
#: The lowest mode left out by the modal cutoff must lie at least this multiple above the
#: highest frequency asked: at 2x its residual term is off by 8.3 % of its static share
#: (module notes), and the series diverges as the frequency reaches the mode.
MIN_CUTOFF_RATIO = 2.0
#: Frequencies from this one up (Hz) have an angular frequency squared that overflows a double.
MAX_FREQUENCY_HZ = 0.25 * float(np.sqrt(np.finfo(float).max)) / np.pi
#: A cutoff whose residual-term bound at the highest frequency asked exceeds this draws a
#: warning (the bound is 1.2e-6 at the default cutoff, 1e-3 at 5.6 x fmax).
CUTOFF_WARN = 1e-3
#: A direct solve whose round-off bound eps x cond exceeds this draws a warning.
DIRECT_RTOL = 1e-6
#: An elastic mode whose damping ratio is below this counts as undamped (round-off of a
#: damping matrix that does not act on it).
UNDAMPED_ZETA = 1e-9
#: Bytes an FRF takes a frequency (omega, its powers) and a frequency and output channel (the
#: response and the residual terms: a few complex arrays); measured: 81 B a frequency with one
#: channel (nrel5mw, 1e6 frequencies, whole process).
FRF_BYTES = (64, 96)


def check_frf_size(n_freq: int, n_channels: int) -> None:
    """SceneError at ``len(frequency_hz)`` when ``n_freq`` frequencies of ``n_channels``
    output channels (a stress output has six) exceed the memory budget
    (:func:`assembly.dynamics.budget.check_memory`)."""
    from .budget import check_memory
    check_memory("len(frequency_hz)", n_freq, float(n_freq) * (FRF_BYTES[0] + FRF_BYTES[1] * n_channels),
                 f"{n_freq:.3g} frequencies x {n_channels} output channels", "fewer frequencies or outputs")


@dataclass(frozen=True)
class FRF:
    """Frequency response of one input: ``frequency_hz`` (n_f,), ``outputs`` {output name:
    complex array (n_f,)} per unit input, ``units`` {output name: "out unit/(in unit)"},
    ``natural_hz``: the undamped elastic natural frequencies (Hz), ``method`` and ``time_s``
    of the solve, ``warnings``: what limits the result's accuracy (module notes)."""

    input: str
    frequency_hz: np.ndarray
    outputs: dict
    units: dict
    natural_hz: np.ndarray = field(default_factory=lambda: np.zeros(0))
    method: str = "modal"
    time_s: float = 0.0
    warnings: tuple = ()


def frequency_response(model, input: str, outputs, frequency_hz, method: str = "modal", result=None,
                       modes_hz: float | None = None, residual: bool = True) -> FRF:
    """FRF of ``model`` from ``input`` to each of ``outputs`` (names of
    :mod:`assembly.dynamics.frf_channels`) at ``frequency_hz`` (Hz, >= 0; > 0 when the
    model has a rigid-body mode). ``result``: the model's :class:`assembly.analysis.modal.ModalResult`
    with every mode, if already solved. ``modes_hz`` (Hz): the modal cutoff of
    ``method="modal"`` (module notes); default :data:`MODAL_CUTOFF_FACTOR` x ``max(frequency_hz)``,
    ``inf`` for every mode; ``residual=False`` drops the modes above it altogether (plain
    truncation, to see what the correction buys). SceneError for a cutoff that cannot be
    accurate, for 0 Hz on a free model and for a response that is not finite."""
    from .. import arguments as check  # each argument's kind, one SceneError naming it
    model = sparse_model(model_argument("model", model))
    check.text("input", input)
    outputs = check.names("outputs", outputs)
    frequency_hz = check.frequencies("frequency_hz", frequency_hz)
    check.one_of("method", method, METHODS, "method")
    check.optional(modes_argument, "result", result)
    check.optional(check.number, "modes_hz", modes_hz, "Hz", gt=0.0, infinite="every mode")
    check.flag("residual", residual)
    t0 = time.perf_counter()
    f = np.atleast_1d(np.asarray(frequency_hz, float))
    if method not in METHODS:
        raise SceneError("method", method, f"must be one of {list(METHODS)}")
    if f.size == 0 or not np.all(np.isfinite(f)) or np.any(f < 0):
        raise SceneError("frequency_hz", f.tolist()[:4], "frequencies must be finite and >= 0 Hz")
    if not f.max() < MAX_FREQUENCY_HZ:
        raise SceneError("frequency_hz", float(f.max()), "its angular frequency squared overflows a double: no "
                                                          "response can be computed there")
    if modes_hz is None:
        modes_hz = MODAL_CUTOFF_FACTOR * float(f.max()) if f.max() > 0 else np.inf
    if not (modes_hz > 0):
        raise SceneError("modes_hz", modes_hz, "the modal cutoff must be a frequency > 0 Hz")
    if method == "modal" and residual:
        cutoff_check(modes_hz, float(f.max()))
    if isinstance(outputs, str):
        outputs = [outputs]
    src = input_channel(model, input)
    outs = [c for name in outputs for c in output_channels(model, name)]
    check_frf_size(f.size, len(outs))
    omega = 2 * np.pi * f
    if np.any(omega == 0) and (result.n_rigid if result is not None else rigid_body_count(model)):
        raise SceneError("frequency_hz", 0.0, "the model has a free rigid-body mode: its response at 0 Hz is "
                                              "unbounded; use frequencies > 0")
    notes = []
    # one BLAS thread for small models, as the modal solve (assembly.analysis.modal.SMALL_DENSE)
    with threadpool_limits(1 if model.K.shape[0] <= SMALL_DENSE else None):
        if method == "modal":
            result = low_accurate(result if result is not None else _every_mode(model))
            notes += cutoff_warnings(result, modes_hz, float(f.max()) if residual else 0.0)
            H = _modal(result, src, outs, omega, modes_hz, residual)
        else:
            if result is None:
                result = _every_mode(model) if needs_modes(model) else _modes_for_checks(model)
            if needs_modes(model):
                result = low_accurate(result)
            H, rtol = _direct(model, result, src, outs, omega)
            if rtol > DIRECT_RTOL:
                notes.append(f"direct solve: round-off up to {rtol:.2g} of the response at the lowest frequency "
                             f"({f.min():.4g} Hz): a damped rigid-body mode leaves the dynamic stiffness nearly "
                             "singular there; use method 'modal'")
    H = H * np.where([c.derivative == 2 for c in outs], -(omega ** 2)[:, None], 1.0)
    if result is not None:
        notes += undamped_warnings(result, f)
    _check_finite(H, f, outs, result)
    natural = np.zeros(0) if result is None else result.frequencies_hz[result.n_rigid:]
    values, units = {}, {}
    per = f"({src.unit})" if " " in src.unit else src.unit
    for j, c in enumerate(outs):
        if c.group is None:
            values[c.name], units[c.name] = H[:, j], f"{c.unit}/{per}"
        elif c.group not in values:                                  # von Mises of its six components
            cols = [i for i, o in enumerate(outs) if o.group == c.group]
            values[c.group] = von_mises_peak(H[:, cols]).astype(complex)
            units[c.group] = f"{c.unit}/{per}"
    for w in notes:
        log.warning("FRF %s: %s", input, w)
    dt = time.perf_counter() - t0
    log.info("FRF %s -> %d outputs, %d frequencies, %s: %.3f s", input, len(values), len(f), method, dt)
    return FRF(input, f, values, units, natural, method, dt, tuple(notes))


def cutoff_check(modes_hz: float, fmax_hz: float, lowest_left_out_hz: float | None = None) -> list:
    """Refuse a modal cutoff below :data:`MIN_CUTOFF_RATIO` x ``fmax_hz`` (SceneError at
    ``modes_hz``: the modes left out could lie where their residual term is off by more
    than 8 % of their static share, or diverges), or list the warning of one whose
    residual-term bound at ``fmax_hz`` exceeds that of the default cutoff.
    ``lowest_left_out_hz``: the lowest mode above the cutoff (default: the cutoff itself,
    the worst case before the modes are known)."""
    if not fmax_hz > 0 or not np.isfinite(modes_hz):
        return []
    if modes_hz < MIN_CUTOFF_RATIO * fmax_hz:
        raise SceneError("modes_hz", modes_hz,
                         f"below {MIN_CUTOFF_RATIO:g} x the highest frequency asked ({fmax_hz:.6g} Hz): a mode left "
                         f"out just above the cutoff answers with a residual term off by "
                         f"{_residual_bound(fmax_hz / modes_hz):.3g} of its static share there (inf: the series "
                         f"diverges); use at least {MODAL_CUTOFF_FACTOR:g} x {fmax_hz:.6g} Hz (the default), or inf")
    f_t = modes_hz if lowest_left_out_hz is None else lowest_left_out_hz
    bound = _residual_bound(fmax_hz / f_t)
    if bound > CUTOFF_WARN:
        return [f"modal cutoff {modes_hz:.6g} Hz: the modes left out (from {f_t:.6g} Hz) answer with an error up "
                f"to {bound:.2g} of their static share at {fmax_hz:.6g} Hz (the default cutoff, "
                f"{MODAL_CUTOFF_FACTOR:g} x fmax: {_residual_bound(1.0 / MODAL_CUTOFF_FACTOR):.2g})"]
    return []


def _residual_bound(ratio: float) -> float:
    """Relative error ``x^2 / (1 - x)`` (``x = ratio^2``) of the residual term of an
    undamped mode at ``ratio`` = frequency / mode frequency (module notes); inf at >= 1."""
    x = ratio * ratio
    return x * x / (1.0 - x) if x < 1.0 else np.inf


def cutoff_warnings(result, modes_hz: float, fmax_hz: float) -> list:
    """:func:`cutoff_check` with the lowest mode ``result`` leaves out above ``modes_hz``."""
    f = result.frequencies_hz[result.n_rigid:]
    out = f[f > modes_hz]
    return cutoff_check(modes_hz, fmax_hz, float(out[0]) if out.size else None) if out.size else []


def undamped_warnings(result, f_hz: np.ndarray) -> list:
    """A warning naming the elastic modes within the frequencies asked (``f_hz`` from its
    lowest to its highest) whose damping ratio is below :data:`UNDAMPED_ZETA`: the
    response at them is unbounded, between them it depends on the frequency grid."""
    r = result.n_rigid
    fr = result.frequencies_hz[r:]
    inside = np.flatnonzero((fr >= f_hz.min() * (1 - 1e-6)) & (fr <= f_hz.max() * (1 + 1e-6)))
    if not inside.size:
        return []
    # C symmetric positive semi-definite: phi' C phi = 0 means C phi = 0, no coupling either
    c = np.diag(damping_in_modes(result, mode_ratios(result)))[r + inside]
    zeta = c / (2 * 2 * np.pi * fr[inside])
    bad = inside[zeta < UNDAMPED_ZETA]
    if not bad.size:
        return []
    names = ", ".join(f"{r + i + 1} ({fr[i]:.6g} Hz)" for i in bad[:8]) + (" ..." if bad.size > 8 else "")
    return [f"{bad.size} mode(s) in the band asked have no damping: {names}; the response at them is unbounded "
            "(add element dampers or a [damping] table)"]


def _check_finite(H: np.ndarray, f: np.ndarray, outs: list, result) -> None:
    """SceneError at the first frequency where the response is not finite, with the cause."""
    bad = ~np.all(np.isfinite(H), axis=1)
    if not bad.any():
        return
    j = int(np.argmax(bad))
    if not np.isfinite((2 * np.pi * f[j]) ** 2 * 1e3):
        why = "its angular frequency squared overflows"
    elif result is not None:
        fr = result.frequencies_hz[result.n_rigid:]
        k = int(np.argmin(np.abs(fr - f[j]))) if fr.size else -1
        why = (f"it is the natural frequency of mode {result.n_rigid + k + 1} ({fr[k]:.6g} Hz), which has no damping"
               if k >= 0 and abs(fr[k] - f[j]) <= 1e-6 * fr[k] else "the solve overflowed")
    else:
        why = "the solve overflowed"
    raise SceneError("frequency_hz", float(f[j]), f"the response is not finite there: {why}")


def _every_mode(model):
    """Every mode of ``model`` for the modal method (SceneError naming the method when the
    model has too many DOFs for them)."""
    from ..analysis.modal import solve_modes
    res = solve_modes(model)
    if res.shapes.shape[1] < model.K.shape[0]:
        raise SceneError("method", "modal", f"the model has {model.K.shape[0]} DOFs and only "
                                            f"{res.shapes.shape[1]} modes: use method='direct'")
    return res


def _modes_for_checks(model):
    """The modes a direct solve reports and checks its frequencies against (natural
    frequencies, undamped modes): every mode of a model that has a dense modal solve,
    else None."""
    from ..analysis.modal import DENSE_MAX, solve_modes
    return solve_modes(model) if model.K.shape[0] <= DENSE_MAX else None


def low_accurate(result):
    """``result`` with its modes solved again from the inverted pencil ``M v = mu (K +
    sigma M) v`` (``lambda = 1/mu - sigma``, ``sigma`` the lowest elastic eigenvalue, scaled to
    a unit mass diagonal). The direct pencil resolves each eigenvalue to ~eps x lambda_max
    absolute, so a 1.8 Hz rotor mode beside 2.4e4 Hz bodies only to ~1e-6 relative, and an
    FRF at that lightly damped resonance is off by ~1e-6 / zeta. The inverted pencil resolves
    them to ~eps x (lambda + sigma) / sigma: the low modes, which an FRF needs exactly, to a
    few eps; a mode at f to eps (f / f_1)^2 (4e-8 at 2.4e4 Hz beside 1.8 Hz). Rigid-body
    modes keep their count (the structural one of ``result``) and eigenvalue 0. Solved once
    per result (kept in ``result.memo``), as a study calls the FRF many times on one model."""
    model, r = result.model, result.n_rigid
    if len(result.eigenvalues) <= r or result.shapes.shape[1] < model.K.shape[0]:
        return result
    if result.memo.get("inverted") is not None:
        return result.memo["inverted"]
    u = 1.0 / np.sqrt(model.M.diagonal())
    K = u[:, None] * model.K.toarray() * u
    M = u[:, None] * model.M.toarray() * u
    sigma = float(result.eigenvalues[r])
    if not sigma > 0:
        return result
    mu, V = sla.eigh(M, K + sigma * M)
    mu, V = mu[::-1], V[:, ::-1]                                      # descending mu: ascending lambda
    lam = 1.0 / mu - sigma
    lam[:r] = 0.0
    Phi = u[:, None] * (V / np.sqrt(mu)[None, :])                     # mass-normalised on q
    f = np.sqrt(np.maximum(lam, 0.0)) / (2 * np.pi)
    refined = dataclasses.replace(result, eigenvalues=lam, frequencies_hz=f, shapes=Phi,
                                  abs_shapes=np.asarray(model.T @ Phi), info=dict(result.info), memo={})
    result.memo["inverted"] = refined
    return refined


def _rigid_free(C: np.ndarray, n_rigid: int) -> int:
    """How many leading (rigid-body) modes no damper acts on: all ``n_rigid`` or none."""
    scale = np.abs(C).max(initial=0.0)
    return n_rigid if n_rigid and np.abs(C[:n_rigid]).max() <= RIGID_RTOL * scale else 0


def _modal_outputs(result, outs: list, ratios: np.ndarray, undamped_rigid: int):
    """``(Ok, Oc)``: the outputs' spring and damper rows on the modal coordinates. A
    section load's rows vanish in every rigid-body mode (module notes: its spring part in
    all of them, its damper part in those no damper acts on) and its damper part takes the
    scene's damping share ``Ok_r d_r / lambda_r`` (:func:`assembly.dynamics.damping.section_factors`)."""
    Ok, Oc = (O @ result.shapes for O in output_rows(outs))
    sec = np.array([c.section for c in outs], bool)
    if sec.any():
        Ok[sec, :result.n_rigid] = 0.0
        Oc[sec, :undamped_rigid] = 0.0
        Oc[sec] = Oc[sec] + Ok[sec] * section_factors(result, ratios)[None, :]
    return Ok, Oc


def _modal(result, src: Channel, outs: list, omega: np.ndarray, modes_hz: float = np.inf,
           residual: bool = True) -> np.ndarray:
    """(n_f x n_out) superposition over the modes up to ``modes_hz`` (set k), the rest (set
    t) by their residual flexibility, damping coupling included to first order (module
    notes): ``y_t = L_t^-1 (p_t - i w C_tk y_k) + L_t^-1 (w^2 - i w C_tt) L_t^-1 p_t``, so
    the kept modes see the input ``p_k - i w C_kt L_t^-1 p_t`` and the outputs read
    ``O_k - i w O_t L_t^-1 C_tk`` on ``y_k``. Every term is a power of ``i w`` times a
    modal gain: ``H = sum_j (i w)^j G R_j``."""
    Phi = result.shapes
    ratios = mode_ratios(result)
    C = damping_in_modes(result, ratios)
    lam = np.asarray(result.eigenvalues, float).copy()
    lam[:result.n_rigid] = 0.0
    p = Phi.T @ src.k_row                                            # modal input
    r = _rigid_free(C, result.n_rigid)
    Ok, Oc = _modal_outputs(result, outs, ratios, r)                  # modal outputs: spring, damper parts
    n = max(result.n_rigid, int(np.searchsorted(result.frequencies_hz, modes_hz, side="right")))
    if not residual:
        lam, C, p, Ok, Oc = lam[:n], C[:n, :n], p[:n], Ok[:, :n], Oc[:, :n]
    k, t = slice(0, n), slice(n, None)
    Lt = 1.0 / lam[t]
    # inputs p_a and outputs O_b on y_k, each multiplying (i w)^a, (i w)^b
    P = [p[k], -C[k, t] @ (Lt * p[t])]
    G_ = (Lt[:, None] * C[t, k])                                     # L_t^-1 C_tk
    O = [Ok[:, k], Oc[:, k] - Ok[:, t] @ G_, -Oc[:, t] @ G_]
    H = _residual(lam[t], C[t, t], Ok[:, t], Oc[:, t], p[t], omega)
    # i w C_kt y_t holds (i w)(-i w) C_kt L_t^-1 C_tk y_k = w^2 E y_k: the kept modes' mass
    # becomes I - E; with I - E = L L' (Cholesky) the kept problem in x = L' y_k has unit mass
    E = C[k, t] @ G_
    lam, C = lam[k], C[k, k]
    if np.abs(E).max(initial=0.0) > 0.0:
        try:
            L = sla.cholesky(np.eye(n) - E, lower=True)
        except sla.LinAlgError as exc:
            raise SolverError("modes_hz", modes_hz, "the damping coupling of the truncated modes is too strong "
                                                    "for a residual correction: raise the cutoff") from exc
        Li = sla.solve_triangular(L, np.eye(n), lower=True)
        Kx, C = Li @ np.diag(lam) @ Li.T, Li @ C @ Li.T
        P, O = [Li @ q for q in P], [o @ Li.T for o in O]
    else:
        Kx = np.diag(lam)
    off = C - np.diag(np.diag(C))
    if not E.any() and np.abs(off).max(initial=0.0) <= RIGID_RTOL * np.abs(C).max(initial=0.0):
        c = np.diag(C).copy()
        c[:r] = 0.0                                                  # round-off of undamped rigid modes
        return H + _sum(lambda w: 1.0 / (lam[None, :] - w[:, None] ** 2 + 1j * w[:, None] * c[None, :]),
                        _residues(O, P), omega)
    s, Y, a = _state_modes(Kx[r:, r:], C[r:, r:])
    H += _sum_poles(s, _residues([o[:, r:] @ Y for o in O], [(Y.T @ q[r:]) / a for q in P]), omega)
    if r:
        with np.errstate(divide="ignore"):
            H += _sum(lambda w: np.repeat(-1.0 / w[:, None] ** 2, r, axis=1),
                      _residues([o[:, :r] for o in O], [q[:r] for q in P]), omega)
    return H


def _residues(O: list, P: list) -> list:
    """``R_j = sum_{a + b = j} O_b * P_a`` (n_out x n_modes): the residues of ``(i w)^j``."""
    R = [np.zeros((O[0].shape[0], O[0].shape[1]), complex) for _ in range(len(O) + len(P) - 1)]
    for b, o in enumerate(O):
        for a, q in enumerate(P):
            R[a + b] = R[a + b] + o * q[None, :]
    return R


def _residual(lam, Ctt, Ok, Oc, p, omega) -> np.ndarray:
    """(n_f x n_out) quasi-static response of the truncated modes (eigenvalues ``lam``,
    modal damping ``Ctt``, modal outputs ``Ok``, ``Oc``, modal input ``p``):
    ``(Ok + i w Oc) [L^-1 p + L^-1 (w^2 - i w Ctt) L^-1 p]``."""
    if lam.size == 0:
        return np.zeros((len(omega), Ok.shape[0]), complex)
    v0 = p / lam
    v1, v2 = v0 / lam, (Ctt @ v0) / lam
    w = omega[:, None]
    H = np.zeros((len(omega), Ok.shape[0]), complex)
    for O, factor in ((Ok, 1.0), (Oc, 1j * w)):
        H += factor * ((O @ v0)[None, :] + w ** 2 * (O @ v1)[None, :] - 1j * w * (O @ v2)[None, :])
    return H


def _state_modes(K, C):
    """Complex modes of ``(K + s C + s^2 I) y = 0`` (``K`` the diagonal of modal eigenvalues,
    or near it; ``K``, ``C`` symmetric), from the state form in the scaled state
    ``u = [D y; y']`` (``D = sqrt(diag K)``, 1 for a damped rigid-body mode): eigenvalues
    ``s`` (2m,), coordinates ``Y`` (m x 2m) and the normalisation ``a_r = y_r' (C + 2 s_r I)
    y_r``, so that ``(K + s C + s^2 I)^-1 = sum_r y_r y_r' / (a_r (s - s_r))`` (plain
    transpose: symmetric matrices, Lancaster's partial fractions of a quadratic pencil)."""
    s, Y = state_form(K, C)
    a = np.einsum("ir,ir->r", Y, C @ Y) + 2.0 * s * np.einsum("ir,ir->r", Y, Y)
    if np.any(np.abs(a) <= 1e-10 * np.abs(s) * np.einsum("ir,ir->r", np.abs(Y), np.abs(Y))):
        raise SolverError("state eigenvectors", "defective", "defective damped modes (a critically damped "
                                                             "mode?): use method='direct'")
    return s, Y, a


def _sum_poles(s: np.ndarray, R: list, omega: np.ndarray) -> np.ndarray:
    """``sum_r sum_j (i w)^j R_j[:, r] / (i w - s_r)`` with one matrix product per block of
    frequencies: ``(i w)^j / (i w - s) = s^j / (i w - s) + sum_{m<j} (i w)^(j-1-m) s^m``, so
    the pole part takes the residues ``sum_j s^j R_j`` and the rest is a polynomial in ``i w``
    with coefficients ``sum_r R_j s^m``."""
    Rs = sum(Rj * s[None, :] ** j for j, Rj in enumerate(R))
    poly = [np.zeros(R[0].shape[0], complex) for _ in range(max(len(R) - 1, 1))]
    for j, Rj in enumerate(R):
        for m in range(j):
            poly[j - 1 - m] = poly[j - 1 - m] + Rj @ s ** m
    H = _sum(lambda w: 1.0 / (1j * w[:, None] - s[None, :]), [Rs], omega)
    iw = 1j * omega[:, None]
    for j in range(len(poly) - 1, -1, -1):
        H = H + iw ** j * poly[j][None, :]
    return H


def _sum(gain, R: list, omega: np.ndarray) -> np.ndarray:
    """``sum_r G_r(omega) sum_j (i omega)^j R_j[:, r]`` for (n_out x n_modes) residues ``R_j``,
    in blocks of frequencies; ``gain(omega_block)`` gives the (n_b x n_modes) modal gains.
    One matrix product per block: the residues side by side."""
    n_out = R[0].shape[0]
    while len(R) > 1 and not R[-1].any():                             # no work for zero high powers
        R = R[:-1]
    Rall = np.concatenate(R, axis=0).T
    H = np.empty((len(omega), n_out), complex)
    for a in range(0, len(omega), BLOCK):
        w = omega[a:a + BLOCK]
        GR = gain(w) @ Rall
        iw = 1j * w[:, None]
        h = GR[:, (len(R) - 1) * n_out:]
        for j in range(len(R) - 2, -1, -1):                          # Horner in i w
            h = h * iw + GR[:, j * n_out:(j + 1) * n_out]
        H[a:a + BLOCK] = h
    return H


def _direct(model, result, src: Channel, outs: list, omega: np.ndarray):
    """((n_f x n_out) response, its round-off bound) by one dense LU per frequency, on the
    problem scaled to a unit mass diagonal (``D (K - w^2 M + i w C) D``, ``D =
    diag(M)^-1/2``). Section loads take the scene's damping share ``Ok G q'``
    (:func:`assembly.dynamics.damping.section_share`).

    A free model whose rigid-body modes ``Phi_r`` (mass-normalised, from the structure,
    :func:`assembly.mechanics.nullity.rigid_body_modes`) no damper acts on is solved deflated, by
    inertia relief: ``q = -Phi_r Phi_r' f / w^2 + q_e`` with ``q_e`` from the bordered system
    ``[[K - w^2 M + i w C, M Phi_r], [Phi_r' M, 0]] [q_e; mu] = [f; 0]``, whose condition stays
    that of the static problem as w -> 0 (the plain matrix's grows as 1/w^2). Its first rows
    times ``Phi_r'`` give ``mu = Phi_r' f`` (``Phi_r' K = Phi_r' C = 0``, ``Phi_r' M q_e = 0``):
    the multiplier takes the rigid-body part of ``f``, so ``q_e`` answers ``f - M Phi_r Phi_r'
    f`` without that being formed. Section loads read ``q_e`` alone (their rigid-body part is
    zero by structure). The
    bound returned is eps x LAPACK's condition estimate of the matrix solved at the lowest
    frequency. Where a damper acts on a rigid-body mode the plain matrix is solved; its smallest
    eigenvalues are then about ``w c_r`` (``c_r`` the rigid-body modes' damping, mass-scaled)
    or ``w^2``, and the bound returned is eps ``lambda_max / (w_min max(c_r, w_min))``; 0
    otherwise (the deflated or held problem's conditioning does not grow with 1/w)."""
    u = 1.0 / np.sqrt(model.M.diagonal())
    K = u[:, None] * model.K.toarray() * u
    M = u[:, None] * model.M.toarray() * u
    C = u[:, None] * damping_on_q(model, result) * u
    Ok, Oc = output_rows(outs)
    sec = np.array([c.section for c in outs], bool)
    G = section_share(model, result)
    if G is not None and sec.any():
        Oc[sec] = Oc[sec] + Ok[sec] @ G if np.ndim(G) else Oc[sec] + G * Ok[sec]
    Ok, Oc = Ok * u, Oc * u
    F = src.k_row * u
    n = K.shape[0]
    Pr = rigid_body_modes(model) / u[:, None]                       # scaled coordinates x = q / u
    if Pr.shape[1]:
        Pr = Pr @ np.linalg.inv(sla.cholesky(Pr.T @ M @ Pr))         # M-orthonormal
    deflate = Pr.shape[1] > 0 and np.abs(C @ Pr).max(initial=0.0) <= RIGID_RTOL * np.abs(C).max(initial=0.0)
    if deflate:
        MP = M @ Pr
        y_r = Pr.T @ F                                               # rigid-body modal input
        rhs = np.concatenate([F, np.zeros(Pr.shape[1])])
        rigid_out = np.where(sec[:, None], 0.0, Ok @ Pr) @ y_r       # section loads: none
        border = np.block([[np.zeros((n, n)), MP], [MP.T, np.zeros((Pr.shape[1], Pr.shape[1]))]])
    H = np.empty((len(omega), len(outs)), complex)
    rtol, w_min = 0.0, float(omega.min())
    if Pr.shape[1] and not deflate and w_min > 0:
        c_r = float(np.linalg.eigvalsh(Pr.T @ C @ Pr).min())
        rtol = np.finfo(float).eps * float(np.abs(K).sum(axis=1).max()) / (w_min * max(c_r, w_min))
    for j in range(len(omega)):
        w = omega[j]
        A = K - w * w * M + 1j * w * C
        if deflate:
            A = border + np.pad(A, ((0, Pr.shape[1]), (0, Pr.shape[1])))
        try:
            with warnings.catch_warnings():              # its bound is reported (rtol), not LAPACK's rcond
                warnings.simplefilter("ignore", sla.LinAlgWarning)
                x = sla.solve(A, rhs if deflate else F, check_finite=False)[:n]
        except (sla.LinAlgError, ValueError) as exc:
            raise SceneError("frequency_hz", float(w / (2 * np.pi)),
                             "the dynamic stiffness is singular there") from exc
        H[j] = Ok @ x + 1j * w * (Oc @ x)
        if deflate:
            H[j] -= rigid_out / (w * w)
    return H, rtol
