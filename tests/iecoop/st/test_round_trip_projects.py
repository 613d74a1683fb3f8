"""Three TwinCAT projects go out as they came in, and through the writer they run the same.

FillStation (a CASE state machine, FOR loops, a PROPERTY, an INTERFACE, located I/O, pragmas), PackLine
(ABSTRACT / FINAL / EXTENDS / IMPLEMENTS, interfaces extending __SYSTEM.IQueryInterface, FB_init with an
input, a Set accessor of its own access, STRUCT EXTENDS, UNION, alias, subrange, VAR_IN_OUT, VAR_STAT,
RETAIN and PERSISTENT lists, ARRAYs bounded by a constant, POINTER TO, REFERENCE TO, S= / R=, WHILE,
REPEAT, CONTINUE, CASE ranges, bit access, typed literals, AND_THEN / OR_ELSE / XOR, __QUERYINTERFACE,
the shifts and string functions) and DoseCell (an ACTION, FB_exit, call_after_init, VAR_INST, VAR_TEMP,
VAR_IN_OUT CONSTANT, TOF / TP / F_TRIG / SR / RS / CTD / CTUD, `=>` outputs, __NEW / __DELETE, MEMCPY /
MEMSET / MEMCMP, TEST_AND_SET, MUX / MOVE / EXPT / TRUNC, __TRY / __CATCH / __FINALLY, D#, TOD#, DT#,
LTIME#, WSTRING, string escapes, TO_STRING of an enumeration, a PROGRAM called by another).
"""

from __future__ import annotations

import pathlib
from typing import Any

import blark.parse
import pytest

from iecoop import T, st
from iecoop.memory.typeinfo import AggregateInfo, ArrayInfo, ElementaryInfo, EnumInfo
from iecoop.metadata import fields_of, kind_of
from iecoop.runtime import Runtime, Task
from iecoop.st.read.origin import fingerprint

PROJECTS = pathlib.Path(__file__).parent / "data" / "projects"
#: the input each project's trace switches on from cycle 3 to cycle 30
STIMULUS = {"FillStation": ("GVL_IO", "bStartButton"), "PackLine": ("GVL_Plant", "bRun"), "DoseCell": ("PRG_Dose", "bStart")}
SUFFIXES = (".TcPOU", ".TcDUT", ".TcGVL", ".TcIO")


def _originals(name: str) -> list[pathlib.Path]:
    return sorted(p for p in (PROJECTS / name).rglob("*") if p.suffix in SUFFIXES and "__iecoop_cache__" not in p.parts)


def _snapshot(obj: Any, path: str, out: dict[str, object], depth: int = 0) -> None:
    """Every elementary value ``obj`` holds (nested blocks and STRUCTs too), by path."""
    for record in fields_of(type(obj)):
        value = getattr(obj, record.name)
        where = f"{path}.{record.name}"
        if isinstance(record.info, (ElementaryInfo, EnumInfo)) or isinstance(value, str):
            out[where] = value
        elif isinstance(record.info, ArrayInfo) and isinstance(record.info.elem, (ElementaryInfo, EnumInfo)):
            out[where] = list(value)
        elif isinstance(record.info, AggregateInfo) and depth < 4 and kind_of(type(value)) is not None:
            _snapshot(value, where, out, depth + 1)


def trace(plc: Any, name: str, cycles: int) -> list[dict[str, object]]:
    """The values of every program and global list after each of ``cycles`` cycles of a 10 ms task."""
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms"), priority=20), plc.MAIN)
    holder, variable = STIMULUS[name]
    rows = []
    objects = {n: getattr(plc, n) for n in sorted(plc.__st_sources__) if kind_of(type(getattr(plc, n))) in ("program", "gvl")}
    for cycle in range(cycles):
        setattr(getattr(plc, holder), variable, 3 <= cycle < 30)
        runtime.run(cycles=1)
        row: dict[str, object] = {}
        for key, obj in objects.items():
            _snapshot(obj, key, row)
        rows.append(row)
    return rows


def load(folder: pathlib.Path, name: str) -> Any:
    return st.load(folder / f"{name}.plcproj")


NAMES = ["FillStation", "PackLine", "DoseCell"]


@pytest.mark.parametrize("name", NAMES)
def test_unchanged_objects_are_written_back_byte_for_byte(name: str, tmp_path: pathlib.Path) -> None:
    st.export(load(PROJECTS / name, name), tmp_path, format="twincat")
    assert len(_originals(name)) >= 7
    # diff -r against the project: the same files in the same folders, byte for byte (the read cache aside)
    assert _tree(tmp_path) == _tree(PROJECTS / name)


def _tree(folder: pathlib.Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in folder.rglob("*") if p.is_file() and "__iecoop_cache__" not in p.parts}


@pytest.mark.parametrize("name", NAMES)
def test_every_object_through_the_writer_parses_and_runs_the_same(name: str, tmp_path: pathlib.Path) -> None:
    plc = load(PROJECTS / name, name)
    # another format than the one read: every object goes through the writer, strictly
    for path in st.export(plc, tmp_path, format="st"):
        blark.parse.parse_source_code(path.read_text(encoding="utf-8"))
    again = st.load(tmp_path)
    assert trace(again, name, 60) == trace(load(PROJECTS / name, name), name, 60)


def _travel(self: Any) -> Any:
    """FB_Conveyor.Travel as Python: the same steps, written by hand."""
    delta = max(-self.fStep, min(self.stTarget.fX - self.fPos, self.fStep))
    self.fPos = self.fPos + delta
    return self.MoveTo(fTarget=self.stTarget.fX)


def test_a_pou_changed_in_python_is_written_parsed_and_runs_the_same(tmp_path: pathlib.Path) -> None:
    plc = load(PROJECTS / "PackLine", "PackLine")
    conveyor = plc.FB_Conveyor
    before = fingerprint(conveyor)
    _travel.__annotations__ = {"return": "BOOL"}
    _travel.__globals__["BOOL"] = __import__("iecoop").BOOL
    conveyor.Travel = _travel
    assert fingerprint(conveyor) != before
    written = {p.name: p.read_bytes() for p in st.export(plc, tmp_path, format="twincat")}
    original = (PROJECTS / "PackLine" / "POUs" / "FB_Conveyor.TcPOU").read_bytes()
    assert written["FB_Conveyor.TcPOU"] != original and b"LIMIT" not in written["FB_Conveyor.TcPOU"]
    assert written["MAIN.TcPOU"] == (PROJECTS / "PackLine" / "POUs" / "MAIN.TcPOU").read_bytes()
    blark.parse.parse_source_code(st.dump([conveyor]))
    again = st.load(tmp_path / "PackLine.plcproj")
    assert trace(again, "PackLine", 60) == trace(load(PROJECTS / "PackLine", "PackLine"), "PackLine", 60)


def test_load_export_load_export_gives_the_same_files_every_time(tmp_path: pathlib.Path) -> None:
    import patterns.creational.singleton as python_module  # a GVL of its own (PlantLog) written from Python

    first = {p.name: p.read_bytes() for p in st.export(python_module, tmp_path / "python0")}
    folder = PROJECTS / "PackLine"
    files: list[dict[str, bytes]] = []
    for round_ in range(3):
        plc = load(folder, "PackLine")
        folder = tmp_path / f"round{round_}"
        files.append({p.name: p.read_bytes() for p in st.export(plc, folder)})
        # nothing a load registers reaches the export of another module, nor the next load
        assert {p.name: p.read_bytes() for p in st.export(python_module, tmp_path / f"python{round_ + 1}")} == first
        back = st.load(tmp_path / "python0")
        assert {p.name: p.read_bytes() for p in st.export(back, tmp_path / f"back{round_}")}.keys() >= first.keys()
    assert files[0] == files[1] == files[2]


@pytest.mark.parametrize("name", NAMES)
def test_a_project_written_as_plcopen_xml_is_read_back_and_runs_the_same(name: str, tmp_path: pathlib.Path) -> None:
    """The form CODESYS imports and exports: every object through the PLCopen writer, then through its reader."""
    (xml,) = st.export(load(PROJECTS / name, name), tmp_path, format="plcopen")
    again = st.load(xml)
    assert trace(again, name, 60) == trace(load(PROJECTS / name, name), name, 60)
