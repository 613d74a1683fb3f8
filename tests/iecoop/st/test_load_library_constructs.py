"""Constructs public TwinCAT libraries write: each loaded and run across cycles, values worked by hand."""

from __future__ import annotations

import pytest

st = pytest.importorskip("iecoop.st")


def test_an_interface_with_an_access_specifier_is_called_through() -> None:
    # INTERFACE INTERNAL / PUBLIC: a library's own interface; the counter adds 3 then 4 through it: 3, 7
    plc = st.load("""INTERFACE INTERNAL I_Adder
END_INTERFACE
METHOD Add : DINT
VAR_INPUT nBy : DINT; END_VAR
END_METHOD
INTERFACE PUBLIC I_Named
END_INTERFACE
METHOD Name : STRING
END_METHOD
FUNCTION_BLOCK FB_Counter IMPLEMENTS I_Adder, I_Named
VAR nSum : DINT; END_VAR
END_FUNCTION_BLOCK
METHOD Add : DINT
VAR_INPUT nBy : DINT; END_VAR
nSum := nSum + nBy;
Add := nSum;
END_METHOD
METHOD Name : STRING
Name := 'counter';
END_METHOD
FUNCTION_BLOCK FB_User
VAR_OUTPUT nSeen : DINT; sName : STRING; END_VAR
VAR fbCounter : FB_Counter; itfAdd : I_Adder; itfName : I_Named; nCycle : DINT; END_VAR
itfAdd := fbCounter;
itfName := fbCounter;
nCycle := nCycle + 1;
nSeen := itfAdd.Add(nCycle + 2);
sName := itfName.Name();
END_FUNCTION_BLOCK""")
    fb = plc.FB_User()
    fb()
    assert (fb.nSeen, fb.sName) == (3, "counter")
    fb()
    assert fb.nSeen == 7

