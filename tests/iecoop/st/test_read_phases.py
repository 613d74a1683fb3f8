"""The read wing's passes hand each other data: pass 1 collects a symbol table that is frozen before pass 2 reads it."""

from __future__ import annotations

import pytest

pytest.importorskip("blark")

from iecoop import st  # noqa: E402
from iecoop.st.read.parse import parse_sources  # noqa: E402
from iecoop.st.read.table import FrozenTableError, Member  # noqa: E402
from iecoop.st.read.translate import Translator  # noqa: E402

SOURCE = """
FUNCTION_BLOCK FB_Counter
VAR
    count : INT;
END_VAR
count := count + 1;
END_FUNCTION_BLOCK

METHOD Step : INT
VAR_INST
    calls : DINT := 5;
END_VAR
calls := calls + 1;
Step := count;
END_METHOD

PROGRAM P_Count
VAR
    counter : INT;
END_VAR
counter := counter + 1;
END_PROGRAM

PROGRAM MAIN
VAR
    seen : INT;
END_VAR
seen := P_Count.counter;
END_PROGRAM
"""


def _after_pass_1() -> Translator:
    translator = Translator(parse_sources(SOURCE))
    translator.collect()
    translator.resolve_members()
    translator.collect_named_programs()
    translator.freeze()
    return translator


def test_pass_1_collects_a_methods_var_inst_and_the_programs_read_by_name() -> None:
    table = _after_pass_1()
    calls = table.decls["fb_counter"].members["calls"]
    assert (calls.name, calls.section, calls.type.name if calls.type else None) == ("calls", "VAR_INST", "DINT")
    assert set(table.named_programs) == {"P_Count"}


def test_the_table_is_read_only_after_pass_1() -> None:
    table = _after_pass_1()
    decl = table.decls["fb_counter"]
    with pytest.raises(FrozenTableError, match="read-only after pass 1"):
        table._add_member(decl, Member("extra", None, "VAR_INST"))  # what pass 2 once did with a VAR_INST
    with pytest.raises(FrozenTableError, match="FB_Counter.name"):
        decl.name = "Other"
    with pytest.raises(FrozenTableError):
        decl.bases.append("FB_Base")
    with pytest.raises(FrozenTableError):
        table.decls["other"] = decl
    with pytest.raises(FrozenTableError):
        table.globals.setdefault("x", ("GVL", Member("x", None, "VAR")))
    with pytest.raises(FrozenTableError):
        table.named_programs.add("MAIN")
    with pytest.raises(AttributeError):  # the records in the table are frozen dataclasses
        decl.members["count"].section = "VAR_OUTPUT"  # type: ignore[misc]


def test_the_var_inst_is_written_after_the_blocks_fields_and_the_named_program_with_its_decorator() -> None:
    text = st.to_python(SOURCE)
    lines = text.splitlines()
    count = lines.index("    count: INT = VAR()")
    assert lines[count + 1] == '    calls: DINT = VAR_INST(5, method="Step")'
    assert lines[lines.index("class P_Count(Program):") - 1] == "@_program_instance"
    assert "@_program_instance" not in lines[lines.index("class MAIN(Program):") - 1]


def test_a_named_program_whose_python_name_differs_gets_its_decorator() -> None:
    # The decorator is written with the class, not looked for later in the text (which has st_name= here).
    text = st.to_python("PROGRAM lambda\nVAR x : INT; END_VAR\nx := x + 1;\nEND_PROGRAM\n"
                        "PROGRAM MAIN\nVAR y : INT; END_VAR\ny := lambda.x;\nEND_PROGRAM\n")
    lines = text.splitlines()
    assert lines[lines.index('class lambda_(Program, st_name="lambda"):') - 1] == "@_program_instance"
    assert "y = lambda_.x" in text


def test_decisions_are_made_on_the_expression_record_not_its_printed_code() -> None:
    from iecoop.st import StUnsupportedError

    with pytest.raises(StUnsupportedError, match="writes its control variable lambda$"):  # the ST name
        st.to_python("PROGRAM P\nVAR lambda : INT; END_VAR\nFOR lambda := 1 TO 3 DO lambda := 2; END_FOR\nEND_PROGRAM\n")
    with pytest.raises(StUnsupportedError, match="E_Mode.RUN is no variable; ADR / REF= need a variable"):
        st.to_python("TYPE E_Mode : (IDLE, RUN); END_TYPE\n"
                     "PROGRAM P\nVAR p : POINTER TO E_Mode; END_VAR\np := ADR(E_Mode.RUN);\nEND_PROGRAM\n")
