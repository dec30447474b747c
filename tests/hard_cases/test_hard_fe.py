"""FE-side hard cases reachable from a scene (issue 7 item 5)."""
import dataclasses
import logging
from pathlib import Path

import numpy as np
import pytest

from assembly import assemble, load_scene

SCENE = Path(__file__).parent.parent / "data" / "flex_pair.toml"


def test_cutoff_below_band_warns(caplog):
    sc = load_scene(SCENE)
    b0 = sc.bodies[0]
    low = dataclasses.replace(b0, flex=dataclasses.replace(b0.flex, n_modes=None, cutoff_hz=0.5 * sc.band_hz))
    with caplog.at_level(logging.WARNING, logger="assembly.flexible"):
        assemble(dataclasses.replace(sc, bodies=(low,) + sc.bodies[1:]))
    assert any("below the scene's band" in r.getMessage() for r in caplog.records)


def test_more_modes_than_dofs_is_an_error():
    from cms.craig_bampton import CraigBamptonReductor
    from cms.errors import ReductionError
    from cms.models import box
    m = box(divisions=(4, 1, 1), order=1)
    n = m.K.shape[0]
    with pytest.raises(ReductionError, match="n_modes"):
        CraigBamptonReductor(m.K, m.M, np.arange(6), n_modes=n)


def test_interface_leaving_a_mechanism_is_named():
    # Boundary = the three translations of one node: the rest of the free body can still
    # rotate about that node, so K_ii is singular; the error names the free motion.
    from cms.craig_bampton import CraigBamptonReductor
    from cms.errors import MechanismError
    from cms.models import box
    m = box(divisions=(4, 1, 1), order=1)
    with pytest.raises(MechanismError) as exc:
        CraigBamptonReductor(m.K, m.M, np.arange(3), n_modes=2, node_coords=m.node_coords).reduce()
    assert "rotation" in str(exc.value)
