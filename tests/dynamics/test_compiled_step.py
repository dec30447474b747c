"""The compiled step (assembly.dynamics.step_kernel, numba) against the Python step of
assembly.dynamics.transient: the same algorithm on the same arrays (the meshes' and shaft
torques' laws are one code, assembly.dynamics.mesh_laws / torque_laws), so the two runs agree
to round-off -- 1e-12 relative on every recorded output, with the same Newton iteration counts and contact losses. Scene: the shipped ``nrel5mw_transient`` (126
DOFs, 13 meshes with stiffness driven by the gear angle and 0.4 mm backlash: rank 26), rated
operation, dt = 1e-4 s.
"""
from __future__ import annotations

import numpy as np
import pytest

from assembly.dynamics import jit
from assembly.dynamics.history import MemoryHistory
from assembly.dynamics.simulate import simulate
from assembly.dynamics.step_kernel import (
    lu_factor,
    lu_factor_rows,
    lu_solve,
    lu_solve_rows,
    newton_matrix,
    newton_matrix_rows,
)
from assembly.dynamics.transient import Diverged
from assembly.model.assemble import assemble
from assembly.scene.schema import load_scene, scene_from_dict
from tests.support.gear_pair_scene import gear_pair

needs_numba = pytest.mark.skipif(not jit.COMPILED, reason="numba not installed (the speed extra) or switched off")
DT = 1e-4
AGREE = 1e-12                   # relative: the two steps do the same arithmetic

#: the drive torques: a PI generator from its rated torque (Jonkman 2009: 43 093.55 N m, rated
#: generator speed 1173.7 rpm = 122.91 rad/s), the HSS brake ramping in during the run, and
#: ElastoDyn's gearbox efficiency 94.4 % (Jonkman 2009)
TORQUES = {"simulation.generator": {"law": "pi", "torque": 43093.55, "rated_speed": 122.91, "kp": 2000.0,
                                    "ki": 1.0e4},
           "simulation.brake": {"torque": 2.0e4, "deploy_time": 0.01, "ramp_time": 0.01},
           "simulation.gearbox_efficiency": 0.944}


@pytest.fixture(scope="module")
def transient_model():
    return assemble(load_scene("nrel5mw_transient"))


def _both(model, steps: int, monkeypatch, **kw):
    """{"compiled": result, "python": result} of ``steps`` steps of ``model``."""
    out = {}
    for path in ("compiled", "python"):
        monkeypatch.setattr(jit, "ENABLED", path == "compiled")
        out[path] = simulate(model, steps * DT, DT, **kw)
        assert out[path].info["compiled"] is (path == "compiled")
    return out


def _agree(runs) -> None:
    c, p = runs["compiled"], runs["python"]
    assert c.info["mean_iterations"] == p.info["mean_iterations"]
    assert [m["contact_losses"] for m in c.meshes] == [m["contact_losses"] for m in p.meshes]
    np.testing.assert_array_equal(c.time_s, p.time_s)
    for name, ref in p.outputs.items():
        assert np.all(np.isfinite(c.outputs[name]))
        assert np.max(np.abs(c.outputs[name] - ref)) <= AGREE * np.max(np.abs(ref)), name


@needs_numba
def test_compiled_step_is_the_python_step_on_the_5mw_drivetrain(transient_model, monkeypatch):
    runs = _both(transient_model, 300, monkeypatch)
    assert runs["compiled"].info["rank"] == 26 and runs["compiled"].info["dofs"] == 126
    _agree(runs)


@needs_numba
def test_compiled_step_is_the_python_step_with_pi_generator_brake_and_friction(monkeypatch):
    scene = load_scene("nrel5mw_transient").with_values(TORQUES)
    runs = _both(assemble(scene), 300, monkeypatch, outputs=["speed:generator", "torque:main_shaft",
                                                               "force:stage3", "acceleration:generator:spin"])
    _agree(runs)
    # the torques act: the brake (in from 0.01 s) and the PI law slow the generator
    w = np.abs(runs["compiled"].outputs["speed:generator"])
    assert w[-1] < w[0]


@needs_numba
@pytest.mark.slow
def test_compiled_step_is_the_python_step_on_the_flexible_5mw_drivetrain(monkeypatch):
    scene = load_scene("nrel5mw_transient").with_values({"stages.stage1.carrier.fidelity": "flexible",
                                                         "stages.stage2.carrier.fidelity": "flexible",
                                                         "bodies.wheel.fidelity": "flexible"})
    runs = _both(assemble(scene), 300, monkeypatch)
    assert runs["compiled"].info["dofs"] == 322
    _agree(runs)


def test_without_numba_the_python_step_gives_the_same_results(transient_model, monkeypatch):
    # numba absent: the Python step, the laws on numpy arrays (every mesh at once), Newton's
    # matrix summed and factored in the compiled step's order (newton_matrix_rows,
    # lu_factor_rows, lu_solve_rows): the same arithmetic, so the runs agree to round-off
    # (AGREE) with the same Newton iteration counts
    available = jit.COMPILED
    monkeypatch.setattr(jit, "ENABLED", False)
    monkeypatch.setattr(jit, "COMPILED", False)
    r = simulate(transient_model, 300 * DT, DT)
    assert r.info["compiled"] is False and r.complete
    if available:
        monkeypatch.setattr(jit, "ENABLED", True)
        monkeypatch.setattr(jit, "COMPILED", True)
        c = simulate(transient_model, 300 * DT, DT)
        assert c.info["mean_iterations"] == r.info["mean_iterations"]
        for name, ref in r.outputs.items():
            assert np.max(np.abs(c.outputs[name] - ref)) <= AGREE * np.max(np.abs(ref)), name


def test_newton_matrix_and_solve_without_numba_are_the_compiled_bits():
    # the pieces whose rounding could differ between the paths: random Newton matrices of the
    # step's shape (a mesh's two columns coupled, every other entry zero) and dense ones; the LU
    # factors, the pivots and the solve bit for bit, and the solve backward-stable (partial
    # pivoting: residual within a few eps x |J| |x|, Higham, Accuracy and Stability of Numerical
    # Algorithms, 2002, thm 9.4, growth small for these sizes)
    rng = np.random.default_rng(7)
    for _ in range(200):
        mm = int(rng.integers(1, 30))
        T = rng.standard_normal((mm, mm)) * (rng.random((mm, mm)) < rng.random())
        S = rng.standard_normal((mm, mm))
        J = newton_matrix(T, S)
        np.testing.assert_array_equal(newton_matrix_rows(T, S), J)
        r = rng.standard_normal(mm)
        (A, p), (A2, p2) = lu_factor(J), lu_factor_rows(J)
        np.testing.assert_array_equal(A2, A)
        np.testing.assert_array_equal(p2, p)
        x = lu_solve(A, p, r)
        np.testing.assert_array_equal(lu_solve_rows(A, p, r), x)
        assert np.max(np.abs(J @ x - r)) <= 4 * mm * np.finfo(float).eps * np.max(np.abs(J) @ np.abs(x))


@pytest.mark.usefixtures("step_path")
def test_progress_and_history_blocks_are_the_steps(transient_model, monkeypatch):
    # progress: every n_steps // 200 steps and the last, as the Python step calls it; the blocks a
    # history receives are the rows of the run, in order
    calls, blocks = [], []

    class Spy(MemoryHistory):
        def append(self, t_block, y_block, iterations_block):
            blocks.append(len(t_block))
            super().append(t_block, y_block, iterations_block)

    import assembly.dynamics.simulate as sim_module
    real = sim_module.integrate

    def integrate(*a, **kw):
        return real(*a, **{**kw, "history": Spy(451)})

    monkeypatch.setattr(sim_module, "integrate", integrate)
    r = simulate(transient_model, 450 * DT, DT, progress=lambda i, n, t: calls.append((i, n, t)))
    assert [c[0] for c in calls] == list(range(2, 451, 2))
    assert all(c[1] == 450 and c[2] == pytest.approx(c[0] * DT, rel=1e-15) for c in calls)
    assert sum(blocks) == 451 == len(r.time_s) and blocks[0] == 1


@needs_numba
def test_a_run_that_cannot_converge_stops_at_the_same_step_on_both(monkeypatch):
    # tests/dynamics/test_newton_floor.py's refused run (90 % stiffness variation with backlash,
    # 0.6 steps per mesh period): the same message and the same partial rows on both steps
    d = gear_pair(0.01, 0.05, 0.05, 0.15, 1.0e7, backlash=1.0e-4, amplitudes=(0.9,), roles=("rotor", None),
                  simulation={"speed": 50.0, "static_start": False, "loads": [{"body": "g1", "value": 100.0}]})
    model = assemble(scene_from_dict(d))
    out = {}
    for path in ("compiled", "python"):
        monkeypatch.setattr(jit, "ENABLED", path == "compiled")
        with pytest.raises(Diverged) as e:
            simulate(model, 0.05, 1e-2, ["force:m"])
        out[path] = e.value
    assert str(out["compiled"]) == str(out["python"]) and "did not converge" in str(out["compiled"])
    c, p = out["compiled"].partial, out["python"].partial
    assert not c.complete and c.info["compiled"] and not p.info["compiled"]
    np.testing.assert_array_equal(c.time_s, p.time_s)
    np.testing.assert_allclose(c.outputs["force:m"], p.outputs["force:m"], rtol=AGREE)
