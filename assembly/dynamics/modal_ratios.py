"""Modal damping ratios of a scene's ``[damping]`` table, one per mode of a modal result.

``modal_ratio`` gives every elastic mode its zeta; ``class_ratios`` ({mode class: zeta})
overrides it for the modes of those classes (:func:`assembly.analysis.classify.classify_modes`).
Rigid-body (0 Hz) modes get 0: modal damping acts on elastic modes only.
"""
from __future__ import annotations

import numpy as np

from ..analysis.classify import classify_modes


def mode_ratios(result) -> np.ndarray:
    """Damping ratio (dimensionless) of every mode of ``result`` from its scene's
    ``[damping]`` modal ratios (zeros without any)."""
    zeta = np.zeros(len(result.frequencies_hz))
    d = result.model.scene.damping
    if d is None or not d.modal:
        return zeta
    zeta[:] = d.modal_ratio or 0.0
    if d.class_ratios:
        for info in classify_modes(result, nodal_diameters=False):
            if info.mode_class in d.class_ratios:
                zeta[info.index] = d.class_ratios[info.mode_class]
    zeta[:result.n_rigid] = 0.0
    return zeta
