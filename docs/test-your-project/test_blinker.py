"""Python tests of the Blinker project: fresh instances and a fresh virtual PLC for every test."""

import pytest

from iecoop import T
from iecoop.testing.plugin import StProject

pytestmark = pytest.mark.st_project("Blinker/Blinker.plcproj")


def test_a_fresh_blinker_is_dark(st_project: StProject) -> None:
    blinker = st_project.new("FB_Blinker", bEnable=False)
    blinker()
    assert not blinker.bLamp


def test_the_first_flash_comes_after_250_ms(st_project: StProject) -> None:
    prg = st_project.add("PRG_TEST")              # a fresh PRG_TEST on a fresh PLC: 10 ms PlcTask
    took = st_project.plc.run_until(lambda: prg.fbBlinker_Test.fbFirst.bLamp, timeout=T("1s"))
    assert took == 260                            # the cycle at t = 250 ms has run


def test_a_forced_variable_holds(st_project: StProject) -> None:
    prg = st_project.add("PRG_TEST")
    st_project.force("PlcTask.PRG_TEST.fbBlinker_Test.nFirst", 100)
    st_project.plc.run_cycles(30)
    assert prg.fbBlinker_Test.nFirst == 100
