"""The steps of a run in stretches: the plan of where Python takes over between them (its
loads, the progress calls, the history), and the compiled step's arrays gathered from the run's
parts (:mod:`assembly.dynamics.step_kernel`).

A compiled stretch spans :data:`STRETCH_MAX` steps (a few tens of ms of compiled steps: the
progress calls it passed are made after it); a stretch of the Python step ends at a multiple
of the progress period and spans at least :data:`STRETCH_MIN` steps. Python evaluates what
depends on time alone for the whole stretch at once (the external loads at the steps' ``t_i +
(1 - alpha_f) dt``, the generator's recorded torque, the brake torque, the wind speed and the
pitch at ``t_{i+1}``), then one call runs it. A sampled load's times end stretches too
(:mod:`assembly.dynamics.sampled`).
"""
from __future__ import annotations

import numpy as np

from . import jit
from .step_kernel import OFF_SURFACE, run_stretch

#: Dense models up to this size keep the predictor's map Z (n x 2n, 3n with alpha_m) and run compiled.
PREDICTOR_MAX = 1500


def predictor_map(Ainv, M, C, K, dt: float, scheme) -> np.ndarray:
    """``Z`` with ``Z [qp; vp] = (1 - alpha_f) A0^-1 (K qp + C vp)`` (n x 2n), and ``Z [qp; vp;
    a]`` adding ``alpha_m A0^-1 M a`` (n x 3n) when alpha_m != 0: the part of the step's ``x0``
    known from the step's predictors ``qp = q + dt v + dt^2 (1/2 - beta) a``, ``vp = v + dt (1 -
    gamma) a``, in one product. (A map of ``[q; v; a]`` would read 3n columns a step for the
    same numbers; the dense step is bound by reading this map from memory.)"""
    am, af = scheme.alpha_m, scheme.alpha_f
    blocks = [(1 - af) * (Ainv @ K), (1 - af) * (Ainv @ C)]
    if am != 0.0:
        blocks.append(am * (Ainv @ M))
    return np.hstack(blocks)


#: Steps of a stretch: the fewest (the cost of a call from Python spread over them) and the most
#: (the loads evaluated ahead, and the rows of a block).
STRETCH_MIN, STRETCH_MAX = 64, 1024


def plan(n_steps: int, report: int, sample: int = 0, compiled: bool = False):
    """[(first step, steps)] of the run's stretches (module notes); ``sample`` > 0: every
    multiple of that many steps ends a stretch too (a sampled load's times,
    :mod:`assembly.dynamics.sampled`)."""
    size = STRETCH_MAX if compiled else max(1, min(STRETCH_MAX, report * -(-STRETCH_MIN // report)))
    cuts = set(range(0, n_steps, size))
    if sample > 0:
        cuts.update(range(0, n_steps, sample))
    ends = sorted(cuts) + [n_steps]
    return [(a, b - a) for a, b in zip(ends[:-1], ends[1:])]


#: The nonlinear parts the compiled step knows (their ``compiled``), in the order of their columns.
KINDS = ("meshes", "torques", "rotor")


def compiled_parts(nl, observe, Z):
    """(meshes, torques, rotor) of a run the compiled step can take (None for a part it does not
    have), or None: a dense model, rows to record (:class:`assembly.dynamics.observe_rows.Rows`,
    whose picks read the rotor's state), and nonlinear parts that are the meshes (exact
    tangents), the shaft torques and the rotor's aerodynamics, each at most once and in that
    order (module notes); ``Z``: the predictor's map of a dense model (:func:`predictor_map`) or
    None."""
    if not (jit.ENABLED and jit.COMPILED) or Z is None:
        return None
    if not all(hasattr(observe, k) for k in ("sparse", "swap")):
        return None
    parts = list(getattr(nl, "parts", [nl]))
    kinds = [getattr(p, "compiled", None) for p in parts]
    if not all(k in KINDS for k in kinds) or kinds != sorted(set(kinds), key=KINDS.index):
        return None
    meshes, torques, rotor = (parts[kinds.index(k)] if k in kinds else None for k in KINDS)
    if meshes is not None and meshes.gap_slope != 0.0:
        return None
    if getattr(observe, "picks", ()) and getattr(observe, "values", None) is not rotor:
        return None
    return meshes, torques, rotor


def load_block(force, t_a: np.ndarray):
    """(LV, LH, direct): the loads at the times ``t_a`` as ``LV @ LH[k]`` (a force with load
    ``vectors`` and time ``histories``, e.g. :class:`assembly.dynamics.run_loads.RunLoads`), or
    ``LH[k]`` itself (``direct``: any callable, one call a step). C-ordered arrays, whatever
    order the force keeps its vectors in (the compiled step has one signature)."""
    vecs, hist = getattr(force, "vectors", None), getattr(force, "histories", None)
    if vecs is not None and hist is not None:
        if not len(hist):
            return np.zeros((np.shape(vecs)[0], 0)), np.zeros((len(t_a), 0)), False
        return (np.ascontiguousarray(vecs, float), np.column_stack([np.asarray(h(t_a), float) for h in hist]),
                False)
    return np.zeros((0, 0)), np.array([np.asarray(force(t), float) for t in t_a]), True


class CompiledSteps:
    """Runs stretches of steps by :func:`assembly.dynamics.step_kernel.run_stretch` on the
    run's arrays: the model (``Ainv`` the kept inverse of the effective matrix, ``Z`` the
    predictor's map, ``AinvL`` the inverse times the load vectors), the parts' laws, the rows,
    and the state ``(q, v, a, Ma, F, xi, xi_prev)`` (updated in place)."""

    def __init__(self, parts, M, Ainv, Z, AinvL, W, S, U, scheme, dt, observe, force, state):
        meshes, torques, rotor = parts
        self.dt, self.force, self.torques, self.rotor = dt, force, torques, rotor
        self.scheme = np.array([scheme.alpha_m, scheme.alpha_f, scheme.beta, scheme.gamma, dt])
        C = np.ascontiguousarray                 # one layout for every run: one compiled signature
        self.model = (C(Ainv), C(M), C(Z), C(W), C(S), C(U.T))
        self.AinvL = C(AinvL)
        if meshes is not None and meshes.m:
            self.mesh = (*(C(x) for x in meshes.laws()), float(meshes.consistent))
            self.mesh_state = (meshes.contact, meshes.losses, meshes.last_force)
        else:
            z = np.zeros(0)
            self.mesh = (z, z, np.zeros((0, 0)), np.zeros((0, 0)), np.zeros((0, 0)), z, z, z, 0.0)
            self.mesh_state = (np.zeros(0, bool), np.zeros(0, np.int64), z)
        self.torque = (torques.p, torques.s) if torques is not None else (np.zeros(0), np.zeros(0))
        t0 = 2 * meshes.m if meshes is not None else 0          # the parts' first columns (U's order)
        r0 = t0 + (torques.U.shape[1] if torques is not None else 0)
        self.offsets = (t0, r0)
        if rotor is not None:
            self.aero = (rotor.p, *rotor.tables, rotor.s)
        else:
            z = np.zeros(0)
            self.aero = (z, z, z, np.zeros((0, 0)), np.zeros((0, 0)), z)
        swap = np.array(observe.swap, np.int64).reshape(-1, 2)
        picks = np.array(getattr(observe, "picks", ()), np.int64).reshape(-1, 2)
        parts = [(X.indptr.astype(np.int64), X.indices.astype(np.int64), X.data) for X in observe.sparse]
        self.rows = (*(a for p in parts for a in p), swap[:, 0].copy(), swap[:, 1].copy(), picks[:, 0].copy(),
                     picks[:, 1].copy())
        self.state = state

    def now(self):
        """(q, v) of the last step."""
        return self.state[0], self.state[1]

    def run(self, t: np.ndarray, Y: np.ndarray, its: np.ndarray):
        """The ``len(t) - 1`` steps from ``t[0]`` (rows into ``Y``, counts into ``its``):
        (steps done, why it stopped or DONE, the residual or the coordinate); a rotor state the
        surface does not cover raises its SceneError, as the Python step does
        (:meth:`assembly.dynamics.rotor_aero.RotorAero.refuse`)."""
        count = len(t) - 1
        af = self.scheme[1]
        LV, LH, direct = load_block(self.force, t[:-1] + (1 - af) * self.dt)
        if self.torques is not None:
            table = np.asarray(self.torques.table(t[1:]), float)
            brake = np.asarray(self.torques.brake_torque(t[1:]), float)
        else:
            table = brake = np.zeros(count)
        wind, beta = self.rotor.inputs(t[1:]) if self.rotor is not None else (np.zeros(count), np.zeros(count))
        t0, r0 = self.offsets
        done, why, value = run_stretch(count, t, self.scheme, *self.model, LV, self.AinvL, LH, direct, *self.mesh,
                                       *self.torque, table, brake, self.torques is not None, t0, *self.aero, wind,
                                       beta, self.rotor is not None, r0, *self.rows, *self.state, *self.mesh_state,
                                       Y, its)
        if why == OFF_SURFACE:
            self.rotor.refuse(t[done + 1], value)
        return done, why, value

