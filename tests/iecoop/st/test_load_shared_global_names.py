"""Two global lists declaring one name, as TwinCAT takes them: each read through its list, a plain use refused.

Real projects keep a list per machine part (``GVL_Fan.nSpeed``, ``GVL_Pump.nSpeed``),
usually ``{attribute 'qualified_only'}``; the name alone would be ambiguous,
which the PLC's compiler refuses at the use, as the reader does.
"""

from __future__ import annotations

import pytest

st = pytest.importorskip("iecoop.st")

PARTS = """// GVL GVL_Fan
{attribute 'qualified_only'}
VAR_GLOBAL
    nSpeed : INT;
    bRun : BOOL;
END_VAR
// GVL GVL_Pump
{attribute 'qualified_only'}
VAR_GLOBAL
    nSpeed : INT := 100;
    bRun : BOOL;
END_VAR
PROGRAM MAIN
VAR
    nCycles : INT;
END_VAR
nCycles := nCycles + 1;
GVL_Fan.nSpeed := GVL_Fan.nSpeed + 10;
GVL_Pump.nSpeed := GVL_Pump.nSpeed - 1;
GVL_Fan.bRun := nCycles > 2;
GVL_Pump.bRun := NOT GVL_Fan.bRun;
END_PROGRAM
"""


def test_each_list_keeps_its_own_variable_over_cycles() -> None:
    module = st.load(PARTS)
    for _ in range(4):
        module.MAIN()
    assert (module.GVL_Fan.nSpeed, module.GVL_Pump.nSpeed) == (40, 96)
    assert (module.GVL_Fan.bRun, module.GVL_Pump.bRun) == (True, False)


def test_written_back_as_st_the_lists_stay_apart() -> None:
    module = st.load(st.dump(st.load(PARTS)))
    module.MAIN()
    assert (module.GVL_Fan.nSpeed, module.GVL_Pump.nSpeed) == (10, 99)


def test_the_plain_name_is_refused_at_its_line() -> None:
    source = PARTS.replace("{attribute 'qualified_only'}\n", "").replace("GVL_Fan.bRun := nCycles > 2;", "bRun := nCycles > 2;")
    with pytest.raises(st.StUnsupportedError, match=r"<st>:18: global bRun is declared in GVL_Fan and GVL_Pump: name its list \(GVL_Fan\.bRun\)"):
        st.load(source)
