"""The course examples written again in Structured Text give the same trace as their Python versions.

Each chapter's ST file (data/course/) is loaded and run with the showcase's
scenario for that chapter: the same script of operator inputs, the same
traced variables (under their ST names), the same number of cycles.
"""

from __future__ import annotations

import dataclasses
import pathlib
from collections.abc import Callable
from typing import Any

import pytest

from iecoop import st
from iecoop.runtime import Runtime
from iecoop_examples import ch03_method_return_types as ch03
from iecoop_examples import ch06_struct_and_interface_extends as ch06
from iecoop_examples.ch11_abstract_fb_vs_interface import solution1_abstract_fb, solution2_interface, solution3_combination
from patterns.showcase import run_entry, table
from patterns.showcase.catalogue import Column, Entry, find, plc_task
from patterns.showcase.entry import Script, press, steps

COURSE = pathlib.Path(__file__).parent / "data" / "course"

#: chapter -> (ST file, Python name -> ST name: a whole traced path, or one part of a path or input name)
CHAPTERS: dict[str, tuple[str, dict[str, str]]] = {
    "ch09": ("ch09_pointers_and_references.st", {
        "": "SR_Average", "avg_values": "fAvgValues", "avg_reference": "fAvgReference"}),
    "ch14": ("ch14_operators.st", {
        "": "MAIN_Operators", "before": "nBefore", "after_new": "nAfterNew", "after_delete": "nAfterDelete",
        "deleted_is_null": "bDeletedIsNull", "valid_before": "bValidBefore"}),
    "ch01": ("ch01_classes_and_objects.st", {
        "accelerate": "bAccelerate", "drive": "bDrive", "brake": "bBrake", "mercedes": "fbMercedes",
        "bmw": "fbBmw", "audi": "fbAudi", "last_action": "sAction", "color": "sColor"}),
    "ch02": ("ch02_fb_declaration_and_access.st", {
        "start": "bStart", "stop": "bStop", "pump": "fbPump", "running": "bRunning", "pump_starts": "nPumpStarts"}),
    "ch04": ("ch04_properties.st", {"tank": "fbTank", "setpoint": "Setpoint", "level": "Level", "volume": "Volume"}),
    "ch05": ("ch05_inheritance.st", {
        "engine": "fbEngine", "new_engine": "fbNewEngine", "running": "bRunning", "odometer": "lrOdometer",
        "gear": "Gear"}),
    "ch08": ("ch08_interfaces.st", {
        "start_all": "bStartAll", "stop_all": "bStopAll", "running": "nRunning", "motor.running": "fbMotor.Running",
        "valve.running": "fbValve.Running", "lamp.running": "fbLamp.Running", "motor": "fbMotor", "valve": "fbValve", "lamp": "fbLamp",
        "run_cycles": "nRunCycles"}),
    "ch10": ("ch10_abstract.st", {
        "raw": "nRaw", "temperature": "fbTemperature", "pressure": "fbPressure", "value": "rValue",
        "alarms": "nAlarms"}),
    "ch12": ("ch12_fluent_interface.st", {"cycle": "nCycle", "result": "fResult", "half": "fHalf", "error": "bError"}),
    "ch13": ("ch13_interface_vs_inheritance.st", {
        "all_on": "bAllOn", "all_off": "bAllOff", "dim": "nDim", "count_on": "nOn", "dimmer": "fbDimmer",
        "brightness": "Brightness", "fan": "fbFan", "rpm": "nRpm", "valve": "fbValve", "open": "bOpen",
        "switchings": "nSwitchings"}),
    "ch15": ("ch15_exst.st", {
        "start": "bStart", "stop": "bStop", "fault": "bFault", "ack": "bAck", "motor": "fbMotor",
        "running": "bRunning", "follow": "bFollow", "alarm": "bAlarm"}),
    "ch07": ("ch07_this_and_super.st", {
        "i_base_cnt": "iBaseCnt", "i_fb1_cnt": "iFb1Cnt", "fb1": "fb1", "i_this": "iThis", "i_base": "iBase"}),
}


class Renamed:
    """The ST program seen under the Python example's names, so the chapter's script and columns apply."""

    def __init__(self, program: Any, names: dict[str, str], path: str = "") -> None:
        object.__setattr__(self, "_program", program)
        object.__setattr__(self, "_names", names)
        object.__setattr__(self, "_path", path)

    def _st_name(self, name: str) -> str:
        # A dotted entry ("motor.running": "fbMotor.Running") names a member in its place; a plain one anywhere.
        full = f"{self._path}.{name}" if self._path else name
        if full in self._names:
            return str(self._names[full].rsplit(".", 1)[-1])
        return str(self._names.get(name, name))

    def __getattr__(self, name: str) -> Any:
        full = f"{self._path}.{name}" if self._path else name
        return self._wrap(getattr(self._program, self._st_name(name)), full)

    def __getitem__(self, index: Any) -> Any:
        return self._wrap(self._program[index], self._path)

    def __setattr__(self, name: str, value: Any) -> None:
        setattr(self._program, self._st_name(name), value)

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return self._program(*args, **{self._names.get(k, k): v for k, v in kwargs.items()})

    def _wrap(self, value: Any, path: str) -> Any:
        # A nested block, STRUCT or ARRAY is seen under the Python names too (a column p.mercedes.last_action).
        if isinstance(value, (bool, int, float, str, bytes)) or value is None:
            return value
        return Renamed(value, self._names, path)


def st_path(path: str, names: dict[str, str]) -> str:
    if path in names:
        return names[path]
    return ".".join(names.get(part, part) for part in path.split("."))


def st_entry(entry: Entry, source: pathlib.Path, names: dict[str, str]) -> Entry:
    def builder(module: Any, runtime: Runtime) -> list[Any]:
        program = getattr(st.load(source), names.get("", "MAIN"))
        runtime.add_task(plc_task(), program)
        return [Renamed(program, names)]

    columns = tuple(
        dataclasses.replace(c, source=st_path(c.source, names)) if isinstance(c.source, str) else c for c in entry.columns
    )
    return dataclasses.replace(entry, columns=columns, builder=builder, program=None)


@pytest.mark.parametrize("chapter", sorted(CHAPTERS))
def test_st_version_gives_the_same_trace(chapter: str) -> None:
    entry = find(chapter)
    assert entry is not None
    file, names = CHAPTERS[chapter]
    python = run_entry(entry, entry.cycles, every=1)
    structured = run_entry(st_entry(entry, COURSE / file, names), entry.cycles, every=1)
    assert python.fault is None and structured.fault is None
    assert len(python.rows) == entry.cycles
    assert table(structured) == table(python)


def _staff(pointers: bool, count: int) -> tuple[Column, ...]:
    """Each employee's full name and salary, read through the staff array (its pointers, or its interfaces)."""

    def employee(index: int, method: str) -> Callable[[Any], object]:
        def read(program: Any) -> object:
            item = program.staff[index].deref if pointers else program.staff[index]
            return getattr(item, method)()

        return read

    columns: list[Column] = []
    for index in range(1, count + 1):
        columns.append(Column(f"aStaff[{index}].GetFullName()", employee(index, "get_full_name")))
        columns.append(Column(f"aStaff[{index}].GetMonthlySalary()", employee(index, "get_monthly_salary"), ".2f"))
    return (Column("fPayroll", "payroll", ".2f"), *columns)


_EMPLOYEES = {"staff": "aStaff", "payroll": "fPayroll", "get_full_name": "GetFullName",
              "get_monthly_salary": "GetMonthlySalary"}

#: The chapters whose example is a main() rather than a traced program: the trace of their MAIN is made here.
#: name -> (chapter, ST file, Python name -> ST name, Python Program, columns, script, cycles)
DEMOS: dict[str, tuple[str, str, dict[str, str], type, tuple[Column, ...], Script | None, int]] = {
    "ch03": ("ch03", "ch03_method_return_types.st", {
        "set_cmd": "bSet", "single_get": "nSingleGet", "st_get": "stGet", "st_copy": "stCopy", "fb_copy": "fbCopy",
        "n_var": "nVar", "count_value": "nCount", "sample": "fbSample", "my_prop": "MyProp", "change_copy": "ChangeCopy"},
        ch03.Main, (Column("bSet", "set_cmd"), Column("nSingleGet", "single_get"), Column("stGet.nVar", "st_get.n_var"),
                    Column("stCopy.nVar", "st_copy.n_var"), Column("fbCopy.nCount", "fb_copy.count_value"),
                    Column("fbSample.MyProp.nVar", "sample.my_prop.n_var")),
        steps(*press("set_cmd", 4)), 6),
    "ch06": ("ch06", "ch06_struct_and_interface_extends.st", {
        "structure2": "stStructure2", "structure11": "stStructure11", "i_int": "iInt", "r_real": "rReal",
        "t_time": "tTime", "b_bool2": "bBool2", "s_struct": "sStruct", "b_bool": "bBool", "motor": "fbMotor",
        "starts": "nStarts", "speed": "Speed", "running": "bRunning", "cycle": "nCycle"},
        ch06.Main, (Column("nCycle", "cycle"), Column("iInt", "structure2.i_int"), Column("rReal", "structure2.r_real"),
                    Column("tTime", "structure2.t_time"), Column("bBool2", "structure2.b_bool2"),
                    Column("sStruct.bBool", "structure11.s_struct.b_bool"), Column("nStarts", "motor.starts"),
                    Column("Speed", "motor.speed"), Column("bRunning", "motor.running")),
        None, 101),
    "ch11-solution1": ("ch11", "ch11_solution1_abstract_fb.st", _EMPLOYEES, solution1_abstract_fb.Main, _staff(True, 2), None, 2),
    "ch11-solution2": ("ch11", "ch11_solution2_interface.st", _EMPLOYEES, solution2_interface.Main, _staff(False, 2), None, 2),
    "ch11-solution3": ("ch11", "ch11_solution3_combination.st", _EMPLOYEES, solution3_combination.Main, _staff(False, 3), None, 2),
}


@pytest.mark.parametrize("name", sorted(DEMOS))
def test_st_version_of_a_demo_chapter_gives_the_same_trace(name: str) -> None:
    chapter, file, names, program, columns, script, cycles = DEMOS[name]
    demo = find(chapter)
    assert demo.demo  # the chapter's own showcase runs its main(): its MAIN's trace is declared above
    entry = dataclasses.replace(demo, demo=False, program=program, columns=columns, script=script, cycles=cycles)
    python = run_entry(entry, cycles, every=1)
    structured = run_entry(st_entry(entry, COURSE / file, names), cycles, every=1)
    assert python.fault is None and structured.fault is None
    assert len(python.rows) == cycles
    assert table(structured) == table(python)


def test_st_structs_of_chapter_6_have_the_python_layout() -> None:
    from iecoop import DefinitionError, sizeof, var_info

    module = st.load(COURSE / "ch06_struct_and_interface_extends.st")
    assert [sizeof(module.ST_Base1), sizeof(module.ST_Sub1), sizeof(module.ST_Sub2)] == [
        sizeof(ch06.StructBase1), sizeof(ch06.StructSub1), sizeof(ch06.StructSub2)] == [8, 48, 56]
    assert var_info(module.ST_Sub2(), "bBool2").ByteOffset == var_info(ch06.StructSub2(), "b_bool2").ByteOffset == 48
    source = (COURSE / "ch06_struct_and_interface_extends.st").read_text(encoding="utf-8")
    # the chapter's two compile errors, in ST: a member repeated along EXTENDS, an interface method left out
    with pytest.raises(DefinitionError, match="bBool1 is already declared in ST_Base1"):
        st.load(source + "TYPE ST_Bad EXTENDS ST_Base1 : STRUCT bBool1 : BOOL; END_STRUCT END_TYPE\n")
    half = source.split("PROGRAM MAIN")[0].replace("FB_Motor", "FB_HalfMotor").replace(
        "METHOD Stop : BOOL               // TRUE if it was running\nStop := bRunning;", "METHOD Halt : BOOL\n")
    with pytest.raises(DefinitionError, match="no implementation for method 'Stop' defined in interface 'I_Motor'"):
        st.load(half)


def test_st_version_of_chapter_11_refuses_an_abstract_instance() -> None:
    from iecoop import DefinitionError

    source = (COURSE / "ch11_solution3_combination.st").read_text(encoding="utf-8")
    with pytest.raises(DefinitionError, match="ABSTRACT FB_Employee cannot be instantiated"):
        st.load(source + "PROGRAM P_Office\nVAR fbEmployee : FB_Employee; END_VAR\nEND_PROGRAM\n")


def test_st_version_of_chapter_3_returns_copies_as_the_python_one() -> None:
    python, structured = ch03.Main(), Renamed(getattr(st.load(COURSE / "ch03_method_return_types.st"), "MAIN"),
                                              DEMOS["ch03"][2])
    for program in (python, structured):
        for cycle in range(1, 6):
            program.set_cmd = cycle == 4
            program()
        program.change_copy()  # stGet.nVar := -1 changes a copy
    assert (structured.st_get.n_var, structured.sample.my_prop.n_var) == (python.st_get.n_var, python.sample.my_prop.n_var) == (-1, 102)
