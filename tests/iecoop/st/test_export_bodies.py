"""The ST writer on the statements beyond the basic subset: each Python class in, the exact ST out,
and where the ST reader knows the construct, the ST loaded back runs as the Python does."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies

from iecoop import (
    ARRAY, BOOL, DINT, INT, LREAL, POINTER_TO, REAL, REFERENCE_TO, STRING, TIME, UDINT, VAR, VAR_INPUT, VAR_OUTPUT, WORD, FunctionBlock, IecEnum, Interface,
    IQueryInterface, PlcException, Program, Struct, T, VAR_IN_OUT, DWORD, adr, method, prop, query_interface, var_info,
)
from iecoop import st
from iecoop.runtime import current_task
from iecoop.stdlib import R, S
from iecoop.conversions import BOOL_TO_STRING, REAL_TO_STRING, TIME_TO_STRING
from iecoop.functions import CONCAT
from iecoop.st.export import StExportError, dump, export
from tests.iecoop.st.test_export import validate_plcopen

COUNT = 3


def body_of(text: str, name: str) -> str:
    """The statements of POU ``name`` in the flat text (between its last END_VAR and its END_)."""
    start = text.index(f"PROGRAM {name}\n")
    end = text.index("END_PROGRAM", start)
    return text[text.rindex("END_VAR\n", start, end) + len("END_VAR\n") : end]


def same_run(cls: Any, cycles: int, *names: str, types: tuple[Any, ...] = ()) -> None:
    """Dump ``cls`` (after ``types``), load the ST back, run both ``cycles`` times: the named variables
    agree each cycle."""
    loaded = getattr(st.load(dump([*types, cls])), cls.__name__)
    original = cls()
    for _ in range(cycles):
        loaded()
        original()
        assert [getattr(loaded, n) for n in names] == [getattr(original, n) for n in names]


class Texts(Program):
    tag: STRING = VAR("P1")
    running: BOOL = VAR(True)
    n: INT = VAR(-5)
    w: WORD = VAR(7)
    out: STRING = VAR("")
    flag: STRING = VAR("")
    empty: STRING = VAR("x")

    def body(self) -> None:
        self.n += 1
        self.running = not self.running
        self.out = f"{self.tag} {'on' if self.running else 'off'} n={self.n} w={self.w} of {COUNT}"
        self.flag = f"{self.running}"
        self.empty = f""


def test_an_f_string_is_nested_concat_with_integer_and_bool_texts() -> None:
    assert body_of(dump([Texts]), "Texts") == (
        "n := n + 1;\n"
        "running := NOT running;\n"
        "out := CONCAT(CONCAT(CONCAT(CONCAT(CONCAT(CONCAT(CONCAT(CONCAT(tag, ' '), SEL(running, 'off', 'on')), ' n='), "
        "INT_TO_STRING(n)), ' w='), WORD_TO_STRING(w)), ' of '), DINT_TO_STRING(COUNT));\n"
        "flag := SEL(running, 'False', 'True');\n"
        "empty := '';\n"
    )


def test_an_f_string_loaded_back_gives_pythons_text() -> None:
    same_run(Texts, 3, "out", "flag", "empty")


class VendorTexts(Program):
    level: REAL = VAR(0.5)
    delay: TIME = VAR(T("1s"))
    lit: BOOL = VAR(False)
    out: STRING = VAR("")

    def body(self) -> None:
        self.level += 0.25
        self.delay += T("250ms")
        self.lit = not self.lit
        self.out = CONCAT(CONCAT(REAL_TO_STRING(self.level), TIME_TO_STRING(self.delay)), BOOL_TO_STRING(self.lit))


def test_to_string_conversions_are_written_as_called_and_load_back() -> None:
    assert body_of(dump([VendorTexts]), "VendorTexts").endswith(
        "out := CONCAT(CONCAT(REAL_TO_STRING(level), TIME_TO_STRING(delay)), BOOL_TO_STRING(lit));\n"
    )
    same_run(VendorTexts, 3, "out")
    texts = VendorTexts()
    texts()
    texts()
    assert texts.out == "1.0T#1s500msFALSE"


class Mode(IecEnum, base=INT):
    AUTO = 0
    MANUAL = 1


class EnumName(Program):
    mode: Mode = VAR(Mode.MANUAL)
    out: STRING = VAR("")

    def body(self) -> None:
        self.out = f"mode {self.mode.name}"


def test_an_enumeration_name_is_to_string_of_an_enum_declared_with_to_string() -> None:
    text = dump([Mode, EnumName])
    assert text.startswith("{attribute 'to_string'}\nTYPE Mode :\n")
    assert "out := CONCAT('mode ', TO_STRING(mode));" in text
    # Without a .name read the enumeration keeps its plain declaration.
    assert dump([Mode]).startswith("TYPE Mode :\n")


class RealText(Program):
    r: REAL = VAR(1.5)
    out: STRING = VAR("")

    def body(self) -> None:
        self.out = f"r={self.r:.1f}"


class RealPlain(Program):
    x: LREAL = VAR(1.5)
    out: STRING = VAR("")

    def body(self) -> None:
        self.out = f"x={self.x}"


class TimeText(Program):
    t: TIME = VAR(T("2s"))
    out: STRING = VAR("")

    def body(self) -> None:
        self.out = f"{self.t} ms"


class ReprText(Program):
    out: STRING = VAR("")

    def body(self) -> None:
        self.out = f"{self.out!r}"


class EnumNumber(Program):
    mode: Mode = VAR(Mode.MANUAL)
    out: STRING = VAR("")

    def body(self) -> None:
        self.out = f"{self.mode}"


@pytest.mark.parametrize(("cls", "words"), [
    (RealText, r"the f-string format :\.1f \(ST has no format specifiers: round to an integer and write CONCAT\(\.\.\.\) with DINT_TO_STRING"),
    (RealPlain, r"a REAL value in an f-string \(Python writes repr\(\)"),
    (TimeText, r"a TIME or DATE value in an f-string .*TIME_TO_DINT"),
    (ReprText, r"the f-string conversion !r"),
    (EnumNumber, r"an enumeration value in an f-string .*\{x\.name\}"),
])
def test_an_f_string_whose_st_text_would_differ_is_refused_with_what_to_write(cls: Any, words: str) -> None:
    with pytest.raises(StExportError, match=rf"test_export_bodies\.py:\d+: {words}.* \(in {cls.__name__}\.body\)"):
        dump([cls])


class Rounding(Program):
    x: LREAL = VAR(0.0)
    r: REAL = VAR(0.0)
    n: INT = VAR(0)
    m: INT = VAR(0)
    k: INT = VAR(7)

    def body(self) -> None:
        self.x += 0.25
        self.r -= 0.75
        self.n = round(self.x * 10.0)
        self.m = round(self.r) + round(self.k)


def test_round_of_a_real_is_real_to_dint_and_of_an_integer_the_integer() -> None:
    assert body_of(dump([Rounding]), "Rounding") == (
        "x := x + 0.25;\nr := r - 0.75;\nn := LREAL_TO_DINT(x * 10.0);\nm := REAL_TO_DINT(r) + k;\n"
    )


def test_round_loaded_back_rounds_half_to_even_as_python() -> None:
    same_run(Rounding, 8, "n", "m")


class RoundDigits(Program):
    x: LREAL = VAR(0.0)

    def body(self) -> None:
        self.x = round(self.x, 2)


def test_round_to_digits_is_refused() -> None:
    with pytest.raises(StExportError, match=r"round\(\) with a number of digits"):
        dump([RoundDigits])


# ---------------------------------------------------------------------------
# for over an ARRAY, enumerate(), a literal tuple
# ---------------------------------------------------------------------------


class Cell(Struct):
    value: INT = 0
    hits: INT = 0


class Loops(Program):
    cells: ARRAY[Cell] = VAR(bounds=(1, 3))
    weights: ARRAY[INT] = VAR([2, 3, 4], bounds=(0, 2))
    total: DINT = VAR(0)
    last: DINT = VAR(0)
    a: INT = VAR(1)
    b: INT = VAR(10)
    c: INT = VAR(100)

    def body(self) -> None:
        for cell in self.cells:
            cell.hits += 1
            cell.value = cell.hits * 2
        for k, weight in enumerate(self.weights, 1):
            if weight == 4:
                break
            self.total += k * weight
        for k, weight in enumerate(self.weights):
            self.last = k
        for n in (self.a, self.b, self.c):
            self.total += n
        for i, n in ((1, self.a), (2, self.b)):
            self.cells[i].value += n


LOOPS = """\
FOR cell_index := 1 TO 3 DO
    cell REF= cells[cell_index];
    cell.hits := cell.hits + 1;
    cell.value := cell.hits * 2;
END_FOR
FOR weight_index := 0 TO 2 DO
    k := weight_index + 1;
    weight := weights[weight_index];
    IF weight = 4 THEN
        EXIT;
    END_IF
    total := total + k * weight;
END_FOR
FOR k := 0 TO 2 DO
    weight := weights[k];
    last := k;
END_FOR
total := total + a;
total := total + b;
total := total + c;
cells[1].value := cells[1].value + a;
cells[2].value := cells[2].value + b;
"""


def test_for_over_an_array_enumerate_and_a_tuple() -> None:
    text = dump([Cell, Loops])
    assert body_of(text, "Loops") == LOOPS
    assert "VAR_TEMP\n    cell_index : DINT;\n    cell : REFERENCE TO Cell;\n    weight_index : DINT;\n    k : DINT;\n    weight : INT;\nEND_VAR" in text


def test_for_loops_loaded_back_run_as_python() -> None:
    loaded = st.load(dump([Cell, Loops])).Loops
    original = Loops()
    for _ in range(3):
        loaded()
        original()
        assert (loaded.total, loaded.last) == (original.total, original.last)
        assert [(c.value, c.hits) for c in loaded.cells] == [(c.value, c.hits) for c in original.cells]


class TupleBreak(Program):
    a: INT = VAR(0)

    def body(self) -> None:
        for n in (1, 2):
            if n == self.a:
                break


class TupleRebind(Program):
    a: INT = VAR(0)

    def body(self) -> None:
        for n in (1, 2):
            n = n + 1
            self.a = n


class Grid(Program):
    grid: ARRAY[INT] = VAR(bounds=((1, 2), (1, 2)))
    s: INT = VAR(0)

    def body(self) -> None:
        for row in self.grid:
            self.s = row


@pytest.mark.parametrize(("cls", "words"), [
    (TupleBreak, "a loop over a tuple whose body breaks, continues or assigns the loop names"),
    (TupleRebind, "a loop over a tuple whose body breaks, continues or assigns the loop names"),
    (Grid, "a for loop over an ARRAY of several dimensions"),
])
def test_loops_without_a_faithful_st_form_are_refused(cls: Any, words: str) -> None:
    with pytest.raises(StExportError, match=rf"test_export_bodies\.py:\d+: {words}"):
        dump([cls])


# ---------------------------------------------------------------------------
# Method chains and members of a call's result
# ---------------------------------------------------------------------------


class ICounter(Interface):
    @method
    def add(self, n: INT) -> ICounter:
        raise NotImplementedError

    @prop
    def value(self) -> INT:
        raise NotImplementedError


class Counter(FunctionBlock, ICounter):
    total: INT = VAR(0)
    saved: Cell = VAR()

    @method
    def add(self, n: INT) -> ICounter:
        self.total += n
        return self

    @prop
    def value(self) -> INT:
        return self.total

    @method
    def snapshot(self) -> Cell:
        self.saved.value = self.total
        return self.saved


class Chains(Program):
    counter: Counter = VAR()
    seen: INT = VAR(0)
    copied: INT = VAR(0)

    def body(self) -> None:
        self.seen = self.counter.add(1).add(2).value
        if self.counter.snapshot().value > 5:
            self.copied = self.counter.snapshot().value + self.counter.snapshot().value


CHAINS = """\
add_result := counter.add(1).add(2);
seen := add_result.value;
snapshot_result REF= counter.snapshot();
IF snapshot_result.value > 5 THEN
    snapshot_result REF= counter.snapshot();
    snapshot_result1 REF= counter.snapshot();
    copied := snapshot_result.value + snapshot_result1.value;
END_IF
"""


def test_a_chain_is_written_as_is_and_a_member_of_its_result_reads_a_temporary() -> None:
    text = dump([Cell, ICounter, Counter, Chains])
    assert body_of(text, "Chains") == CHAINS
    # snapshot() hands out the block's own STRUCT: REFERENCE TO it, as Python hands out the STRUCT itself
    assert "METHOD PUBLIC snapshot : REFERENCE TO Cell\n" in text
    assert "VAR_TEMP\n    add_result : ICounter;\n    snapshot_result : REFERENCE TO Cell;\n    snapshot_result1 : REFERENCE TO Cell;\nEND_VAR" in text


def test_chains_loaded_back_run_as_python() -> None:
    loaded = st.load(dump([Cell, ICounter, Counter, Chains])).Chains
    original = Chains()
    for _ in range(3):
        loaded()
        original()
        assert (loaded.seen, loaded.copied) == (original.seen, original.copied)


class Maker(FunctionBlock):
    total: INT = VAR(0)

    @method
    def make(self) -> Cell:
        """A new value, no variable of the block: the result is a copy in ST."""
        made: Cell
        made.value = self.total
        return made


class WriteThroughCall(Program):
    maker: Maker = VAR()

    def body(self) -> None:
        self.maker.make().value = 3


class ChainInWhile(Program):
    counter: Counter = VAR()

    def body(self) -> None:
        while self.counter.add(1).value < 10:
            pass


@pytest.mark.parametrize(("cls", "words"), [
    (WriteThroughCall, r"a write into a member of a call's result \(the METHOD returns a copy in ST"),
    (ChainInWhile, r"a member of a call's result in a while or elif condition"),
])
def test_a_member_of_a_call_without_a_faithful_st_form_is_refused(cls: Any, words: str) -> None:
    with pytest.raises(StExportError, match=rf"test_export_bodies\.py:\d+: {words}"):
        dump([Cell, ICounter, Counter, Maker, cls])


class TaskCycle(Program):
    ms: UDINT = VAR(0)

    def body(self) -> None:
        self.ms = current_task().CycleTime // 10_000


def test_current_task_is_twincats_task_info() -> None:
    assert body_of(dump([TaskCycle]), "TaskCycle") == "ms := _TaskInfo[GETCURTASKINDEXEX()].CycleTime / 10000;\n"


# ---------------------------------------------------------------------------
# try / except, match, tuple assignments, enumeration conversions
# ---------------------------------------------------------------------------


class Guarded(Program):
    divisor: INT = VAR(0)
    result: INT = VAR(0)
    cleanups: INT = VAR(0)

    def body(self) -> None:
        try:
            self.result = 100 // self.divisor
        except (PlcException, ZeroDivisionError):
            self.result = -1
        finally:
            self.cleanups += 1
        self.divisor += 1


def test_try_except_finally_is_try_catch_finally() -> None:
    text = dump([Guarded])
    assert body_of(text, "Guarded") == (
        "__TRY\n    result := 100 / divisor;\n__CATCH(exc)\n    result := -1;\n"
        "__FINALLY\n    cleanups := cleanups + 1;\n__ENDTRY\ndivisor := divisor + 1;\n"
    )
    assert "exc : __SYSTEM.ExceptionCode;" in text


def test_try_except_loaded_back_runs_as_python() -> None:
    same_run(Guarded, 3, "result", "cleanups")


class FinallyOnly(Program):
    n: INT = VAR(0)

    def body(self) -> None:
        try:
            self.n += 1
        finally:
            self.n = 0


class CaughtCode(Program):
    code: UDINT = VAR(0)

    def body(self) -> None:
        try:
            self.code = 0
        except PlcException as fault:
            self.code = fault.code


def test_except_plc_exception_binds_the_exception_code() -> None:
    assert body_of(dump([CaughtCode]), "CaughtCode") == "__TRY\n    code := 0;\n__CATCH(fault)\n    code := fault;\n__ENDTRY\n"


class NarrowExcept(Program):
    n: INT = VAR(0)

    def body(self) -> None:
        try:
            self.n = 10 // self.n
        except PlcException:
            self.n = 0


@pytest.mark.parametrize(("cls", "words"), [
    (FinallyOnly, r"try / finally without except \(ST goes on after __FINALLY"),
    (NarrowExcept, r"an except clause other than except PlcException, except \(PlcException, ZeroDivisionError\)"),
])
def test_try_forms_whose_meaning_differs_are_refused(cls: Any, words: str) -> None:
    with pytest.raises(StExportError, match=rf"test_export_bodies\.py:\d+: {words}"):
        dump([cls])


class Selector(Program):
    mode: Mode = VAR(Mode.AUTO)
    n: INT = VAR(0)
    out: INT = VAR(0)

    def body(self) -> None:
        self.n += 1
        self.mode = Mode(self.n % 2)
        match self.n:
            case 1 | 3:
                self.out = 10
            case 2:
                self.out = 20
            case _:
                self.out = self.out + 1


class ModeSelector(Program):
    mode: Mode = VAR(Mode.AUTO)
    out: INT = VAR(0)

    def body(self) -> None:
        match self.mode:
            case Mode.AUTO:
                self.out += 100
            case Mode.MANUAL:
                pass


def test_match_is_case_and_an_enum_conversion_is_its_value() -> None:
    assert body_of(dump([Mode, Selector]), "Selector") == (
        "n := n + 1;\nmode := n MOD 2;\nCASE n OF\n    1, 3:\n        out := 10;\n    2:\n        out := 20;\n"
        "ELSE\n    out := out + 1;\nEND_CASE\n"
    )
    # Qualified labels: right for an enumeration declared {attribute 'qualified_only'} too.
    assert body_of(dump([Mode, ModeSelector]), "ModeSelector") == (
        "CASE mode OF\n    Mode.AUTO:\n        out := out + 100;\n    Mode.MANUAL:\n        ;\nEND_CASE\n"
    )


def test_match_loaded_back_runs_as_python() -> None:
    same_run(Selector, 5, "n", "out", types=(Mode,))


class Swap(Program):
    a: INT = VAR(1)
    b: INT = VAR(2)
    c: INT = VAR(3)
    left: INT = VAR(0)

    def body(self) -> None:
        self.a, self.b, self.c = self.b, self.a + self.c, self.a
        self.left, self.c = self.left + 1, self.c


def test_a_tuple_assignment_reading_an_earlier_target_keeps_that_value_in_a_temporary() -> None:
    text = dump([Swap])
    assert body_of(text, "Swap") == (
        "b_new := a + c;\nc_new := a;\na := b;\nb := b_new;\nc := c_new;\nleft := left + 1;\nc := c;\n"
    )
    assert "VAR_TEMP\n    b_new : INT;\n    c_new : INT;\nEND_VAR" in text


def test_tuple_assignments_loaded_back_run_as_python() -> None:
    same_run(Swap, 4, "a", "b", "c", "left")


# ---------------------------------------------------------------------------
# math, len() of constants, functions without a result, query_interface() tests, enumeration loops
# ---------------------------------------------------------------------------

NAMES = ("a", "b", "c")


def bump(cell: POINTER_TO[Cell]) -> None:
    if cell:
        cell.deref.hits += 1


class IShown(IQueryInterface):
    @method
    def show(self) -> INT:
        raise NotImplementedError


class Shown(FunctionBlock, IShown):
    @method
    def show(self) -> INT:
        return 1


class Builtins(Program):
    angle: REAL = VAR(0.0)
    wave: REAL = VAR(0.0)
    root: LREAL = VAR(0.0)
    size: DINT = VAR(0)
    cell: Cell = VAR()
    shown: Shown = VAR()
    target: IShown = VAR()
    is_shown: BOOL = VAR(False)
    not_shown: BOOL = VAR(True)
    modes: INT = VAR(0)

    def body(self) -> None:
        self.angle += 0.5
        self.wave = 2.0 + math.sin(self.angle) * 3
        self.root = math.sqrt(self.root + 4.0)
        self.size = len(NAMES) + len(Mode)
        bump(adr(self, "cell"))
        self.is_shown = query_interface(self.shown, IShown) is not None
        self.not_shown = query_interface(self.shown, IShown) is None
        for mode in Mode:
            self.modes += mode


BUILTINS = """\
angle := angle + 0.5;
wave := 2.0 + SIN(TO_LREAL(angle)) * 3;
root := SQRT(root + 4.0);
size := 3 + 2;
bump(ADR(cell));
is_shown := __QUERYINTERFACE(shown, IShown_query);
not_shown := NOT __QUERYINTERFACE(shown, IShown_query);
modes := modes + Mode.AUTO;
modes := modes + Mode.MANUAL;
"""


def test_math_len_functions_query_tests_and_enumeration_loops() -> None:
    text = dump([Mode, Cell, IShown, Shown, Builtins])
    assert body_of(text, "Builtins") == BUILTINS
    # The vendors' FUNCTIONs have a result: one that returns nothing in Python is a BOOL left FALSE.
    assert "FUNCTION bump : BOOL\nVAR_INPUT\n    cell : POINTER TO Cell;\nEND_VAR\nIF cell <> 0 THEN\n    cell^.hits := cell^.hits + 1;\nEND_IF\nEND_FUNCTION" in text
    assert "VAR_TEMP\n    IShown_query : IShown;\nEND_VAR" in text


def test_math_len_functions_query_tests_and_enumeration_loops_loaded_back_run_as_python() -> None:
    same_run(Builtins, 4, "angle", "wave", "root", "size", "is_shown", "not_shown", "modes", types=(Mode, Cell, IShown, Shown))


class Logarithms(Program):
    level: LREAL = VAR(1.0)
    natural: LREAL = VAR(0.0)
    decimal: LREAL = VAR(0.0)

    def body(self) -> None:
        self.level = self.level * 2.0
        self.natural = math.log(self.level)
        self.decimal = math.log10(self.level)


def test_math_functions_are_the_vocabulary_s_every_one_log_is_ln() -> None:
    # math.log is the natural logarithm, ST's LN; math.log10 is LOG (iecoop.st.language.MATH_FUNCTIONS).
    assert body_of(dump([Logarithms]), "Logarithms") == "level := level * 2.0;\nnatural := LN(level);\ndecimal := LOG(level);\n"
    same_run(Logarithms, 3, "level", "natural", "decimal")


class Info(Program):
    cell: Cell = VAR()
    offset: UDINT = VAR(0)

    def body(self) -> None:
        info = var_info(self.cell, "hits")
        self.offset = info.ByteOffset


def test_var_info_is_varinfo_into_a_system_var_info_local() -> None:
    text = dump([Cell, Info])
    assert body_of(text, "Info") == "info := __VARINFO(cell.hits);\noffset := info.ByteOffset;\n"
    assert "VAR_TEMP\n    info : __SYSTEM.VAR_INFO;\nEND_VAR" in text


def test_an_enumeration_whose_names_are_read_comes_along_with_to_string() -> None:
    # EnumName uses Mode: the export brings it, declared so that TO_STRING gives the component's name.
    text = dump([EnumName])
    assert text.startswith("{attribute 'to_string'}\nTYPE Mode :\n")
    assert "out := CONCAT('mode ', TO_STRING(mode));" in text


class Formats(Program):
    i: INT = VAR_INPUT(0)
    u: UDINT = VAR_INPUT(0)
    flag: BOOL = VAR_INPUT(False)
    name: STRING = VAR_INPUT("", length=20)
    out: STRING = VAR_OUTPUT("", length=200)

    def body(self) -> None:
        self.out = f"[{self.name}] i={self.i} u={self.u} {self.flag}"


_FORMATS = st.load(dump([Formats])).Formats


@given(
    i=strategies.integers(-32768, 32767), u=strategies.integers(0, 2**32 - 1), flag=strategies.booleans(),
    name=strategies.text(strategies.characters(min_codepoint=32, max_codepoint=126), max_size=20),
)
def test_an_f_string_gives_the_same_text_in_st_for_any_integer_bool_and_string(i: int, u: int, flag: bool, name: str) -> None:
    original = Formats()
    for block in (original, _FORMATS):
        block(i=i, u=u, flag=flag, name=name)
    assert _FORMATS.out == original.out


def test_the_to_string_attribute_is_in_the_twincat_and_plcopen_files(tmp_path: Path) -> None:
    mode_dut, _ = export([Mode, EnumName], tmp_path / "tc")
    assert "{attribute 'to_string'}\nTYPE Mode :" in mode_dut.read_text().replace("\r\n", "\n")
    (project,) = export([Mode, EnumName], tmp_path / "xml", format="plcopen")
    validate_plcopen(project)
    text = project.read_text()
    data = text[text.index('<dataType name="Mode">') : text.index("</dataType>")]
    assert '<data name="http://www.3s-software.com/plcopenxml/attributes" handleUnknown="implementation">' in data
    assert '<Attribute Name="to_string" Value="" />' in data


# ---------------------------------------------------------------------------
# Inputs passed as they are, VAR_IN_OUT bindings, S= / R= chains, shifts, ARRAY bounds
# ---------------------------------------------------------------------------


class Tally(FunctionBlock):
    @method
    def count(self, cell: Cell, step: INT) -> INT:
        cell.hits += step
        return cell.hits


class Buffered(FunctionBlock):
    data: INT = VAR_IN_OUT()

    def body(self) -> None:
        self.data += 1


class Passing(Program):
    tally: Tally = VAR()
    buffered: Buffered = VAR()
    cell: Cell = VAR()
    shared: INT = VAR(0)
    seen: INT = VAR(0)
    running: BOOL = VAR(False)
    alarm: BOOL = VAR(False)
    trip: BOOL = VAR(False)
    mask: DWORD = VAR(0)
    n: INT = VAR(0)
    cells: ARRAY[Cell] = VAR(bounds=(2, 5))
    span: INT = VAR(0)

    def body(self) -> None:
        self.n += 1
        self.seen = self.tally.count(self.cell, 2)
        self.buffered(data=adr(self, "shared"))
        self.trip = self.n % 3 == 0
        S(self, "alarm", R(self, "running", self.trip))
        S(self, "running", self.n % 2 == 1)
        self.mask = 1 << self.n
        self.span = self.cells.high - self.cells.low


PASSING = """\
n := n + 1;
seen := tally.count(cell, 2);
buffered(data := shared);
trip := n MOD 3 = 0;
running R= trip;
alarm S= trip;
running S= n MOD 2 = 1;
mask := SHL(DWORD#1, n);
span := 5 - 2;
"""


def test_a_struct_input_is_a_reference_a_var_in_out_gets_the_variable_and_chains_are_split() -> None:
    text = dump([Cell, Tally, Buffered, Passing])
    assert body_of(text, "Passing") == PASSING
    # Python hands the method the caller's STRUCT: a VAR_INPUT of that type would be a copy.
    assert "METHOD PUBLIC count : INT\nVAR_INPUT\n    cell : REFERENCE TO Cell;\n    step : INT;\nEND_VAR\n" in text


def test_inputs_chains_and_shifts_loaded_back_run_as_python() -> None:
    same_run(Passing, 6, "seen", "shared", "running", "alarm", "mask", "span", types=(Cell, Tally, Buffered))


class OnceChain(Program):
    a: BOOL = VAR(False)
    b: BOOL = VAR(True)

    def body(self) -> None:
        S(self, "a", R(self, "b", self.b))


def test_a_chain_whose_condition_reads_a_target_stays_one_st_chain() -> None:
    assert body_of(dump([OnceChain]), "OnceChain") == "a S= b R= b;\n"


class TextMethod(Program):
    name: STRING = VAR("")

    def body(self) -> None:
        self.name = self.name.upper()


def test_a_python_method_of_a_string_is_refused() -> None:
    with pytest.raises(StExportError, match=r"test_export_bodies\.py:\d+: the Python method upper\(\) of a STRING\(80\) value"):
        dump([TextMethod])


class Sample(Struct):
    n_var: INT = 0


class SampleHolder(FunctionBlock):
    st_local: Sample = VAR()
    sets: INT = VAR(0)

    @prop
    def my_prop(self) -> REFERENCE_TO[Sample]:
        return self.st_local

    @my_prop.setter
    def my_prop(self, value: REFERENCE_TO[Sample]) -> None:
        self.st_local = value
        self.sets += 1


class SetThroughReference(Program):
    holder: SampleHolder = VAR()
    st_set: Sample = VAR()
    seen: INT = VAR(0)
    sets: INT = VAR(0)

    def body(self) -> None:
        self.st_set.n_var += 7
        self.holder.my_prop = self.st_set
        self.st_set.n_var += 100  # after the Set: the block keeps its copy
        self.seen = self.holder.my_prop.n_var
        self.sets = self.holder.sets


def test_a_reference_property_is_set_with_ref_as_the_course_writes_it() -> None:
    text = dump([Sample, SampleHolder, SetThroughReference])
    assert "holder.my_prop REF= st_set;\n" in body_of(text, "SetThroughReference")
    same_run(SetThroughReference, 3, "seen", "sets", types=(Sample, SampleHolder))


def test_ref_to_a_property_of_another_type_is_refused() -> None:
    text = dump([Sample, SampleHolder]) + (
        "PROGRAM Wrong\nVAR holder : SampleHolder; n : INT; END_VAR\nholder.my_prop REF= n;\nEND_PROGRAM\n"
    )
    with pytest.raises(st.StUnsupportedError, match=r"REF= of self\.holder\.my_prop needs a Sample variable, got self\.n"):
        st.load(text)


class Unequal(Program):
    a: INT = VAR(1)
    b: INT = VAR(0)
    c: INT = VAR(2)
    d: INT = VAR(0)
    differ: BOOL = VAR(False)

    def body(self) -> None:
        self.differ = not ((self.a | self.b) == (self.c | self.d))


def test_not_of_a_comparison_whose_operands_are_in_parentheses_keeps_the_comparison_whole() -> None:
    # NOT binds tighter than =: NOT (a OR b) = (c OR d) would compare the bitwise NOT of a OR b.
    assert body_of(dump([Unequal]), "Unequal") == "differ := NOT ((a OR b) = (c OR d));\n"
    same_run(Unequal, 1, "differ")
