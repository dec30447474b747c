"""Benchmark table 4 of ``flexgear bench transient``: flexgear's time step beside a peer's on the
same reduced linear model.

The peer is Exudyn (the ``bench`` extra): its ``ObjectGenericODE2`` holds the model's M, C, K
(dense) and a constant force vector, and its implicit solver integrates it with Newmark's
average acceleration (beta 1/4, gamma 1/2), modified Newton with the Jacobian factorised once
(the model is linear, so each step is one solve), one thread, nothing written to files.
flexgear integrates the same M, C, K, force and start with the same scheme
(:func:`assembly.dynamics.transient.integrate`, no nonlinear forces; the compiled step when numba
is installed; the force given as a run's loads are, one load vector times a unit history), one
BLAS thread, recording the coordinates at every step (Exudyn records nothing). The models are ``nrel5mw`` (rigid gearbox bodies) and ``nrel5mw_flexible`` reduced, at rated
speed (the start velocity of :func:`rated_5mw`'s scene), over ``t_end`` at ``dt``.

The row shows both wall times, their ratio (Exudyn / flexgear: > 1 means flexgear is faster)
and the largest difference of the end states relative to the largest coordinate: the same
scheme on the same equations, so it is round-off (it shows the two solved the same problem).
"""
from __future__ import annotations

import time

import numpy as np
from threadpoolctl import threadpool_limits

from .rated import DT_5MW, rated_5mw

#: The goal: flexgear at least this many times faster than the peer, at both sizes.
PEER_GOAL = 5.0


def _dense(X) -> np.ndarray:
    return X.toarray() if hasattr(X, "toarray") else np.asarray(X, float)


def linear_problem(name: str):
    """(M, C, K dense, v0, force vector) of the reduced scene ``name`` at rated operation: its
    matrices as ``simulate`` builds them, the start velocity, and a force of the rated
    generator and rotor torques (:func:`rated_5mw`'s loads, as constant vectors)."""
    from ...dynamics.run_loads import run_loads
    from ...dynamics.run_model import model_matrices
    from ...dynamics.run_start import start_velocity
    from ...model.assemble import assemble
    from ...scene.time_domain import Simulation
    scene = rated_5mw(name)
    model = assemble(scene)
    M, K, C, _ = model_matrices(model)
    sim = scene.simulation or Simulation()
    v0, phi, reference = start_velocity(model, scene, sim, None)
    loads = run_loads(model, scene, sim, DT_5MW, v0, ".", phi if reference else None)
    return _dense(M), _dense(C), _dense(K), v0, np.asarray(loads.force(0.0), float)


def flexgear_run(M, C, K, v0, f, dt: float, t_end: float) -> tuple[float, np.ndarray]:
    """(wall s, end coordinates) of flexgear's integration of the linear problem."""
    from ...dynamics.integrators import newmark
    from ...dynamics.observe_rows import state_rows
    from ...dynamics.run_loads import RunLoads
    from ...dynamics.transient import integrate
    n = M.shape[0]
    # the constant force as a run's loads are given: one vector times a unit history, so that the
    # step applies A0^-1 f formed once, as Exudyn applies its constant load
    load = RunLoads(np.asarray(f, float)[:, None], (lambda t: np.ones(np.shape(t)),))
    with threadpool_limits(1):
        # once first: loading the compiled step (numba's cache) is a cost of the process, not of a run
        integrate(M, C, K, load, np.zeros(n), v0, dt, 10 * dt, newmark(), observe=state_rows(n))
        t0 = time.perf_counter()
        r = integrate(M, C, K, load, np.zeros(n), v0, dt, t_end, newmark(), observe=state_rows(n))
        wall = time.perf_counter() - t0
    return wall, r.y[-1]


def exudyn_run(M, C, K, v0, f, dt: float, t_end: float) -> tuple[float, np.ndarray]:
    """(wall s, end coordinates) of Exudyn's integration of the same problem (module notes)."""
    import exudyn as exu
    from exudyn.itemInterface import NodeGenericODE2, ObjectGenericODE2
    n = M.shape[0]
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    node = mbs.AddNode(NodeGenericODE2(referenceCoordinates=[0.0] * n, initialCoordinates=[0.0] * n,
                                       initialCoordinates_t=list(map(float, v0)), numberOfODE2Coordinates=n))
    mbs.AddObject(ObjectGenericODE2(nodeNumbers=[node], massMatrix=M, stiffnessMatrix=K, dampingMatrix=C,
                                    forceVector=list(map(float, f))))
    mbs.Assemble()
    s = exu.SimulationSettings()
    ti = s.timeIntegration
    ti.numberOfSteps, ti.endTime, ti.verboseMode = int(round(t_end / dt)), t_end, 0
    ti.generalizedAlpha.useNewmark = True
    ti.generalizedAlpha.newmarkBeta, ti.generalizedAlpha.newmarkGamma = 0.25, 0.5
    ti.generalizedAlpha.computeInitialAccelerations = True
    ti.newton.useModifiedNewton = True
    ti.newton.modifiedNewtonJacUpdatePerStep = False
    ti.reuseConstantMassMatrix = True
    s.linearSolver.solverType = exu.LinearSolverType.EigenDense
    s.parallel.numberOfThreads = 1
    s.solutionSettings.writeSolutionToFile = False
    s.solutionSettings.sensorsWritePeriod = 2 * t_end
    t0 = time.perf_counter()
    exu.SolveDynamic(mbs, s, solverType=exu.DynamicSolverType.GeneralizedAlpha)
    wall = time.perf_counter() - t0
    return wall, np.array(mbs.GetNodeOutput(node, exu.OutputVariableType.Coordinates))


def peer_table(names, dt: float, t_end: float, out) -> None:
    """Print table 4 (module notes) for the scenes ``names``."""
    try:
        import exudyn  # noqa: F401
        have = True
    except ImportError:
        have = False
    print(f"`flexgear bench transient` 4: the same linear M, C, K beside Exudyn, {t_end:g} s at dt = {dt:g} s, "
          "Newmark, one thread\n", file=out)
    print("| scene | DOFs | steps | flexgear [s] | us/step | Exudyn [s] | Exudyn / flexgear | goal | "
          "end-state difference |", file=out)
    print("|---|---|---|---|---|---|---|---|---|", file=out)
    steps = int(round(t_end / dt))
    for name in names:
        M, C, K, v0, f = linear_problem(name)
        wall, q = flexgear_run(M, C, K, v0, f, dt, t_end)
        if have:
            ex_wall, qe = exudyn_run(M, C, K, v0, f, dt, t_end)
            diff = float(np.abs(qe - q).max() / np.abs(q).max())
            ex = f"{ex_wall:.3f} | {ex_wall / wall:.2f} | >= {PEER_GOAL:g} | {diff:.1e}"
        else:
            ex = "not installed (extra [bench]) | | | "
        print(f"| {name} | {M.shape[0]} | {steps} | {wall:.3f} | {wall / steps * 1e6:.1f} | {ex} |", file=out)
    print("", file=out)
