"""The ST writer writes only inside its folder and only the ST it means: names, strings and paths checked."""

from __future__ import annotations

import gc
import os
import re
import sys
import typing
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as hs

from iecoop import INT, STRING, VAR, WSTRING, VAR_INST, FunctionBlock, GlobalVariables, IecEnum, Interface, Program, Struct, method
from iecoop.exceptions import DefinitionError
from iecoop.st import load
from iecoop.st.export import StExportError, dump, export
from iecoop.st.read.names import st_name_of

FORMATS = ("twincat", "st", "plcopen")


def _files(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file() or p.is_symlink()}


def _enum(name: str, members: Any) -> Any:
    """An enumeration made by a call, as a program that builds names would (``IecEnum("E_Mode", ["A", "B"])``)."""
    return typing.cast(Any, IecEnum)(name, members)


def _fb(name: str, annotations: dict[str, Any], **namespace: Any) -> Any:
    return type(name, (FunctionBlock,), {"__annotations__": annotations, "__module__": __name__, **namespace})


def _struct(name: str, annotations: dict[str, Any]) -> Any:
    return type(name, (Struct,), {"__annotations__": annotations, "__module__": __name__})


def _declared(text: str) -> set[str]:
    """The POU, type and GVL names ``load`` makes of ``text`` (each is a module attribute)."""
    module = load(text)
    try:
        return {st_name_of(k) for k, v in vars(module).items()
                if getattr(v, "__module__", None) == module.__name__ or type(v).__module__ == module.__name__}
    finally:
        # A loaded GVL holds its global names while it lives: the next example may declare them again.
        del sys.modules[module.__name__]
        del module
        gc.collect()


# ---------------------------------------------------------------------------
# 1. Nothing is written outside the target folder
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("name", ["../../escaped", "../escaped", "a/b", "/tmp/escaped", "..", "a\\b"])
def test_a_name_that_leaves_the_folder_is_refused_and_nothing_is_written(tmp_path: Path, fmt: str, name: str) -> None:
    work = tmp_path / "work"
    work.mkdir()
    enum_cls = _enum(name, ["A", "B"])
    with pytest.raises(StExportError, match="not an ST identifier") as raised:
        export([enum_cls], work / "a" / "b" / "out", format=fmt)
    assert repr(name) in str(raised.value) or name in str(raised.value)
    assert _files(tmp_path) == set()


@pytest.mark.parametrize("fmt", ["twincat", "st"])
def test_a_symlink_in_the_folder_is_not_written_through(tmp_path: Path, fmt: str) -> None:
    outside = tmp_path / "outside.txt"
    outside.write_text("keep")
    folder = tmp_path / "out"
    folder.mkdir()
    suffix = ".TcDUT" if fmt == "twincat" else ".st"
    (folder / f"E_Link{suffix}").symlink_to(outside)
    with pytest.raises(StExportError, match="symbolic link"):
        export([_enum("E_Link", ["A"])], folder, format=fmt)
    assert outside.read_text() == "keep"


def test_a_module_name_that_leaves_the_folder_does_not_name_the_plcopen_file(tmp_path: Path) -> None:
    import types

    module = types.ModuleType("../../escaped")
    module.E_Mod = _enum("E_Mod", ["A"])  # type: ignore[attr-defined]
    module.E_Mod.__module__ = module.__name__
    with pytest.raises(StExportError, match="leaves the folder|not an ST identifier"):
        export(module, tmp_path / "a" / "out", format="plcopen")
    assert _files(tmp_path) == set()


@pytest.mark.parametrize("name", ["../x.st", "sub/x.st", "/tmp/x.st", "..", ""])
def test_the_file_layer_refuses_a_path_outside_the_folder(tmp_path: Path, name: str) -> None:
    from iecoop.st.export import _write

    (tmp_path / "out").mkdir()
    with pytest.raises(StExportError, match="outside the folder"):
        _write(tmp_path / "out", name, "text")
    assert _files(tmp_path) == set()


# ---------------------------------------------------------------------------
# 2. A name is written only if it is an ST identifier
# ---------------------------------------------------------------------------

INJECTED = "A := 1\n) INT;\nEND_TYPE\nPROGRAM Injected\nEND_PROGRAM\nTYPE X :\n(B"


def _injections() -> list[tuple[str, Any]]:
    class IStart(Interface):
        pass

    return [
        ("enum value", lambda: [_enum("E_Inj", {INJECTED: 1, "C": 2})]),
        ("enum name", lambda: [_enum("E_X : INT; END_TYPE PROGRAM Injected", ["A"])]),
        ("struct member", lambda: [_struct("ST_Inj", {"ok; END_STRUCT END_TYPE PROGRAM Injected": INT})]),
        ("field", lambda: [_fb("FB_Inj", {"x : INT; END_VAR END_FUNCTION_BLOCK PROGRAM Injected": INT})]),
        ("class name", lambda: [_renamed(_fb("FB_A", {}), "FB_A\nEND_FUNCTION_BLOCK\nPROGRAM Injected")]),
        ("non-ASCII class name", lambda: [_fb("FB_Förder", {})]),
        ("gvl name", lambda: [_renamed(type("GVL_A", (GlobalVariables,), {"__annotations__": {"g": INT}, "__module__": __name__}), "GVL_A\nPROGRAM Injected")]),
        ("gvl variable", lambda: [type("GVL_B", (GlobalVariables,), {"__annotations__": {"g : INT; END_VAR": INT}, "__module__": __name__})]),
        ("interface name", lambda: [type("I_A;PROGRAM Injected", (IStart,), {"__module__": __name__})]),
        ("method name", lambda: [_fb("FB_M", {}, **{"go;\nEND_METHOD": method(lambda self: None)})]),
        ("string member name", lambda: [_fb("FB_S", {"a)": STRING})]),
    ]


def _renamed(cls: Any, name: str) -> Any:
    """A class renamed after it was made (Python takes any text as ``__name__``)."""
    cls.__name__ = name
    return cls


@pytest.mark.parametrize("what, make", _injections(), ids=[w for w, _ in _injections()])
def test_a_name_that_is_not_an_st_identifier_is_refused(what: str, make: Any) -> None:
    classes = make()
    with pytest.raises(StExportError, match="not an ST identifier") as raised:
        dump(classes)
    message = str(raised.value)
    assert "letter or underscore" in message


def test_the_injected_enum_value_does_not_create_a_program() -> None:
    with pytest.raises(StExportError, match=r"E_Inj.*not an ST identifier"):
        dump([_enum("E_Inj", {INJECTED: 1, "C": 2})])


#: Text a name could be: identifiers, keywords, and what ST gives a meaning to.
_NAME_TEXT = hs.one_of(
    hs.from_regex(r"[A-Za-z_][A-Za-z0-9_]{0,8}", fullmatch=True),
    hs.sampled_from(["Case", "Then", "END_IF", "VAR", "TO", "Förderband", "a__b", "_x", "x_", "Injected"]),
    hs.text(alphabet=hs.characters(codec="utf-8", exclude_categories=["Cs"]), min_size=0, max_size=10),
    hs.text(alphabet=" ;:=()\n\r\t'\"$*/{}[]^.,#@-+<>AXYZ_019", min_size=1, max_size=12),
)


@settings(max_examples=60, deadline=None, database=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    kind=hs.sampled_from(["enum", "struct", "fb", "gvl"]),
    type_name=_NAME_TEXT,
    members=hs.lists(_NAME_TEXT, min_size=1, max_size=3, unique=True),
)
@pytest.mark.slow  # seconds each: once, in the slow gate
def test_any_name_is_refused_or_loads_back_with_the_same_declarations(kind: str, type_name: str, members: list[str]) -> None:
    try:
        if kind == "enum":
            classes: list[Any] = [_enum(type_name, {m: i for i, m in enumerate(members)})]
        elif kind == "struct":
            classes = [_struct(type_name, {m: INT for m in members})]
        elif kind == "gvl":
            classes = [type(type_name, (GlobalVariables,), {"__annotations__": {m: INT for m in members}, "__module__": __name__})]
        else:
            classes = [_fb(type_name, {m: INT for m in members})]
    except Exception:
        return  # Python or the class builder refused the class: nothing to export
    try:
        text = dump(classes)
    except StExportError as exc:
        assert re.search("not an ST identifier|keyword|differ only in case", str(exc)), exc
        return
    assert _declared(text) == {type_name}


# ---------------------------------------------------------------------------
# 3. Control characters in STRING values are $ escapes
# ---------------------------------------------------------------------------

CONTROL = ["\x01", "\x1b", "\x7f", "\x00", "\x0c", "\x1f", "\n", "\t", "$", "'"]


@pytest.mark.parametrize("char", CONTROL, ids=[f"{ord(c):02x}" for c in CONTROL])
def test_a_control_character_in_a_string_initial_value_is_escaped_and_reads_back(tmp_path: Path, char: str) -> None:
    value = f"a{char}b"
    fb = _fb("FB_Ctl", {"s": STRING}, s=VAR(value))
    expected = fb().s
    written = export([fb], tmp_path / "tc", format="twincat")
    text = written[0].read_text("utf-8")
    ET.fromstring(text.encode("utf-8"))  # well-formed
    assert not re.search(r"[\x00-\x08\x0b\x0c\x0e-\x1f\x7f]", text)
    assert load(written[0]).FB_Ctl().s == expected
    plcopen = export([fb], tmp_path / "po", format="plcopen")[0]
    initial = ET.parse(plcopen).getroot().find(".//{*}variable[@name='s']/{*}initialValue/{*}simpleValue")
    assert initial is not None and not re.search(r"[\x00-\x1f\x7f]", initial.get("value", ""))
    assert load(f"PROGRAM P\nVAR s : STRING := {initial.get('value')}; END_VAR\nEND_PROGRAM\n").P.s == expected


def test_each_control_character_is_written_as_two_hex_digits() -> None:
    fb = _fb("FB_Hex", {"s": STRING}, s=VAR("\x01\x1b\x7f\x0c\r\n\t$'"))
    assert "s : STRING := '$01$1B$7F$P$R$N$T$$$'';" in dump([fb])


WIDE = [c for c in CONTROL if c != "\x00"] + ["\u20ac", "\uffff", "\ufffe"]


@pytest.mark.parametrize("char", WIDE, ids=[f"{ord(c):02x}" for c in WIDE])
def test_a_wstring_initial_value_reads_back_as_written(tmp_path: Path, char: str) -> None:
    """A WSTRING's character code is four hex digits ($000A): read as two, the text was cut at the NUL of $00."""
    value = f"a{char}b"
    fb = _fb("FB_Wide", {"w": WSTRING}, w=VAR(value))
    written = export([fb], tmp_path, format="twincat")[0]
    assert load(written).FB_Wide().w == fb().w == value


def test_a_wstring_code_is_four_hex_digits_and_a_string_code_two() -> None:
    plc = load("PROGRAM P\nVAR w : WSTRING := \"$0041$00E9$20AC$000A$$\"; s : STRING := '$41$E9$0A0'; END_VAR\nEND_PROGRAM\n")
    assert (plc.P.w, plc.P.s) == ("A\u00e9\u20ac\n$", "A\u00e9\n0")


def test_a_wstring_code_no_utf8_file_can_hold_is_refused_at_its_line() -> None:
    with pytest.raises(DefinitionError, match=r"^<st>:1: P\.w: initial value of the wrong type: WSTRING holds UCS-2"):
        load('PROGRAM P\nVAR w : WSTRING := "$D800"; END_VAR\nEND_PROGRAM\n')


class StringBody(Program):
    s: STRING = VAR("")

    def body(self) -> None:
        self.s = "x\x01\x1b\x7fy"


def test_a_control_character_in_a_body_literal_is_escaped_and_reads_back(tmp_path: Path) -> None:
    text = dump([StringBody])
    assert "s := 'x$01$1B$7Fy';" in text
    written = export([StringBody], tmp_path, format="twincat")[0]
    ET.parse(written)
    program = load(written).StringBody
    program()
    assert program.s == "x\x01\x1b\x7fy"


# ---------------------------------------------------------------------------
# 4. Keywords, non-ASCII names and names differing only in case
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["Case", "Then", "Until", "END_IF", "VAR", "TO", "function_block"])
def test_a_type_named_like_a_keyword_is_refused_with_what_to_write(name: str) -> None:
    with pytest.raises(StExportError, match=rf"{name}.*ST keyword.*E_{name}"):
        dump([_enum(name, ["A"])])
    with pytest.raises(StExportError, match=rf"{name}.*ST keyword.*FB_{name}"):
        dump([_fb(name, {"x": INT})])


class E_Step(IecEnum, base=INT):
    TO = 1
    Then = 2
    idle = 0


class Stepper(Program):
    step: E_Step = VAR(E_Step.TO)

    def body(self) -> None:
        if self.step == E_Step.TO:
            self.step = E_Step.Then


def test_an_enum_member_named_like_a_keyword_is_renamed_at_every_reference() -> None:
    text = dump([E_Step, Stepper])
    assert "    TO_ := 1, // TO is an ST keyword: TO_ in ST\n" in text
    assert "step : E_Step := E_Step.TO_;" in text
    assert "IF step = E_Step.TO_ THEN" in text and "step := E_Step.Then_;" in text
    loaded = load(text)
    # read back, the ST names TO_ and Then_ are the Python names TO and Then again
    assert {m.name for m in loaded.E_Step} == {"TO", "Then", "idle"}
    loaded.Stepper()
    assert loaded.Stepper.step == loaded.E_Step.Then


def test_a_field_named_like_a_keyword_is_renamed_and_says_so() -> None:
    point = _struct("ST_Kw", {"Then": INT, "x": INT})
    text = dump([point])
    assert "Then_ : INT; // Then is an ST keyword" in text
    assert {"Then", "x"} <= set(dir(load(text).ST_Kw()))  # read back, Then_ is the Python name Then again


@pytest.mark.parametrize("make", [
    lambda: [_enum("Förderband", ["A"])],
    lambda: [_enum("E_Band", ["Förder"])],
    lambda: [_fb("FB_Band", {"größe": INT})],
    lambda: [_struct("ST_Band", {"größe": INT})],
], ids=["enum", "enum-member", "fb-field", "struct-member"])
def test_a_non_ascii_name_is_refused_with_the_rule(make: Any) -> None:
    with pytest.raises(StExportError, match="not an ST identifier.*ASCII"):
        dump(make())


@pytest.mark.parametrize("make, where", [
    (lambda: [_fb("FB_Case", {"speed": INT, "Speed": INT})], "FB_Case"),
    (lambda: [_struct("ST_Case", {"speed": INT, "Speed": INT})], "ST_Case"),
    (lambda: [_enum("E_Case", ["idle", "IDLE"])], "E_Case"),
    (lambda: [type("GVL_Case", (GlobalVariables,), {"__annotations__": {"g": INT, "G": INT}, "__module__": __name__})], "GVL_Case"),
    (lambda: [_struct("ST_Kw2", {"Then": INT, "then_": INT})], "ST_Kw2"),
], ids=["fb", "struct", "enum", "gvl", "renamed-keyword"])
def test_names_that_differ_only_in_case_are_refused(make: Any, where: str) -> None:
    with pytest.raises(StExportError, match=rf"{where}.*differ only in case"):
        dump(make())


def test_a_method_and_a_field_that_differ_only_in_case_are_refused() -> None:
    fb = _fb("FB_MCase", {"start": INT}, **{"Start": method(lambda self: None)})
    with pytest.raises(StExportError, match=r"FB_MCase.*differ only in case"):
        dump([fb])


def test_double_underscores_are_kept(tmp_path: Path) -> None:
    point = _struct("ST__Pair", {"a__b": INT})
    text = dump([point])
    assert "a__b : INT;" in text
    assert _declared(text) == {"ST__Pair"}


def test_plcopen_writes_the_renamed_names_the_bodies_use(tmp_path: Path) -> None:
    written = export([E_Step, Stepper, _struct("ST_Kw3", {"Then": INT})], tmp_path, format="plcopen")[0]
    root = ET.parse(written).getroot()
    assert {v.get("name") for v in root.iterfind(".//{*}enum/{*}values/{*}value")} == {"TO_", "Then_", "idle"}
    assert [v.get("name") for v in root.iterfind(".//{*}dataType[@name='ST_Kw3']//{*}variable")] == ["Then_"]


def test_the_xml_writers_refuse_a_character_xml_cannot_hold() -> None:
    from iecoop.st.write.units import Unit
    from iecoop.st.write.files import plcopen_project, twincat_file

    unit = Unit("gvl", "GVL_Raw", "VAR_GLOBAL\n    s : STRING := '\x01';\nEND_VAR\n")
    with pytest.raises(StExportError, match="control character.*XML"):
        twincat_file(unit)
    with pytest.raises(StExportError, match="control character.*XML"):
        plcopen_project("raw\x02", [])


class Tally(FunctionBlock):
    @method
    def constant(self) -> INT:
        """A METHOD named like a keyword (CONSTANT), with a VAR_INST of its own."""
        self.calls += 1
        return self.calls

    calls: INT = VAR_INST(0, method="constant")


def test_a_renamed_method_keeps_its_var_inst() -> None:
    text = dump([Tally])
    assert "METHOD PUBLIC constant_ : INT\n// constant is an ST keyword: constant_ in ST\nVAR_INST\n    calls : INT;\nEND_VAR\n" in text
    tally = load(text).Tally()
    tally.constant()  # read back, the ST name constant_ is the Python name constant again
    assert tally.constant() == 2


def test_a_loaded_projects_layout_is_written_in_folders_that_stay_inside(tmp_path: Path) -> None:
    from iecoop.st.export import _write

    out = tmp_path / "out"
    out.mkdir()
    assert _write(out, "POUs/MAIN.TcPOU", "x", nested=True).read_text() == "x"
    assert (out / "POUs" / "MAIN.TcPOU").is_file()
    for name in ("POUs/../../x.st", "../x.st", "POUs//x.st"):
        with pytest.raises(StExportError, match="outside the folder"):
            _write(out, name, "x", nested=True)
    (tmp_path / "elsewhere").mkdir()
    (out / "DUTs").symlink_to(tmp_path / "elsewhere")
    with pytest.raises(StExportError, match="symbolic link"):
        _write(out, "DUTs/E.TcDUT", "x", nested=True)
    assert not (tmp_path / "elsewhere" / "E.TcDUT").exists()
