"""Viscous damping matrices of an assembled model, on its independent coordinates ``q``,
and the share of the scene's damping that each section load carries.

Element dampers sit beside the springs, on the same strain rows ``B`` (:class:`assembly.
elements.Element` ``c``): ``C_abs = sum L' B' diag(c) B L`` is assembled exactly as
``K_abs`` is, and ``C = T' C_abs T`` (N s/m, N m s/rad entries on q).

Rayleigh damping ``alpha M + beta K`` (alpha in 1/s, beta in s) gives a mode of angular
frequency omega (rad/s) the ratio ``zeta = alpha / (2 omega) + beta omega / 2``. Its
``alpha M`` part would also act on a rigid-body mode (a free rotor-generator spin would be
braked at the rate alpha, as by a damper to ground that no bearing holds). Rayleigh's
alpha is a device to fit the elastic modes' ratios, not a drag on the housing, so it is
applied with the rigid-body modes ``Phi_r`` (mass-normalised) projected out:
``alpha (M - M Phi_r Phi_r' M)``. Every elastic mode, M-orthogonal to ``Phi_r``, sees
``alpha`` exactly as before, and every rigid-body mode sees nothing: it stays at s = 0.

**Section loads** (a shaft's torque, a mesh's or a bearing's force, a stress). An element's
own damper is its own: the load is ``k e + c e'``. The scene's ``[damping]`` is not tied to
an element, so its force ``C_s q'`` must be shared out among them. With the mass-normalised
modes (``K phi_r = lambda_r M phi_r``) every form of it is diagonal in the elastic modes,
``C_s = beta K + M Phi_e diag(d_r) Phi_e' M`` with ``d_r = alpha + 2 zeta_r omega_r`` (1/s),
and ``M phi_r = K phi_r / lambda_r`` turns it into ``C_s = K G`` with

    G = beta I + Phi_e diag(d_r / lambda_r) Phi_e' M        (s; rigid-body modes: 0).

``K = sum_e B_e' k_e B_e``, so ``C_s q' = sum_e B_e' k_e B_e (G q')``: element ``e`` carries
``k_e B_e G q'``, its spring row applied to ``G q'``. For Rayleigh's beta that is the
element's own ``beta k_e e'``; for modal ratios and alpha it is, mode by mode, the damping
force of the mode ``d_r y_r'`` applied as the static load pattern ``M phi_r`` and carried
by the element in proportion to its strain in that mode. The shares of all elements add up
to ``C_s q'`` exactly, so every body's balance ``M q'' + K q + C q' = f`` holds with the
section loads: where an element's cut separates the model (a shaft of a chain), its load is
the force-summation cut, the inertia and external forces on one side. A stress takes the
same share: the stress of ``u + G u'``, its flexible body's strain plus its damping share.
"""
from __future__ import annotations

import numpy as np

from ..errors import SceneError
from ..mechanics.dense import dense
from ..model.damping import damping_matrix
from .modal_ratios import mode_ratios


def needs_modes(model) -> bool:
    """Whether the scene's ``[damping]`` needs every mode of the model (modal ratios or
    Rayleigh alpha; beta alone is ``beta K``)."""
    d = model.scene.damping
    return d is not None and (d.modal or d.rayleigh_alpha > 0)


def every_mode(model):
    """Every mode of ``model`` (:func:`assembly.analysis.modal.solve_modes`); SceneError when the
    model is too large for a full modal basis."""
    from ..analysis.modal import solve_modes
    res = solve_modes(model)
    if res.shapes.shape[1] < model.K.shape[0]:
        raise SceneError("damping", model.scene.damping,
                         f"modal ratios and Rayleigh alpha need every mode: the model has {model.K.shape[0]} "
                         f"DOFs and only {res.shapes.shape[1]} modes were solved; use element dampers or "
                         "rayleigh_beta")
    return res


def _elastic_eigenvalues(result) -> np.ndarray:
    lam = np.asarray(result.eigenvalues, float).copy()
    lam[:result.n_rigid] = 0.0
    return np.maximum(lam, 0.0)


def scene_modal_damping(result, ratios: np.ndarray | None = None) -> np.ndarray:
    """``d_r`` (1/s) of every mode of ``result``: the scene's ``[damping]`` on the modal
    coordinates, ``alpha + beta lambda_r + 2 zeta_r omega_r`` for an elastic mode, 0 for a
    rigid-body mode (module notes). ``ratios``: the modal ratios (default
    :func:`assembly.dynamics.modal_ratios.mode_ratios`)."""
    lam = _elastic_eigenvalues(result)
    zeta = mode_ratios(result) if ratios is None else np.asarray(ratios, float)
    diag = 2.0 * zeta * np.sqrt(lam)
    d = result.model.scene.damping
    if d is not None:
        diag = diag + d.rayleigh_alpha * (lam > 0) + d.rayleigh_beta * lam
    diag[:result.n_rigid] = 0.0
    return diag


def section_factors(result, ratios: np.ndarray | None = None) -> np.ndarray:
    """``d_r / lambda_r`` (s) of every mode of ``result`` (0 for a rigid-body mode): a
    section load's damping share in modal coordinates is its spring row times this factor
    (module notes)."""
    lam = _elastic_eigenvalues(result)
    g = np.zeros_like(lam)
    el = lam > 0
    g[el] = scene_modal_damping(result, ratios)[el] / lam[el]
    return g


def damping_in_modes(result, ratios: np.ndarray) -> np.ndarray:
    """Dense damping (1/s) on the modal coordinates of ``result`` (mass-normalised shapes
    Phi, eigenvalues lambda = omega^2): ``Phi' C Phi`` of the element dampers, plus the
    scene's ``[damping]`` (:func:`scene_modal_damping`). Exact for a result holding every
    mode; with fewer, the damping of the modes kept (modal truncation)."""
    Phi = result.shapes
    C = Phi.T @ (damping_matrix(result.model) @ Phi)
    C = C + np.diag(scene_modal_damping(result, ratios))
    return 0.5 * (C + C.T)


def damping_on_q(model, result=None) -> np.ndarray:
    """Dense damping on q (N s/m, N m s/rad entries): element dampers, Rayleigh with the
    rigid-body modes projected out, modal ratios as ``M Phi diag(2 zeta omega) Phi' M``
    (``result``: every mode, needed for the last two)."""
    C = dense(damping_matrix(model))
    d = model.scene.damping
    if d is None:
        return C
    if d.rayleigh_beta:
        C += d.rayleigh_beta * dense(model.K)
    if needs_modes(model):
        MP = dense(model.M) @ result.shapes
        lam = _elastic_eigenvalues(result)
        diag = 2.0 * mode_ratios(result) * np.sqrt(lam) + d.rayleigh_alpha * (lam > 0)
        diag[:result.n_rigid] = 0.0
        C += (MP * diag) @ MP.T
    return 0.5 * (C + C.T)


def section_share(model, result=None):
    """``G`` of the module notes on q, or None without scene damping: a section load's
    damping share is its spring row times ``G q'``. Dense (n x n) when the scene has modal
    ratios or Rayleigh alpha (``result``: every mode, as for :func:`damping_on_q`); Rayleigh
    beta alone gives the scalar ``beta`` (``G = beta I``)."""
    d = model.scene.damping
    if d is None or not (d.rayleigh_beta or needs_modes(model)):
        return None
    if not needs_modes(model):
        return float(d.rayleigh_beta)
    Phi = result.shapes
    g = section_factors(result) - (d.rayleigh_beta if d.rayleigh_beta else 0.0) * (_elastic_eigenvalues(result) > 0)
    G = (Phi * g) @ (Phi.T @ dense(model.M))
    G[np.diag_indices_from(G)] += d.rayleigh_beta
    return G
