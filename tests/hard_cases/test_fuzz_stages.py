"""Fuzz the stage data of the NREL 5 MW drivetrain: teeth +-3, profile shifts in (-1, 1),
planet counts 1..8, face widths x0.5..2, shaft station positions. Every draw is either
accepted and solves (frequencies finite and non-negative, eigen residuals at round-off, the
one rigid-body mode of the drivetrain) or refused -- when the scene is built, or by the
solve's resolution check (assembly/analysis/resolution.py: a single planet leaves a 0.04 Hz mode the
solve cannot resolve) -- with one SceneError line naming a field that exists in the scene
(:func:`assembly.scene.edit.get_value` finds it) and its value.

Rigid bodies only: the carriers' component tables (which would mesh a new carrier for every
planet count) are replaced by two steel cheek discs of the component's own size, lumped at
the stage centre; the stage-3 wheel keeps its component (one mesh, cached).
"""
import copy
import math
import tomllib

import numpy as np
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from assembly.analysis.modal import solve_modes
from assembly.errors import SceneError
from assembly.model.assemble import assemble
from assembly.scene.edit import get_value
from assembly.scene.schema import SCENE_DIR, scene_from_dict
from tests.support.fuzz import examples

STEEL = 7850.0   # kg/m^3


def lumped_carriers(tree: dict) -> dict:
    """``tree`` with each stage carrier a plain rigid member: two steel discs of the
    component's cheek diameter D and thickness t, m = 2 rho pi D^2 t / 4, J = m D^2 / 8;
    bearings and shafts that named a carrier interface act at the carrier centre instead."""
    tree = copy.deepcopy(tree)
    carriers = set()
    for stage in tree["stages"]:
        c = stage["carrier"]
        comp = c.pop("component")
        c.pop("flex", None)
        d, t = comp["cheek_diameter"], comp["cheek_thickness"]
        c["mass"] = 2 * STEEL * math.pi * d ** 2 / 4 * t
        c["polar_inertia"] = c["mass"] * d ** 2 / 8
        carriers.add(f"{stage['name']}.carrier")
    for br in tree["bearings"]:
        if br["body"] in carriers:
            br.pop("interface", None)
    for sh in tree["shafts"]:
        for k in (1, 2):
            if sh[f"body{k}"] in carriers:
                sh.pop(f"interface{k}", None)
    return tree


BASE = lumped_carriers(tomllib.loads((SCENE_DIR / "nrel5mw.toml").read_text()))
BASE_SCENE = scene_from_dict(copy.deepcopy(BASE))
MEMBERS = ("sun", "planets", "ring")


@st.composite
def perturbed(draw):
    """(tree, list of (path, value) changed): 1 to 4 changes of stage or station data."""
    tree = copy.deepcopy(BASE)
    changes = []
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(["teeth", "shift", "count", "face_width", "station"]))
        if kind == "station":
            i = draw(st.sampled_from([i for i, s in enumerate(tree["shafts"]) if "stations" in s]))
            j = draw(st.integers(0, len(tree["shafts"][i]["stations"]) - 1))
            node, key, path = tree["shafts"][i]["stations"][j], "at", f"shafts[{i}].stations[{j}].at"
            value = draw(st.floats(-0.2, 3.5))
        else:
            i = draw(st.integers(0, len(tree["stages"]) - 1))
            stage = tree["stages"][i]
            if kind == "count":
                node, key, path = stage["planets"], "count", f"stages[{i}].planets.count"
                value = draw(st.integers(1, 8))
            elif kind == "face_width":
                node, key, path = stage, "face_width", f"stages[{i}].face_width"
                value = stage["face_width"] * draw(st.floats(0.5, 2.0))
            else:
                member = draw(st.sampled_from(MEMBERS))
                node = stage[member]
                key = "teeth" if kind == "teeth" else "profile_shift"
                path = f"stages[{i}].{member}.{key}"
                value = node["teeth"] + draw(st.integers(-3, 3)) if kind == "teeth" \
                    else draw(st.floats(-0.999, 0.999))
        node[key] = value
        changes.append((path, value))
    return tree, changes


@settings(max_examples=examples(50), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(case=perturbed())
def test_perturbed_stage_data_solves_or_names_an_existing_field(case):
    tree, changes = case
    try:   # refused when the scene is built, or by the solve's own resolution check
        res = solve_modes(assemble(scene_from_dict(tree)))
    except SceneError as exc:
        msg = str(exc)
        assert "\n" not in msg and msg.startswith(f"{exc.path} = {exc.value!r}: "), msg
        get_value(BASE_SCENE, exc.path)   # raises SceneError for a path the scene does not have
        event(f"refused: {exc.path.split('.')[-1]}")
        return
    event("accepted")
    f = res.frequencies_hz
    assert np.all(np.isfinite(f)) and np.all(f >= 0), changes
    assert res.max_residual < 1e-8, (res.max_residual, changes)
    assert res.n_rigid == 1, (res.n_rigid, changes)   # the drivetrain turns as a whole, nothing else
