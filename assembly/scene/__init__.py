"""The scene floor: the language a drivetrain is written in.

Its tables (:mod:`.tables`, :mod:`.time_domain`), reading and writing them (:mod:`.schema`
loads TOML and checks every field, :mod:`.save` writes it back, :mod:`.variant` and
:mod:`.edit` change fields by path, :mod:`.docs` says what each key means), and what a scene
derives from itself before anything is assembled: gear numbers from teeth (:mod:`.gears`,
:mod:`.mesh_excitation`), bodies placed by their meshes (:mod:`.placement`), planetary stages
and beam shafts expanded into bodies, bearings and meshes (:mod:`.planetary`,
:mod:`.planet_spacing`, :mod:`.shafts`), where springs attach (:mod:`.attach`), the
Craig-Bampton cutoff it sets (:mod:`.cutoffs`), where each part came from (:mod:`.paths`),
and the named rules it must obey (:mod:`.validate`, :mod:`.validate_loads`,
:mod:`.body_names`, :mod:`.sizes`). Building a :class:`~.tables.Scene` resolves and
validates it, all on this floor; it imports only the mechanics and base floors.
"""
