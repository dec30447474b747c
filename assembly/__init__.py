"""flexgear multibody core: scene -> bodies/elements -> assembly -> modal results."""
from .classify import classify_modes, pair_modes
from .errors import MechanismError, SceneError, SolverError
from .modal import solve_modes
from .model import assemble
from .scene import Bearing, Body, Fixed, GearMesh, Scene, Shaft, scale_bearings, with_fidelity
from .planetary import BearingSpec, Member, PlanetaryStage, Planets
from .toml_io import load_scene

__all__ = ["Bearing", "BearingSpec", "Body", "Fixed", "GearMesh", "MechanismError", "Member",
           "PlanetaryStage", "Planets", "Scene", "SceneError", "Shaft", "SolverError", "assemble",
           "classify_modes", "load_scene", "pair_modes", "scale_bearings", "solve_modes", "with_fidelity"]
