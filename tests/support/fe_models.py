"""Small linear-elastic example components (scikit-fem): test fixtures of the cms tests
and the Craig-Bampton benchmark.

DOF order is scikit-fem's ``ElementVector``: for P1/P2 tetrahedra the vector
basis numbers DOFs 3*node + xyz, where "node" runs over ``basis.doflocs[:, ::3]``
(vertices, then edge midpoints for P2).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import Basis, BilinearForm, ElementTetP1, ElementTetP2, ElementVector, MeshTet, asm
from skfem.helpers import dot
from skfem.models.elasticity import lame_parameters, linear_elasticity


@dataclass
class ElasticModel:
    K: sp.csr_matrix        # stiffness, N/m
    M: sp.csr_matrix        # consistent mass, kg
    basis: Basis            # vector basis (ElementVector)
    node_coords: np.ndarray  # (n/3, 3) position of DOF nodes, m
    E: float                # Young's modulus, Pa
    nu: float               # Poisson ratio
    rho: float              # density, kg/m^3

    @property
    def n(self) -> int:
        return self.K.shape[0]

    def dofs_where(self, predicate) -> np.ndarray:
        """All 3 DOFs of every node whose coordinates (3, m) satisfy ``predicate``."""
        nodes = np.flatnonzero(predicate(self.node_coords.T))
        return (3 * nodes[:, None] + np.arange(3)).ravel()


def assemble(mesh, E: float, nu: float, rho: float, order: int = 2) -> ElasticModel:
    elem = ElementVector(ElementTetP2() if order == 2 else ElementTetP1())
    basis = Basis(mesh, elem, intorder=2 * order)
    K = asm(linear_elasticity(*lame_parameters(E, nu)), basis)

    @BilinearForm
    def mass(u, v, w):
        return rho * dot(u, v)

    M = asm(mass, basis)
    return ElasticModel(K.tocsr(), M.tocsr(), basis, basis.doflocs[:, ::3].T.copy(), E, nu, rho)


def box(lengths=(1.0, 0.1, 0.1), divisions=(10, 2, 2), E=210e9, nu=0.3, rho=7850.0,
        order: int = 2, origin=(0.0, 0.0, 0.0)) -> ElasticModel:
    """Rectangular block [origin, origin + lengths] (m), steel by default."""
    axes = [np.linspace(o, o + L, d + 1) for o, L, d in zip(origin, lengths, divisions)]
    return assemble(MeshTet.init_tensor(*axes), E, nu, rho, order)
