"""Constructs the catalogue's round trip met: the exact ST the writer gives, and the ST read back runs as the Python does."""

from __future__ import annotations

from pathlib import Path
from xml.etree import ElementTree

import pytest

from iecoop import (
    ARRAY, BOOL, INT, LREAL, POINTER_TO, PRIVATE, PROTECTED, TIME, VAR, VAR_INPUT, VAR_OUTPUT, WORD, AccessError, ExceptionCode, FunctionBlock,
    Program, Struct, T, adr, call_after_init, method, prop, try_catch,
)
from iecoop import st
from iecoop.runtime import Runtime, Task
from iecoop.st.export import dump, export
from tests.iecoop.st.test_export import validate_plcopen


class Image(Struct):
    inputs: ARRAY[WORD] = VAR(bounds=(0, 3))


class Reader(FunctionBlock):
    image: POINTER_TO[Image] = VAR_INPUT()
    bus: Image = VAR_INPUT()
    seen: WORD = VAR(0)

    @method
    def first(self) -> INT:
        if not self.image:
            return -1
        image = self.image.deref
        self.seen = image.inputs[1]
        return 1


def test_a_local_hides_the_variable_of_its_name_before_its_first_assignment() -> None:
    text = dump([Image, Reader])
    assert "IF THIS^.image = 0 THEN\n    first := -1;\n    RETURN;\nEND_IF\nimage REF= THIS^.image^;\n" in text


def test_a_local_named_like_a_variable_loaded_back_reads_the_variable() -> None:
    module = st.load(dump([Image, Reader]))
    reader = module.Reader()
    assert reader.first() == -1
    reader.bus.inputs[1] = 42
    reader.image = adr(reader, "bus")
    assert (reader.first(), reader.seen) == (1, 42)


def test_a_dereference_before_a_subscripted_field_is_read_first() -> None:
    # blark puts the ^ of image^.inputs[1] on the field selector after it.
    module = st.load("""
TYPE BusImage :
STRUCT
    inputs : ARRAY[0..3] OF WORD;
END_STRUCT
END_TYPE
FUNCTION_BLOCK FB_Card
VAR image : POINTER TO BusImage; bus : BusImage; nRead : WORD; nCall : WORD; END_VAR
image := ADR(bus);
bus.inputs[1] := bus.inputs[1] + 7;
nRead := image^.inputs[1];
nCall := MAX(image^.inputs[1], 10);
END_FUNCTION_BLOCK
""")
    card = module.FB_Card()
    card()
    card()
    assert (card.nRead, card.nCall) == (14, 14)


class Ramp(FunctionBlock):
    duration: TIME = VAR_INPUT(T("500ms"))
    velocity: LREAL = VAR_OUTPUT(0.0)
    per_second: LREAL = VAR_OUTPUT(0.0)
    share: LREAL = VAR_OUTPUT(0.0)

    def body(self) -> None:
        velocity = self.velocity + 1.0
        self.per_second = 100.0 / (self.duration / 1000)
        self.share = self.duration / T("2s")
        self.velocity = velocity


def test_python_division_of_times_is_written_on_lreal() -> None:
    text = dump([Ramp])
    assert "per_second := 100.0 / (TO_LREAL(duration) / 1000);\n" in text
    assert "share := TO_LREAL(duration) / TO_LREAL(T#2S);\n" in text


def test_a_body_local_named_like_a_variable_takes_a_var_temp_name_of_its_own() -> None:
    text = dump([Ramp])
    assert "VAR_TEMP\n    velocity_temp : LREAL;\nEND_VAR" in text
    assert "velocity_temp := velocity + 1.0;\n" in text
    assert "velocity := velocity_temp;\n" in text


def test_times_divided_and_a_renamed_local_loaded_back_run_as_python() -> None:
    loaded, original = st.load(dump([Ramp])).Ramp(), Ramp()
    for _ in range(3):
        loaded()
        original()
        assert (loaded.velocity, loaded.per_second, loaded.share) == (original.velocity, original.per_second, original.share)
    assert (original.velocity, original.per_second, original.share) == (3.0, 200.0, 0.25)


def test_an_input_before_a_reference_to_input_is_required_as_in_python() -> None:
    module = st.load("""
TYPE ST_Event :
STRUCT
    nCode : INT;
END_STRUCT
END_TYPE
FUNCTION_BLOCK FB_Log
VAR aCodes : ARRAY[0..1] OF INT := [11, 22]; END_VAR
END_FUNCTION_BLOCK
METHOD Newest : BOOL
VAR_INPUT
    nAge : UINT;
    stEvent : REFERENCE TO ST_Event;
END_VAR
IF nAge > 1 THEN
    RETURN;
END_IF
stEvent.nCode := aCodes[nAge];
Newest := TRUE;
END_METHOD
PROGRAM MAIN
VAR fbLog : FB_Log; stA : ST_Event; stB : ST_Event; bA : BOOL; bB : BOOL; bOld : BOOL := TRUE; END_VAR
bA := fbLog.Newest(0, stA);
bB := fbLog.Newest(nAge := 1, stEvent := stB);
bOld := fbLog.Newest(2, stB);
END_PROGRAM
""")
    module.MAIN()
    main = module.MAIN
    assert (main.bA, main.stA.nCode, main.bB, main.stB.nCode, main.bOld) == (True, 11, True, 22, False)


#: A module constant whose name differs from a variable's only in case.
LIMIT = 3


class Counter(FunctionBlock):
    limit: INT = VAR_INPUT(10)
    count: INT = VAR_OUTPUT(0)
    capped: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self.count < self.limit:
            self.count += 1
        self.capped = min(self.count, LIMIT)


def test_a_constant_named_like_a_variable_but_for_case_is_read_from_its_list() -> None:
    text = dump([Counter])
    # ST names ignore case: a bare LIMIT would be the input limit.
    assert "capped := MIN(count, GVL_Constants.LIMIT);\n" in text
    assert "IF count < limit THEN\n" in text


@pytest.mark.parametrize("fmt", ["st", "twincat"])
def test_a_constant_named_like_a_variable_loaded_back_runs_as_python(tmp_path: Path, fmt: str) -> None:
    # The exported files name the global list (the flat text of dump() does not).
    export([Counter], tmp_path, format=fmt)
    loaded, original = st.load(tmp_path).Counter(), Counter()
    for _ in range(5):
        loaded()
        original()
        assert (loaded.count, loaded.capped) == (original.count, original.capped)
    assert (original.count, original.capped) == (5, 3)


class Folder(FunctionBlock):
    total: INT = VAR_OUTPUT(0)

    @method
    def constant(self, value: INT) -> INT:
        """A method whose name is an ST keyword (CONSTANT)."""
        return value * 2

    def body(self) -> None:
        self.total += self.constant(3)


def test_a_method_named_like_a_keyword_is_declared_and_called_by_one_name() -> None:
    text = dump([Folder])
    assert "METHOD PUBLIC constant_ : INT\n" in text
    assert "constant_ := value * 2;\n" in text
    assert "total := total + constant_(3);\n" in text
    loaded = st.load(text).Folder()
    loaded()
    loaded()
    assert loaded.total == 12


class Limits(Struct):
    high: INT = 0


class LimitSource(FunctionBlock):
    kept: Limits = VAR()

    @prop
    def limits(self) -> Limits:
        return self.kept

    @method
    def raise_to(self, high: INT) -> None:
        self.kept.high = high


class LimitUser(FunctionBlock):
    source: LimitSource = VAR()
    seen: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.source.raise_to(self.seen + 5)
        limits = self.source.limits
        self.seen = limits.high


def test_a_local_bound_to_a_property_s_structure_is_the_structure_itself() -> None:
    text = dump([Limits, LimitSource, LimitUser])
    # The Get accessor hands out the block's own STRUCT, as Python's getter does: REFERENCE TO it, bound with REF=.
    assert "PROPERTY PUBLIC limits : REFERENCE TO Limits\nVAR\nEND_VAR\nlimits REF= kept;\n" in text
    assert "VAR_TEMP\n    limits : REFERENCE TO Limits;\nEND_VAR" in text
    assert "limits REF= source.limits;\nseen := limits.high;\n" in text
    loaded = st.load(text).LimitUser()
    loaded()
    loaded()
    assert loaded.seen == 10


class LimitTuner(FunctionBlock):
    source: LimitSource = VAR()
    seen: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        limits = self.source.limits
        limits.high = limits.high + 5  # in Python, the source's own STRUCT
        self.seen = self.source.kept.high


def test_a_write_through_a_property_s_structure_reaches_the_block_once_loaded_back() -> None:
    original = LimitTuner()
    loaded = st.load(dump([Limits, LimitSource, LimitTuner])).LimitTuner()
    for _ in range(3):
        original()
        loaded()
        assert loaded.seen == original.seen
    assert original.seen == 15


class Wired(FunctionBlock):
    source: LimitSource = VAR()
    ready: BOOL = VAR_OUTPUT(False)
    calls: INT = VAR_OUTPUT(0)

    @call_after_init
    def wire(self) -> None:
        self.source.raise_to(7)
        self.ready = True

    @method
    def probe(self) -> BOOL:
        self.calls += 1
        return True

    def body(self) -> None:
        if self.ready and self.probe():
            self.ready = self.source.limits.high == 7
        if self.ready or self.probe():
            self.calls += 10


def test_call_after_init_is_written_on_the_method_and_the_block() -> None:
    text = dump([Limits, LimitSource, Wired])
    assert "{attribute 'call_after_init'}\nFUNCTION_BLOCK Wired\n" in text
    assert "{attribute 'call_after_init'}\nMETHOD PUBLIC wire\n" in text


def test_an_operand_that_calls_after_the_first_is_guarded_by_and_then_or_else() -> None:
    text = dump([Limits, LimitSource, Wired])
    assert "IF ready AND_THEN probe() THEN\n" in text
    assert "IF ready OR_ELSE probe() THEN\n" in text


@pytest.mark.parametrize("fmt", ["st", "twincat"])
def test_call_after_init_and_short_circuits_loaded_back_run_as_python(tmp_path: Path, fmt: str) -> None:
    export([Limits, LimitSource, Wired], tmp_path, format=fmt)
    loaded, original = st.load(tmp_path).Wired(), Wired()
    assert (loaded.ready, loaded.source.limits.high) == (original.ready, original.source.limits.high) == (True, 7)
    for _ in range(3):
        loaded()
        original()
        assert (loaded.ready, loaded.calls) == (original.ready, original.calls)
    assert original.calls == 33


class Gauge(FunctionBlock):
    span_internal: INT = VAR(10)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, span: INT = 10) -> BOOL:
        self.span = span
        return True

    @prop
    def span(self) -> INT:
        return self.span_internal

    @span.setter
    @method(PRIVATE)
    def span(self, value: INT) -> None:
        self.span_internal = max(value, 1)

    @method
    def widen(self, by: INT) -> INT:
        self.span = self.span + by
        return self.span

    @method(PROTECTED)
    def narrow(self) -> None:
        self.span = self.span - 1


def test_an_accessor_s_own_specifier_heads_its_declaration() -> None:
    text = dump([Gauge])
    # The property keeps the Get's specifier; the Set's own follows the PROPERTY line, as in TwinCAT's flat form.
    assert "// Get\nPROPERTY PUBLIC span : INT\nVAR\nEND_VAR\n" in text
    assert "// Set\nPROPERTY PUBLIC span : INT\nPRIVATE\nVAR\nEND_VAR\n" in text


def test_an_accessor_s_own_specifier_is_in_the_twincat_accessor_declaration(tmp_path: Path) -> None:
    export([Gauge], tmp_path, format="twincat")
    pou = (tmp_path / "Gauge.TcPOU").read_text(encoding="utf-8")
    assert "<Declaration><![CDATA[PROPERTY PUBLIC span : INT\n]]></Declaration>" in pou
    get, set_ = pou.split('<Get Name="Get"')[1].split("</Get>")[0], pou.split('<Set Name="Set"')[1].split("</Set>")[0]
    assert "<Declaration><![CDATA[VAR\nEND_VAR\n]]></Declaration>" in get
    assert "<Declaration><![CDATA[PRIVATE\nVAR\nEND_VAR\n]]></Declaration>" in set_


def test_an_accessor_s_own_specifier_is_in_codesys_plcopen_add_data(tmp_path: Path) -> None:
    (path,) = export([Gauge], tmp_path, format="plcopen")
    validate_plcopen(path)
    root = ElementTree.parse(path).getroot()
    tc6 = "{http://www.plcopen.org/xml/tc6_0201}"
    (prop,) = root.iter(f"{tc6}Property")
    modifiers = {
        element.tag.removeprefix(tc6): [dict(m.attrib) for m in element.iter(f"{tc6}AccessModifiers")]
        for element in prop if element.tag != f"{tc6}interface"
    }
    # the PUBLIC property and its Get carry none; the Set carries its own, in its interface's addData
    assert modifiers == {"GetAccessor": [], "SetAccessor": [{"Private": "true"}]}
    assert not list(prop.find(f"{tc6}interface").iter(f"{tc6}AccessModifiers"))  # type: ignore[union-attr]
    methods = {m.get("name"): [dict(a.attrib) for a in m.iter(f"{tc6}AccessModifiers")] for m in root.iter(f"{tc6}Method")}
    assert methods == {"FB_init": [], "widen": [], "narrow": [{"Protected": "true"}]}


@pytest.mark.parametrize("fmt", ["st", "twincat"])
def test_a_private_set_accessor_loaded_back_refuses_a_write_from_outside(tmp_path: Path, fmt: str) -> None:
    export([Gauge], tmp_path, format=fmt)
    module = st.load(tmp_path)
    loaded, original = module.Gauge(span=0), Gauge(span=0)
    for gauge in (loaded, original):
        assert gauge.span == 1  # FB_init writes it through the PRIVATE Set, from the block's own code
        assert gauge.widen(4) == 5
        with pytest.raises(AccessError, match=r"PRIVATE PROPERTY Gauge\.span \(Set\) cannot be called from"):
            gauge.span = 50
        assert gauge.span == 5


def test_an_accessor_s_own_specifier_overrides_the_property_s_when_read() -> None:
    # PROPERTY PUBLIC n : INT PROTECTED: blark's reading of a Get whose declaration starts with PROTECTED.
    module = st.load("""
FUNCTION_BLOCK FB_Base
VAR nValue : INT := 3; END_VAR
END_FUNCTION_BLOCK
PROPERTY PUBLIC n.Get : INT
PROTECTED
VAR
END_VAR
n := nValue;
END_PROPERTY
PROPERTY PUBLIC n.Set : INT
VAR
END_VAR
nValue := n * 2;
END_PROPERTY
FUNCTION_BLOCK FB_Child EXTENDS FB_Base
VAR_OUTPUT nSeen : INT; END_VAR
nSeen := n;
END_FUNCTION_BLOCK
""")
    child = module.FB_Child()
    child.n = 4  # the Set stays PUBLIC
    child()
    assert child.nSeen == 8  # a derived block reads the PROTECTED Get
    with pytest.raises(AccessError, match=r"PROTECTED PROPERTY FB_Base\.n \(Get\) cannot be called from"):
        child.n


class Divide(Program):
    divisor: INT = VAR_INPUT(1)
    result: INT = VAR(0)
    errors: INT = VAR(0)

    def body(self) -> None:
        with try_catch() as exc:
            self.result = 100 // self.divisor
        if exc.code != ExceptionCode.RTSEXCPT_NOEXCEPTION:
            self.result = -1
            self.errors += 1


def test_a_body_s_python_local_is_a_var_temp_fresh_at_every_task_call() -> None:
    text = dump([Divide])
    assert "VAR_TEMP\n    exc : __SYSTEM.ExceptionCode;\nEND_VAR" in text
    loaded, original = st.load(text).Divide, Divide()  # a loaded PROGRAM's name is its instance
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), loaded, original)
    seen = []
    for divisor in (5, 0, 4, 4):
        loaded.divisor = original.divisor = divisor
        rt.run(cycles=1)
        seen.append((loaded.result, loaded.errors))
        assert (loaded.result, loaded.errors) == (original.result, original.errors)
    # the exception caught at 100 / 0 is not seen again by the next cycles: their exc starts at 0
    assert seen == [(20, 0), (-1, 1), (25, 1), (25, 1)]
