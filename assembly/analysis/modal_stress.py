"""Modal stresses at a stated physical amplitude.

A mass-normalised mode shape has no physical size (its modal coordinate is 1 kg^1/2), so
stresses of it are not MPa of anything. Each mode is scaled here so that the largest
nodal displacement magnitude over every FE node of every flexible body is
MODAL_PEAK_DISPLACEMENT_M; its stresses are then "MPa at 1 mm peak displacement of the
flexible bodies", comparable between modes and linear in the amplitude (stress at a peak
displacement d = the stated value x d / 1 mm). A flexible body whose share of the mode's
strain energy is below :data:`assembly.analysis.energy.NEGLIGIBLE_STRAIN_SHARE` carries no stress
in that mode: it is skipped rather than given a colour scale of round-off.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .energy import NEGLIGIBLE_STRAIN_SHARE, strain_by_body

#: Peak displacement (m) over the flexible bodies that each mode is scaled to for its
#: stresses.
MODAL_PEAK_DISPLACEMENT_M = 1e-3
#: A flexible body holding less than this share of a mode's strain energy gets no stress image
#: in that mode (its stresses stay in modal_stress.csv): a colour scale of a few hundred MPa on a
#: body that carries 0.03 % of the mode misleads more than it tells.
IMAGE_STRAIN_SHARE = 0.01


def drawn(amplitude, body: str) -> bool:
    """Whether ``body``'s stress image is drawn in the mode of ``amplitude`` (a
    :class:`ModalAmplitude`): its share of the mode's strain energy is at least
    :data:`IMAGE_STRAIN_SHARE`."""
    return body not in amplitude.skipped and amplitude.strain_share.get(body, 0.0) >= IMAGE_STRAIN_SHARE


#: How the scaled modal stresses are labelled (titles, captions, docs) and their CSV column.
MODAL_AMPLITUDE_LABEL = f"{MODAL_PEAK_DISPLACEMENT_M * 1e3:g} mm peak displacement of the flexible bodies"
MODAL_STRESS_COLUMN = f"max_von_mises_Pa_at_{MODAL_PEAK_DISPLACEMENT_M * 1e3:g}mm_peak_displacement"


@dataclass(frozen=True)
class ModalAmplitude:
    """One mode scaled for stresses. ``factor``: modal coordinate (kg^1/2) giving the peak
    displacement ``MODAL_PEAK_DISPLACEMENT_M`` (m); 0 for a mode without displacement of the
    flexible bodies. ``strain_share``: body -> share of the mode's strain energy;
    ``skipped``: flexible bodies below NEGLIGIBLE_STRAIN_SHARE; ``carrier``: the flexible
    body with the largest share (None when every one is skipped)."""

    mode: int
    factor: float
    strain_share: dict
    skipped: tuple
    carrier: str | None


def flexible_names(model) -> list:
    return [n for n, bm in model.bodies.items() if bm.flexible]


def peak_displacement(model, z: np.ndarray) -> float:
    """Largest nodal displacement magnitude (m) over the FE nodes of every flexible body of
    ``model`` for absolute DOFs ``z`` (back-expanded)."""
    peak = 0.0
    for b in flexible_names(model):
        d = model.bodies[b].displacement_global(z[model.body_slice(b)])
        peak = max(peak, float(np.sqrt((d * d).sum(axis=1)).max(initial=0.0)))
    return peak


def modal_amplitudes(result, modes, peak_m: float = MODAL_PEAK_DISPLACEMENT_M) -> list:
    """:class:`ModalAmplitude` of each mode index (0-based) in ``modes``."""
    model = result.model
    names = list(model.bodies)
    flex = flexible_names(model)
    shares = strain_by_body(result)
    out = []
    for i in modes:
        z = result.abs_shapes[:, i]
        peak = peak_displacement(model, z)
        share = {b: float(shares[i, names.index(b)]) for b in flex}
        skipped = tuple(b for b in flex if share[b] < NEGLIGIBLE_STRAIN_SHARE)
        carrier = max((b for b in flex if b not in skipped), key=share.get, default=None)
        out.append(ModalAmplitude(int(i), peak_m / peak if peak > 0 else 0.0, share, skipped, carrier))
    return out
