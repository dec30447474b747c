"""Every JSON flexgear writes or prints is strict JSON (RFC 8259 has no NaN or Infinity): a
non-finite number is an error naming where it is, never a bare ``NaN`` with exit code 0."""
from __future__ import annotations

import json
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from assembly.app.strict_json import dumps, first_non_finite
from assembly.errors import SolverError
from tests.support.fuzz import examples

LEAVES = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(), st.text(max_size=3),
                   st.booleans(), st.none())
TREES = st.recursive(LEAVES, lambda kids: st.one_of(st.lists(kids, max_size=4),
                                                    st.dictionaries(st.text(max_size=3), kids, max_size=4)),
                     max_leaves=12)


def test_the_first_non_finite_number_is_named():
    with pytest.raises(SolverError) as err:
        dumps({"outputs": {"torque:s": [1.0, 2.0, math.nan]}, "x": math.inf})
    assert str(err.value).startswith("result.outputs.torque:s[2] = 'NaN/inf':")
    assert dumps({"a": [1.0, 2]}, indent=None) == '{"a": [1.0, 2]}'


@settings(max_examples=examples(200), deadline=None)
@given(tree=TREES)
def test_any_tree_is_strict_json_or_refused(tree):
    try:
        text = dumps(tree)
    except SolverError:
        assert first_non_finite(tree) is not None
        return
    assert first_non_finite(tree) is None
    json.loads(text, parse_constant=lambda c: pytest.fail(f"non-JSON constant {c}"))
