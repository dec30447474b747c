"""``torque:BODY:INTERFACE``: the torque a body passes through an interface, without a body and
shaft added to read it. On the quill drive the wheel's bore carries the quill shaft and the wheel's
bearing (radial and axial springs through the bore on the axis: no moment about it), so the bore's
torque is the quill's section torque -- in the frequency response and in a time run, to round-off
(1e-10 of the peak)."""
from __future__ import annotations

import numpy as np
import pytest

from assembly.dynamics.frf import frequency_response
from assembly.dynamics.simulate import simulate
from assembly.errors import SceneError
from assembly.model.assemble import assemble
from assembly.scene.schema import load_scene
from assembly.scene.time_domain import Simulation, TimeLoad


@pytest.fixture(scope="module")
def quill():
    return assemble(load_scene("two_stage_quill"))


def test_the_bores_torque_is_the_quills_in_the_frequency_response(quill):
    f = np.linspace(10.0, 2000.0, 400)
    r = frequency_response(quill, "torque:pinion", ["torque:wheel:bore", "torque:quill"], f)
    a, b = r.outputs["torque:wheel:bore"], r.outputs["torque:quill"]
    assert np.max(np.abs(a - b)) <= 1e-10 * np.max(np.abs(b))
    assert r.units["torque:wheel:bore"] == r.units["torque:quill"]


def test_the_bores_torque_is_the_quills_in_a_run(quill):
    sim = Simulation(loads=(TimeLoad("pinion", value=100.0, end_value=0.0, t_start=0.0, t_end=1e-3),))   # a pulse
    run = simulate(quill, 0.02, 1e-4, ["torque:wheel:bore", "torque:quill"], simulation=sim)
    a, b = run.outputs["torque:wheel:bore"], run.outputs["torque:quill"]
    assert np.max(np.abs(b)) > 0 and np.max(np.abs(a - b)) <= 1e-10 * np.max(np.abs(b))


def test_an_interface_without_springs_is_refused_naming_those_with(quill):
    with pytest.raises(SceneError) as e:
        frequency_response(quill, "torque:pinion", ["torque:wheel:nowhere"], [100.0])
    assert "bore" in str(e.value) and "\n" not in str(e.value)
