"""A scikit-fem reference mapping that computes the inverse Jacobian of every element at a
set of quadrature points once.

scikit-fem's :class:`~skfem.assembly.CellBasis` evaluates ``mapping.invDF(X)`` once per
basis function (``Element.gbasis``): 30 times for a vector P2 tetrahedron, each time the
full isoparametric Jacobian of every element. Every basis of one mesh built on this mapping
(stiffness, mass, stress projection, their scalar twins by ``with_element``) shares the one
array per point set: the same numbers, computed once (0.7 s of a warm ``flexgear run`` of
the flexible parallel stage went to the repeats).
"""
from __future__ import annotations

import numpy as np


def memoised_mapping(mesh):
    """The mesh's default reference mapping, with ``invDF`` over all elements memoised per
    point set when the mapping is isoparametric (an affine mapping's ``invDF`` is already a
    broadcast of per-element inverses: returned as it is)."""
    from skfem.mapping import MappingIsoparametric

    class MemoisedIsoparametric(MappingIsoparametric):
        """MappingIsoparametric whose ``invDF(X)`` (all elements) is computed once per X;
        the kept arrays are read-only."""

        def invDF(self, X, tind=None):
            if tind is not None:
                return super().invDF(X, tind)
            X = np.asarray(X)
            key = (X.shape, X.dtype.str, X.tobytes())
            memo = self.__dict__.setdefault("invdf_memo", {})
            if key not in memo:
                inv = super().invDF(X)
                inv.flags.writeable = False
                memo[key] = inv
            return memo[key]

    if mesh.affine:
        return mesh.mapping()
    return MemoisedIsoparametric(mesh, mesh.elem(), mesh.bndelem)
