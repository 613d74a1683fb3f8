"""Tc2_System's ADS client blocks from Structured Text: the handshake, and the answer of a system without the device."""

from __future__ import annotations

import pytest

from iecoop.libraries import tc2_system
from iecoop.runtime.clock import default_clock

st = pytest.importorskip("iecoop.st")

POLL = """TYPE ST_Inputs :
STRUCT
    nButtons : WORD;
    fStick : REAL;
END_STRUCT
END_TYPE
FUNCTION_BLOCK FB_Poll
VAR_INPUT
    sNetId : T_AmsNetId;
    nPort : UINT;
END_VAR
VAR_OUTPUT
    stInputs : ST_Inputs := (fStick := 1.5);
    nErrors : UINT;
    nLastError : UDINT;
    bBusySeen : BOOL;
END_VAR
VAR
    fbRead : ADSREAD;
    fbWrite : ADSWRITE;
    fbBoth : ADSRDWRT;
    nCommand : DWORD := 16#11;
END_VAR
fbRead(NETID := sNetId, PORT := nPort, IDXGRP := 16#10000, IDXOFFS := 0, LEN := SIZEOF(stInputs),
       DESTADDR := ADR(stInputs), READ := TRUE, TMOUT := T#5S);
bBusySeen := bBusySeen OR fbRead.BUSY;
IF fbRead.ERR THEN
    nErrors := nErrors + 1;
    nLastError := fbRead.ERRID;
    MEMSET(ADR(stInputs), 0, SIZEOF(stInputs));
END_IF
fbRead(READ := FALSE);
fbWrite(NETID := sNetId, PORT := nPort, IDXGRP := 16#10000, IDXOFFS := 16, LEN := SIZEOF(nCommand),
        SRCADDR := ADR(nCommand), WRITE := NOT fbWrite.BUSY);
fbBoth(NETID := sNetId, PORT := nPort, WRITELEN := 4, READLEN := 4, SRCADDR := ADR(nCommand),
       DESTADDR := ADR(nCommand), WRTRD := TRUE);
END_FUNCTION_BLOCK
"""


@pytest.mark.parametrize(("netid", "port", "code"), [("", 25733, 6), ("5.1.2.3.1.1", 851, 7), ("", 851, 0x701)])
def test_a_request_answers_at_a_later_cycle_as_a_system_without_the_device(netid: str, port: int, code: int) -> None:
    plc = st.load(POLL, libraries={"Tc2_System": tc2_system})
    fb = plc.FB_Poll()
    clock = default_clock()
    clock.set(0)
    fb(sNetId=netid, nPort=port)
    fb(sNetId=netid, nPort=port)  # the same cycle: no answer yet, however often the block is called
    assert (fb.bBusySeen, fb.nErrors, fb.fbRead.BUSY, fb.stInputs.fStick) == (True, 0, True, 1.5)
    clock.advance(10_000_000)  # the next cycle, 10 ms on
    fb(sNetId=netid, nPort=port)
    assert (fb.nErrors, fb.nLastError, fb.stInputs.fStick) == (1, code, 0.0)  # ERR; the code cleared its buffer
    assert (fb.fbWrite.ERR, fb.fbWrite.ERRID, fb.fbBoth.ERR, fb.fbBoth.ERRID) == (True, code, True, code)
    for _ in range(4):
        clock.advance(10_000_000)
        fb(sNetId=netid, nPort=port)
    assert fb.nErrors == 3  # READ fell after the answer: every other cycle a new request, answered the next
    assert fb.nCommand == 0x11  # nothing read back into the buffer
