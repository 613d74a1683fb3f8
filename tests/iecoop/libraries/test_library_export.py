"""Code written in Python against the vendor libraries exports as calls to them: references, never their bodies."""

from __future__ import annotations

import pathlib
from collections.abc import Iterator
from typing import Any

import pytest

from iecoop import BOOL, DINT, INT, LREAL, VAR, VAR_INPUT, VAR_OUTPUT, FunctionBlock, Program, T, st
from iecoop.libraries import tc2_system as tc2
from iecoop.libraries.codesys_util import BLINK, HYSTERESIS
from iecoop.libraries.tc2_mc2 import AXIS_REF, MC_MoveAbsolute, MC_Power
from iecoop.libraries.tc2_standard import R_TRIG, TON
from iecoop.libraries.tc2_system import ADSLOG_MSGTYPE_HINT, ADSLOGSTR, T_MaxString
from iecoop.libraries.tc2_utilities import F_LREAL, FB_FormatString
from iecoop.runtime import Runtime, Task
from iecoop.st.read.parse import library_references


class FB_Tour(FunctionBlock):
    """One item of each TwinCAT library: a TON, a simulated axis, FB_FormatString, ADSLOGSTR into a T_MaxString."""

    bStart: BOOL = VAR_INPUT(False)
    bDone: BOOL = VAR_OUTPUT(False)
    sReport: T_MaxString = VAR_OUTPUT("")
    axis: AXIS_REF = VAR()
    fbDelay: TON = VAR()
    fbPower: MC_Power = VAR()
    fbMove: MC_MoveAbsolute = VAR()
    fbFormat: FB_FormatString = VAR()
    fbDone: R_TRIG = VAR()
    nLogged: DINT = VAR(-1)

    def body(self) -> None:
        self.fbDelay(IN=self.bStart, PT=T("50ms"))
        self.fbPower(Axis=self.axis, Enable=self.fbDelay.Q, Enable_Positive=True, Enable_Negative=True)
        self.fbMove(Axis=self.axis, Execute=self.fbPower.Status, Position=10.0, Velocity=100.0)
        self.fbDone(CLK=self.fbMove.Done)
        if self.fbDone.Q:
            self.fbFormat(sFormat="at %.1f mm", arg1=F_LREAL(self.axis.NcToPlc.ActPos))
            self.sReport = self.fbFormat.sOut
            self.nLogged = ADSLOGSTR(ADSLOG_MSGTYPE_HINT, "tour: %s", self.sReport)
        self.bDone = self.fbMove.Done


class MAIN(Program):
    fbTour: FB_Tour = VAR()
    fPos: LREAL = VAR(0.0)

    def body(self) -> None:
        self.fbTour(bStart=True)
        self.fPos = self.fbTour.axis.NcToPlc.ActPos


class FB_Lamp(FunctionBlock):
    """CODESYS Util: a BLINK and a HYSTERESIS."""

    nLevel: INT = VAR_INPUT(0)
    bOn: BOOL = VAR_OUTPUT(False)
    bLow: BOOL = VAR_OUTPUT(False)
    fbBlink: BLINK = VAR()
    fbLevel: HYSTERESIS = VAR()

    def body(self) -> None:
        self.fbBlink(ENABLE=True, TIMELOW=T("20ms"), TIMEHIGH=T("30ms"))
        self.fbLevel(IN=self.nLevel, HIGH=60, LOW=40)
        self.bOn = self.fbBlink.OUT
        self.bLow = self.fbLevel.OUT


class PLC_PRG(Program):
    fbLamp: FB_Lamp = VAR()
    nStep: INT = VAR(0)
    nOn: INT = VAR(0)

    def body(self) -> None:
        self.nStep += 10
        self.fbLamp(nLevel=100 - self.nStep)
        if self.fbLamp.bOn:
            self.nOn += 1


@pytest.fixture(autouse=True)
def clean_log() -> Iterator[None]:
    tc2.clear_adslog()
    yield
    tc2.clear_adslog()


def _trace(program: Any, cycles: int, *names: str, profile: str = "twincat") -> list[tuple[Any, ...]]:
    runtime = Runtime(store=":memory:", profile=profile)
    runtime.add_task(Task("PlcTask", interval=T("10ms")), program)
    rows = []
    for _ in range(cycles):
        runtime.run(cycles=1)
        rows.append(tuple(_path(program, name) for name in names))
    return rows


def _path(obj: Any, dotted: str) -> Any:
    for part in dotted.split("."):
        obj = getattr(obj, part)
    return obj


def test_a_twincat_export_references_each_library_and_runs_the_same_when_loaded_back(tmp_path: pathlib.Path) -> None:
    files = st.export([FB_Tour, MAIN], tmp_path)
    assert sorted(f.name for f in files) == ["FB_Tour.TcPOU", "FB_Tour.plcproj", "MAIN.TcPOU"]
    assert {r.name for r in library_references(tmp_path)} == {"Tc2_Standard", "Tc2_System", "Tc2_Utilities", "Tc2_MC2"}
    tour = (tmp_path / "FB_Tour.TcPOU").read_text()
    for declaration in ("axis : AXIS_REF;", "fbMove : MC_MoveAbsolute;", "fbFormat : FB_FormatString;",
                        "sReport : STRING(255);"):
        assert declaration in tour
    # the library's constant and function are the library's: called, never declared in the export
    assert "ADSLOGSTR(ADSLOG_MSGTYPE_HINT, 'tour: %s', sReport)" in tour
    assert "ADSLOG_MSGTYPE_HINT :" not in tour and not (tmp_path / "GVL_Constants.TcGVL").exists()
    names = ("fPos", "fbTour.bDone", "fbTour.sReport")
    python = _trace(MAIN(), 30, *names)
    logged = [m.text for m in tc2.adslog_messages()]
    tc2.clear_adslog()
    back = st.load(tmp_path / "FB_Tour.plcproj")
    loaded = _trace(back.MAIN, 30, *names)
    assert loaded == python
    # the TON holds the enable 5 cycles, MC_Power shows Status in the next, then 20 cycles of a 10 mm triangle
    assert python[-1] == (10.0, True, "at 10.0 mm")
    assert [m.text for m in tc2.adslog_messages()] == logged == ["tour: at 10.0 mm"]


def test_a_codesys_export_references_util_and_runs_the_same_when_loaded_back(tmp_path: pathlib.Path) -> None:
    files = st.export([FB_Lamp, PLC_PRG], tmp_path)
    assert sorted(f.name for f in files) == ["FB_Lamp.TcPOU", "FB_Lamp.plcproj", "PLC_PRG.TcPOU"]
    assert [r.name for r in library_references(tmp_path)] == ["Util"]
    assert "fbBlink : BLINK;" in (tmp_path / "FB_Lamp.TcPOU").read_text()
    assert not (tmp_path / "BLINK.TcPOU").exists()
    names = ("nOn", "fbLamp.bLow")
    python = _trace(PLC_PRG(), 10, *names, profile="codesys")
    back = st.load(tmp_path / "FB_Lamp.plcproj", profile="codesys")
    assert _trace(back.PLC_PRG, 10, *names, profile="codesys") == python
    # HYSTERESIS: OUT is set below LOW (40) and stays until IN exceeds HIGH; the level falls 10 a cycle
    assert [low for _, low in python] == [False] * 6 + [True] * 4


def test_a_string_of_255_is_written_with_its_length_beside_the_library_s_t_maxstring() -> None:
    from iecoop import STRING

    class FB_Texts(FunctionBlock):
        sLibrary: T_MaxString = VAR("")
        sOwn: STRING = VAR("", length=255)
        sShort: STRING = VAR("")

    text = st.dump([FB_Texts])
    assert "sLibrary : STRING(255);" in text and "sOwn : STRING(255);" in text and "sShort : STRING;" in text
