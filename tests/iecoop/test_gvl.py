"""Global variable lists: @gvl, VAR_EXTERNAL, CONSTANT globals, global FB instances."""

from __future__ import annotations

import pytest

from iecoop import (
    ARRAY, BOOL, INT, VAR, VAR_EXTERNAL, AccessError, DefinitionError, FunctionBlock, GlobalVariables, Program, gvl,
)
from iecoop.gvl import global_lists
from tests import checked_only


@gvl
class GVL_CountingLine(GlobalVariables):
    """VAR_GLOBAL: the line's shared signals (a name no project of the test data gives a list: the registry is by name)."""

    parts: INT = 0
    running: BOOL = False
    MAX_PARTS: INT = VAR(100, constant=True)
    speeds: ARRAY[INT] = VAR([10, 20, 30], bounds=(1, 3))


class Counter(Program):
    parts: INT = VAR_EXTERNAL()
    running: BOOL = VAR_EXTERNAL()
    MAX_PARTS: INT = VAR_EXTERNAL(constant=True)

    def body(self) -> None:
        if self.running and self.parts < self.MAX_PARTS:
            self.parts += 1


def test_var_external_reads_and_writes_the_global_of_that_name() -> None:
    GVL_CountingLine.parts = 0
    GVL_CountingLine.running = True
    counter = Counter()
    for _ in range(3):
        counter()
    assert GVL_CountingLine.parts == 3 and counter.parts == 3
    GVL_CountingLine.parts = 99
    counter()
    counter()
    assert GVL_CountingLine.parts == 100  # stops at the CONSTANT limit
    assert list(GVL_CountingLine.speeds) == [10, 20, 30]
    assert global_lists()["GVL_CountingLine"] is GVL_CountingLine


@checked_only
def test_a_constant_global_cannot_be_written() -> None:
    with pytest.raises(AccessError, match=r"GVL_CountingLine\.MAX_PARTS is CONSTANT and cannot be written"):
        GVL_CountingLine.MAX_PARTS = 5
    assert GVL_CountingLine.MAX_PARTS == 100


@checked_only
def test_a_global_of_the_wrong_kind_names_the_variable() -> None:
    with pytest.raises(TypeError, match=r"GVL_CountingLine\.parts: cannot store str 'x' in INT"):
        GVL_CountingLine.parts = "x"  # type: ignore[assignment]


def test_two_lists_may_declare_one_name_each_read_through_its_list() -> None:
    @gvl
    class GVL_Other(GlobalVariables):
        parts: INT = 7

    GVL_CountingLine.parts = 3
    assert (GVL_CountingLine.parts, GVL_Other.parts) == (3, 7)
    with pytest.raises(DefinitionError, match=r"Shared\.parts: VAR_EXTERNAL 'parts' is declared by several global lists "
                                              r"\(GVL_CountingLine, GVL_Other\): read it through its list"):

        class Shared(FunctionBlock):
            parts: INT = VAR_EXTERNAL()


def test_var_external_needs_a_global_of_that_name() -> None:
    with pytest.raises(DefinitionError, match=r"Orphan\.nowhere: VAR_EXTERNAL 'nowhere' has no global variable of that name"):

        class Orphan(FunctionBlock):
            nowhere: INT = VAR_EXTERNAL()


def test_gvl_needs_a_global_variables_class() -> None:
    with pytest.raises(DefinitionError, match="@gvl needs a GlobalVariables subclass with variables"):
        gvl(GlobalVariables)
