"""A member or class carries its ST name (``st_name=``): messages, var_info and getattr use it."""

from __future__ import annotations

from typing import Any, cast

import pytest

from iecoop import (
    ABSTRACT, BOOL, INT, PRIVATE, VAR, VAR_INPUT, VAR_OUTPUT, VAR_STAT, FunctionBlock, GlobalVariables, IecEnum, Interface,
    Struct, gvl, method, prop, var_info,
)
from iecoop import _config
from iecoop.exceptions import AccessError, DefinitionError
from iecoop.metadata import member_named, st_name
from iecoop.sections import FieldSpec

checked = pytest.mark.skipif(not _config.CHECKS, reason="checked mode refuses the write")


class IGate_(Interface, st_name="IGate"):
    @method(st_name="open")
    def open_(self) -> BOOL: ...


class Gate_(FunctionBlock, IGate_, st_name="FB_Gate"):
    """ST: ``FUNCTION_BLOCK FB_Gate IMPLEMENTS IGate`` with ``in``, ``_x`` and ``T``."""

    in_: INT = VAR_INPUT(0, st_name="in")
    st_x_: INT = VAR_OUTPUT(0, st_name="_x")
    T_: BOOL = VAR(False, st_name="T")
    count_: INT = VAR_STAT(0, st_name="count")

    @method(st_name="open")
    def open_(self) -> BOOL:
        return self.T_

    @method(PRIVATE, st_name="body")
    def body_(self) -> INT:
        return 5

    @prop
    @method(st_name="None")
    def None_(self) -> INT:
        return self.st_x_

    def body(self) -> None:
        self.st_x_ = self.in_ + 1
        self.T_ = self.st_x_ > 3


class Mode_(IecEnum, st_name="E_Mode", st_names={"None_": "None"}):
    None_ = 0
    RUN = 1


class Point_(Struct, st_name="ST_Point"):
    in_: INT = VAR(0, st_name="in")


@gvl
class Globals_(GlobalVariables, st_name="GVL_Names"):
    from_: INT = VAR(4, st_name="from")


def test_the_accessor_gives_st_names_of_classes_and_members_and_python_names_otherwise() -> None:
    assert [st_name(c) for c in (Gate_, IGate_, Mode_, Point_, type(Globals_))] == [
        "FB_Gate", "IGate", "E_Mode", "ST_Point", "GVL_Names",
    ]
    assert [st_name(Gate_, m) for m in ("in_", "st_x_", "T_", "count_", "open_", "body_", "None_")] == [
        "in", "_x", "T", "count", "open", "body", "None",
    ]
    assert st_name(Mode_, "None_") == "None" and st_name(Mode_, "RUN") == "RUN"
    assert member_named(Gate_, "IN") == "in_" and member_named(Gate_, "_X") == "st_x_"
    assert member_named(Gate_, "nothing") is None


def test_the_accessor_refuses_an_unknown_member_and_a_class_iecoop_did_not_build() -> None:
    with pytest.raises(AttributeError, match="FB_Gate declares no variable, METHOD, PROPERTY or value 'nothing'"):
        st_name(Gate_, "nothing")
    with pytest.raises(TypeError, match="not a class declared with iecoop"):
        st_name(int, "real")


@checked
def test_a_write_refused_from_outside_names_the_st_variable_and_block() -> None:
    gate = Gate_()
    with pytest.raises(AccessError) as info:
        gate.st_x_ = 1
    assert str(info.value).startswith("VAR_OUTPUT FB_Gate._x cannot be written from")
    assert "only FB_Gate's own code" in str(info.value) and "st_x_" not in str(info.value)


@checked
def test_a_value_of_the_wrong_type_is_refused_naming_the_st_variable() -> None:
    with pytest.raises(TypeError, match="FB_Gate.in: cannot store str"):
        Gate_().in_ = "x"  # type: ignore[assignment]


def test_a_guarded_method_is_refused_naming_the_st_name_in_both_modes() -> None:
    with pytest.raises(AccessError, match="PRIVATE METHOD FB_Gate.body cannot be called"):
        Gate_().body_()


def test_var_info_symbol_is_the_st_name() -> None:
    assert var_info(Gate_(), "in_").Symbol == "FB_Gate.in"
    assert var_info(Point_(), "in_").Symbol == "ST_Point.in"


def test_getattr_by_the_st_name_reaches_a_variable_and_member_named_a_method_or_property() -> None:
    gate = Gate_()
    setattr(gate, "in", 4)
    gate()
    assert getattr(gate, "in") == 4 and getattr(gate, "_x") == 5 and getattr(gate, "T") is True
    assert getattr(gate, member_named(Gate_, "open") or "")() is True
    assert getattr(gate, member_named(Gate_, "none") or "") == 5
    assert not hasattr(gate, "None")  # a METHOD or PROPERTY has no second name: none runs twice or as a hook
    point = Point_()
    setattr(point, "in", 3)
    assert point.in_ == 3 and getattr(Globals_, "from") == 4


def test_the_st_name_alias_is_the_member_itself_and_never_hides_a_name_the_class_has() -> None:
    # nothing new stands on the way to in_: the ST name is the same descriptor under a second name
    assert Gate_.__dict__["in"] is Gate_.__dict__["in_"]
    # METHOD body keeps its Python name body_: the block's own body is not replaced
    assert Gate_.__dict__["body"] is not Gate_.__dict__["body_"]


def test_no_st_name_becomes_a_hook_python_ctypes_or_the_block_would_call() -> None:
    class Hooks(FunctionBlock):
        a_: INT = VAR(1, st_name="fb_init")
        b_: INT = VAR(2, st_name="__del__")
        c_: INT = VAR(3, st_name="_pack_")

    assert not {"fb_init", "__del__", "_pack_"} & set(vars(Hooks))
    assert Hooks().a_ == 1 and st_name(Hooks, "b_") == "__del__"


@checked
def test_a_write_by_the_st_name_keeps_the_variables_rules() -> None:
    gate = Gate_()
    with pytest.raises(AccessError, match="VAR_OUTPUT FB_Gate._x cannot be written"):
        setattr(gate, "_x", 1)
    with pytest.raises(TypeError, match="FB_Gate.in: cannot store str"):
        setattr(gate, "in", "x")
    with pytest.raises(TypeError, match="ST_Point.in: cannot store str"):
        setattr(Point_(), "in", "x")


def test_an_override_keeps_the_st_name_of_the_member_it_overrides() -> None:
    class Door(Gate_):
        def open_(self) -> BOOL:
            return False

    assert st_name(Door, "open_") == "open" and st_name(Door) == "Door"


def _declare(field: Any = None, **keywords: Any) -> None:
    class Valve(FunctionBlock, **keywords):  # noqa: F841 - declared for its definition-time check
        position: INT = VAR(0) if field is None else field


@pytest.mark.parametrize("bad", ["1x", "a-b", "", "in put", "ä", 5])
def test_a_variables_st_name_that_is_no_st_identifier_is_refused_at_definition(bad: Any) -> None:
    with pytest.raises(DefinitionError, match=r"FUNCTION_BLOCK Valve\.position: st_name=.* is not an ST identifier"):
        _declare(VAR(0, st_name=bad))


def test_a_class_methods_or_enum_values_bad_st_name_is_refused_at_definition() -> None:
    with pytest.raises(DefinitionError, match="FUNCTION_BLOCK Valve: st_name='FB Valve' is not an ST identifier"):
        _declare(st_name="FB Valve")
    with pytest.raises(DefinitionError, match=r"METHOD .*Pump\.start: st_name='2start' is not an ST identifier"):
        class Pump(FunctionBlock):
            @method(st_name="2start")
            def start(self) -> None: ...
    with pytest.raises(DefinitionError, match=r"enumeration E\.A: st_name='A B' is not an ST identifier"):
        class E(IecEnum, st_names={"A": "A B"}):
            A = 0
    with pytest.raises(DefinitionError, match="st_names= names 'B', which is no value of E"):
        class E2(IecEnum, st_names={"B": "B"}):  # noqa: F841
            A = 0
    with pytest.raises(DefinitionError, match="STRUCT S: st_name='S!' is not an ST identifier"):
        class S(Struct, st_name="S!"):  # noqa: F841
            a: INT = 0
    with pytest.raises(DefinitionError, match="INTERFACE I: st_name='' is not an ST identifier"):
        class I(Interface, st_name=""):  # noqa: E742, F841
            pass


def test_without_st_name_everything_keeps_the_python_name() -> None:
    class Valve(FunctionBlock):
        position: INT = VAR_OUTPUT(0)

    assert st_name(Valve) == "Valve" and st_name(Valve, "position") == "position"
    assert var_info(Valve(), "position").Symbol == "Valve.position"
    assert cast(FieldSpec, VAR_OUTPUT(0, st_name="p")).as_python() == "VAR_OUTPUT(0, st_name='p')"


def test_a_definition_error_about_a_method_names_its_st_name() -> None:
    with pytest.raises(DefinitionError, match="FUNCTION_BLOCK FB_Valve: METHOD body: ABSTRACT cannot be combined with PRIVATE"):
        class Valve(FunctionBlock, abstract=True, st_name="FB_Valve"):  # noqa: F841
            @method(PRIVATE | ABSTRACT, st_name="body")
            def body_(self) -> None: ...
