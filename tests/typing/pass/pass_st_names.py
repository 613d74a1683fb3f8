"""ST names Python cannot spell, declared with ``st_name=``: mypy sees the same types as without it.

ST::

    INTERFACE IQueryInterface
    METHOD open : BOOL
    END_METHOD
    END_INTERFACE

    FUNCTION_BLOCK in IMPLEMENTS IQueryInterface
    VAR_INPUT T : INT; END_VAR
    VAR_OUTPUT _x : INT; END_VAR
    METHOD body : INT
"""

from __future__ import annotations

from typing import assert_type

from iecoop import (
    BOOL, INT, STRING, VAR, VAR_IN_OUT, VAR_INPUT, VAR_OUTPUT, VAR_STAT, VAR_TEMP, FunctionBlock, IecEnum, Interface,
    Struct, method, prop, PRIVATE,
)
from iecoop.metadata import st_name


class IQueryInterface_(Interface, st_name="IQueryInterface"):
    @method(st_name="open")
    def open_(self) -> BOOL: ...


class E_Opt(IecEnum, base=INT, st_names={"None_": "None"}):
    None_ = 0
    Some = 1


class ST_Point(Struct, st_name="ST_Point"):
    in_: INT = VAR(0, st_name="in")


class in_(FunctionBlock, IQueryInterface_, st_name="in"):
    T_: INT = VAR_INPUT(0, st_name="T")
    st_x_: INT = VAR_OUTPUT(0, st_name="_x")
    name_: STRING = VAR("", length=20, st_name="name")
    count_: INT = VAR_STAT(0, st_name="count")
    scratch_: INT = VAR_TEMP(0, st_name="scratch")
    buffer_: INT = VAR_IN_OUT(st_name="buffer")

    @method(st_name="open")
    def open_(self) -> BOOL:
        return self.st_x_ > 0

    @method(PRIVATE, st_name="body")
    def body_(self) -> INT:
        return self.T_

    @prop
    @method(st_name="None")
    def None_(self) -> INT:
        return self.st_x_

    def body(self) -> None:
        self.st_x_ = self.T_ + 1


def use(block: in_) -> None:
    assert_type(block.T_, int)
    assert_type(block.st_x_, int)
    assert_type(block.name_, str)
    assert_type(block.open_(), bool)
    assert_type(block.None_, int)
    assert_type(st_name(in_, "T_"), str)
    assert_type(int(E_Opt.None_), int)


def main() -> None:
    block = in_()
    use(block)
    assert st_name(in_) == "in" and st_name(in_, "st_x_") == "_x" and st_name(E_Opt, "None_") == "None"
    assert getattr(block, "T") == 0 and block.open_() is False
