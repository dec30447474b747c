"""Whether an eigen solve resolves a model's modes, and which scene field spoils it if not.

A dense solve of ``A x = lambda B x`` (LAPACK) is backward stable: its eigenpairs are
exact for ``A + E``, ``B + F`` with ``||E|| ~ eps ||A||``, ``||F|| ~ eps ||B||``. To first
order that moves eigenvalue i by ``x_i' (E - lambda_i F) x_i`` (Stewart & Sun, Matrix
Perturbation Theory, 1990, ch. VI), so with B-normalised x_i and ``||A|| <= lambda_max ||B||``
the error is about ``ROUNDOFF eps (lambda_max + |lambda_i|) ||B|| ||x_i||^2``. B is the mass
matrix scaled to unit diagonal; ``||x_i||^2`` is about 1 unless the mode moves along a
nearly massless combination (a planet on a carrier 1e3 lighter). So the relative error of
a mode grows with the spread ``lambda_max / lambda``: a rigid-body mode comes out at that
round-off level instead of 0, and an elastic mode far below the highest one loses its
digits. :func:`check` compares the computed spectrum with that bound:

- the first ``n_zero`` eigenvalues (rigid-body modes, counted from the structure by
  :mod:`assembly.mechanics.nullity`) must lie within the round-off bound;
- the lowest elastic frequency must be resolved to FREQ_RTOL.

Otherwise it raises :class:`~assembly.errors.SceneError` naming the field at fault: first
the field that put a body a hair off the axis of a body it is joined to, when that lever arm
is what removes a rigid-body mode from the structure (:func:`cause`,
:mod:`assembly.analysis.lever_arms`); else the field whose magnitude sets the spread
(:func:`culprit`): a stiff spring or light body taking part in the highest
mode when that one lies further above the band than the lowest elastic mode lies below it,
else a soft spring or heavy body -- the one furthest, in decades, from the median of the
scene's other values of its unit (N/m, N m/rad, kg, kg m^2).
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from fe_components.params import component_kind

from ..errors import SceneError
from ..scene.paths import body_origins, element_paths

log = logging.getLogger(__name__)


#: Documented accuracy: every reported elastic frequency is resolved to this relative
#: error; frequencies closer than it count as repeated (:data:`assembly.analysis.modal.REPEAT_RTOL`
#: is this constant: grouping is only meaningful above the errors). Set by the whole NREL
#: 5 MW drivetrain with flexible carriers and wheel (assembly/scenes/nrel5mw_flexible.toml):
#: the rotor's tilt on its main bearings at 1.76 Hz (and planet axial modes near 2 Hz: Nejad et
#: al. 2016's planet bearings, K_x 9.1e4 N/m) beside superelement modes up to 2.4e4 Hz give a
#: round-off bound of 1.4e-6 there; 1e-5
#: resolves frequency ratios f_max / f_low up to about 1e5, which such a drivetrain needs,
#: and stays far below any model error (a published stiffness is rarely known to 1 %).
FREQ_RTOL = 1e-5
#: Above this bound on the lowest elastic frequency's relative error (a hundredth of
#: FREQ_RTOL: the round-off is no longer negligible against the documented accuracy) the
#: solve logs a warning naming the field that sets the spread.
WARN_RTOL = FREQ_RTOL / 100
#: Eigenvalue round-off of the dense solve, in units of the first-order size above,
#: ``eps (lambda_max + |lambda_i|) ||B||_1 ||x_i||^2``. Measured against a 60-digit solve
#: (mpmath) of the same matrices on 500 random members of the class in
#: tests/hard_cases/test_magnitudes.py (mesh x1e-8 ... 1e12, bearings x1e-3 ... 1e12, one
#: body's mass and inertias x1e-15 ... 1e15): at most 3.8; 0.74 for a carrier or planets
#: 1e3 ... 1e7 off in mass or inertia (where the error reached 1650 eps lambda_max); 0.28
#: on the shipped flexible scenes. 10 covers them; that test checks every accepted solve
#: of its class against this bound.
ROUNDOFF = 10.0
EPS = float(np.finfo(float).eps)

_UNITS = {"stiffness": "N/m", "k_radial": "N/m", "k_radial_x": "N/m", "k_radial_y": "N/m", "k_axial": "N/m",
          "k_shear": "N/m", "k_tilt": "N m/rad", "k_tilt_x": "N m/rad", "k_tilt_y": "N m/rad",
          "k_torsion": "N m/rad", "k_bending": "N m/rad",
          "mass": "kg", "polar_inertia": "kg m^2", "transverse_inertia": "kg m^2"}


@dataclass(frozen=True)
class Spectrum:
    """Eigenvalues of one solve in a scaled unit, ``lam = 4**p4 * lambda`` with lambda in
    (rad/s)^2, kept scaled so that absurd magnitudes never overflow (a power of 4, so that
    scaling and unscaling are exact)."""

    lam: np.ndarray          # computed eigenvalues, ascending (scaled)
    lam_max: float           # highest eigenvalue of the problem (scaled; an estimate if not solved)
    weight: np.ndarray       # (lambda_max + |lambda_i|) ||B|| ||x_i||^2 of each computed mode (scaled)
    p4: int = 0

    def hz(self, lam):
        """Frequency (Hz) of scaled eigenvalue(s), 0 for lam <= 0 (inf beyond double precision)."""
        with np.errstate(over="ignore"):
            return np.ldexp(np.sqrt(np.clip(lam, 0.0, None)), -self.p4) / (2 * math.pi)

    def unscaled(self) -> np.ndarray:
        """The eigenvalues in (rad/s)^2."""
        with np.errstate(over="ignore"):
            return np.ldexp(self.lam, -2 * self.p4)

    @property
    def roundoff(self) -> np.ndarray:
        """Absolute error bound of each computed eigenvalue (scaled)."""
        return ROUNDOFF * EPS * self.weight


def mode_weights(lam: np.ndarray, lam_max: float, X: np.ndarray, B_norm: float) -> np.ndarray:
    """``(lambda_max + |lambda_i|) ||B|| ||x_i||^2``: the first-order size of the change of
    eigenvalue i under a backward error ``eps ||A||`` in A and ``eps ||B||`` in B, for
    B-normalised eigenvectors x_i (columns of X) of the scaled problem, ||A|| <= lambda_max ||B||."""
    return (lam_max + np.abs(lam)) * B_norm * np.einsum("ij,ij->j", X, X)


def frequency_rtol(spec: Spectrum, n_zero: int) -> float:
    """Bound on the relative error of the lowest elastic frequency (0 if none computed):
    half the relative eigenvalue error."""
    if n_zero >= len(spec.lam):
        return 0.0
    low = spec.lam[n_zero]
    return math.inf if low <= 0 else 0.5 * spec.roundoff[n_zero] / low


def check(model, spec: Spectrum, n_zero: int, top: np.ndarray) -> float:
    """Raise SceneError unless ``spec`` resolves the model (see module doc); return the
    bound of :func:`frequency_rtol`. ``top``: the highest mode (independent coordinates),
    or a vector that excites it."""
    lam, bound = spec.lam, spec.roundoff
    f_max = spec.hz(spec.lam_max)
    bad = [i for i in range(min(n_zero, len(lam))) if abs(lam[i]) > bound[i]]
    if bad:
        i = bad[-1]
        why = (f"the structure has {n_zero} rigid-body modes, but mode {i + 1} comes out at "
               f"{spec.hz(abs(lam[i])):.3g} Hz, far above the solve's round-off ({spec.hz(bound[i]):.3g} Hz "
               f"with the highest frequency at {f_max:.3g} Hz)")
        raise cause(model, n_zero, why) or culprit(model, top, "top", why)
    rtol = frequency_rtol(spec, n_zero)
    if rtol > WARN_RTOL:            # WARN_RTOL < FREQ_RTOL
        low, f_round = lam[n_zero], spec.hz(bound[n_zero])
        what = (f"resolves the lowest elastic mode ({spec.hz(low):.4g} Hz) only to {rtol:.1e} relative"
                if low > bound[n_zero] else f"loses the lowest elastic mode in its round-off (below {f_round:.3g} Hz)")
        why = (f"the eigen solve {what}, needs <= {FREQ_RTOL:g}: eigenvalue round-off grows with the highest "
               f"frequency, {f_max:.3g} Hz")
        f_low = spec.hz(max(low, bound[n_zero]))
        band = model.scene.band
        end = "top" if math.log(f_max / band) >= math.log(band / max(f_low, 1e-300)) else "low"
        if rtol > FREQ_RTOL:
            raise cause(model, n_zero, why) or culprit(model, top, end, why)
        why = why.replace(", needs <= ", ", within ")
        log.warning("accuracy: %s", cause(model, n_zero, why) or culprit(model, top, end, why))
    if not math.isfinite(f_max):
        raise culprit(model, top, "top", "the frequencies exceed double precision")
    return rtol


def cause(model, n_zero: int, why: str) -> SceneError | None:
    """SceneError naming a body placed a hair off the axis of a body it is joined to, when
    that offset is what takes a rigid-body mode from the structure (a lever arm, not a
    magnitude: :func:`assembly.analysis.lever_arms.hair_error`), else None."""
    from .lever_arms import hair_error  # it reads the scene paths defined here
    return hair_error(model, n_zero, why, scene_paths(model))


# ---------------------------------------------------------------- naming the culprit
#: A field counts as taking part in the highest mode when it holds at least this share of
#: its strain or kinetic energy.
PARTICIPATION = 0.01


@dataclass(frozen=True)
class Candidate:
    """A scene field that sets a stiffness or an inertia of the model."""

    path: str
    value: object
    field: str
    magnitude: float        # the model's value of the field (N/m, kg, ...)
    log_energy: float = -math.inf   # log of its strain or kinetic energy in a given motion

    @property
    def unit(self):
        return _UNITS.get(self.field)


#: A body field is named instead of the spring only when it lies this many decades
#: further from its median than the spring does: masses and inertias of one drivetrain
#: differ by a factor of 100 as a matter of course (shaft against gear wheel), and a whole
#: class of springs scaled together (all bearings x1e7) moves the median with it.
BODY_MARGIN_DECADES = 2.0


def culprit(model, top: np.ndarray, end: str, why: str) -> SceneError:
    """SceneError naming the field whose magnitude makes the spectrum unresolvable.

    ``end = "top"``: the highest frequency is out of place (compared with the band): the
    culprit is the stiffest spring taking part in the highest mode ``top`` (its strain
    energy sets lambda_max), or the lightest body field moving in it if that lies
    BODY_MARGIN_DECADES further from its median. ``"low"``: the lowest elastic mode is out
    of place (and lost in round-off, so every field qualifies): the softest spring, or the
    heaviest body field by the same margin. "Stiff", "light", ... are measured in decades
    from the median of the scene's other values of the same unit.
    """
    springs, bodies = spring_energies(model, top), kinetic_energies(model, top)
    everything = springs + bodies
    sign = 1 if end == "top" else -1
    if end == "top":
        springs, bodies = _participating(springs), _participating(bodies) + _moving(bodies)
    def most(cands, sgn):
        """(decades, candidate) furthest in direction ``sgn``; ties go to the larger energy."""
        scored = [(sgn * _decades(c, everything), c.log_energy, c) for c in cands]
        return max(scored, key=lambda t: t[:2], default=None)

    s, b = most(springs, sign), most(bodies, -sign)
    if s is None and b is None:
        return SceneError("scene", model.scene.name, why)
    best = b[2] if s is None or (b is not None and b[0] > s[0] + BODY_MARGIN_DECADES) else s[2]
    ref = _median_of_others(best, everything)
    if ref and best.magnitude > 0:
        why = f"{best.magnitude / ref:.1e} x the median of the scene's other {best.unit} values ({ref:.3g}); {why}"
    return SceneError(best.path, best.value, why)


def _decades(c: Candidate, cands: list) -> float:
    """log10 of ``c``'s magnitude over the median of the other values of its unit (0 if
    it has none)."""
    ref = _median_of_others(c, cands)
    return math.log10(c.magnitude / ref) if ref and c.magnitude > 0 else 0.0


def _participating(cands: list) -> list:
    """The candidates holding at least PARTICIPATION of the energy of their kind."""
    le = np.array([c.log_energy for c in cands])
    if not len(le) or not np.isfinite(le.max()):
        return []
    share = np.exp(le - le.max())
    return [c for c, x in zip(cands, share / share.sum()) if x >= PARTICIPATION]


def _moving(cands: list) -> list:
    """Body fields whose motion (energy / magnitude) is at least PARTICIPATION of the
    largest motion of the same unit: a body far lighter than the rest moves in the
    highest mode even where its kinetic energy is negligible (a singular mass matrix)."""
    out = []
    for unit in {c.unit for c in cands}:
        group = [c for c in cands if c.unit == unit and c.magnitude > 0 and np.isfinite(c.log_energy)]
        motion = [c.log_energy - math.log(c.magnitude) for c in group]
        out += [c for c, m in zip(group, motion) if m >= max(motion) + math.log(PARTICIPATION)]
    return out


def _median_of_others(c: Candidate, cands: list) -> float | None:
    vals = {o.path: o.magnitude for o in cands if o.unit == c.unit and o.path != c.path and o.magnitude > 0}
    if c.unit is None or not vals:
        return None
    return float(np.exp(np.median(np.log(list(vals.values())))))


def _log_energy(a, b) -> float:
    """log(a * b^2) for a >= 0 without overflow (-inf for a zero product)."""
    if a <= 0 or b == 0:
        return -math.inf
    return math.log(a) + 2 * math.log(abs(b))


def spring_energies(model, q: np.ndarray) -> list:
    """One Candidate per spring row of ``model`` with its strain energy in the motion
    ``q`` (independent coordinates)."""
    z = model.T @ q
    paths = scene_paths(model)
    out = []
    for el in model.elements:
        e = el.B @ (model.attachment_operator(el) @ z)
        for j, (k, ej) in enumerate(zip(el.k, e)):
            field = el.fields[j] if el.fields else "stiffness"
            path, value = element_field(paths, el, field)
            out.append(Candidate(path, value, field, float(k), _log_energy(k, ej)))
    return out


def kinetic_energies(model, q: np.ndarray) -> list:
    """One Candidate per body mass field (mass, polar/transverse inertia; a flexible
    body's component) with its kinetic energy in the motion ``q``."""
    z = model.T @ q
    paths = scene_paths(model)
    out = []
    for name, bm in model.bodies.items():
        zb = z[model.body_slice(name)]
        if bm.flexible:
            path, value = body_field(paths, name, "component")
            out.append(Candidate(path, value, "component", 0.0, _log_energy(zb @ (bm.M @ zb), 1.0)))
            continue
        R = bm.axes
        u, th = R.T @ zb[:3], R.T @ zb[3:]
        J = R.T @ bm.inertia @ R
        jt = 0.5 * (J[0, 0] + J[1, 1])
        for field, mag, energy in (("mass", bm.mass, _log_energy(bm.mass, np.linalg.norm(u))),
                                   ("polar_inertia", J[2, 2], _log_energy(J[2, 2], th[2])),
                                   ("transverse_inertia", jt, _log_energy(jt, np.linalg.norm(th[:2])))):
            path, value = body_field(paths, name, field)
            out.append(Candidate(path, value, field, float(mag), energy))
    return out


# ---------------------------------------------------------------- scene paths
@dataclass(frozen=True)
class ScenePaths:
    """Where each body and spring of a model was written in the user's scene."""

    bodies: dict            # body name -> (table path, the body as written; stages expanded)
    elements: dict          # element item, e.g. ("bearings", 2) -> (table path, the item as written)


def scene_paths(model) -> ScenePaths:
    """The :class:`ScenePaths` of ``model``'s source scene (the scene as the user gave it);
    of its own scene when the user's does not expand to the same tables."""
    src = model.source if model.source is not None else model.scene
    exp = src.expanded()
    same = all(len(getattr(exp, k)) == len(getattr(model.scene, k)) for k in ("bodies", "bearings", "meshes"))
    if not same:
        src = exp = model.scene
    origin = body_origins(src, exp)
    # stages make bodies, bearings and meshes: every shaft is one of the user's own
    elements = {(key, i): entry for key, attr in (("bearings", "body"), ("shafts", "body1"), ("meshes", "gear1"))
                for i, entry in enumerate(element_paths(src, exp, key, origin, attr))}
    return ScenePaths({b.name: (origin[b.name], b) for b in exp.bodies}, elements)


def _plain(v):
    """A numpy scalar as the Python number a user would have written."""
    return v.item() if isinstance(v, np.generic) else v


def body_field(paths: ScenePaths, body: str, field: str) -> tuple:
    """(path, value) of a body's mass field as the user wrote it."""
    path, b = paths.bodies[body]
    if b.component is not None:
        return f"{path}.component", component_kind(b.component)
    if b.inertia_tensor is not None and field != "mass":
        field = "inertia_tensor"
    elif field == "transverse_inertia" and b.transverse_inertia is None:
        field = "polar_inertia"      # transverse defaults to polar / 2
    return f"{path}.{field}", _plain(getattr(b, field))


def element_field(paths: ScenePaths, el, field: str) -> tuple:
    """(path, value) of the scene field behind one spring row of element ``el``."""
    path, item = paths.elements[el.item]
    if el.item[0] == "meshes" and path.startswith("stages["):
        # a stage's mesh: its stiffness is the stage's k_mesh_sun or k_mesh_ring
        sun = paths.bodies[item.gear1][1].role == "sun"
        return f"{path}.{'k_mesh_sun' if sun else 'k_mesh_ring'}", _plain(item.stiffness)
    return f"{path}.{field}", _plain(getattr(item, field))
