"""Tiny stand-ins for file-rule tests (what a command writes, not what it computes): a small
reduced body with a superelement to export, and an integrator that stops after a few steps.

* :func:`tiny_body`: a steel bar 0.2 x 0.05 x 0.05 m (P1 tetrahedra, 2 x 1 x 1 cells) with its
  end faces tied by RBE2 to masters "a" and "b", Craig-Bampton with 2 fixed-interface modes:
  the object ``assembly.app.export.superelement.write_body`` takes (``name``,
  ``superelement``, ``origin``, ``axes``), reduced in a fraction of a second.
* :func:`stop_after`: a replacement for ``assembly.dynamics.simulate.integrate`` that runs the
  first ``steps`` steps and then raises Diverged with them, as when a state stops being finite.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from cms.craig_bampton import CraigBamptonReductor
from fe_components.coupling import couple_nodes
from tests.support.fe_models import box

BAR = (0.2, 0.05, 0.05)        # m
STOP_REASON = "the run diverged at t = 0.001 s (rotor.rz is not finite)"


def tiny_body(name: str = "bar"):
    m = box(lengths=BAR, divisions=(2, 1, 1), order=1)
    X = m.node_coords
    ends = {"a": (np.flatnonzero(np.isclose(X[:, 0], 0.0)), [0.0, BAR[1] / 2, BAR[2] / 2], "rbe2"),
            "b": (np.flatnonzero(np.isclose(X[:, 0], BAR[0])), [BAR[0], BAR[1] / 2, BAR[2] / 2], "rbe2")}
    c = couple_nodes(m.K, m.M, X, ends)
    se = CraigBamptonReductor(c.K_c, c.M_c, c.boundary_dofs, n_modes=2, dof_layout=c.dof_layout(X),
                              dof_names=c.boundary_names).reduce()
    return SimpleNamespace(name=name, superelement=se, origin=np.zeros(3), axes=np.eye(3))


def stop_after(steps: int, calls: list | None = None):
    """``integrate`` that stops after ``steps`` steps (simulate's positional call: ``(M, C, K,
    force, q0, v0, dt, t_end, scheme, ...)``, and its ``history``, closed as stopped); each
    call is appended to ``calls``."""
    from assembly.dynamics.transient import Diverged, integrate

    def stops(*args, history=None, **options):
        if calls is not None:
            calls.append(args[7])
        held = None if history is None else SimpleNamespace(append=history.append, close=lambda *a: None)
        full = integrate(*args[:7], steps * args[6], *args[8:], history=held, **options)
        info = {"stopped": STOP_REASON, "steps": steps}
        if history is not None:
            history.close(False, info)
        raise Diverged(STOP_REASON, type(full)(full.time_s, full.y, full.iterations, full.scheme, info,
                                               complete=False, history=history))
    return stops
