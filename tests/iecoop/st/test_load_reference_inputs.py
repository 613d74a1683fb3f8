"""A FUNCTION_BLOCK's ``VAR_INPUT refName : REFERENCE TO STRING`` given a variable at the call is bound to it."""

from __future__ import annotations

import pytest

st = pytest.importorskip("iecoop.st")

TAGS = """FUNCTION_BLOCK FB_Tag
VAR_INPUT
    refName : REFERENCE TO STRING;
    refCount : REFERENCE TO UINT;
END_VAR
refName := CONCAT('tag-', UINT_TO_STRING(refCount));
refCount := refCount + 1;
END_FUNCTION_BLOCK
PROGRAM MAIN
VAR
    fbTag : FB_Tag;
    sFirst : STRING;
    sSecond : STRING;
    nTags : UINT;
END_VAR
fbTag(refName := sFirst, refCount := nTags);
fbTag(refName := sSecond, refCount := nTags);
END_PROGRAM
"""


def test_each_call_binds_the_reference_and_writes_go_through() -> None:
    module = st.load(TAGS)
    module.MAIN()
    assert (module.MAIN.sFirst, module.MAIN.sSecond, module.MAIN.nTags) == ("tag-0", "tag-1", 2)
    module.MAIN()
    assert (module.MAIN.sFirst, module.MAIN.sSecond, module.MAIN.nTags) == ("tag-2", "tag-3", 4)


def test_a_value_that_is_no_variable_is_refused_at_its_line() -> None:
    with pytest.raises(st.StUnsupportedError, match=r"<st>:16: "):
        st.load(TAGS.replace("fbTag(refName := sFirst, refCount := nTags);", "fbTag(refName := 'x', refCount := nTags);"))
