"""The ST writer on the statements beyond the basic subset: each Python class in, the exact ST out,
and where the ST reader knows the construct, the ST loaded back runs as the Python does."""

from __future__ import annotations

from typing import Any

import pytest

from iecoop import BOOL, INT, LREAL, REAL, STRING, TIME, WORD, VAR, IecEnum, Program, T
from iecoop import st
from iecoop.st.export import StExportError, dump

COUNT = 3


def body_of(text: str, name: str) -> str:
    """The statements of POU ``name`` in the flat text (between its last END_VAR and its END_)."""
    start = text.index(f"PROGRAM {name}\n")
    end = text.index("END_PROGRAM", start)
    return text[text.rindex("END_VAR\n", start, end) + len("END_VAR\n") : end]


def same_run(cls: Any, cycles: int, *names: str) -> None:
    """Dump ``cls``, load the ST back, run both ``cycles`` times: the named variables agree each cycle."""
    loaded = getattr(st.load(dump([cls])), cls.__name__)
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
