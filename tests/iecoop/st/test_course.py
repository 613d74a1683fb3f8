"""The course examples written again in Structured Text give the same trace as their Python versions.

Each chapter's ST file (data/course/) is loaded and run with the showcase's
scenario for that chapter: the same script of operator inputs, the same
traced variables (under their ST names), the same number of cycles.
"""

from __future__ import annotations

import dataclasses
import pathlib
from typing import Any

import pytest

from iecoop import st
from iecoop.runtime import Runtime
from patterns.showcase import run_entry, table
from patterns.showcase.catalogue import Column, Entry, find, plc_task

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
        "bmw": "fbBmw", "audi": "fbAudi", "action": "sAction", "color": "sColor"}),
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
        # A nested block, STRUCT or ARRAY is seen under the Python names too (a column p.mercedes.action).
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
