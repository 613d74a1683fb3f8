"""Loading ST: every legal ST name works, none reaches a Python special or generated name, duplicates are refused."""

from __future__ import annotations

import gc
import keyword

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as hs

from iecoop.exceptions import DefinitionError

st = pytest.importorskip("iecoop.st")
from iecoop.st.read.names import python_name, reserved_names, st_name_of  # noqa: E402
from iecoop.st.language import is_reserved  # noqa: E402

# --- the rule -----------------------------------------------------------------------------------


@pytest.mark.parametrize(("name", "expected"), [
    ("Speed", "Speed"), ("in", "in_"), ("in_", "in__"), ("IN", "IN"), ("T", "T_"), ("t", "t"), ("TON", "TON_"),
    ("adr", "adr_"), ("self", "self_"), ("body", "body_"), ("range", "range_"), ("match", "match_"),
    ("None", "None_"), ("_x", "st_x_"), ("__del__", "st__del___"), ("_fields_", "st_fields__"),
    ("st_x_", "stst_x__"), ("fb_init", "fb_init_"), ("TO_", "TO"), ("Then_", "Then"), ("INT_", "INT__"),
    ("TO__", "TO___"),
])
def test_python_name_table(name: str, expected: str) -> None:
    assert python_name(name) == expected


@pytest.mark.parametrize(("name", "expected"), [
    ("open", "open"), ("LIMIT", "LIMIT"), ("match", "match"), ("in", "in_"), ("T", "T_"), ("body", "body_"),
    ("method", "method_"), ("VAR", "VAR_"), ("_x", "st_x_"), ("__del__", "st__del___"), ("x_", "x__"),
])
def test_attribute_names_keep_builtins(name: str, expected: str) -> None:
    # a variable, METHOD or enumeration value is read as x.name: only its class body can meet a name
    assert python_name(name, attribute=True) == expected


def test_no_reserved_name_ends_with_the_suffix() -> None:
    # the rule's images of mapped names end with "_": none of them can be a reserved name
    assert not [n for n in reserved_names() if n.endswith("_")]
    assert reserved_names(attribute=True) < reserved_names()


IDENTIFIER = hs.from_regex(r"\A_{0,2}[A-Za-z][A-Za-z0-9]{0,3}(_[A-Za-z0-9]{1,2})?_{0,2}\Z").filter(
    lambda n: not is_reserved(n))  # an ST keyword is no ST name
SPECIAL = hs.sampled_from(["in", "in_", "_x", "__x__", "__del__", "self", "body", "T", "TON", "adr", "None", "class",
                           "match", "range", "copy", "cls", "fb_init", "_fields_", "st_x_", "_x_", "lambda", "def"])
NAMES = hs.one_of(SPECIAL, IDENTIFIER)


@given(hs.lists(NAMES, min_size=2, max_size=8, unique_by=str.lower), hs.booleans())
def test_python_name_is_injective_and_never_private(names: list[str], attribute: bool) -> None:
    mapped = [python_name(n, attribute) for n in names]
    assert len(set(mapped)) == len(mapped)
    for name in mapped:
        assert name.isidentifier() and not name.startswith("_")
        assert not keyword.iskeyword(name)
        assert name not in reserved_names(attribute)


@given(NAMES, hs.booleans())
def test_the_st_name_comes_back_from_the_python_name(name: str, attribute: bool) -> None:
    assert st_name_of(python_name(name, attribute)) == name


# --- the reproduced problems --------------------------------------------------------------------

DEL_SOURCE = """
VAR_GLOBAL nFreed : INT; END_VAR
FUNCTION_BLOCK FB_A
VAR_INPUT x : INT; END_VAR
END_FUNCTION_BLOCK
METHOD __del__ : BOOL
nFreed := 99;
END_METHOD
METHOD __setattr__ : BOOL
nFreed := 98;
END_METHOD
METHOD __eq__ : BOOL
VAR_INPUT other : INT; END_VAR
__eq__ := TRUE;
END_METHOD
"""


def test_method_del_never_runs_as_a_finaliser() -> None:
    plc = st.load(DEL_SOURCE)
    block = plc.FB_A()
    block.x = 5  # no __setattr__ of the ST runs
    assert block.x == 5 and plc.GVL.nFreed == 0
    assert block != 1  # Python's __eq__ is not the METHOD
    assert block.st__eq___(other=1) is True
    del block
    gc.collect()
    assert plc.GVL.nFreed == 0
    assert "def __" not in plc.__python__


NAMES_SOURCE = """
FUNCTION range : INT
VAR_INPUT T : INT; in : INT; in_ : INT; END_VAR
VAR self : INT; copy : INT; _x : INT; END_VAR
self := T + in + in_; copy := 1; _x := 2;
range := self + copy + _x;
END_FUNCTION
TYPE E_Kw : (None, is, pass, yield, match, A) INT; END_TYPE
TYPE ST_S : STRUCT _fields_ : INT; lambda : INT := 3; END_STRUCT END_TYPE
FUNCTION_BLOCK body
VAR_INPUT lambda : INT; from : INT; END_VAR
VAR_OUTPUT def : INT; as : E_Kw := E_Kw.pass; END_VAR
VAR i : INT; s : ST_S; t5 : TIME := T#5S; END_VAR
FOR i := 1 TO 2 DO def := def + range(T := lambda, in := 1, in_ := 2); END_FOR
as := E_Kw.yield;
END_FUNCTION_BLOCK
METHOD body : INT
VAR_INPUT copy : INT; range : INT; END_VAR
body := copy + range + s.lambda;
END_METHOD
PROGRAM MAIN
VAR fb : body; n : INT; END_VAR
fb(lambda := 10, from := 1);
n := fb.body(copy := 1, range := 2);
END_PROGRAM
"""


def test_python_keywords_builtins_and_generated_names_as_st_names() -> None:
    plc = st.load(NAMES_SOURCE)
    plc.MAIN.body()
    assert plc.MAIN.fb.def_ == 2 * (10 + 1 + 2 + 1 + 2)  # range: T + in + in_, then + copy + _x
    assert plc.MAIN.n == 1 + 2 + 3
    assert plc.MAIN.fb.as_ == plc.E_Kw.yield_
    assert plc.range_(T_=1, in_=1, in__=1) == 6
    assert plc.MAIN.fb.t5 == 5000  # T#5S beside an input named T


def test_the_fb_body_is_not_replaced_by_a_method_named_body() -> None:
    plc = st.load(NAMES_SOURCE)
    block = plc.body_()
    block(lambda_=0)
    assert block.def_ == 2 * (0 + 1 + 2 + 1 + 2)


def test_a_type_named_like_an_iecoop_name_stands_beside_it() -> None:
    # the source's own IQueryInterface is IQueryInterface_: __SYSTEM.IQueryInterface is still iecoop's
    plc = st.load("INTERFACE IQueryInterface\nEND_INTERFACE\nPROGRAM MAIN\nVAR itf : __SYSTEM.IQueryInterface; "
                  "own : IQueryInterface; END_VAR\nEND_PROGRAM\n")
    assert plc.IQueryInterface_ is not plc.__dict__.get("IQueryInterface")
    assert "own: IQueryInterface_" in plc.__python__ and "itf: IQueryInterface " in plc.__python__


# --- duplicates ---------------------------------------------------------------------------------

DUPLICATES = {
    "one VAR block": ("FUNCTION_BLOCK FB_D\nVAR a : INT;\na : INT; END_VAR\nEND_FUNCTION_BLOCK", "VAR FB_D.a", 2, 3),
    "input and VAR": ("FUNCTION_BLOCK FB_D\nVAR_INPUT nSpeed : INT; END_VAR\nVAR\nNSPEED : INT; END_VAR\nEND_FUNCTION_BLOCK",
                      "FB_D.NSPEED", 2, 4),
    "methods": ("FUNCTION_BLOCK FB_D\nEND_FUNCTION_BLOCK\nMETHOD Start : BOOL\nEND_METHOD\nMETHOD START : BOOL\nEND_METHOD",
                "METHOD FB_D.START", 3, 5),
    "struct members": ("TYPE ST_D :\nSTRUCT\nx : INT;\nX : INT;\nEND_STRUCT\nEND_TYPE", "ST_D.X", 3, 4),
    "POUs": ("FUNCTION_BLOCK FB_D\nEND_FUNCTION_BLOCK\nPROGRAM fb_d\nEND_PROGRAM", "PROGRAM fb_d", 1, 3),
    "types": ("TYPE E_D : (A, B); END_TYPE\nTYPE e_d :\nSTRUCT\nx : INT;\nEND_STRUCT\nEND_TYPE", "STRUCT e_d", 1, 2),
    "enum values": ("TYPE E_D : (A,\na); END_TYPE", "enumeration value E_D.a", 1, 2),
    "method and variable": ("FUNCTION_BLOCK FB_D\nVAR Run : INT; END_VAR\nEND_FUNCTION_BLOCK\nMETHOD run : BOOL\nEND_METHOD",
                            "METHOD FB_D.run", 2, 4),
    "GVL and block": ("VAR_GLOBAL g : INT; END_VAR\nFUNCTION_BLOCK gvl\nEND_FUNCTION_BLOCK", "FUNCTION_BLOCK gvl", 1, 2),
    "method locals": ("FUNCTION_BLOCK FB_D\nEND_FUNCTION_BLOCK\nMETHOD M : BOOL\nVAR_INPUT i : INT; END_VAR\nVAR\nI : INT;"
                      " END_VAR\nEND_METHOD", "VAR I of METHOD FB_D.M", 4, 6),
}


@pytest.mark.parametrize("case", list(DUPLICATES), ids=list(DUPLICATES))
def test_duplicate_declarations_are_refused_naming_both(case: str) -> None:
    source, second, first_line, second_line = DUPLICATES[case]
    with pytest.raises(DefinitionError) as info:
        st.load(source)
    message = str(info.value)
    assert second in message and "declared twice" in message and "case-insensitive" in message
    assert f"<st>:{first_line}" in message and f"<st>:{second_line}" in message


# --- random names, loaded and run ---------------------------------------------------------------

ST_KEYWORDS = frozenset(
    "ABS ACTION AND ANY ARRAY AT BOOL BY BYTE CASE CLASS CONSTANT DATE DINT DO DT DWORD ELSE ELSIF END EXIT EXTENDS "
    "FALSE FOR FROM FUNCTION GET IF IMPLEMENTS INT INTERFACE INTERNAL LINT LREAL LWORD METHOD MOD NOT OF OR "
    "OVERLAP PRIVATE PROGRAM PROPERTY PROTECTED PUBLIC REAL REF REFERENCE REPEAT RETAIN RETURN SET SINT STRING "
    "STRUCT SUPER THEN THIS TIME TO TOD TRUE TYPE UDINT UINT ULINT UNION UNTIL USINT VAR WHILE WORD WSTRING XOR "
    "POINTER ABSTRACT FINAL CONTINUE JMP NULL PERSISTENT UNION LTIME LDATE LTOD LDT CHAR WCHAR NON_RETAIN "
    "R_EDGE F_EDGE READ_ONLY READ_WRITE TASK WITH CONFIGURATION RESOURCE VAR_GLOBAL AND_THEN OR_ELSE ADR SIZEOF "
    "NEW DELETE D TOD_ LT T".split()
)
LEGAL = NAMES.filter(lambda n: n.upper() not in ST_KEYWORDS and not n.upper().startswith(("END_", "VAR_", "T_", "D_"))
                     and "__" not in n.strip("_"))


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(hs.lists(LEGAL, min_size=7, max_size=7), hs.integers(0, 100))
def test_random_st_names_load_and_run(names: list[str], start: int) -> None:
    pou, var, meth, inp, value, local, other = names
    source = f"""
TYPE E_{value} : (A{value}, {value}) INT; END_TYPE
FUNCTION_BLOCK {pou}
VAR_INPUT {inp} : INT; END_VAR
VAR {var} : INT := {start}; {other} : E_{value} := E_{value}.{value}; END_VAR
{var} := {var} + {inp};
END_FUNCTION_BLOCK
METHOD {meth} : INT
VAR_INPUT {inp} : INT; END_VAR
VAR {local} : INT; END_VAR
{local} := {inp} * 2;
{meth} := {local} + {var};
END_METHOD
"""
    assume(meth.lower() not in (inp.lower(), local.lower()))  # the METHOD's result variable has its name
    assume(local.lower() != var.lower())  # a METHOD's local hides the block's variable of its name
    assume(meth.lower() not in ("fb_init", "fb_reinit", "fb_exit"))  # lifecycle METHODs have inputs of their own
    lowered = [n.lower() for n in (pou, f"e_{value}")]
    members = [n.lower() for n in (inp, var, other, meth)]
    duplicate = len(set(lowered)) < 2 or len(set(members)) < 4 or inp.lower() == local.lower()
    try:
        plc = st.load(source)
    except DefinitionError as error:
        assert duplicate and "declared twice" in str(error), str(error)
        return
    cls = getattr(plc, python_name(pou))
    block = cls()
    block(**{python_name(inp, attribute=True): 3})  # the block's input: a field
    assert getattr(block, python_name(var, attribute=True)) == start + 3
    assert getattr(block, python_name(other, attribute=True)) == 1
    assert getattr(block, python_name(meth, attribute=True))(**{python_name(inp): 4}) == 8 + start + 3
