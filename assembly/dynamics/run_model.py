"""The matrices and the scheme of a time-domain run: M, K and the damping C of the assembled
model on q (dense for a reduced model, sparse above :data:`DENSE_INVERSE_MAX` DOFs), the
section loads' share G of the scene damping (:mod:`assembly.dynamics.damping`), and the
integration scheme its ``[simulation]`` table names.
"""
from __future__ import annotations

from ..errors import SceneError
from ..model.damping import damping_matrix
from ..scene.time_domain import Simulation
from .damping import damping_on_q, every_mode, needs_modes, section_share
from .integrators import DENSE_INVERSE_MAX, generalized_alpha, hht, newmark


def scheme_of(sim: Simulation):
    """The integration scheme the ``[simulation]`` table names."""
    if sim.scheme == "hht":
        return hht(sim.alpha)
    if sim.scheme == "generalized-alpha":
        return generalized_alpha(sim.rho_inf)
    return newmark()


def model_matrices(model):
    """(M, C, K, G) of a run on q: dense for a reduced model, sparse above
    DENSE_INVERSE_MAX DOFs (C: :func:`run_damping`; G: the section loads' share of the
    scene damping, :func:`assembly.dynamics.damping.section_share`)."""
    sparse = model.K.shape[0] > DENSE_INVERSE_MAX
    M, K = (model.M, model.K) if sparse else (model.M.toarray(), model.K.toarray())
    return (M, K, *run_damping(model))


def run_damping(model):
    """(C, G) on q: dense for a reduced model; the unreduced model's element dampers and
    Rayleigh beta (sparse C, scalar G). One modal basis serves both, so that the section
    loads' shares add up to the damping force integrated."""
    d = model.scene.damping
    n = model.K.shape[0]
    if n <= DENSE_INVERSE_MAX:
        modes = every_mode(model) if needs_modes(model) else None
        return damping_on_q(model, modes), section_share(model, modes)
    if needs_modes(model):
        raise SceneError("damping", d, f"modal ratios and Rayleigh alpha need every mode: the model has {n} "
                                       "DOFs; use element dampers or rayleigh_beta")
    C = damping_matrix(model)
    C = C + d.rayleigh_beta * model.K if d is not None and d.rayleigh_beta else C
    return C, section_share(model)
