"""The VAR-section rule table: the specifiers, the class builder, the write checks and the docs follow it."""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import sys
from pathlib import Path
from typing import Any

import pytest

from iecoop import INT, AccessError, DefinitionError, FunctionBlock, GlobalVariables, Struct, gvl, method
from iecoop import _config, declarations
from iecoop.memory.layout import FieldSpec
from iecoop.sections import SECTION_RULES, SECTIONS, AtCall, Kind, Qualifier, Section, Storage, Writer, sections_of

ROOT = Path(__file__).resolve().parent.parent.parent
checked = pytest.mark.skipif(not _config.CHECKS, reason="the write rules are checked-mode rules")


def test_one_row_per_section_in_st_order() -> None:
    assert tuple(SECTION_RULES) == SECTIONS == tuple(Section)
    assert all(rule.section is section for section, rule in SECTION_RULES.items())
    assert SECTIONS[:4] == ("VAR_INPUT", "VAR_OUTPUT", "VAR_IN_OUT", "VAR")


def test_the_table_is_frozen() -> None:
    with pytest.raises(TypeError):
        SECTION_RULES[Section.VAR] = SECTION_RULES[Section.VAR_INPUT]  # type: ignore[index]
    with pytest.raises(dataclasses.FrozenInstanceError):
        SECTION_RULES[Section.VAR].written_by = Writer.ANYONE  # type: ignore[misc]


def test_a_section_is_its_st_keyword() -> None:
    assert Section.VAR_IN_OUT == "VAR_IN_OUT" and f"{Section.VAR_STAT}" == "VAR_STAT"
    assert FieldSpec("VAR_TEMP").section is Section.VAR_TEMP
    with pytest.raises(ValueError, match="VAR_CONFIG"):
        FieldSpec("VAR_CONFIG")


@pytest.mark.parametrize("section", [s for s in Section if hasattr(declarations, s.value)])
def test_each_specifier_takes_exactly_the_qualifiers_of_its_row(section: Section) -> None:
    params = inspect.signature(getattr(declarations, section.value)).parameters
    taken = {name for name in params if name in {q.keyword for q in Qualifier}}
    assert taken == {q.keyword for q in SECTION_RULES[section].qualifiers}
    assert (getattr(declarations, section.value)(**({"method": "m"} if section is Section.VAR_INST else {}))).section is section


def test_remanent_sections_are_those_that_take_retain() -> None:
    remanent = {s for s, rule in SECTION_RULES.items() if rule.remanent}
    assert remanent == {Section.VAR_INPUT, Section.VAR_OUTPUT, Section.VAR, Section.VAR_GLOBAL}


def test_the_builders_allow_the_sections_of_their_kind() -> None:
    assert sections_of(Kind.STRUCT) == sections_of(Kind.UNION) == (Section.VAR,)
    assert sections_of(Kind.GVL) == (Section.VAR, Section.VAR_GLOBAL)
    assert sections_of(Kind.FUNCTION_BLOCK) == sections_of(Kind.PROGRAM) == tuple(
        s for s in Section if s is not Section.VAR_GLOBAL
    )
    assert sections_of(Kind.INTERFACE) == ()
    with pytest.raises(DefinitionError, match=r"Point.x: VAR_INPUT is not allowed in a STRUCT \(allowed: VAR\)"):

        class Point(Struct):
            x: INT = declarations.VAR_INPUT(0)

    with pytest.raises(DefinitionError, match=r"VAR_TEMP is not allowed in a GVL \(allowed: VAR, VAR_GLOBAL\)"):

        class GVL_Sections(GlobalVariables):
            x: INT = declarations.VAR_TEMP(0)


def test_sections_outside_the_instance_are_not_in_its_memory() -> None:
    @gvl
    class GVL_SectionRows(GlobalVariables):
        row_global: INT = 0

    class Rows(FunctionBlock):
        inside: INT = declarations.VAR(1)
        shared: INT = declarations.VAR_STAT(2)
        row_global: INT = declarations.VAR_EXTERNAL()

    fields = {name for name, _ in Rows._fields_}  # type: ignore[attr-defined]
    for name, section in (("inside", Section.VAR), ("shared", Section.VAR_STAT), ("row_global", Section.VAR_EXTERNAL)):
        assert (name in fields) is SECTION_RULES[section].in_instance
    assert SECTION_RULES[Section.VAR_STAT].storage is Storage.CLASS
    assert GVL_SectionRows.row_global == 0


def test_the_call_takes_the_call_parameters_of_the_table() -> None:
    class Params(FunctionBlock):
        a: INT = declarations.VAR_INPUT(0)
        b: INT = declarations.VAR_IN_OUT()
        c: INT = declarations.VAR_OUTPUT(0)
        d: INT = declarations.VAR_TEMP(0)

    keywords = list(inspect.signature(Params.__call__).parameters)[1:]
    layout: Any = Params._iec_layout_
    assert keywords == [r.name for r in layout.fields if SECTION_RULES[r.section].call_parameter] == ["a", "b"]
    assert SECTION_RULES[Section.VAR_IN_OUT].at_call is AtCall.BOUND
    with pytest.raises(TypeError, match="VAR_IN_OUT 'b' must be assigned at every call"):
        block: Any = Params()
        block(a=1)


@checked
@pytest.mark.parametrize(
    "section", [Section.VAR_INPUT, Section.VAR_OUTPUT, Section.VAR, Section.VAR_STAT, Section.VAR_TEMP, Section.VAR_INST]
)
def test_checked_mode_writes_follow_the_written_by_column(section: Section) -> None:
    options = {"method": "step"} if section is Section.VAR_INST else {}
    namespace: dict[str, Any] = {
        "__annotations__": {"x": INT},
        "x": getattr(declarations, section.value)(0, **options),
        "step": method(lambda self: None),
    }
    meta: Any = type(FunctionBlock)
    block = meta(f"Rule{section.value}", (FunctionBlock,), namespace)()
    if SECTION_RULES[section].inside_only:
        with pytest.raises(AccessError, match=f"{section}|C0576"):
            block.x = 5
        assert block.x == 0
    else:
        block.x = 5
        assert block.x == 5


def test_the_docs_table_is_generated_from_the_rule_table() -> None:
    pytest.importorskip("sphinx")
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    try:
        pages = importlib.import_module("iecoop_pages")
    finally:
        sys.path.remove(str(ROOT / "docs" / "_ext"))
    lines: list[str] = pages.section_table()
    rows = [line[len("   * - ``"):-2] for line in lines if line.startswith("   * - ``")]
    assert rows == [s.value for s in Section]
    inst = lines.index("   * - ``VAR_INST``")
    assert lines[inst + 1:inst + 7] == [
        "     - ``VAR_INST(initial, method=...)``",
        "     - in the instance",
        "     - its METHOD only",
        "     - keeps its value",
        "     - none",
        "     - FUNCTION_BLOCK, PROGRAM",
    ]
    page = (ROOT / "docs" / "concepts" / "var-sections.md").read_text(encoding="utf-8")
    assert "```{eval-rst}\n.. iecoop-section-table::\n```" in page
