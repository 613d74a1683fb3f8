"""st.load on hostile or unusual files: names from XML and file names, projects, XML safety, encodings, limits."""

from __future__ import annotations

import os
import re
import sys
import tempfile
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies

from iecoop.exceptions import DefinitionError
from iecoop import st
from iecoop.st.read import parse

POU = """<?xml version="1.0" encoding="utf-8"?>
<TcPlcObject Version="1.1.0.1" ProductVersion="3.1.4024.12">
  <POU Name="{pou}" Id="{{5a0e3c57-0000-4000-8000-000000000001}}" SpecialFunc="None">
    <Declaration><![CDATA[FUNCTION_BLOCK FB_Counter
VAR_INPUT
    bUp : BOOL;
END_VAR
VAR_OUTPUT
    nCount : INT;
END_VAR
]]></Declaration>
    <Implementation>
      <ST><![CDATA[IF bUp THEN
    nCount := nCount + 1;
END_IF]]></ST>
    </Implementation>
    <Method Name="{method}" Id="{{5a0e3c57-0000-4000-8000-000000000002}}">
      <Declaration><![CDATA[METHOD Add : INT
VAR_INPUT
    nStep : INT;
END_VAR
]]></Declaration>
      <Implementation>
        <ST><![CDATA[nCount := nCount + nStep;
Add := nCount;]]></ST>
      </Implementation>
    </Method>
    <Property Name="{property}" Id="{{5a0e3c57-0000-4000-8000-000000000003}}">
      <Declaration><![CDATA[PROPERTY Count : INT
]]></Declaration>
      <Get Name="Get" Id="{{5a0e3c57-0000-4000-8000-000000000004}}">
        <Declaration><![CDATA[VAR
END_VAR
]]></Declaration>
        <Implementation>
          <ST><![CDATA[Count := nCount;]]></ST>
        </Implementation>
      </Get>
    </Property>
    <Action Name="{action}" Id="{{5a0e3c57-0000-4000-8000-000000000005}}">
      <Implementation>
        <ST><![CDATA[nCount := 0;]]></ST>
      </Implementation>
    </Action>
  </POU>
</TcPlcObject>
"""
NAMES = {"pou": "FB_Counter", "method": "Add", "property": "Count", "action": "Reset"}


def pou(**names: str) -> str:
    return POU.format(**{**NAMES, **names})


def write(path: Path, text: str | bytes) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text, encoding="utf-8")
    return path


def test_the_pou_file_of_these_tests_loads(tmp_path: Path) -> None:
    plc = st.load(write(tmp_path / "FB_Counter.TcPOU", pou()))
    counter = plc.FB_Counter()
    counter(bUp=True)
    assert counter.Add(nStep=4) == 5 and counter.Count == 5


# 1. Names read from XML attributes become ST code: each must be an ST identifier.

def line_of(text: str, words: str) -> int:
    return next(number for number, line in enumerate(text.splitlines(), start=1) if words in line)


@pytest.mark.parametrize("element, tag", [("action", "Action"), ("method", "Method"), ("property", "Property"), ("pou", "POU")])
@pytest.mark.parametrize("name", ["Reset:&#10;nCount := 5;&#10;END_ACTION&#10;ACTION Other", "Add Sub", "Ä", "1st", ""])
def test_a_name_from_xml_that_is_no_identifier_is_refused(tmp_path: Path, element: str, tag: str, name: str) -> None:
    path = write(tmp_path / "FB_Counter.TcPOU", pou(**{element: name}))
    line = line_of(pou(), f"<{tag} Name=")
    shown = name.replace("&#10;", "\n")
    with pytest.raises(st.StSyntaxError, match="not an ST identifier") as caught:
        st.load(path)
    assert f"FB_Counter.TcPOU:{line}:" in str(caught.value)
    assert repr(shown) in str(caught.value)


# 2. A GVL takes its name from its file name: an ASCII ST identifier, and no POU's name.

@pytest.mark.parametrize("source, words", [
    ("FUNCTION_BLOCK INT\nVAR_OUTPUT q : INT; END_VAR\nEND_FUNCTION_BLOCK\n", "FUNCTION_BLOCK INT: INT is an ST keyword"),
    ("TYPE string : STRUCT a : INT; END_STRUCT END_TYPE\n", "STRUCT string: STRING is an ST keyword"),
    ("FUNCTION True : BOOL\nEND_FUNCTION\n", "FUNCTION True: TRUE is an ST keyword"),
])
def test_a_pou_or_type_named_like_a_keyword_is_refused(source: str, words: str) -> None:
    """plc.INT was iecoop's INT (the module imports it), not the FUNCTION_BLOCK INT the source declared."""
    with pytest.raises(st.StUnsupportedError, match=rf"^<st>:1: {words}, which no POU, type or GVL may be named"):
        st.load(source)


def test_a_gvl_file_with_fullwidth_letters_does_not_replace_main(tmp_path: Path) -> None:
    write(tmp_path / "ＭＡＩＮ.st", "VAR_GLOBAL\n    x : INT;\nEND_VAR\n")
    write(tmp_path / "prog.st", "PROGRAM MAIN\nVAR y : INT; END_VAR\ny := 1;\nEND_PROGRAM\n")
    with pytest.raises(st.StSyntaxError, match=r"ＭＡＩＮ\.st:\d+: the GVL takes its name 'ＭＡＩＮ' from the file name.*not an ST identifier"):
        st.load(tmp_path)


@pytest.mark.parametrize("gvl_file, pou_file", [("main.st", "prog.st"), ("Main.st", "a_prog.st")], ids=["gvl-first", "pou-first"])
def test_a_gvl_named_like_a_pou_is_refused_naming_both(tmp_path: Path, gvl_file: str, pou_file: str) -> None:
    write(tmp_path / gvl_file, "VAR_GLOBAL\n    x : INT;\nEND_VAR\n")
    write(tmp_path / pou_file, "PROGRAM MAIN\nVAR y : INT; END_VAR\ny := 1;\nEND_PROGRAM\n")
    with pytest.raises(st.StSyntaxError) as caught:
        st.load(tmp_path)
    message = str(caught.value)
    assert f"{gvl_file}:" in message and f"GVL {gvl_file[:-3]}" in message
    assert f"Program MAIN ({tmp_path / pou_file}:1)" in message


# 3. A .plcproj reads only existing files below its own folder.

GVL_MAIN = """<?xml version="1.0" encoding="utf-8"?>
<TcPlcObject Version="1.1.0.1">
  <GVL Name="GVL_Main" Id="{5a0e3c57-0000-4000-8000-000000000009}">
    <Declaration><![CDATA[VAR_GLOBAL
    nLimit : INT := 7;
END_VAR
]]></Declaration>
  </GVL>
</TcPlcObject>
"""


def project(tmp_path: Path, include: str) -> Path:
    write(tmp_path / "proj" / "POUs" / "FB_Counter.TcPOU", pou())
    return write(tmp_path / "proj" / "Counter.plcproj", f"""<?xml version="1.0" encoding="utf-8"?>
<Project xmlns="http://schemas.microsoft.com/developer/msbuild/2003">
  <ItemGroup>
    <Compile Include="POUs\\FB_Counter.TcPOU"><SubType>Code</SubType></Compile>
    <Compile Include="{include}"><SubType>Code</SubType></Compile>
    <None Include="PlcTask.TcTTO"><SubType>Code</SubType></None>
  </ItemGroup>
</Project>
""")


def test_a_project_loads_its_files_and_skips_what_is_not_structured_text(tmp_path: Path) -> None:
    plc = st.load(project(tmp_path, "VISUs\\Visu.TcVIS"))
    assert plc.FB_Counter().Count == 0


def test_an_include_with_spaces_around_it_is_read_not_skipped(tmp_path: Path) -> None:
    """MSBuild trims an item's Include; read with its spaces, the suffix was '.TcPOU ' and the POU silently left out."""
    write(tmp_path / "proj" / "GVLs" / "GVL_Main.TcGVL", GVL_MAIN)
    plc = st.load(project(tmp_path, "  GVLs\\GVL_Main.TcGVL \n    "))
    assert plc.GVL_Main.nLimit == 7


def test_a_project_listing_a_missing_file_is_refused(tmp_path: Path) -> None:
    with pytest.raises(st.StSyntaxError, match=r"Counter\.plcproj:5: Compile Include='POUs\\\\Missing\.TcPOU'.*does not exist"):
        st.load(project(tmp_path, "POUs\\Missing.TcPOU"))


@pytest.mark.parametrize("include, rule", [
    ("..\\..\\etc\\x.TcPOU", "outside the project folder"),
    ("POUs\\..\\..\\x.TcPOU", "outside the project folder"),
    ("C:\\TwinCAT\\x.TcPOU", "absolute path"),
    ("/etc/x.TcPOU", "absolute path"),
])
def test_a_project_reads_nothing_outside_its_folder(tmp_path: Path, include: str, rule: str) -> None:
    write(tmp_path / "x.TcPOU", pou())
    with pytest.raises(st.StSyntaxError, match=rf"Counter\.plcproj:5: Compile Include=.* is (an )?{rule}"):
        st.load(project(tmp_path, include))



@pytest.mark.skipif(not hasattr(os, "symlink") or sys.platform == "win32", reason="symbolic links need privileges on Windows")
@pytest.mark.parametrize("name", ["leak.st", "POUs/leak.TcPOU"])
def test_a_folder_reads_nothing_outside_it_through_a_link(tmp_path: Path, name: str) -> None:
    secret = write(tmp_path / "secret.txt", "PASSWORD := hunter2\n")
    folder = tmp_path / "project"
    write(folder / "POUs" / "FB_Counter.TcPOU", pou())
    os.symlink(secret, folder / name)
    with pytest.raises(st.StSyntaxError, match=rf"{re.escape(name)}: a link to .*secret\.txt', outside the folder .*project'") as caught:
        st.load(folder)
    assert "hunter2" not in str(caught.value)


@pytest.mark.skipif(not hasattr(os, "symlink") or sys.platform == "win32", reason="symbolic links need privileges on Windows")
def test_a_link_that_stays_inside_the_folder_is_read(tmp_path: Path) -> None:
    folder = tmp_path / "project"
    write(folder / "versions" / "FB_Counter.v2", pou())
    os.symlink(folder / "versions" / "FB_Counter.v2", folder / "FB_Counter.TcPOU")
    assert st.load(folder).FB_Counter().Count == 0


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes are POSIX")
def test_a_pipe_named_as_a_source_is_refused_not_read_for_ever(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "main.st")
    with pytest.raises(st.StUnsupportedError, match=r"main\.st: not a regular file \(a pipe, device or socket is not read"):
        st.load(tmp_path / "main.st")

# 4. XML is parsed without DTDs, entities or network; every XML failure names the file and line.

BOMB = """<?xml version="1.0"?>
<!DOCTYPE lolz [
 <!ENTITY lol "lol">
 <!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
 <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
 <!ENTITY lol4 "&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;">
]>
"""
XXE = """<?xml version="1.0"?>
<!DOCTYPE x [<!ENTITY x SYSTEM "file:///etc/passwd">]>
"""


@pytest.mark.parametrize("prolog, entity", [(BOMB, "&lol4;"), (XXE, "&x;"), ('<?xml version="1.0"?>\n<!DOCTYPE TcPlcObject>\n', "")],
                         ids=["billion-laughs", "external-entity", "plain-doctype"])
def test_a_doctype_is_refused(tmp_path: Path, prolog: str, entity: str) -> None:
    body = pou().split("\n", 1)[1].replace("nCount := 0;", f"]]>{entity}<![CDATA[nCount := 0;")
    path = write(tmp_path / "FB_Counter.TcPOU", prolog + body)
    with pytest.raises(st.StSyntaxError, match=r"FB_Counter\.TcPOU:2: a DOCTYPE is not allowed"):
        st.load(path)


@pytest.mark.parametrize("cut", [10, 300, 900, -20])
def test_a_truncated_twincat_file_is_a_syntax_error_naming_file_and_line(tmp_path: Path, cut: int) -> None:
    text = pou()[:cut]
    path = write(tmp_path / "FB_Counter.TcPOU", text)
    with pytest.raises(st.StSyntaxError, match=r"FB_Counter\.TcPOU:\d+: not well-formed XML"):
        st.load(path)


def test_a_truncated_project_is_a_syntax_error_naming_file_and_line(tmp_path: Path) -> None:
    text = project(tmp_path, "POUs\\FB_Counter.TcPOU").read_text()
    write(tmp_path / "proj" / "Counter.plcproj", text[:150])
    with pytest.raises(st.StSyntaxError, match=r"Counter\.plcproj:4: not well-formed XML"):
        st.load(tmp_path / "proj" / "Counter.plcproj")


def test_xml_that_is_no_twincat_object_is_a_syntax_error(tmp_path: Path) -> None:
    path = write(tmp_path / "FB_Counter.TcPOU", '<?xml version="1.0"?>\n<TcPlcObject><Unknown Name="X"/></TcPlcObject>\n')
    with pytest.raises(st.StSyntaxError, match=r"FB_Counter\.TcPOU: not a TwinCAT file blark can read"):
        st.load(path)


# 5. Decimal literals with leading zeros are ordinary decimals (IEC 61131-3: digits, no octal meaning).

def test_leading_zeros_are_decimal() -> None:
    plc = st.load("""
PROGRAM MAIN
VAR
    n : INT;
    k : INT := 010;
    a : ARRAY[01..03] OF INT := [01, 02, 003];
    t : TIME := T#05s;
    w : WORD := 16#00FF;
    r : REAL := 007.50;
    d : DINT := DINT#0042;
END_VAR
n := 007 + a[02] + k;
END_PROGRAM
""")
    plc.MAIN()
    # 7 + a[2] (= 2) + 10
    assert plc.MAIN.n == 19
    assert list(plc.MAIN.a) == [1, 2, 3]
    assert (plc.MAIN.t, plc.MAIN.w, plc.MAIN.r, plc.MAIN.d) == (5000, 255, 7.5, 42)



def test_the_largest_ulint_literal_loads_in_each_base() -> None:
    plc = st.load(program("").replace("END_VAR", "u : ULINT := 18446744073709551615; h : LWORD := 16#FFFF_FFFF_FFFF_FFFF;\n"
                                      "o : ULINT := 8#1777777777777777777777;\nEND_VAR"))
    assert (plc.MAIN.u, plc.MAIN.h, plc.MAIN.o) == (2**64 - 1, 2**64 - 1, 2**64 - 1)


@pytest.mark.parametrize("literal, shown", [
    ("18446744073709551616", "18446744073709551616"),
    ("9" * 5000, r"99999999999999999999\.\.\.9999999999 \(5000 digits\)"),
    ("16#1_0000_0000_0000_0000", "1_0000_0000_0000_0000"),
    ("2#" + "1" * 20000, r"1{20}\.\.\.1{10} \(20000 digits\)"),
    ("LINT#" + "9" * 5000, r"9{20}\.\.\.9{10} \(5000 digits\)"),
])
@pytest.mark.parametrize("where", ["n := {};", "CASE n OF {}: n := 1; END_CASE", "a[{}] := 1;"])
def test_an_integer_literal_larger_than_ulint_is_refused_at_its_line(literal: str, shown: str, where: str) -> None:
    """Python itself refuses to read or print integers of more than 4300 decimal digits; ST's types end at 64 bits."""
    with pytest.raises(st.StUnsupportedError, match=rf"^<st>:8: the integer literal {shown} is larger than any integer type holds"):
        st.load(program(where.format(literal)))


def test_an_integer_literal_larger_than_ulint_is_refused_in_a_declaration() -> None:
    with pytest.raises(st.StUnsupportedError, match=r"^<st>:\d+: the integer literal .* \(5000 digits\) is larger than any"):
        st.load(program("").replace("END_VAR", "big : ARRAY[0.." + "9" * 5000 + "] OF INT;\nEND_VAR"))

# 6. Nesting limits: checked on the parse tree, named in the error, before any Python is generated.

def program(body: str) -> str:
    return f"PROGRAM MAIN\nVAR\n    n : INT;\n    i : INT;\n    b : BOOL := TRUE;\n    a : ARRAY[0..3] OF INT;\nEND_VAR\n{body}\nEND_PROGRAM\n"


# Each runs its body once: the innermost statement sets n, which ends every WHILE.
OPENERS = {"IF b THEN": "END_IF", "FOR i := 1 TO 1 DO": "END_FOR", "WHILE n < 1 DO": "END_WHILE", "CASE n OF 0:": "END_CASE",
           "__TRY": "__ENDTRY", "REPEAT": "UNTIL TRUE END_REPEAT"}


def nested(depth: int, inner: str, openers: list[str] | None = None) -> str:
    kinds = openers or list(OPENERS)
    chosen = [kinds[level % len(kinds)] for level in range(depth)]
    return "\n".join([*chosen, inner, *(OPENERS[opener] for opener in reversed(chosen))])


def test_the_deepest_nesting_allowed_loads_and_runs() -> None:
    assert (parse.MAX_STATEMENT_NESTING, parse.MAX_EXPRESSION_NESTING, parse.MAX_EXPRESSION_OPERATORS) == (20, 16, 200)
    parens = "(" * 16 + "1" + ")" * 16
    chain = " + ".join(["1"] * 184)
    plc = st.load(program(nested(20, f"n := {parens} + ABS(a[ABS(-2)]) + {chain};")))
    plc.MAIN()
    # 1 + |a[2]| (= 0) + 184 ones
    assert plc.MAIN.n == 185


@pytest.mark.parametrize("body, line, words", [
    ("n := " + "(" * 60 + "1" + ")" * 60 + ";", 8, "nested 17 deep: parentheses, call arguments and subscripts nest at most 16"),
    ("n := " + "ABS(" * 17 + "1" + ")" * 17 + ";", 8, "at most 16 deep in one expression (MAX_EXPRESSION_NESTING)"),
    (nested(22, "n := 1;", ["FOR i := 1 TO 1 DO"]), 28, "FOR nested 21 deep: statements (IF, CASE, FOR, WHILE, REPEAT, __TRY) nest at most 20"),
    (nested(101, "n := 1;", ["IF b THEN"]), 28, "IF nested 21 deep"),
    (nested(21, "n := 1;"), 28, "WHILE nested 21 deep"),
    ("n := " + " + ".join(["1"] * 3000) + ";", 8, "more than 200 operators chained or nested in one expression"),
], ids=["parentheses", "calls", "for", "if", "mixed", "chain"])
@pytest.mark.slow  # seconds each: once, in the slow gate
def test_nesting_beyond_a_limit_is_refused_naming_line_and_limit(body: str, line: int, words: str) -> None:
    with pytest.raises(st.StUnsupportedError, match=rf"^<st>:{line}: ") as caught:
        st.load(program(body))
    assert words in str(caught.value)


def test_a_limit_applies_in_a_twincat_file_at_its_own_line(tmp_path: Path) -> None:
    text = pou().replace("nCount := 0;", "nCount := " + "(" * 17 + "0" + ")" * 17 + ";")
    line = line_of(text, "nCount := ((")
    with pytest.raises(st.StUnsupportedError, match=rf"FB_Counter\.TcPOU:{line}: an expression nested 17 deep"):
        st.load(write(tmp_path / "FB_Counter.TcPOU", text))


def test_generated_python_that_cpython_refuses_is_an_st_error(monkeypatch: pytest.MonkeyPatch) -> None:
    """The last line of defence: without the limit, CPython's own one (20 nested blocks) surfaces as StUnsupportedError."""
    monkeypatch.setattr(parse, "MAX_STATEMENT_NESTING", 1000)
    with pytest.raises(st.StUnsupportedError, match=r"^st: the Python generated for it cannot run .*SyntaxError: too many statically nested blocks"):
        st.load(program(nested(22, "n := 2;", ["FOR i := 1 TO 1 DO"])))


@pytest.mark.slow  # seconds each: once, in the slow gate
def test_translation_too_deep_for_the_stack_is_an_st_error(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(parse, "MAX_EXPRESSION_OPERATORS", 10**6)
    with pytest.raises(st.StUnsupportedError, match=r"^st: the source nests too deeply to translate"):
        st.load(program("n := " + " + ".join(["2"] * 3000) + ";"))



@pytest.mark.parametrize("source, chain", [
    ("FUNCTION_BLOCK FB_A EXTENDS FB_B\nEND_FUNCTION_BLOCK\nFUNCTION_BLOCK FB_B EXTENDS FB_A\nEND_FUNCTION_BLOCK\n",
     "FUNCTION_BLOCK FB_A is built from itself: FB_A -> FB_B -> FB_A"),
    ("FUNCTION_BLOCK FB_A EXTENDS fb_a\nEND_FUNCTION_BLOCK\n", "FUNCTION_BLOCK FB_A is built from itself: FB_A -> FB_A"),
    ("INTERFACE I_A EXTENDS I_C\nEND_INTERFACE\nINTERFACE I_B EXTENDS I_A\nEND_INTERFACE\nINTERFACE I_C EXTENDS I_X, I_B\nEND_INTERFACE\n"
     "INTERFACE I_X\nEND_INTERFACE\n", "INTERFACE I_A is built from itself: I_A -> I_C -> I_B -> I_A"),
    ("TYPE ST_A EXTENDS ST_A : STRUCT a : INT; END_STRUCT END_TYPE\n", "STRUCT ST_A is built from itself: ST_A -> ST_A"),
    ("TYPE T_A : T_B; END_TYPE\nTYPE T_B : T_A; END_TYPE\n", "TYPE T_A is built from itself: T_A -> T_B -> T_A"),
    ("TYPE T_A : T_A; END_TYPE\n", "TYPE T_A is built from itself: T_A -> T_A"),
])
def test_a_type_built_from_itself_is_refused_naming_the_chain(source: str, chain: str) -> None:
    """Before, a Python NameError or "nests too deeply" without a line said it."""
    with pytest.raises(st.StUnsupportedError, match=rf"^<st>:1: {chain} \(EXTENDS and aliases may not come back"):
        st.load(source + program("").replace("n : INT;", "n : INT; p : POINTER TO T_Node;")
                + "TYPE T_Node : STRUCT pNext : POINTER TO T_Node; END_STRUCT END_TYPE\n")


def test_a_long_chain_of_extends_loads() -> None:
    blocks = "".join(f"FUNCTION_BLOCK FB_{i}{f' EXTENDS FB_{i - 1}' if i else ''}\nEND_FUNCTION_BLOCK\n" for i in range(40))
    plc = st.load(blocks)
    assert plc.FB_0 in plc.FB_39.__mro__


def _no_memory() -> bool:
    raise MemoryError


def test_a_program_the_machine_has_no_memory_for_is_an_st_error_naming_it() -> None:
    """As a 2 GiB ARRAY where the process may hold less: the load fails naming the PROGRAM, not with a bare MemoryError."""
    source = ("FUNCTION F_Alloc : BOOL\nEND_FUNCTION\n" + program("n := 1;")
              + "METHOD FB_init : BOOL\nVAR_INPUT bInitRetains : BOOL; bInCopyCode : BOOL; END_VAR\nFB_init := F_Alloc();\nEND_METHOD\n")
    with pytest.raises(st.StUnsupportedError, match=r"^<st>:3: PROGRAM MAIN cannot be made: MemoryError: the machine has no memory"):
        st.load(source, externals={"F_Alloc": _no_memory})


@pytest.mark.parametrize("declaration, body", [
    ("z : ARRAY[0..3] OF INT := [1000000000000(0)];", ""),
    ("z : ARRAY[0..3] OF INT := [1000(1000(1000(0)))];", ""),
    ("z : ARRAY[0..3] OF INT := [600000(1), 600000(2)];", ""),
    ("z : ARRAY[0..3] OF INT;", "z := [1000000000000(0)];"),
], ids=["repeated", "nested", "summed", "assigned"])
def test_an_array_initialiser_of_too_many_values_is_refused_before_they_are_made(declaration: str, body: str) -> None:
    """A repetition count is counted, not expanded: [10**12(0)] took hours and all memory building its list."""
    with pytest.raises(st.StUnsupportedError, match=rf"^<st>:\d+: an ARRAY initialiser of more than {1 << 20} values"):
        st.load(program(body).replace("END_VAR", declaration + "\nEND_VAR", 1))


def test_an_array_initialiser_with_repetitions_loads() -> None:
    plc = st.load(program("").replace("END_VAR", "r : ARRAY[0..5] OF INT := [2(1), 2(2(3))];\nEND_VAR", 1))
    assert list(plc.MAIN.r) == [1, 1, 3, 3, 3, 3]

# 7. Encodings: UTF-8 (with or without BOM), else Windows-1252; XML as its declaration says.

ST_SOURCE = "PROGRAM MAIN\nVAR\n    s : STRING := '°C';\nEND_VAR\n// 20 °C is room temperature\nEND_PROGRAM\n"


@pytest.mark.parametrize("encoding", ["cp1252", "utf-8-sig", "utf-8", "utf-16", "utf-32"])
def test_an_st_file_is_read_in_its_encoding(tmp_path: Path, encoding: str) -> None:
    plc = st.load(write(tmp_path / "main.st", ST_SOURCE.encode(encoding)))
    assert plc.MAIN.s == "°C"


def test_a_file_that_decodes_under_no_encoding_is_refused(tmp_path: Path) -> None:
    # 0x81 is undefined in Windows-1252 and not valid UTF-8
    path = write(tmp_path / "main.st", b"PROGRAM MAIN\n// \x81\nEND_PROGRAM\n")
    with pytest.raises(st.StSyntaxError, match=r"main\.st:2: cannot decode byte 0x81 as utf-8 or cp1252"):
        st.load(path)


def test_a_twincat_file_is_read_in_the_encoding_its_xml_declaration_names(tmp_path: Path) -> None:
    text = pou().replace('encoding="utf-8"', 'encoding="windows-1252"').replace("nCount : INT;\nEND_VAR", "nCount : INT;\n    s : STRING := '°C';\nEND_VAR")
    plc = st.load(write(tmp_path / "FB_Counter.TcPOU", text.encode("cp1252")))
    assert plc.FB_Counter().s == "°C"


def test_a_file_larger_than_the_limit_is_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(parse, "MAX_FILE_BYTES", 100)
    with pytest.raises(st.StUnsupportedError, match=r"main\.st: \d+ bytes is more than the 100 bytes one file may hold"):
        st.load(write(tmp_path / "main.st", ST_SOURCE + "//" + "x" * 100 + "\n"))


# 8. Mutated sources: st.load succeeds or raises a DefinitionError, never a Python internal error.

ST_SEED = """TYPE E_Mode : (IDLE, RUN := 5) INT; END_TYPE
FUNCTION_BLOCK FB_Counter
VAR_INPUT bUp : BOOL; END_VAR
VAR_OUTPUT nCount : INT; END_VAR
VAR aHist : ARRAY[1..3] OF INT; eMode : E_Mode; END_VAR
IF bUp THEN
    nCount := nCount + 1;
    aHist[1] := (nCount * 2) MOD 7;
END_IF
CASE eMode OF
    E_Mode.RUN: nCount := 0;
END_CASE
END_FUNCTION_BLOCK
METHOD Add : INT
VAR_INPUT nStep : INT := 1; END_VAR
Add := nCount + nStep;
END_METHOD
PROGRAM MAIN
VAR fb : FB_Counter; i : INT; s : STRING := 'x'; t : TIME := T#1S; END_VAR
FOR i := 1 TO 3 DO
    fb(bUp := TRUE);
END_FOR
WHILE i > 0 DO i := i - 1; END_WHILE
s := CONCAT(s, 'y');
END_PROGRAM
"""
TOKENS = ["(", ")", ";", ":=", "END_IF", "IF", "THEN", "VAR", "END_VAR", "FUNCTION_BLOCK", "'", "\"", "(*", "*)", "//",
          "[", "]", "..", "#", "T#", "16#", ".", ",", "^", "REF=", "__TRY", "0", "007", "MAIN", "\n", "<", "&", "]]>", "<![CDATA["]


@strategies.composite
def mutated(draw: Any, seed: str) -> str:
    text = seed
    for _ in range(draw(strategies.integers(1, 4))):
        kind = draw(strategies.sampled_from(["delete", "insert", "token", "duplicate", "truncate", "swap"]))
        at = draw(strategies.integers(0, len(text)))
        if kind == "delete":
            text = text[:at] + text[at + draw(strategies.integers(1, 12)):]
        elif kind == "insert":
            text = text[:at] + draw(strategies.text(max_size=4)) + text[at:]
        elif kind == "token":
            text = text[:at] + draw(strategies.sampled_from(TOKENS)) + text[at:]
        elif kind == "duplicate":
            text = text[:at] + text[at:at + draw(strategies.integers(1, 40))] + text[at:]
        elif kind == "truncate":
            text = text[:at]
        else:
            lines = text.split("\n")
            first, second = draw(strategies.integers(0, len(lines) - 1)), draw(strategies.integers(0, len(lines) - 1))
            lines[first], lines[second] = lines[second], lines[first]
            text = "\n".join(lines)
    return text


def load_only_definition_errors(text: str, suffix: str) -> None:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"FB_Counter{suffix}"
        path.write_bytes(text.encode("utf-8", "surrogatepass"))
        try:
            st.load(path)
        except DefinitionError:
            pass


MUTATION = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
SLOW_MUTATION = settings(max_examples=600, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@MUTATION
@given(mutated(ST_SEED))
def test_a_mutated_st_file_raises_only_definition_errors(text: str) -> None:
    load_only_definition_errors(text, ".st")


@MUTATION
@given(mutated(pou()))
def test_a_mutated_twincat_file_raises_only_definition_errors(text: str) -> None:
    load_only_definition_errors(text, ".TcPOU")


@pytest.mark.slow
@SLOW_MUTATION
@given(mutated(ST_SEED), mutated(pou()))
def test_many_mutated_files_raise_only_definition_errors(st_text: str, pou_text: str) -> None:
    load_only_definition_errors(st_text, ".st")
    load_only_definition_errors(pou_text, ".TcPOU")
