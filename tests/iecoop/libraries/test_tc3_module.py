"""Tc3_Module: the HRESULT type and its checks SUCCEEDED / FAILED, in ST and in Python."""

from __future__ import annotations

import pytest

from iecoop.libraries import tc3_module

st = pytest.importorskip("iecoop.st")


def test_succeeded_and_failed_read_the_sign_of_an_hresult() -> None:
    assert [tc3_module.SUCCEEDED(hr) for hr in (0, 1, 0x203, -1)] == [True, True, True, False]
    assert [tc3_module.FAILED(hr) for hr in (0, -2147467259, -2147024809)] == [False, True, True]


def test_a_block_checks_its_hresult_each_cycle() -> None:
    # hr starts at S_OK (0) and goes down by one a cycle: succeeded, then failed; E_FAIL (16#80004005) fails
    plc = st.load("""FUNCTION_BLOCK FB_Result
VAR_OUTPUT bOk : BOOL; bFail : BOOL; nSeen : INT; END_VAR
VAR hr : HRESULT := 0; hrFail : Tc3_Module.HRESULT := DINT#16#80004005; END_VAR
bOk := SUCCEEDED(hr) AND NOT Tc3_Module.FAILED(hr);
bFail := FAILED(hrFail);
IF SUCCEEDED(hrFail) THEN nSeen := nSeen + 1; ELSE nSeen := nSeen + 10; END_IF
hr := hr - 1;
END_FUNCTION_BLOCK""", libraries={"Tc3_Module": tc3_module})
    fb = plc.FB_Result()
    fb()
    assert (fb.bOk, fb.bFail, fb.nSeen, fb.hrFail) == (True, True, 10, -2147467259)
    fb()
    assert (fb.bOk, fb.nSeen) == (False, 20)
