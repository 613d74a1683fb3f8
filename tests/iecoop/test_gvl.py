"""Global variable lists: @gvl, VAR_EXTERNAL, CONSTANT globals, global FB instances."""

from __future__ import annotations

import pytest

from iecoop import (
    ARRAY, BOOL, INT, VAR, VAR_EXTERNAL, AccessError, DefinitionError, FunctionBlock, GlobalVariables, Program, gvl,
)
from iecoop.gvl import global_lists
from tests import checked_only


@gvl
class GVL_Line(GlobalVariables):
    """VAR_GLOBAL: the line's shared signals."""

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
    GVL_Line.parts = 0
    GVL_Line.running = True
    counter = Counter()
    for _ in range(3):
        counter()
    assert GVL_Line.parts == 3 and counter.parts == 3
    GVL_Line.parts = 99
    counter()
    counter()
    assert GVL_Line.parts == 100  # stops at the CONSTANT limit
    assert list(GVL_Line.speeds) == [10, 20, 30]
    assert global_lists()["GVL_Line"] is GVL_Line


@checked_only
def test_a_constant_global_cannot_be_written() -> None:
    with pytest.raises(AccessError, match=r"GVL_Line\.MAX_PARTS is CONSTANT and cannot be written"):
        GVL_Line.MAX_PARTS = 5
    assert GVL_Line.MAX_PARTS == 100


@checked_only
def test_a_global_of_the_wrong_kind_names_the_variable() -> None:
    with pytest.raises(TypeError, match=r"GVL_Line\.parts: cannot store str 'x' in INT"):
        GVL_Line.parts = "x"  # type: ignore[assignment]


def test_a_global_name_is_declared_once() -> None:
    with pytest.raises(DefinitionError, match=r"GVL GVL_Other: global 'parts' is already declared in GVL GVL_Line"):

        @gvl
        class GVL_Other(GlobalVariables):
            parts: INT = 0


def test_var_external_needs_a_global_of_that_name() -> None:
    with pytest.raises(DefinitionError, match=r"Orphan\.nowhere: VAR_EXTERNAL 'nowhere' has no global variable of that name"):

        class Orphan(FunctionBlock):
            nowhere: INT = VAR_EXTERNAL()


def test_gvl_needs_a_global_variables_class() -> None:
    with pytest.raises(DefinitionError, match="@gvl needs a GlobalVariables subclass with variables"):
        gvl(GlobalVariables)
