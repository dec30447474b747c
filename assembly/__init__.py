"""flexgear drivetrain model: scene -> bodies and springs -> assembly -> modes.

The model core (this package) never imports :mod:`assembly.app` (command line, pipeline,
report, rendering, plots, studies, benchmarks) nor a plotting library.

Public names are imported on first use (``from assembly import assemble`` works), so that
the command line starts without loading what a command does not need.
"""
from __future__ import annotations

from fe_components.lazy import lazy_exports

# ``compare`` and ``stage_alone`` are also the names of submodules: importing a submodule
# rebinds the package attribute to the module, so these functions are bound here once, eagerly
# (``from assembly import stage_alone`` gave the module once assembly.scene.stage_alone was imported).
from .analysis.compare import compare
from .errors import MechanismError, SceneError, SolverError
from .scene.tables import (Bearing, BearingSpec, Body, Fixed, FlexOptions, GearMesh, LoadCase, Member, PlanetaryStage,
                    Planets, PointLoad, Scene, Shaft, Support, scale_bearings, with_fidelity)
from .scene.stage_alone import stage_alone

#: Public name -> submodule, imported on first use.
_EXPORTS = {
    "classify_modes": "analysis.classify", "pair_modes": "analysis.classify", "CacheDirs": "model.components",
    "get_value": "scene.edit", "with_value": "scene.edit", "with_values": "scene.edit",
    "solve_modes": "analysis.modal", "assemble": "model.assemble", "load_scene": "scene.schema", "scene_from_dict": "scene.schema",
    "save_scene": "scene.save", "scene_to_toml": "scene.save", "Branch": "analysis.tracking", "track_modes": "analysis.tracking",
    "check_part": "analysis.part_check", "check_body_part": "analysis.part_check",
}

__all__ = sorted(["Bearing", "BearingSpec", "Body", "Fixed", "FlexOptions", "GearMesh", "LoadCase", "MechanismError",
                  "Member", "PlanetaryStage", "Planets", "PointLoad", "Scene", "SceneError", "Shaft", "SolverError",
                  "Support", "compare", "stage_alone",
                  "scale_bearings", "with_fidelity", *_EXPORTS])


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())
