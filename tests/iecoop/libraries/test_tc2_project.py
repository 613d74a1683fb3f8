"""A TwinCAT project that references Tc2_System and Tc2_Utilities, loaded from its .plcproj and run."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from iecoop import T, st
from iecoop.libraries import tc2_system as tc2
from iecoop.runtime import Runtime, Task
from iecoop.runtime.clock import default_clock

PROJECT = Path(__file__).parent / "data" / "Tc2Demo" / "Tc2Demo.plcproj"


@pytest.fixture(autouse=True)
def clean_log() -> Iterator[None]:
    tc2.clear_adslog()
    yield
    tc2.clear_adslog()
    default_clock().set(0)


def test_the_project_calls_both_libraries_plain_and_qualified() -> None:
    code = st.to_python(PROJECT)
    assert "from iecoop.libraries.tc2_utilities import" in code and "FB_FormatString" in code
    assert "from iecoop.libraries.tc2_system import" in code and "DRAND" in code


def test_the_project_runs_on_a_runtime_with_the_libraries_values() -> None:
    plc = st.load(PROJECT)
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), plc.MAIN)
    rt.run(cycles=3)
    main = plc.MAIN
    assert main.nCycle == 3
    assert main.sText == "cycle 3 of demo"  # FB_FormatString with F_DINT and Tc2_Utilities.F_STRING
    assert main.sUpper == "CYCLE 3 OF DEMO"  # Tc2_Utilities.F_ToUCase into a Tc2_System.T_MaxString
    assert main.nLogged == 0
    assert [m.text for m in tc2.adslog_messages()][-2:] == ["main: CYCLE 3 OF DEMO", "cycle 3"]
    assert [m.msg_ctrl_mask for m in tc2.adslog_messages()][-2:] == [tc2.ADSLOG_MSGTYPE_HINT, tc2.ADSLOG_MSGTYPE_WARN]
    first = tc2.DRAND()
    first(Seed=3)
    assert main.fFirst == first.Num  # Tc2_System.DRAND, the same sequence from the same seed
    # The third cycle starts 20 ms after the first, at the task clock's 0 = 1970-01-01.
    assert main.nSystemTime == 116_444_736_000_000_000 + 200_000
    assert main.sStamp == "1970-01-01-00:00:00.020"  # Tc2_Utilities.T_FILETIME64 and its conversions
