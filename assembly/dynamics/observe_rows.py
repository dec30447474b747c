"""What a time-domain run records at each step, as rows on its state: ``Ok q + Oc v`` (a
nonlinear mesh's force, ``swap`` (row, mesh): its contact force plus ``Os v``), then ``Oa a``
and ``Sv v`` -- arrays that the Python step and the compiled step
(:mod:`assembly.dynamics.step_kernel`) read alike. A row may instead be picked from the state of
the rotor's aerodynamics at the accepted step (``picks`` (row, j): ``values.s[j]``, the wind
speed, pitch, aerodynamic torque or thrust, :mod:`assembly.dynamics.rotor_laws`), and ``held``
fills, after each stretch of steps, the rows of values held over it (a sampled load's: the
controller's generator torque), both steps' rows alike
(:func:`assembly.dynamics.transient.integrate` calls it).

Both read them as compressed sparse rows (:attr:`Rows.sparse`): an output row touches the few
coordinates of the bodies it is on (a mesh force two gears', a recorded coordinate one), so a
step's rows cost their nonzeros, not outputs x n. Each row is summed in its column order,
SciPy's CSR product and the compiled step's alike (:func:`assembly.dynamics.step_kernel.csr_into`),
so both steps record the same numbers.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp


@dataclass(frozen=True, eq=False)
class Rows:
    """The recorded rows (module notes); ``meshes``: the run's
    :class:`assembly.dynamics.mesh_contact.Meshes` whose ``last_force`` the swaps read (None
    without swaps); ``values``: the :class:`assembly.dynamics.rotor_aero.RotorAero` whose state
    ``s`` the ``picks`` read (None without picks); ``held(Y)``: fills a block of rows ``Y`` with
    the values held over its stretch, or None. Called as ``observe(q, v, a, nu)`` (the rows
    before ``held``)."""

    Ok: np.ndarray
    Oc: np.ndarray
    Oa: np.ndarray
    Sv: np.ndarray
    Os: np.ndarray | None = None
    swap: tuple = ()
    meshes: object = None
    picks: tuple = ()
    values: object = None
    held: object = None

    def __post_init__(self):
        Os = self.Os if self.Os is not None else np.zeros_like(self.Ok)
        Ok, Oc = np.array(self.Ok, float), np.array(self.Oc, float)
        swapped = [i for i, _ in self.swap]
        Ok[swapped], Oc[swapped] = 0.0, 0.0          # rows a swap replaces: not summed at all
        object.__setattr__(self, "sparse", tuple(csr(X) for X in (Ok, Oc, Os, self.Oa, self.Sv)))

    @property
    def size(self) -> int:
        return self.Ok.shape[0] + self.Oa.shape[0] + self.Sv.shape[0]

    def __call__(self, q, v, a, nu):
        Ok, Oc, Os, Oa, Sv = self.sparse
        y = Ok @ q + Oc @ v
        if self.swap:
            ys = Os @ v
            for i, j in self.swap:
                y[i] = self.meshes.last_force[j] + ys[i]
        out = np.concatenate([y, Oa @ a, Sv @ v])
        for i, j in self.picks:
            out[i] = self.values.s[j]
        return out


def csr(X) -> sp.csr_matrix:
    """``X`` as compressed sparse rows, its zeros dropped and each row's columns in order."""
    m = sp.csr_matrix(np.asarray(X, float))
    m.eliminate_zeros()
    m.sort_indices()
    return m


def state_rows(n: int, q=True, v=False, a=False) -> Rows:
    """Rows recording the coordinates, velocities and accelerations asked for (in that order)
    of a model of ``n`` coordinates."""
    eye, none = np.eye(n), np.zeros((0, n))
    return Rows(eye if q else none, np.zeros((n, n)) if q else none, eye if a else none, eye if v else none)
