"""``st.load`` of damaged sources fails only with the reader's own errors, each naming the file and a line.

The sources are the course's ST and the TwinCAT project beside these tests, damaged as an editor or a
merge damages them: tokens deleted, doubled or swapped, the text cut short, a keyword dropped in; and a
``.TcPOU`` whose XML, CDATA sections or attributes are broken. Whatever the damage, ``load`` raises
``StSyntaxError``, ``StUnsupportedError`` or ``DefinitionError`` (or loads): never a Python internal error.

The run is derandomized (the same examples every run) and small, as the Earley parser takes about half a
second per source; ``IECOOP_FUZZ_EXAMPLES=500`` explores further.
"""

from __future__ import annotations

import os
import pathlib
import re
import shutil

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as s

from iecoop.exceptions import DefinitionError

st = pytest.importorskip("iecoop.st")

DATA = pathlib.Path(__file__).parent / "data"
EXAMPLES = int(os.environ.get("IECOOP_FUZZ_EXAMPLES", "0"))

settings.register_profile(
    "st-fuzz", max_examples=EXAMPLES or 14, derandomize=not EXAMPLES, deadline=None, database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.function_scoped_fixture],
)

#: Realistic sources, cut at their POUs so one load stays small: (name, text).
_COURSE = sorted((DATA / "course").glob("*.st"))
_END = re.compile(r"^(END_FUNCTION_BLOCK|END_METHOD|END_PROPERTY|END_INTERFACE|END_TYPE|END_PROGRAM|END_FUNCTION)\s*$", re.M)


def _pieces() -> list[str]:
    pieces = []
    for path in _COURSE:
        text = path.read_text(encoding="utf-8")
        ends = [m.end() for m in _END.finditer(text)]
        start = 0
        chunk: list[str] = []
        for end in ends:
            chunk.append(text[start:end])
            start = end
            if sum(map(len, chunk)) > 500:
                pieces.append("".join(chunk))
                chunk = []
        if chunk:
            pieces.append("".join(chunk))
    return pieces


PIECES = _pieces()
TOKEN = re.compile(r"\w+|:=|=>|\(\*|\*\)|//|[^\s\w]")
KEYWORDS = [
    "IF", "THEN", "END_IF", "CASE", "OF", "FOR", "TO", "BY", "DO", "END_FOR", "WHILE", "REPEAT", "UNTIL", "RETURN", "EXIT",
    "VAR", "VAR_INPUT", "VAR_OUTPUT", "VAR_IN_OUT", "VAR_STAT", "VAR_TEMP", "END_VAR", "CONSTANT", "RETAIN", "AT", "%I*",
    "METHOD", "END_METHOD", "PROPERTY", "END_PROPERTY", "FUNCTION_BLOCK", "END_FUNCTION_BLOCK", "EXTENDS", "IMPLEMENTS",
    "INTERFACE", "STRUCT", "END_STRUCT", "TYPE", "END_TYPE", "ARRAY", "[*]", "POINTER TO", "REFERENCE TO", "REF=", "^",
    "THIS^", "SUPER^", "ABSTRACT", "FINAL", "PRIVATE", "INTERNAL", "ANY_NUM", "__NEW", "ADR", "SIZEOF", "(", ")", ",",
    ";", ":=", "=>", "0", "-1", "32768", "T#1s", "'text'", "1.5E400", "16#FFFFFFFFFFFFFFFFF", "x.3",
]


def _mutate(text: str, data: s.DataObject) -> str:
    tokens = [m for m in TOKEN.finditer(text)]
    kind = data.draw(s.sampled_from(["delete", "duplicate", "swap", "truncate", "keyword"]), label="kind")
    if not tokens:
        return text
    for _ in range(data.draw(s.integers(1, 3), label="count")):
        tokens = [m for m in TOKEN.finditer(text)]
        if not tokens:
            break
        i = data.draw(s.integers(0, len(tokens) - 1), label="token")
        a, b = tokens[i].span()
        if kind == "delete":
            text = text[:a] + text[b:]
        elif kind == "duplicate":
            text = text[:b] + " " + text[a:b] + text[b:]
        elif kind == "swap":
            j = data.draw(s.integers(0, len(tokens) - 1), label="other")
            c, d = tokens[j].span()
            if (a, b) > (c, d):
                a, b, c, d = c, d, a, b
            if b <= c:
                text = text[:a] + text[c:d] + text[b:c] + text[a:b] + text[d:]
        elif kind == "truncate":
            text = text[:a]
            break
        else:
            text = text[:a] + " " + data.draw(s.sampled_from(KEYWORDS), label="keyword") + " " + text[a:]
    return text


def _check(exc: BaseException, file: str) -> None:
    """The failure is one of the reader's errors, and its message names ``file`` and a line."""
    assert isinstance(exc, DefinitionError), f"internal error {type(exc).__name__}: {exc}"
    assert re.search(re.escape(file) + r":\d+", str(exc)), f"{type(exc).__name__} names no {file}:<line>: {exc}"


@settings.get_profile("st-fuzz")
@given(piece=s.sampled_from(PIECES), data=s.data())
def test_damaged_st_fails_only_with_named_errors(piece: str, data: s.DataObject) -> None:
    text = _mutate(piece, data)
    try:
        st.load(text)
    except Exception as exc:  # noqa: BLE001 - the point: which exceptions come out
        _check(exc, "<st>")


_TCPOU = DATA / "twincat" / "POUs" / "FB_Tank.TcPOU"
XML_DAMAGE = [
    ("<![CDATA[", ""), ("]]>", ""), ("]]>", "]]"), ("<![CDATA[", "<![CDATA[ ]]>"), ('Name="', 'Name="1'), ('Name="Fill"', ""),
    ('Name="Fill"', 'Name="Fill Fill"'), ("</Method>", ""), ("<Implementation>", "<Implementation><Implementation>"),
    ("<ST>", "<XX>"), ("</POU>", ""), ('Id="', 'Id="}{'), ("<Declaration>", ""), ('Name="FB_Tank"', 'Name="MAIN"'),
    ("<Method ", "<Property "), ("FUNCTION_BLOCK FB_Tank", "FUNCTION_BLOCK"), ('encoding="utf-8"', 'encoding="bogus"'),
    ("<POU ", "<DUT "), ("<TcPlcObject", "<!DOCTYPE x><TcPlcObject"), ("&", "&amp;"), ("<", "&lt;"), ("\n", ""),
]


@settings.get_profile("st-fuzz")
@given(damage=s.lists(s.sampled_from(XML_DAMAGE), min_size=1, max_size=2), which=s.integers(0, 3), data=s.data())
def test_damaged_twincat_files_fail_only_with_named_errors(
    tmp_path_factory: pytest.TempPathFactory, damage: list[tuple[str, str]], which: int, data: s.DataObject,
) -> None:
    text = _TCPOU.read_text(encoding="utf-8")
    for old, new in damage:
        count = text.count(old)
        if count:
            at = -1
            for _ in range(which % count + 1):
                at = text.find(old, at + 1)
            text = text[:at] + new + text[at + len(old):]
    if data.draw(s.booleans(), label="cut"):
        text = text[: data.draw(s.integers(0, len(text)), label="at")]
    folder = tmp_path_factory.mktemp("tc")
    shutil.copytree(DATA / "twincat", folder, dirs_exist_ok=True)
    path = folder / "POUs" / "FB_Tank.TcPOU"
    path.write_text(text, encoding="utf-8")
    try:
        st.load(folder)
    except Exception as exc:  # noqa: BLE001 - the point: which exceptions come out
        assert isinstance(exc, DefinitionError), f"internal error {type(exc).__name__}: {exc}"
        named = re.search(r"\.Tc\w+:\d+", str(exc))
        assert named, f"{type(exc).__name__} names no file and line: {exc}"
