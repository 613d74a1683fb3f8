"""Tc2_Utilities' pointer and raw-data functions, called from Structured Text as projects call them."""

from __future__ import annotations

import math

import pytest

from iecoop.exceptions import PlcException
from iecoop.libraries import tc2_utilities

st = pytest.importorskip("iecoop.st")

TEXTS = """PROGRAM MAIN
VAR_INPUT
    nCase : INT;
END_VAR
VAR
    sModule : STRING(255) := 'PumpCtrl';
    sMessage : STRING(255) := ': tank level below threshold';
    sLine : STRING(512);
    sShort : STRING(12);
    sTag : STRING(64) := 'EL-12345-PUMP-01';
    sTagOut : STRING(64);
    bOk : BOOL;
    bCut : BOOL;
    bStripped : BOOL;
    aFrame : ARRAY[0..31] OF BYTE;
    aBack : ARRAY[0..3] OF BYTE;
    nBack : UDINT;
    nBad : UDINT;
    sHex : STRING(255);
    sHexLow : STRING(255);
    sNone : STRING(255);
    aBuf : ARRAY[0..255] OF BYTE;
    sLabel : STRING(255);
    sDec : ARRAY[1..4] OF STRING(20);
    fRad : LREAL;
    fDeg : LREAL;
    pNull : POINTER TO STRING;
END_VAR
CASE nCase OF
0:
    bOk := CONCAT2(pSrcString1 := ADR(sModule), pSrcString2 := ADR(sMessage), pDstString := ADR(sLine), nDstSize := SIZEOF(sLine));
    bCut := CONCAT2(ADR(sModule), ADR(sMessage), ADR(sShort), SIZEOF(sShort));
    bStripped := DELETE2(pSrcString := ADR(sTag), pDstString := ADR(sTagOut), nDstSize := SIZEOF(sTagOut), nLen := 3, nPos := 1);
    aFrame[0] := 16#02; aFrame[1] := 16#10; aFrame[2] := 16#AB;
    sHex := DATA_TO_HEXSTR(pData := ADR(aFrame), cbData := 3, bLoCase := FALSE);
    sHexLow := DATA_TO_HEXSTR(ADR(aFrame), SIZEOF(aFrame), TRUE);
    sNone := DATA_TO_HEXSTR(ADR(aFrame), 0);
    nBack := HEXSTR_TO_DATA('DE AD be ef 99', ADR(aBack), SIZEOF(aBack));
    nBad := HEXSTR_TO_DATA('12 3G', ADR(aBack), SIZEOF(aBack));
    aBuf[0] := 16#52; aBuf[1] := 16#41; aBuf[2] := 16#43; aBuf[3] := 16#4B; aBuf[5] := 16#58;
    sLabel := BYTEARR_TO_MAXSTRING(aBuf);
    sDec[1] := DINT_TO_DECSTR(-1234, 1);
    sDec[2] := DINT_TO_DECSTR(-1234, 10);
    sDec[3] := DINT_TO_DECSTR(0, 0);
    sDec[4] := DINT_TO_DECSTR(1234, 6);
    fRad := DEG_TO_RAD(90.0);
    fDeg := RAD_TO_DEG(fRad / 2);
1:
    bOk := CONCAT2(pNull, ADR(sMessage), ADR(sLine), SIZEOF(sLine));
END_CASE
END_PROGRAM
"""


def test_strings_hex_dumps_and_numbers_as_infosys_documents() -> None:
    plc = st.load(TEXTS, libraries={"Tc2_Utilities": tc2_utilities})
    main = plc.MAIN
    main(nCase=0)
    assert (main.bOk, main.sLine) == (True, "PumpCtrl: tank level below threshold")
    assert (main.bCut, main.sShort) == (False, "PumpCtrl: ta")  # SIZEOF(STRING(12)): 12 characters and the 0
    assert (main.bStripped, main.sTagOut) == (True, "12345-PUMP-01")
    assert (main.sHex, main.sNone) == ("02 10 AB", "")
    assert main.sHexLow == "02 10 ab " + " ".join(["00"] * 29)
    assert (main.nBack, [main.aBack[i] for i in range(4)], main.nBad) == (4, [0xDE, 0xAD, 0xBE, 0xEF], 0)
    assert main.sLabel == "RACK"  # to the first 0
    assert [main.sDec[i] for i in range(1, 5)] == ["-1234", "-0000001234", "", "001234"]
    assert main.fRad == pytest.approx(math.pi / 2) and main.fDeg == pytest.approx(45.0)


def test_a_null_string_pointer_is_an_access_violation() -> None:
    plc = st.load(TEXTS, libraries={"Tc2_Utilities": tc2_utilities})
    with pytest.raises(PlcException, match="RTSEXCPT_ACCESS_VIOLATION.*CONCAT2: pSrcString1 is a null pointer"):
        plc.MAIN(nCase=1)


CSV = """PROGRAM MAIN
VAR
    fTemperature : LREAL := 23.5;
    sName : STRING(20) := 'say "hi"';
    aField : ARRAY[0..63] OF BYTE;
    aTiny : ARRAY[0..3] OF BYTE;
    aRaw : ARRAY[0..15] OF BYTE;
    nText : UDINT;
    nRaw : UDINT;
    nTooSmall : UDINT;
    sBack : STRING(20);
    fBack : LREAL;
    nBackText : UDINT;
    nBackRaw : UDINT;
    nUnquoted : UDINT;
    sFirst : STRING(20);
END_VAR
nText := ARG_TO_CSVFIELD(in := F_STRING(sName), bQM := TRUE, pOutput := ADR(aField), cbOutput := SIZEOF(aField));
nBackText := CSVFIELD_TO_ARG(pInput := ADR(aField), cbInput := nText, bQM := TRUE, out := F_BIGTYPE(ADR(sBack), SIZEOF(sBack)));
nUnquoted := CSVFIELD_TO_ARG(ADR(aField), nText, FALSE, F_BIGTYPE(ADR(sFirst), SIZEOF(sFirst)));
nTooSmall := ARG_TO_CSVFIELD(F_STRING(sName), TRUE, ADR(aTiny), SIZEOF(aTiny));
nRaw := ARG_TO_CSVFIELD(F_LREAL(fTemperature), FALSE, ADR(aRaw), SIZEOF(aRaw));
nBackRaw := CSVFIELD_TO_ARG(ADR(aRaw), nRaw, FALSE, F_BIGTYPE(ADR(fBack), SIZEOF(fBack)));
END_PROGRAM
"""


def test_csv_fields_of_a_string_and_of_raw_bytes_go_there_and_back() -> None:
    plc = st.load(CSV, libraries={"Tc2_Utilities": tc2_utilities})
    main = plc.MAIN
    main()
    field = bytes(main.aField[i] for i in range(main.nText))
    assert (main.nText, field) == (12, b'"say ""hi"""')  # the quotes doubled, the field enclosed
    assert (main.nBackText, main.sBack) == (8, 'say "hi"')
    assert (main.nUnquoted, main.sFirst) == (0, "")  # read without bQM, the enclosing quotes are not doubled
    assert main.nTooSmall == 0
    assert (main.nRaw, main.nBackRaw, main.fBack) == (8, 8, 23.5)  # an LREAL's eight bytes, no quote among them
