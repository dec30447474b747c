"""fe_components.mapping_memo: the isoparametric mapping that computes each inverse
Jacobian once gives scikit-fem the very same numbers as its own mapping.

No physics here: the memoised mapping must be an exact stand-in (bit for bit) for
``mesh.mapping()``, so every comparison is exact equality, and the count of Jacobian
inversions is the point of the module (one per point set instead of one per basis function).
"""
import numpy as np
from skfem import Basis, BilinearForm, ElementTetP1, ElementTetP2, ElementVector, MeshTet1, MeshTet2, asm
from skfem.helpers import dot
from skfem.mapping import MappingIsoparametric
from skfem.models.elasticity import lame_parameters, linear_elasticity

from fe_components.mapping_memo import memoised_mapping


def _curved_mesh():
    """48 P2-geometry tetrahedra (isoparametric mapping) of a unit cube."""
    return MeshTet2.from_mesh(MeshTet1.init_tensor(*(np.linspace(0, 1, 3),) * 3))


def test_memoised_mapping_gives_the_same_stiffness_and_mass_bit_for_bit():
    mesh = _curved_mesh()
    assert not mesh.affine
    elem = ElementVector(ElementTetP2())
    memo = memoised_mapping(mesh)
    assert isinstance(memo, MappingIsoparametric)
    lam, mu = lame_parameters(2.1e11, 0.3)

    @BilinearForm
    def mass(u, v, w):
        return dot(u, v)

    for order in (2, 4):
        ref, new = Basis(mesh, elem, intorder=order), Basis(mesh, elem, mapping=memo, intorder=order)
        for form in (linear_elasticity(lam, mu), mass):
            A, B = asm(form, ref).tocsr(), asm(form, new).tocsr()
            assert np.array_equal(A.indptr, B.indptr) and np.array_equal(A.indices, B.indices)
            assert np.array_equal(A.data, B.data)
        assert np.array_equal(ref.dx, new.dx)


def test_one_inversion_per_point_set_shared_by_every_basis_of_the_mesh():
    mesh = _curved_mesh()
    memo = memoised_mapping(mesh)
    calls = []
    inner = MappingIsoparametric.invDF

    def counting(self, X, tind=None):
        calls.append(tind is None)
        return inner(self, X, tind)

    MappingIsoparametric.invDF = counting
    try:
        kb = Basis(mesh, ElementVector(ElementTetP2()), mapping=memo, intorder=4)  # 30 basis functions
        kb.with_element(ElementTetP2())                                              # 10 more, same points
        Basis(mesh, ElementTetP1(), mapping=memo, intorder=4)
        assert calls == [True]
        Basis(mesh, ElementTetP1(), mapping=memo, intorder=2)                     # other points: one more
        assert calls == [True, True]
    finally:
        MappingIsoparametric.invDF = inner
    kept = next(iter(memo.invdf_memo.values()))
    assert not kept.flags.writeable


def test_an_affine_mesh_keeps_its_own_mapping():
    mesh = MeshTet1.init_tensor(*(np.linspace(0, 1, 3),) * 3)
    assert memoised_mapping(mesh) is mesh.mapping()
