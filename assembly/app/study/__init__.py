"""Design studies (``flexgear study``): the study file and its keys (:mod:`.file`,
:mod:`.keys`), its variants (:mod:`.spec`), one variant run (:mod:`.run`), the Dask engine
(:mod:`.engine`) and the result folder (:mod:`.out`)."""
