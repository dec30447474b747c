"""flexgear drivetrain model: scene -> bodies and springs -> assembly -> modes.

The model core (this package) never imports :mod:`assembly.app` (command line, pipeline,
report, rendering, plots, studies, benchmarks) nor a plotting library.
"""
from .classify import classify_modes, pair_modes
from .compare import compare
from .components import CacheDirs
from .errors import MechanismError, SceneError, SolverError
from .modal import solve_modes
from .model import assemble
from .schema import load_scene, scene_from_dict
from .scene import (Bearing, BearingSpec, Body, Fixed, FlexOptions, GearMesh, LoadCase, Member, PlanetaryStage,
                    Planets, Scene, Shaft, scale_bearings, with_fidelity)

__all__ = ["Bearing", "BearingSpec", "Body", "CacheDirs", "Fixed", "FlexOptions", "GearMesh", "LoadCase",
           "MechanismError", "Member", "PlanetaryStage", "Planets", "Scene", "SceneError", "Shaft", "SolverError",
           "assemble", "classify_modes", "compare", "load_scene", "pair_modes", "scale_bearings", "scene_from_dict",
           "solve_modes", "with_fidelity"]
