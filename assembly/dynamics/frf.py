"""Frequency response functions of an assembled model with its damping.

The model ``M q'' + C q' + K q = f e^{i omega t}`` (``C`` the element dampers plus the
scene's Rayleigh and modal ratios, :mod:`assembly.dynamics.damping`) answers with
``q = H(omega) f``; inputs and outputs are the channels of
:mod:`assembly.dynamics.frf_channels` (outputs ``(r_k + i omega r_c) q``: internal loads
from the springs and dampers).

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
drivetrain has a finite response; no pseudo-inverse, no zeroed matrix.

Modal truncation (``modes_hz``): only the modes up to ``modes_hz`` enter the sums above;
the modes left out (set T) answer quasi-statically, by the residual-flexibility term with
its first inertia and damping correction (the expansion of ``1/(lambda_r - omega^2 + i
omega c_r)`` to first order in ``(omega^2 - i omega c_r) / lambda_r``):

    q_T(omega) = sum_{r in T} phi_r (phi_r' f) [1/lambda_r + (omega^2 - i omega c_r) / lambda_r^2]

(``c_r`` the diagonal of ``C_m``; the damping coupling between kept and truncated modes is
left out). Its error for a mode at ``omega_r`` is of order ``(omega/omega_r)^4``: with
the default cutoff, :data:`CUTOFF_FACTOR` x the highest frequency asked, below 1e-6 of
that mode's static share. ``modes_hz=inf`` keeps every mode (exact). Models above
:data:`assembly.modal.DENSE_MAX` DOFs have no full modal basis: use ``method="direct"``.

``method="direct"``: the reference, ``(K - omega^2 M + i omega C) q = f`` solved per
frequency (dense LU on the mass-diagonal-scaled matrix), ``C`` on q including the Rayleigh
part ``alpha (M - M Phi_r Phi_r' M) + beta K`` and the modal ratios
``M Phi diag(2 zeta omega) Phi' M`` (exact for a model holding every mode).
"""
from __future__ import annotations

import dataclasses
import logging
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
from threadpoolctl import threadpool_limits

from ..errors import SceneError, SolverError
from ..modal import SMALL_DENSE
from .damped_modes import RIGID_RTOL, state_form
from .damping import damping_in_modes, damping_matrix
from .frf_channels import Channel, input_channel, output_channels, output_rows, von_mises_peak
from .modal_ratios import mode_ratios

log = logging.getLogger(__name__)

METHODS = ("modal", "direct")
#: Frequencies per block of the vectorised superposition (bounds the n_f x 2n work array).
BLOCK = 2048
#: Default modal cutoff: modes up to this multiple of the highest frequency asked are
#: superposed, the rest enter by their residual flexibility (module notes).
CUTOFF_FACTOR = 30.0


@dataclass(frozen=True)
class FRF:
    """Frequency response of one input: ``frequency_hz`` (n_f,), ``outputs`` {output name:
    complex array (n_f,)} per unit input, ``units`` {output name: "out unit/(in unit)"},
    ``natural_hz``: the undamped elastic natural frequencies (Hz; empty when the direct
    solve needed no modes), ``method`` and ``time_s`` of the solve."""

    input: str
    frequency_hz: np.ndarray
    outputs: dict
    units: dict
    natural_hz: np.ndarray = field(default_factory=lambda: np.zeros(0))
    method: str = "modal"
    time_s: float = 0.0


def frequency_response(model, input: str, outputs, frequency_hz, method: str = "modal", result=None,
                       modes_hz: float | None = None, residual: bool = True) -> FRF:
    """FRF of ``model`` from ``input`` to each of ``outputs`` (names of
    :mod:`assembly.dynamics.frf_channels`) at ``frequency_hz`` (Hz, >= 0; > 0 when the
    model has undamped rigid-body modes). ``result``: the model's
    :class:`assembly.modal.ModalResult` with every mode, if already solved. ``modes_hz``
    (Hz): the modal cutoff of ``method="modal"`` (module notes); default
    :data:`CUTOFF_FACTOR` x ``max(frequency_hz)``, ``inf`` for every mode; ``residual=False``
    drops the modes above it altogether (plain truncation, to see what the correction buys)."""
    from .. import arguments as check                # each argument's kind, one SceneError naming it
    check.model("model", model)
    check.text("input", input)
    outputs = check.names("outputs", outputs)
    frequency_hz = check.frequencies("frequency_hz", frequency_hz)
    check.one_of("method", method, METHODS, "method")
    check.optional(check.modes, "result", result)
    check.optional(check.number, "modes_hz", modes_hz, "Hz", gt=0.0, infinite="every mode")
    check.flag("residual", residual)
    t0 = time.perf_counter()
    f = np.atleast_1d(np.asarray(frequency_hz, float))
    if method not in METHODS:
        raise SceneError("method", method, f"must be one of {list(METHODS)}")
    if f.size == 0 or not np.all(np.isfinite(f)) or np.any(f < 0):
        raise SceneError("frequency_hz", f.tolist()[:4], "frequencies must be finite and >= 0 Hz")
    if modes_hz is None:
        modes_hz = CUTOFF_FACTOR * float(f.max())
    if not (modes_hz > 0):
        raise SceneError("modes_hz", modes_hz, "the modal cutoff must be a frequency > 0 Hz")
    if isinstance(outputs, str):
        outputs = [outputs]
    src = input_channel(model, input)
    outs = [c for name in outputs for c in output_channels(model, name)]
    omega = 2 * np.pi * f
    if method == "modal" or _needs_modes(model):
        result = low_accurate(result if result is not None else _all_modes(model))
    # one BLAS thread for small models, as the modal solve (assembly.modal.SMALL_DENSE)
    with threadpool_limits(1 if model.K.shape[0] <= SMALL_DENSE else None):
        if method == "modal":
            H = _modal(result, src, outs, omega, modes_hz, residual)
        else:
            H = _direct(model, result, src, outs, omega)
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
    dt = time.perf_counter() - t0
    log.info("FRF %s -> %d outputs, %d frequencies, %s: %.3f s", input, len(values), len(f), method, dt)
    return FRF(input, f, values, units, natural, method, dt)


def low_accurate(result):
    """``result`` with its modes solved again from the inverted pencil ``M v = mu (K +
    sigma M) v`` (``lambda = 1/mu - sigma``, ``sigma`` the lowest elastic eigenvalue, scaled to
    a unit mass diagonal). The direct pencil resolves each eigenvalue to ~eps x lambda_max
    absolute, so a 1.8 Hz rotor mode beside 2.4e4 Hz bodies only to ~1e-6 relative, and an
    FRF at that lightly damped resonance is off by ~1e-6 / zeta. The inverted pencil resolves
    them to ~eps x (lambda + sigma) / sigma: the low modes, which an FRF needs exactly, to a
    few eps; a mode at f to eps (f / f_1)^2 (4e-8 at 2.4e4 Hz beside 1.8 Hz). Rigid-body
    modes keep their count (the structural one of ``result``) and eigenvalue 0. Solved once
    per result (kept in ``result.info``), as a study calls the FRF many times on one model."""
    model, r = result.model, result.n_rigid
    if len(result.eigenvalues) <= r or result.shapes.shape[1] < model.K.shape[0]:
        return result
    if result.info.get("_frf_modes") is not None:
        return result.info["_frf_modes"]
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
                                  abs_shapes=np.asarray(model.T @ Phi), info=dict(result.info))
    result.info["_frf_modes"] = refined
    return refined


def _needs_modes(model) -> bool:
    d = model.scene.damping
    return d is not None and (d.modal or d.rayleigh_alpha > 0)


def _all_modes(model):
    from ..modal import solve_modes
    res = solve_modes(model)
    if res.shapes.shape[1] < model.K.shape[0]:
        raise SceneError("method", "modal", f"the model has {model.K.shape[0]} DOFs and only "
                                            f"{res.shapes.shape[1]} modes: use method='direct'")
    return res


def _rigid_free(C: np.ndarray, n_rigid: int) -> int:
    """How many leading (rigid-body) modes no damper acts on: all ``n_rigid`` or none."""
    scale = np.abs(C).max(initial=0.0)
    return n_rigid if n_rigid and np.abs(C[:n_rigid]).max() <= RIGID_RTOL * scale else 0


def _zero_check(omega: np.ndarray, undamped_rigid: int) -> None:
    if undamped_rigid and np.any(omega == 0):
        raise SceneError("frequency_hz", 0.0, f"the model has {undamped_rigid} free rigid-body mode(s): "
                                              "its response at 0 Hz is unbounded; use frequencies > 0")


def _modal(result, src: Channel, outs: list, omega: np.ndarray, modes_hz: float = np.inf,
           residual: bool = True) -> np.ndarray:
    """(n_f x n_out) superposition over the modes up to ``modes_hz`` (set k), the rest (set
    t) by their residual flexibility, damping coupling included to first order (module
    notes): ``y_t = L_t^-1 (p_t - i w C_tk y_k) + L_t^-1 (w^2 - i w C_tt) L_t^-1 p_t``, so
    the kept modes see the input ``p_k - i w C_kt L_t^-1 p_t`` and the outputs read
    ``O_k - i w O_t L_t^-1 C_tk`` on ``y_k``. Every term is a power of ``i w`` times a
    modal gain: ``H = sum_j (i w)^j G R_j``."""
    Phi = result.shapes
    C = damping_in_modes(result, mode_ratios(result))
    lam = np.asarray(result.eigenvalues, float).copy()
    lam[:result.n_rigid] = 0.0
    p = Phi.T @ src.k_row                                            # modal input
    Ok, Oc = (O @ Phi for O in output_rows(outs))                     # modal outputs: spring, damper parts
    r = _rigid_free(C, result.n_rigid)
    _zero_check(omega, r)
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


def damping_on_q(model, result=None) -> np.ndarray:
    """Dense damping on q (N s/m, N m s/rad entries): element dampers, Rayleigh with the
    rigid-body modes projected out, modal ratios as ``M Phi diag(2 zeta omega) Phi' M``
    (``result``: every mode, needed for the last two)."""
    C = damping_matrix(model).toarray()
    d = model.scene.damping
    if d is None:
        return C
    M = model.M.toarray()
    if d.rayleigh_beta:
        C += d.rayleigh_beta * model.K.toarray()
    if d.rayleigh_alpha or d.modal:
        Phi, r = result.shapes, result.n_rigid
        MP = M @ Phi
        omega = np.sqrt(np.maximum(result.eigenvalues, 0.0))
        omega[:r] = 0.0
        diag = 2.0 * mode_ratios(result) * omega + d.rayleigh_alpha * (omega > 0)
        C += (MP * diag) @ MP.T
    return 0.5 * (C + C.T)


def _direct(model, result, src: Channel, outs: list, omega: np.ndarray) -> np.ndarray:
    """(n_f x n_out) by one dense LU per frequency, on the problem scaled to a unit mass
    diagonal (``D (K - w^2 M + i w C) D``, ``D = diag(M)^-1/2``)."""
    u = 1.0 / np.sqrt(model.M.diagonal())
    K = u[:, None] * model.K.toarray() * u
    M = u[:, None] * model.M.toarray() * u
    C = u[:, None] * damping_on_q(model, result) * u
    Ok, Oc = (O * u for O in output_rows(outs))
    F = src.k_row * u
    H = np.empty((len(omega), len(outs)), complex)
    for j, w in enumerate(omega):
        try:
            x = sla.solve(K - w * w * M + 1j * w * C, F, check_finite=False)
        except sla.LinAlgError as exc:
            raise SceneError("frequency_hz", float(w / (2 * np.pi)),
                             "the dynamic stiffness is singular there (a free rigid-body mode at 0 Hz?)") from exc
        H[j] = Ok @ x + 1j * w * (Oc @ x)
    return H
