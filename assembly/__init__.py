"""flexgear's Python API: ``import assembly as fg``.

Every user-facing name is here, imported on first use, so ``import assembly`` loads no model
(the command line starts without what a command does not need). docs/python_api.md shows a
script that uses them all; docs/architecture.md the floors behind them.

- the scene language: :class:`Scene` and its tables (:class:`Body`, :class:`Bearing`,
  :class:`GearMesh`, :class:`Shaft`, :class:`PlanetaryStage` ...), the time-domain tables
  (:class:`Simulation` ...), the component parameter types (:class:`PinionParams` ...),
  :func:`load_scene`, :func:`save_scene` and the scene edits;
- a model: :func:`assemble` (scene -> :class:`AssembledModel`);
- analyses of one model take the model first: :func:`solve_modes`, :func:`solve_static`,
  :func:`frequency_response`, :func:`campbell`, :func:`simulate` (the last three also take a
  scene, assembled as given); :func:`classify_modes` and :func:`track_modes` take modal results;
- analyses that build variants of a scene take the scene: :func:`compare`, :func:`two_mass`,
  :func:`stage_alone`;
- :func:`run_report` writes what ``flexgear run`` writes (the application floor, loaded only
  when asked for);
- the errors: :class:`SceneError` (bad input, naming the field), :class:`MechanismError` (an
  assembly that can still move where it must not), :class:`SolverError` (a solve that cannot
  give accurate numbers), :class:`Diverged` (a time-domain run that stopped; its ``partial``
  result).

Results are frozen dataclasses.
"""
from __future__ import annotations

import importlib

#: Public name -> the module that defines it, imported on first use.
_EXPORTS = {
    # errors
    "SceneError": "assembly.errors", "MechanismError": "assembly.errors", "SolverError": "assembly.errors",
    # the scene language
    **dict.fromkeys(("Scene", "Body", "Bearing", "GearMesh", "Shaft", "Station", "Fixed", "FlexOptions",
                     "PlanetaryStage", "Member", "Planets", "LoadCase", "PointLoad", "Support", "Damping",
                     "with_fidelity", "scale_bearings"), "assembly.scene.tables"),
    **dict.fromkeys(("Simulation", "TimeLoad", "Generator", "Brake", "StressPoint", "MeshVariation"),
                    "assembly.scene.time_domain"),
    **dict.fromkeys(("PinionParams", "WheelParams", "CarrierParams", "CylinderParams", "GearTeeth",
                     "ShaftSegment", "PartFile"), "fe_components.params"),
    "GearBlank": "fe_components.gear_blank", "Material": "fe_components.material", "STEEL": "fe_components.material",
    "load_scene": "assembly.scene.schema", "scene_from_dict": "assembly.scene.schema",
    "save_scene": "assembly.scene.save", "scene_to_toml": "assembly.scene.save",
    "get_value": "assembly.scene.edit", "with_value": "assembly.scene.edit", "with_values": "assembly.scene.edit",
    "stage_alone": "assembly.scene.stage_alone",
    # the model
    "assemble": "assembly.model.assemble", "AssembledModel": "assembly.model.assemble",
    "CacheDirs": "assembly.model.components",
    # analyses
    "solve_modes": "assembly.analysis.modal", "ModalResult": "assembly.analysis.modal",
    "classify_modes": "assembly.analysis.classify", "pair_modes": "assembly.analysis.classify",
    "ModeInfo": "assembly.analysis.classify",
    "track_modes": "assembly.analysis.tracking", "Branch": "assembly.analysis.tracking",
    "solve_static": "assembly.analysis.static", "StaticResult": "assembly.analysis.static",
    "static_report": "assembly.analysis.reactions", "StaticReport": "assembly.analysis.reactions",
    "gear_table": "assembly.analysis.gear_table", "GearRow": "assembly.analysis.gear_table",
    "referred_inertia": "assembly.analysis.referred",
    "compare": "assembly.analysis.compare", "Comparison": "assembly.analysis.compare",
    "two_mass": "assembly.analysis.two_mass", "TwoMass": "assembly.analysis.drivetrain",
    "check_part": "assembly.analysis.part_check", "check_body_part": "assembly.analysis.part_check",
    "frequency_response": "assembly.dynamics.frf", "FRF": "assembly.dynamics.frf",
    "campbell": "assembly.dynamics.campbell", "Campbell": "assembly.dynamics.campbell",
    "simulate": "assembly.dynamics.simulate", "SimulationResult": "assembly.dynamics.simulate",
    "Diverged": "assembly.dynamics.transient",
    # the report of `flexgear run`: a name only, resolved on use (the core never imports the app)
    "run_report": "assembly.app",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module 'assembly' has no attribute {name!r}")
    value = getattr(importlib.import_module(_EXPORTS[name]), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
