"""The damping matrix of a model's element dampers, and whether a scene has any damping.

Element dampers sit beside the springs, on the same strain rows ``B`` (:class:`assembly.
mechanics.elements.Element` ``c``): ``C_abs = sum L' B' diag(c) B L`` is assembled exactly as
``K_abs`` is, and ``C = T' C_abs T`` (N s/m, N m s/rad entries on q): the third matrix of
the model beside K and M. The scene's ``[damping]`` (modal ratios, Rayleigh) needs the modes
and is added on the dynamics floor (:mod:`assembly.dynamics.damping`).
"""
from __future__ import annotations

import numpy as np

from .assemble import on_q


def damping_matrix(model):
    """Sparse symmetric damping of every element damper of ``model`` on q (zero when the
    scene has no ``c_*`` field set); a dense array for a dense model."""
    if model.dense:
        C_abs = np.zeros((model.n_abs, model.n_abs))
    else:
        import scipy.sparse as sp
        C_abs = sp.csr_matrix((model.n_abs, model.n_abs))
    for el in model.elements:
        if el.c is not None:
            C_abs = C_abs + model.element_damping_abs(el)
    return on_q(model.T, C_abs if model.dense else C_abs.tocsr())


def has_damping(scene) -> bool:
    """Whether ``scene`` (as given or expanded) has any damping: element dampers (``c_*``,
    ``damping``, ``beta``) or a ``[damping]`` table with a non-zero entry."""
    d = scene.damping
    if d is not None and (d.rayleigh or (d.modal and (d.modal_ratio or any((d.class_ratios or {}).values())))):
        return True
    sc = scene.expanded()
    return (any(br.dampings() for br in sc.bearings) or any(m.damping for m in sc.meshes)
            or any(s.beta or s.damping_diagonal().any() for s in sc.shafts))
