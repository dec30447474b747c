"""Stress recovery from a displacement field on a scikit-fem vector basis.

Linear isotropic elasticity (small strain):
    eps = (grad u + grad u^T) / 2,   sigma = lambda tr(eps) I + 2 mu eps,
    lambda = E nu / ((1 + nu)(1 - 2 nu)),  mu = E / (2 (1 + nu))     (Pa).

Stresses are evaluated at the quadrature points of order 2p and L2-projected onto the scalar
Lagrange space of the same order p (P2 for a P2 displacement basis): the six
tensor components solve M_s s = b with one factorization of the scalar mass
matrix M_s and one block solve of 6 right-hand sides. Von Mises and principal
stresses are then evaluated from the projected nodal tensor.

Use with reduced models: ``u = superelement.reconstruct(q)`` (or
``reductor.reconstruct(q)``) then ``recover_stress(basis, u, E, nu)``.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
from skfem import CellBasis, ElementVector, LinearForm, asm
from skfem.quadrature import get_quadrature

from .errors import ReductionError
from .linsolve import factor

log = logging.getLogger(__name__)

#: Voigt order of the six stress components.
VOIGT = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))


@dataclass
class NodalStress:
    """Stress at the nodes of the scalar basis (for P2: vertices + edge midpoints).

    sigma : (n_nodes, 3, 3) Cauchy stress, Pa.
    von_mises : (n_nodes,) equivalent stress sqrt(3/2 s:s), s = deviator, Pa.
    principal : (n_nodes, 3) principal stresses, descending (sigma_1 >= sigma_2 >= sigma_3), Pa.
    points : (n_nodes, 3) node coordinates, m.
    """

    sigma: np.ndarray
    von_mises: np.ndarray
    principal: np.ndarray
    points: np.ndarray


def lame(E: float, nu: float) -> tuple[float, float]:
    if not (E > 0 and -1 < nu < 0.5):
        raise ReductionError("material must have E > 0 and -1 < nu < 0.5", "(E, nu)", (E, nu))
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


def quadrature_stress(basis, u: np.ndarray, E: float, nu: float) -> np.ndarray:
    """Cauchy stress at the quadrature points, shape (3, 3, n_elements, n_qp), Pa."""
    if u.shape != (basis.N,):
        raise ReductionError("displacement does not match the basis", "u.shape", u.shape)
    lam, mu = lame(E, nu)
    G = basis.interpolate(u).grad            # G[i, j] = d u_i / d x_j
    eps = 0.5 * (G + G.transpose(1, 0, 2, 3))
    tr = eps[0, 0] + eps[1, 1] + eps[2, 2]
    sig = 2 * mu * eps
    for k in range(3):
        sig[k, k] += lam * tr
    return sig


def von_mises(sigma: np.ndarray) -> np.ndarray:
    """Von Mises stress of tensors (..., 3, 3)."""
    p = np.trace(sigma, axis1=-2, axis2=-1) / 3
    s = sigma - p[..., None, None] * np.eye(3)
    return np.sqrt(1.5 * np.einsum("...ij,...ij->...", s, s))


def principal(sigma: np.ndarray) -> np.ndarray:
    """Principal stresses of tensors (..., 3, 3), descending."""
    return np.linalg.eigvalsh(sigma)[..., ::-1]


def projection_basis(basis):
    """``basis`` itself if its quadrature integrates the order-p scalar mass matrix exactly
    (order 2p on straight-sided cells), else the same mesh and element at order 2p. A
    stiffness basis (order 2p-2, as ``FEModel.basis``) gives a singular or inaccurate
    projection: measured 7-30 % off on P2 tetrahedra. DOF numbering is that of the mesh and
    element, so ``u`` needs no renumbering; the new basis shares ``basis``'s mapping (and so
whatever that mapping keeps, :mod:`fe_components.mapping_memo`)."""
    elem = getattr(basis, "elem", None)
    if not isinstance(elem, ElementVector) or not hasattr(basis, "mesh"):
        raise ReductionError("stress recovery needs a scikit-fem CellBasis of an ElementVector "
                             "(displacement) element", "basis", type(basis).__name__)
    order = 2 * elem.elem.maxdeg
    _, weights = get_quadrature(basis.mesh.elem.refdom, order)
    if basis.W.shape[0] >= len(weights):
        return basis
    log.debug("stress recovery: rebuilding the basis at quadrature order %d", order)
    return CellBasis(basis.mesh, elem, mapping=basis.mapping, intorder=order)


class StressProjector:
    """L2 projection of quadrature-point stresses onto the scalar element of a vector
    basis, prepared once (projection basis, scalar basis, factorised scalar mass matrix)
    and reused for every displacement field on that basis (load cases, modes)."""

    def __init__(self, basis, backend: str | None = None):
        from skfem import BilinearForm, asm
        self.basis = projection_basis(basis)
        self.sbasis = self.basis.with_element(self.basis.elem.elem)

        @BilinearForm
        def mass(p, q, w):
            return p * q

        self._solver = factor(asm(mass, self.sbasis), backend=backend)

    def __call__(self, u: np.ndarray, E: float, nu: float) -> NodalStress:
        """Nodal stresses (Pa) of the displacement ``u`` (m; DOF vector of the basis)."""
        sig = quadrature_stress(self.basis, u, E, nu)

        @LinearForm
        def load(q, w):
            return w["s"] * q

        B = np.column_stack([asm(load, self.sbasis, s=sig[i, j]) for i, j in VOIGT])
        S = self._solver.solve(B)       # one block solve, 6 RHS
        n = self.sbasis.N
        sigma = np.empty((n, 3, 3))
        for c, (i, j) in enumerate(VOIGT):
            sigma[:, i, j] = S[:, c]
            sigma[:, j, i] = S[:, c]
        return NodalStress(sigma=sigma, von_mises=von_mises(sigma), principal=principal(sigma),
                           points=self.sbasis.doflocs.T.copy())


    def nearest_node(self, point) -> tuple[int, float]:
        """(index, distance in m) of the stress node nearest to ``point`` (basis coordinates)."""
        d = np.linalg.norm(self.sbasis.doflocs.T - np.asarray(point, float)[None, :], axis=1)
        i = int(np.argmin(d))
        return i, float(d[i])

    def node_functional(self, node: int, E: float, nu: float) -> np.ndarray:
        """(6, N) rows ``g`` with ``g @ u`` the projected stress at ``node`` (Pa; Voigt order
        :data:`VOIGT`) of any displacement ``u`` (m) on the basis: the node's value of
        ``M_s^-1 b(u)`` is ``z' b(u) = int sigma(u) z_h dx`` with ``z = M_s^-1 e_node`` (one
        solve), so each component is one linear form ``int sigma_c(v) z_h dx`` in ``v``."""
        lam, mu = lame(E, nu)
        e = np.zeros(self.sbasis.N)
        e[node] = 1.0
        z = self.sbasis.interpolate(self._solver.solve(e[:, None])[:, 0])
        rows = []
        for i, j in VOIGT:
            @LinearForm
            def form(v, w, i=i, j=j):
                G = v.grad
                eps_ij = 0.5 * (G[i, j] + G[j, i])
                tr = G[0, 0] + G[1, 1] + G[2, 2]
                return (2 * mu * eps_ij + (lam * tr if i == j else 0.0)) * w["z"]
            rows.append(asm(form, self.basis, z=z))
        return np.array(rows)


def recover_stress(basis, u: np.ndarray, E: float, nu: float,
                   backend: str | None = None) -> NodalStress:
    """L2-projected nodal stresses (Pa) of the displacement ``u`` (m; DOF vector of ``basis``).

    ``basis`` is a scikit-fem vector basis (``ElementVector`` of a Lagrange element), e.g. an
    FE model's stiffness basis: the stresses are evaluated and projected at quadrature order
    2p (:func:`projection_basis`) onto the scalar element of the same order on the same mesh.
    For many fields on one basis, build a :class:`StressProjector` once instead.
    """
    return StressProjector(basis, backend)(u, E, nu)
