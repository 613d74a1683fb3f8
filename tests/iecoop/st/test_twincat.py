"""A TwinCAT project folder (DUTs, GVL, interface, FB with methods and properties, PROGRAM) loaded and run."""

from __future__ import annotations

import pathlib

import pytest

from iecoop import T
from iecoop.runtime import Runtime, Task
from iecoop import st

PROJECT = pathlib.Path(__file__).parent / "data" / "twincat"


@pytest.mark.parametrize("source", [PROJECT, PROJECT / "Tank.plcproj"], ids=["folder", "plcproj"])
def test_tank_project_runs_on_the_runtime(source: pathlib.Path) -> None:
    plc = st.load(source)
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), plc.MAIN)
    levels = []
    for _ in range(9):
        runtime.run(cycles=1)
        levels.append((plc.MAIN.rLevel, plc.MAIN.fbTank.eState.name))
    # capacity set to 50 through the property's Set accessor; 12.5 per cycle; drained at cycle 8
    assert levels == [
        (12.5, "FILLING"), (25.0, "FILLING"), (37.5, "FILLING"), (50.0, "FULL"), (50.0, "FULL"),
        (50.0, "FULL"), (50.0, "FULL"), (0.0, "IDLE"), (12.5, "FILLING"),
    ]
    assert plc.GVL_Tank.nTankOverflows >= 1
    assert plc.FB_Tank().Capacity == 100.0


def test_property_set_accessor_from_twincat_file() -> None:
    plc = st.load(PROJECT)
    tank = plc.FB_Tank()
    tank.Capacity = 0.0  # the Set accessor clamps to 1.0
    assert tank.Capacity == 1.0
    assert isinstance(tank, plc.I_Tank)


def test_single_twincat_file_names_unknown_types() -> None:
    with pytest.raises(st.StUnsupportedError, match=r"FB_Tank\.TcPOU:\d+: unknown type 'E_TankState'"):
        st.load(PROJECT / "POUs" / "FB_Tank.TcPOU")


def test_to_python_of_the_project_is_ordered_and_commented() -> None:
    text = st.to_python(PROJECT)
    assert text.index("class I_Tank(Interface)") < text.index("class FB_Tank(FunctionBlock, I_Tank)")
    assert "# A tank that fills by a fixed rate and reports when full." in text
    assert "@Capacity.setter" in text
