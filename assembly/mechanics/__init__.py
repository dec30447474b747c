"""The mechanics floor: formulas on plain arrays, with nothing of a scene or a model in them.

Geometry and rigid transfers (:mod:`.kinematics`), spring elements (rank-one and diagonal,
:mod:`.elements`), the Timoshenko beam (:mod:`.beam`), static condensation
(:mod:`.condensation`) and the structural count and basis of rigid-body modes
(:mod:`.nullity`, on any object that exposes an assembled model's parts). It imports only
the base floor (:mod:`assembly.errors`) and the libraries.
"""
