"""The model floor: a scene turned into matrices.

:func:`.assemble.assemble` builds the :class:`~.assemble.AssembledModel`: the body models
(:mod:`.bodies`, rigid; :mod:`.flexible`, Craig-Bampton superelements of the component FE
models of :mod:`.components`, their mass properties cached by :mod:`.mass_cache`), the
constraints (:mod:`.constraints`), the elements of beam shafts (:mod:`.shaft_elements`), the
element damping matrix (:mod:`.damping`) and the body table (:mod:`.body_table`).
:mod:`.probes` is the one public place to push on a model or read it. It imports the
scene, mechanics and base floors only.
"""
