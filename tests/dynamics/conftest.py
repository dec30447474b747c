"""The two steps of a time-domain run (assembly.dynamics.transient.integrate): a test module
that sets ``pytestmark = pytest.mark.usefixtures("step_path")`` runs every test on the
compiled step (numba; skipped where numba is not installed) and on the Python step."""
from __future__ import annotations

import pytest

from assembly.dynamics import jit


@pytest.fixture(params=["compiled", "python"])
def step_path(request, monkeypatch):
    """The step the test's runs take: "compiled" or "python" (the switch
    :data:`assembly.dynamics.jit.ENABLED`; the Python step on the same laws)."""
    if request.param == "compiled" and not jit.COMPILED:
        pytest.skip("numba is not installed (the speed extra) or switched off (FLEXGEAR_NO_NUMBA)")
    monkeypatch.setattr(jit, "ENABLED", request.param == "compiled")
    return request.param
