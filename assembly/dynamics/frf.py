"""Frequency response functions of an assembled model with its damping.

The model ``M q'' + C q' + K q = f e^{i omega t}`` (``C`` the element dampers plus the
scene's Rayleigh and modal ratios, :mod:`assembly.dynamics.damping`) answers with
``q = H(omega) f``; inputs and outputs are the channels of
:mod:`assembly.dynamics.frf_channels` (outputs ``(r_k + i omega r_c) q``: internal loads
from the springs and dampers).

``method="modal"`` (default): superposition over every mode of the model. In the
undamped modal coordinates ``q = Phi y`` (``Phi' M Phi = I``, ``Phi' K Phi = Lambda``) the
problem is ``(Lambda - omega^2 I + i omega C_m) y = Phi' f``:

* a diagonal ``C_m`` (modal ratios, Rayleigh, proportional dampers): every mode on its own,
  ``y_r = phi_r' f / (lambda_r - omega^2 + i omega c_r)``;
* otherwise the complex modes of the first-order (state) form, its state scaled as
  ``u = [Omega y; y']`` (entries of the size omega, not omega^2):
  ``A = [[0, Omega], [-Omega, -C_m]]``, ``A = V diag(s) V^-1`` once, and
  ``H(omega) = sum_r (out_r in_r') / (i omega - s_r)``, vectorised over frequencies.

Rigid-body modes (s = 0) that no damper acts on (``C_m`` rows at round-off, as
:mod:`assembly.dynamics.damped_modes` decides) stay out of the state form: their term is
exactly ``-1/omega^2 (out phi_r)(phi_r' in)``, finite for omega > 0, so a free-free
drivetrain has a finite response; no pseudo-inverse, no zeroed matrix. With every mode
kept the superposition is exact and no residual-flexibility term is missing (it is the
static contribution of the modes left out: zero here). Models above
:data:`assembly.modal.DENSE_MAX` DOFs have no full modal basis: use ``method="direct"``.

``method="direct"``: the reference, ``(K - omega^2 M + i omega C) q = f`` solved per
frequency (dense LU on the mass-diagonal-scaled matrix), ``C`` on q including the Rayleigh
part ``alpha (M - M Phi_r Phi_r' M) + beta K`` and the modal ratios
``M Phi diag(2 zeta omega) Phi' M`` (exact for a model holding every mode).
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
from threadpoolctl import threadpool_limits

from ..errors import SceneError, SolverError
from ..modal import SMALL_DENSE
from .damped_modes import RIGID_RTOL
from .damping import damping_in_modes, damping_matrix
from .frf_channels import Channel, input_channel, output_channels
from .modal_ratios import mode_ratios

log = logging.getLogger(__name__)

METHODS = ("modal", "direct")
#: Frequencies per block of the vectorised superposition (bounds the n_f x 2n work array).
BLOCK = 2048


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


def frequency_response(model, input: str, outputs, frequency_hz, method: str = "modal", result=None) -> FRF:
    """FRF of ``model`` from ``input`` to each of ``outputs`` (names of
    :mod:`assembly.dynamics.frf_channels`) at ``frequency_hz`` (Hz, >= 0; > 0 when the
    model has undamped rigid-body modes). ``result``: the model's
    :class:`assembly.modal.ModalResult` with every mode, if already solved."""
    t0 = time.perf_counter()
    f = np.atleast_1d(np.asarray(frequency_hz, float))
    if method not in METHODS:
        raise SceneError("method", method, f"must be one of {list(METHODS)}")
    if f.size == 0 or not np.all(np.isfinite(f)) or np.any(f < 0):
        raise SceneError("frequency_hz", f.tolist()[:4], "frequencies must be finite and >= 0 Hz")
    if isinstance(outputs, str):
        outputs = [outputs]
    src = input_channel(model, input)
    outs = [c for name in outputs for c in output_channels(model, name)]
    omega = 2 * np.pi * f
    if method == "modal" or _needs_modes(model):
        result = result if result is not None else _all_modes(model)
    # one BLAS thread for small models, as the modal solve (assembly.modal.SMALL_DENSE)
    with threadpool_limits(1 if model.K.shape[0] <= SMALL_DENSE else None):
        if method == "modal":
            H = _modal(result, src, outs, omega)
        else:
            H = _direct(model, result, src, outs, omega)
    natural = np.zeros(0) if result is None else result.frequencies_hz[result.n_rigid:]
    dt = time.perf_counter() - t0
    log.info("FRF %s -> %d outputs, %d frequencies, %s: %.3f s", input, len(outs), len(f), method, dt)
    return FRF(input, f, {c.name: H[:, j] for j, c in enumerate(outs)},
               {c.name: f"{c.unit}/({src.unit})" if " " in src.unit else f"{c.unit}/{src.unit}" for c in outs},
               natural, method, dt)


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


def _modal(result, src: Channel, outs: list, omega: np.ndarray) -> np.ndarray:
    """(n_f x n_out) superposition over every mode (module notes)."""
    Phi = result.shapes
    C = damping_in_modes(result, mode_ratios(result))
    lam = np.asarray(result.eigenvalues, float).copy()
    lam[:result.n_rigid] = 0.0
    p = Phi.T @ src.k_row                                            # modal input
    Ok = np.array([c.k_row for c in outs]) @ Phi                     # modal outputs
    Oc = np.array([np.zeros_like(c.k_row) if c.c_row is None else c.c_row for c in outs]) @ Phi
    r = _rigid_free(C, result.n_rigid)
    off = C - np.diag(np.diag(C))
    if np.abs(off).max(initial=0.0) <= RIGID_RTOL * np.abs(C).max(initial=0.0):
        c = np.diag(C).copy()
        c[:r] = 0.0                                                  # round-off of undamped rigid modes
        _zero_check(omega, r)
        return _sum(lambda w: 1.0 / (lam[None, :] - w[:, None] ** 2 + 1j * w[:, None] * c[None, :]),
                    Ok * p, Oc * p, omega)
    _zero_check(omega, r)
    s, Lk, Lc, R = _state_modes(lam[r:], C[r:, r:], Ok[:, r:], Oc[:, r:], p[r:])
    H = _sum(lambda w: 1.0 / (1j * w[:, None] - s[None, :]), Lk * R, Lc * R, omega)
    if r:
        with np.errstate(divide="ignore"):
            H += _sum(lambda w: np.repeat(-1.0 / w[:, None] ** 2, r, axis=1), Ok[:, :r] * p[:r],
                      Oc[:, :r] * p[:r], omega)
    return H


def _state_modes(lam, C, Ok, Oc, p):
    """Complex modes of ``(diag(lam) + s C + s^2 I) y = p`` in the scaled state
    ``u = [D y; y']`` (``D = sqrt(lam)``, 1 for a damped rigid-body mode): eigenvalues
    ``s`` and the output (n_out x 2m, stiffness and damper parts) and input (2m,) residue
    factors."""
    m = len(lam)
    d = np.where(lam > 0, np.sqrt(np.maximum(lam, 0.0)), 1.0)
    A = np.block([[np.zeros((m, m)), np.diag(d)], [-np.diag(lam / d), -C]])
    s, V = sla.eig(A)
    try:
        W = sla.solve(V, np.eye(2 * m))
    except (sla.LinAlgError, ValueError) as exc:
        raise SolverError("state eigenvectors", "singular", "defective damped modes (critically damped "
                                                            "mode?): use method='direct'") from exc
    Y = V[:m] / d[:, None]                                           # y of each state mode
    return s, Ok @ Y, Oc @ Y, W[:, m:] @ p


def _sum(gain, Rk: np.ndarray, Rc: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """``sum_r G_r(omega) (Rk + i omega Rc)_r`` for (n_out x n_modes) residues, in blocks of
    frequencies; ``gain(omega_block)`` gives the (n_b x n_modes) modal gains."""
    H = np.empty((len(omega), Rk.shape[0]), complex)
    for a in range(0, len(omega), BLOCK):
        w = omega[a:a + BLOCK]
        G = gain(w)
        H[a:a + BLOCK] = G @ Rk.T + 1j * w[:, None] * (G @ Rc.T)
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
    Ok = np.array([c.k_row for c in outs]) * u
    Oc = np.array([np.zeros_like(c.k_row) if c.c_row is None else c.c_row for c in outs]) * u
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
