"""The OOP rules of IEC 61131-3: broken at class definition (DefinitionError), or at run time (AccessError).

Definition-time rules are the analog of compile errors: the class statement
itself raises, naming the block, the member and the rule. Access rules are
checked when a member is used; method and property rules hold in fast mode too.
"""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
import textwrap
import uuid
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    DINT,
    FINAL,
    INT,
    INTERNAL,
    LREAL,
    PRIVATE,
    PROTECTED,
    REAL,
    STRING,
    VAR,
    VAR_INPUT,
    VAR_INST,
    VAR_OUTPUT,
    AccessError,
    DefinitionError,
    ExceptionCode,
    FunctionBlock,
    Interface,
    IQueryInterface,
    PlcException,
    Struct,
    adr,
    method,
    new,
    prop,
    query_interface,
    query_pointer,
)
from tests import checked_only

ROOT = Path(__file__).resolve().parents[2]


class Machine(FunctionBlock):
    """A base block with one member of each kind the rules below refer to."""

    speed: INT = VAR(0)

    @method
    def start(self, gear: INT = 2, velocity: LREAL = 8.0) -> BOOL:
        return True

    @method(FINAL)
    def stop(self) -> None:
        pass

    @method(PRIVATE)
    def calibrate(self) -> INT:
        return 1

    @method(PROTECTED)
    def ramp(self) -> INT:
        return 2

    @prop
    def rpm(self) -> INT:
        return self.speed


class Sealed(FunctionBlock, final=True):
    pass


class Conveyor(FunctionBlock):
    pass


# ---------------------------------------------------------------------------
# EXTENDS and FINAL
# ---------------------------------------------------------------------------


def test_a_second_function_block_base_is_rejected() -> None:
    with pytest.raises(DefinitionError, match=r"FUNCTION_BLOCK Line: EXTENDS allows one function block, got Machine, Conveyor"):

        class Line(Machine, Conveyor):
            pass


def test_a_final_block_cannot_be_extended() -> None:
    with pytest.raises(DefinitionError, match=r"FUNCTION_BLOCK Opened cannot EXTEND Sealed: Sealed is FINAL"):

        class Opened(Sealed):
            pass


def test_a_block_cannot_be_abstract_and_final() -> None:
    with pytest.raises(DefinitionError, match="cannot be both ABSTRACT and FINAL"):

        class Both(FunctionBlock, abstract=True, final=True):
            pass


def test_a_final_method_cannot_be_overridden() -> None:
    with pytest.raises(DefinitionError, match=r"FUNCTION_BLOCK Press: FINAL PUBLIC METHOD Machine\.stop cannot be overridden"):

        class Press(Machine):
            @method
            def stop(self) -> None:
                pass


def test_a_final_property_cannot_be_overridden() -> None:
    class Base(FunctionBlock):
        @prop
        @method(FINAL)
        def level(self) -> INT:
            return 1

    with pytest.raises(DefinitionError, match=r"FINAL PUBLIC PROPERTY Base\.level cannot be overridden"):

        class Derived(Base):
            @prop
            def level(self) -> INT:
                return 2


def test_a_base_that_is_neither_block_nor_interface_is_rejected() -> None:
    class Mixin:
        pass

    with pytest.raises(DefinitionError, match=r"Mixin is neither a function block nor an interface"):

        class Mixed(FunctionBlock, Mixin):
            pass


# ---------------------------------------------------------------------------
# Overriding: same signature (C0094), no narrowing, no PRIVATE
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("gear_type", "velocity_name", "result_type", "here"),
    [
        ("DINT", "velocity", "BOOL", r"\(gear: DINT, velocity: LREAL\) -> BOOL"),
        ("INT", "speed", "BOOL", r"\(gear: INT, speed: LREAL\) -> BOOL"),
        ("INT", "velocity", "INT", r"\(gear: INT, velocity: LREAL\) -> INT"),
    ],
)
def test_overriding_with_another_signature_is_c0094(gear_type: str, velocity_name: str, result_type: str, here: str) -> None:
    source = textwrap.dedent(
        f"""
        class Press(Machine):
            @method
            def start(self, gear: {gear_type} = 2, {velocity_name}: LREAL = 8.0) -> {result_type}:
                return True
        """
    )
    pattern = (
        r"FUNCTION_BLOCK Press: interface of overridden method 'start' of base 'Machine' doesn't match "
        r"declaration \(C0094\): base \(gear: INT, velocity: LREAL\) -> BOOL, here " + here
    )
    with pytest.raises(DefinitionError, match=pattern):
        exec(source, dict(globals()))  # noqa: S102 - each case is one class statement


def test_overriding_with_an_extra_input_is_c0094() -> None:
    with pytest.raises(DefinitionError, match=r"C0094"):

        class Press(Machine):
            @method
            def start(self, gear: INT = 2, velocity: LREAL = 8.0, force: REAL = 1.0) -> BOOL:
                return True


def test_overriding_with_the_same_signature_is_accepted_and_dispatches() -> None:
    class Press(Machine):
        @method
        def start(self, gear: INT = 2, velocity: LREAL = 8.0) -> BOOL:
            return False

    machine: Machine = Press()
    assert machine.start() is False


def test_a_private_method_cannot_be_overridden() -> None:
    with pytest.raises(DefinitionError, match=r"PRIVATE METHOD Machine\.calibrate is PRIVATE and cannot be overridden"):

        class Press(Machine):
            @method(PRIVATE)
            def calibrate(self) -> INT:
                return 5


@pytest.mark.parametrize(
    ("name", "flags", "pattern"),
    [
        ("start", PROTECTED, r"start narrows the access of PUBLIC METHOD Machine\.start to PROTECTED"),
        ("start", PRIVATE, r"start narrows the access of PUBLIC METHOD Machine\.start to PRIVATE"),
        ("ramp", PRIVATE, r"ramp narrows the access of PROTECTED METHOD Machine\.ramp to PRIVATE"),
    ],
)
def test_an_override_cannot_narrow_access(name: str, flags: object, pattern: str) -> None:
    signature = "(self, gear: INT = 2, velocity: LREAL = 8.0) -> BOOL" if name == "start" else "(self) -> INT"
    source = f"class Press(Machine):\n    @method(FLAGS)\n    def {name}{signature}:\n        return 0\n"
    with pytest.raises(DefinitionError, match=pattern):
        exec(source, {**globals(), "FLAGS": flags})  # noqa: S102 - each case is one class statement


def test_an_override_may_widen_protected_to_public() -> None:
    class Press(Machine):
        @method
        def ramp(self) -> INT:
            return 3

    assert Press().ramp() == 3


def test_a_method_cannot_be_overridden_by_a_property() -> None:
    with pytest.raises(DefinitionError, match=r"start overrides a METHOD with a PROPERTY"):

        class Press(Machine):
            @prop
            def start(self) -> BOOL:  # type: ignore[override]
                return True


def test_an_override_cannot_drop_the_set_accessor() -> None:
    class Base(FunctionBlock):
        level_internal: INT = VAR(0)

        @prop
        def level(self) -> INT:
            return self.level_internal

        @level.setter
        def level(self, value: INT) -> None:
            self.level_internal = value

    with pytest.raises(DefinitionError, match=r"PROPERTY level drops the Set accessor its base declares"):

        class Derived(Base):
            @prop  # type: ignore[misc]
            def level(self) -> INT:
                return 0


def test_a_derived_block_cannot_redeclare_a_base_variable() -> None:
    with pytest.raises(DefinitionError, match=r"Press\.speed: speed is already declared in Machine"):

        class Press(Machine):
            speed: INT = VAR(0)


def test_a_variable_and_a_member_of_the_extends_chain_cannot_share_a_name() -> None:
    with pytest.raises(DefinitionError, match=r"variable start reuses the name of PUBLIC METHOD Machine\.start"):

        class Press(Machine):
            start: BOOL = VAR(False)  # type: ignore[assignment]

    with pytest.raises(DefinitionError, match=r"METHOD speed reuses the name of the variable Machine\.speed"):

        class Drill(Machine):
            @method
            def speed(self) -> INT:  # type: ignore[override]
                return 0


def test_a_name_cannot_be_both_variable_and_method_in_one_block() -> None:
    with pytest.raises(DefinitionError, match=r"level is declared both as a variable and as a METHOD / PROPERTY"):

        class Tank(FunctionBlock):
            level: INT = VAR(0)

            @method  # type: ignore[no-redef]
            def level(self) -> INT:
                return 0


# ---------------------------------------------------------------------------
# ABSTRACT
# ---------------------------------------------------------------------------


# A prototype's body is '...' (iecoop rejects any other body); mypy --strict reports such a body
# under a non-None result type as empty-body, hence the ignores on prototypes in this file.
class AbstractAxis(FunctionBlock, abstract=True):
    @method(ABSTRACT)
    def home(self) -> BOOL: ...

    @prop
    @method(ABSTRACT)
    def position(self) -> LREAL: ...

    @method
    def jog(self) -> INT:
        return 1


def test_an_abstract_member_needs_an_abstract_block() -> None:
    with pytest.raises(
        DefinitionError, match=r"FUNCTION_BLOCK Axis: METHOD home is ABSTRACT, so Axis must be declared abstract"
    ):

        class Axis(FunctionBlock):
            @method(ABSTRACT)
            def home(self) -> BOOL: ...

    with pytest.raises(DefinitionError, match=r"PROPERTY position is ABSTRACT, so Axis must be declared abstract"):

        class Axis(FunctionBlock):  # type: ignore[no-redef]
            @prop
            @method(ABSTRACT)
            def position(self) -> LREAL: ...


def test_a_concrete_block_must_implement_every_inherited_abstract_member() -> None:
    with pytest.raises(
        DefinitionError,
        match=r"FUNCTION_BLOCK LinearAxis must be ABSTRACT or implement PUBLIC PROPERTY AbstractAxis\.position",
    ):

        class LinearAxis(AbstractAxis):
            @method
            def home(self) -> BOOL:
                return True


def test_an_abstract_block_may_leave_members_to_a_later_derived_block() -> None:
    class HalfAxis(AbstractAxis, abstract=True):
        @method
        def home(self) -> BOOL:
            return True

    class FullAxis(HalfAxis):
        @prop
        def position(self) -> LREAL:
            return 12.5

    axis = FullAxis()
    assert (axis.home(), axis.position, axis.jog()) == (True, 12.5, 1)


@pytest.mark.parametrize(
    ("flags", "rule"),
    [(ABSTRACT | PRIVATE, "ABSTRACT cannot be combined with PRIVATE"), (ABSTRACT | FINAL, "ABSTRACT cannot be combined with FINAL")],
)
def test_abstract_cannot_be_private_or_final(flags: object, rule: str) -> None:
    source = "class Axis(FunctionBlock, abstract=True):\n    @method(FLAGS)\n    def home(self) -> BOOL: ...\n"
    with pytest.raises(DefinitionError, match=rf"FUNCTION_BLOCK Axis: METHOD home: {rule}"):
        exec(source, {**globals(), "FLAGS": flags})  # noqa: S102 - each case is one class statement


def test_an_abstract_block_cannot_be_instantiated_nor_placed_inline() -> None:
    with pytest.raises(DefinitionError, match=r"ABSTRACT FUNCTION_BLOCK AbstractAxis cannot be instantiated"):
        AbstractAxis()
    with pytest.raises(TypeError, match=r"__NEW: ABSTRACT AbstractAxis cannot be instantiated"):
        new(AbstractAxis)
    with pytest.raises(DefinitionError, match=r"Gantry\.axis: ABSTRACT AbstractAxis cannot be instantiated; use REFERENCE_TO"):

        class Gantry(FunctionBlock):
            axis: AbstractAxis = VAR()


def test_more_than_one_access_specifier_is_rejected() -> None:
    with pytest.raises(DefinitionError, match="choose one of PUBLIC, PRIVATE, PROTECTED, INTERNAL"):

        class Axis(FunctionBlock):
            @method(PRIVATE | PROTECTED)
            def home(self) -> BOOL:
                return True


# ---------------------------------------------------------------------------
# Interfaces
# ---------------------------------------------------------------------------


class ISensor(IQueryInterface):
    @method
    def read(self, channel: INT) -> REAL: ...

    @prop
    def healthy(self) -> BOOL: ...


class IDiagnosable(IQueryInterface):
    @method
    def error_code(self) -> DINT: ...


class IPlain(Interface):
    @method
    def ping(self) -> BOOL: ...


def test_a_missing_interface_method_is_c0087() -> None:
    with pytest.raises(
        DefinitionError,
        match=r"FUNCTION_BLOCK Probe: there is no implementation for method 'read' defined in interface 'ISensor' \(C0087\)",
    ):

        class Probe(FunctionBlock, ISensor):
            @prop
            def healthy(self) -> BOOL:
                return True


def test_a_missing_interface_property_is_c0087() -> None:
    with pytest.raises(DefinitionError, match=r"no implementation for property 'healthy' defined in interface 'ISensor' \(C0087\)"):

        class Probe(FunctionBlock, ISensor):
            @method
            def read(self, channel: INT) -> REAL:
                return 0.0


def test_an_interface_member_with_another_signature_is_rejected() -> None:
    with pytest.raises(
        DefinitionError,
        match=r"read does not match interface ISensor: interface \(channel: INT\) -> REAL, here \(channel: DINT\) -> REAL",
    ):

        class Probe(FunctionBlock, ISensor):
            @method
            def read(self, channel: DINT) -> REAL:
                return 0.0

            @prop
            def healthy(self) -> BOOL:
                return True


def test_an_interface_member_must_be_public() -> None:
    with pytest.raises(DefinitionError, match=r"read implements interface ISensor and must be PUBLIC"):

        class Probe(FunctionBlock, ISensor):
            @method(PROTECTED)
            def read(self, channel: INT) -> REAL:
                return 0.0

            @prop
            def healthy(self) -> BOOL:
                return True


def test_an_interface_met_through_the_base_block_is_satisfied() -> None:
    class ProbeBase(FunctionBlock):
        @method
        def read(self, channel: INT) -> REAL:
            return channel * 0.5

        @prop
        def healthy(self) -> BOOL:
            return True

    class Probe(ProbeBase, ISensor):
        pass

    probe: ISensor = Probe()
    assert probe.read(3) == 1.5


def test_an_interface_extending_interfaces_requires_all_their_members() -> None:
    class ISmartSensor(ISensor, IDiagnosable):
        pass

    with pytest.raises(DefinitionError, match=r"method 'error_code' defined in interface 'ISmartSensor' \(C0087\)"):

        class Probe(FunctionBlock, ISmartSensor):
            @method
            def read(self, channel: INT) -> REAL:
                return 0.0

            @prop
            def healthy(self) -> BOOL:
                return True


def test_an_interface_holds_no_state() -> None:
    with pytest.raises(DefinitionError, match=r"INTERFACE IStateful: interfaces hold no state, but 'level' is declared as a variable"):

        class IStateful(Interface):
            level: INT

    with pytest.raises(DefinitionError, match=r"INTERFACE IStateful: interfaces hold no state, but 'LIMIT' is a class variable"):

        class IStateful(Interface):  # type: ignore[no-redef]
            LIMIT = 5


def test_an_interface_method_has_no_body() -> None:
    with pytest.raises(DefinitionError, match=r"INTERFACE IBody: ping has a body; an interface declares prototypes only"):

        class IBody(Interface):
            @method
            def ping(self) -> BOOL:
                return True


def test_an_interface_prototype_may_raise_not_implemented() -> None:
    # `raise NotImplementedError` is the prototype body that type-checks for a non-None return
    class IValue(Interface):
        @method
        def value(self) -> INT:
            """The current value."""
            raise NotImplementedError

        @prop
        def level(self) -> INT:
            raise NotImplementedError()

    class Value(FunctionBlock, IValue):
        @method
        def value(self) -> INT:
            return 7

        @prop
        def level(self) -> INT:
            return 3

    assert Value().value() == 7 and Value().level == 3
    with pytest.raises(DefinitionError, match=r"INTERFACE IMore: value has a body.*raise NotImplementedError"):

        class IMore(Interface):
            @method
            def value(self) -> INT:
                print("side effect")
                raise NotImplementedError


def test_an_interface_property_has_no_body() -> None:
    with pytest.raises(DefinitionError, match=r"INTERFACE IBody: level has a body"):

        class IBody(Interface):
            @prop
            def level(self) -> INT:
                return 3


@pytest.mark.parametrize("kind", ["plain class", "struct", "function block"])
def test_an_interface_extends_only_interfaces(kind: str) -> None:
    class Mixin:
        pass

    class Recipe(Struct):
        steps: INT = 0

    base = {"plain class": Mixin, "struct": Recipe, "function block": Conveyor}[kind]
    with pytest.raises(DefinitionError, match=r"INTERFACE IBad: an interface can only EXTEND interfaces, not .*" + base.__name__):
        type("IBad", (Interface, base), {})


# ---------------------------------------------------------------------------
# Field types, initial values, STRING lengths and ARRAY bounds
# ---------------------------------------------------------------------------


def test_an_unknown_field_type_is_rejected() -> None:
    with pytest.raises(DefinitionError, match=r"Tank\.level: cannot resolve the annotation 'Undeclared'"):

        class Tank(FunctionBlock):
            level: Undeclared = VAR(0)  # type: ignore[name-defined]  # noqa: F821


def test_a_plain_python_type_is_not_an_iec_type() -> None:
    with pytest.raises(DefinitionError, match=r"Tank\.level: plain int is not an IEC type; use INT"):

        class Tank(FunctionBlock):
            level: int = VAR(0)

    with pytest.raises(DefinitionError, match=r"Tank\.names: list is not an IEC type"):

        class Tank(FunctionBlock):  # type: ignore[no-redef]
            names: list = VAR(0)  # type: ignore[type-arg, arg-type]


@pytest.mark.parametrize(
    ("annotation", "initial", "message"),
    [
        ("INT", "'five'", "cannot store str 'five' in INT"),
        ("BOOL", "1", r"cannot store int 1 in BOOL"),
        ("INT", "2.5", r"cannot store float 2\.5 in INT"),
        ("REAL", "'1.0'", r"cannot store str '1\.0' in REAL"),
        ("STRING", "5", "STRING"),
    ],
)
def test_an_initial_value_of_the_wrong_type_is_rejected(annotation: str, initial: str, message: str) -> None:
    source = f"class Tank(FunctionBlock):\n    level: {annotation} = VAR_INPUT({initial})\n"
    with pytest.raises(DefinitionError, match=rf"Tank\.level: initial value of the wrong type: .*{message}"):
        exec(source, dict(globals()))  # noqa: S102 - each case is one class statement


@pytest.mark.parametrize("length", [0, -5, 65536, 2.5])
def test_a_string_length_outside_1_to_65535_is_rejected(length: Any) -> None:
    with pytest.raises(DefinitionError, match=rf"Tank\.name: STRING length must be an integer 1\.\.65535, got {length}"):
        type("Tank", (FunctionBlock,), {"__annotations__": {"name": STRING}, "name": VAR("", length=length)})


@pytest.mark.parametrize(
    ("bounds", "message"),
    [
        ((5, 1), r"ARRAY\[5\.\.1\] is empty: the upper bound is below the lower one"),
        ((1, 2, 3), r"ARRAY bounds come in \(lo, hi\) pairs"),
        ((1.0, 2), r"ARRAY bounds must be \(lo, hi\) integer pairs"),
        (None, r"ARRAY needs bounds"),
    ],
)
def test_array_bounds_that_make_no_sense_are_rejected(bounds: object, message: str) -> None:
    with pytest.raises(DefinitionError, match=rf"Tank\.levels: {message}"):
        type("Tank", (FunctionBlock,), {"__annotations__": {"levels": ARRAY[INT]}, "levels": VAR(bounds=bounds)})


def test_length_and_bounds_only_where_they_apply() -> None:
    with pytest.raises(DefinitionError, match=r"Tank\.level: bounds= applies to ARRAY, not INT"):

        class Tank(FunctionBlock):
            level: INT = VAR(0, bounds=(1, 2))

    with pytest.raises(DefinitionError, match=r"Tank\.level: length= applies to STRING / WSTRING, not INT"):

        class Tank(FunctionBlock):  # type: ignore[no-redef]
            level: INT = VAR(0, length=3)


# ---------------------------------------------------------------------------
# FB_init / FB_exit signatures, VAR_INST
# ---------------------------------------------------------------------------


def test_fb_init_without_the_two_system_inputs_is_c0119() -> None:
    with pytest.raises(
        DefinitionError, match=r"FUNCTION_BLOCK Drive: fb_init must start with the inputs \(init_retains, in_copy_code\) \(C0119\)"
    ):

        class Drive(FunctionBlock):
            def fb_init(self, in_copy_code: BOOL, axis: INT = 0) -> BOOL:
                return True


def test_a_derived_fb_init_must_repeat_the_base_inputs_in_order() -> None:
    class Drive(FunctionBlock):
        def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, axis: INT = 0) -> BOOL:
            return True

    with pytest.raises(
        DefinitionError,
        match=r"FUNCTION_BLOCK Servo: fb_init must declare the base's FB_init inputs \['init_retains', 'in_copy_code', 'axis'\] first",
    ):

        class Servo(Drive):
            def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, gain: REAL = 1.0) -> BOOL:
                return True

    class GoodServo(Drive):
        def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, axis: INT = 0, gain: REAL = 1.0) -> BOOL:
            return True

    assert GoodServo(axis=2, gain=0.5) is not None


def test_fb_exit_and_fb_reinit_signatures() -> None:
    with pytest.raises(DefinitionError, match=r"fb_exit takes exactly one input, in_copy_code"):

        class Drive(FunctionBlock):
            def fb_exit(self) -> BOOL:
                return True

    with pytest.raises(DefinitionError, match=r"fb_reinit takes no inputs"):

        class Drive(FunctionBlock):  # type: ignore[no-redef]
            def fb_reinit(self, hard: BOOL) -> BOOL:
                return True


def test_var_inst_needs_a_method_the_block_declares() -> None:
    with pytest.raises(DefinitionError, match=r"Drive\.count: VAR_INST needs the method it belongs to"):

        class Drive(FunctionBlock):
            count: INT = VAR_INST(0, method="")

    with pytest.raises(DefinitionError, match=r"Drive\.count: VAR_INST belongs to METHOD 'tick', which Drive does not declare"):

        class Drive(FunctionBlock):  # type: ignore[no-redef]
            count: INT = VAR_INST(0, method="tick")


# ---------------------------------------------------------------------------
# Run-time access rules (checked mode, the default)
# ---------------------------------------------------------------------------


class Motor(FunctionBlock):
    speed: INT = VAR(0)
    running: BOOL = VAR_OUTPUT(False)
    setpoint: INT = VAR_INPUT(0)

    @method(PRIVATE)
    def limit(self) -> INT:
        return 100

    @method(PROTECTED)
    def ramp(self) -> INT:
        return 10

    @method(INTERNAL)
    def service(self) -> INT:
        return 7

    @method
    def start(self) -> INT:
        self.running = True
        return self.limit() + self.ramp() + self.service()

    @prop
    def rpm(self) -> INT:
        return self.speed

    @rpm.setter
    @method(PRIVATE)
    def rpm(self, value: INT) -> None:
        self.speed = value

    @method
    def apply_setpoint(self) -> None:
        self.rpm = self.setpoint

    @prop
    @method(PROTECTED)
    def torque(self) -> INT:
        return 42


class ServoMotor(Motor):
    @method
    def use_limit(self) -> INT:
        return self.limit()

    @method
    def use_ramp(self) -> INT:
        return self.ramp() * 2

    @method
    def use_torque(self) -> INT:
        return self.torque

    @method
    def set_rpm(self, value: INT) -> None:
        self.rpm = value


def test_private_and_protected_methods_from_outside_raise_access_error() -> None:
    motor = Motor()
    with pytest.raises(AccessError, match=r"PRIVATE METHOD Motor\.limit cannot be called from .*callable only inside Motor"):
        motor.limit()
    with pytest.raises(
        AccessError, match=r"PROTECTED METHOD Motor\.ramp cannot be called from .*only inside Motor and its derived blocks"
    ):
        motor.ramp()
    assert motor.running is False


def test_non_public_members_are_callable_from_the_blocks_own_code() -> None:
    motor = Motor()
    assert motor.start() == 117
    assert motor.running is True


def test_a_subclass_cannot_call_a_private_base_method_but_can_call_a_protected_one() -> None:
    servo = ServoMotor()
    with pytest.raises(AccessError, match=r"PRIVATE METHOD Motor\.limit cannot be called from ServoMotor\.use_limit"):
        servo.use_limit()
    assert servo.use_ramp() == 20
    assert servo.use_torque() == 42
    assert servo.start() == 117


def test_protected_property_from_outside_raises() -> None:
    with pytest.raises(AccessError, match=r"PROTECTED PROPERTY Motor\.torque \(Get\) cannot be called from"):
        _ = Motor().torque


def test_property_with_public_get_and_private_set() -> None:
    motor, servo = Motor(), ServoMotor()
    assert motor.rpm == 0
    with pytest.raises(AccessError, match=r"PRIVATE PROPERTY Motor\.rpm \(Set\) cannot be called from test_property_with"):
        motor.rpm = 5
    assert motor.rpm == 0
    for setpoint in (300, 450, 0):
        motor(setpoint=setpoint)
        motor.apply_setpoint()
        assert motor.rpm == setpoint
    with pytest.raises(AccessError, match=r"PRIVATE PROPERTY Motor\.rpm \(Set\) cannot be called from ServoMotor\.set_rpm"):
        servo.set_rpm(5)


def test_internal_method_from_the_same_package_is_allowed() -> None:
    assert Motor().service() == 7


@checked_only
def test_writing_an_output_or_a_local_from_outside_raises_access_error() -> None:
    motor = Motor()
    with pytest.raises(AccessError, match=r"VAR_OUTPUT Motor\.running cannot be written from .*only Motor's own code"):
        motor.running = True
    with pytest.raises(AccessError, match=r"VAR Motor\.speed cannot be written from"):
        motor.speed = 3
    motor.setpoint = 12
    assert (motor.running, motor.speed, motor.setpoint) == (False, 0, 12)


@checked_only
def test_another_blocks_code_cannot_write_a_members_output() -> None:
    class Line(FunctionBlock):
        motor: Motor = VAR()

        def body(self) -> None:
            self.motor.running = True

    with pytest.raises(AccessError, match=r"VAR_OUTPUT Motor\.running cannot be written from Line\.body"):
        Line()()


def _make_counter_class() -> Any:
    class Counter(FunctionBlock):
        count: INT = VAR_OUTPUT(0)

        def body(self) -> None:
            self.count += self.step()

        @method(PRIVATE)
        def step(self) -> INT:
            return 1

    return Counter


@checked_only
def test_a_class_statement_run_twice_gives_two_blocks_that_each_own_their_code() -> None:
    # Both classes share the code objects of the factory's class body.
    first, second = _make_counter_class(), _make_counter_class()
    assert first is not second
    for cls in (second, first, second):
        block: Any = cls()
        block()
        block()
        assert block.count == 2
    with pytest.raises(AccessError, match=r"PRIVATE METHOD Counter\.step cannot be called from"):
        second().step()
    with pytest.raises(AccessError, match=r"VAR_OUTPUT Counter\.count cannot be written from"):
        second().count = 1


@checked_only
def test_writing_an_undeclared_variable_is_rejected() -> None:
    with pytest.raises(AttributeError, match=r"Motor has no variable 'sped'"):
        Motor().sped = 3  # type: ignore[attr-defined]


def test_an_interface_cannot_be_instantiated() -> None:
    with pytest.raises(TypeError, match=r"INTERFACE ISensor cannot be instantiated; implement it in a FunctionBlock"):
        ISensor()


# ---------------------------------------------------------------------------
# INTERNAL across packages
# ---------------------------------------------------------------------------

_PLANTLIB = '''
from iecoop import INT, INTERNAL, FunctionBlock, VAR, method, new


class Valve(FunctionBlock):
    opened: INT = VAR(0)

    @method(INTERNAL)
    def calibrate(self) -> INT:
        return 7

    @method
    def service(self) -> INT:
        return self.calibrate() * 2


class Module(FunctionBlock, internal=True):
    pass


def make_module() -> Module:
    return Module()


def new_module():
    return new(Module)


def calibrate(valve: Valve) -> INT:
    return valve.calibrate()
'''


@pytest.fixture
def plantlib(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[ModuleType]:
    """A second top-level package, so INTERNAL's namespace differs from the tests' one."""
    name = f"plantlib_{uuid.uuid4().hex[:8]}"
    package = tmp_path / name
    package.mkdir()
    (package / "__init__.py").write_text(_PLANTLIB)
    monkeypatch.syspath_prepend(str(tmp_path))
    module = importlib.import_module(name)
    yield module
    sys.modules.pop(name, None)


def test_internal_method_from_another_package_raises(plantlib: ModuleType) -> None:
    valve = plantlib.Valve()
    with pytest.raises(AccessError, match=r"INTERNAL METHOD Valve\.calibrate cannot be called from .*only inside the package 'plantlib_"):
        valve.calibrate()
    assert valve.service() == 14
    assert plantlib.calibrate(valve) == 7


def test_internal_block_from_another_package_cannot_be_instantiated(plantlib: ModuleType) -> None:
    with pytest.raises(AccessError, match=r"INTERNAL FUNCTION_BLOCK Module cannot be instantiated from .*outside the package"):
        plantlib.Module()
    with pytest.raises(AccessError, match=r"INTERNAL Module cannot be created from"):
        new(plantlib.Module)
    assert isinstance(plantlib.make_module(), plantlib.Module)
    assert plantlib.new_module()


def test_internal_block_from_another_package_cannot_be_extended(plantlib: ModuleType) -> None:
    with pytest.raises(DefinitionError, match=r"FUNCTION_BLOCK MyModule cannot EXTEND INTERNAL Module outside the package"):
        type("MyModule", (plantlib.Module,), {})


# ---------------------------------------------------------------------------
# Interface references, __QUERYINTERFACE, __QUERYPOINTER
# ---------------------------------------------------------------------------


class Thermometer(FunctionBlock, ISensor, IDiagnosable):
    offset: REAL = VAR_INPUT(0.0)

    @method
    def read(self, channel: INT) -> REAL:
        return channel * 10.0 + self.offset

    @prop
    def healthy(self) -> BOOL:
        return True

    @method
    def error_code(self) -> DINT:
        return 0


class Hygrometer(FunctionBlock, ISensor, IPlain):
    @method
    def read(self, channel: INT) -> REAL:
        return 55.0

    @prop
    def healthy(self) -> BOOL:
        return False

    @method
    def ping(self) -> BOOL:
        return True


class Display(FunctionBlock):
    sensor: ISensor = VAR_INPUT()
    shown: REAL = VAR_OUTPUT(0.0)

    def body(self) -> None:
        self.shown = self.sensor.read(2)


def test_a_null_interface_reference_is_an_access_violation_when_called() -> None:
    display = Display()
    reference: object = display.sensor
    assert not reference
    assert reference == 0
    with pytest.raises(PlcException, match=r"Display\.sensor: ISensor\.read called through a null interface reference") as info:
        display()
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    with pytest.raises(PlcException) as prop_info:
        _ = display.sensor.healthy
    assert prop_info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_an_interface_reference_dispatches_to_the_assigned_block_across_calls() -> None:
    display = Display()
    thermo, hygro = Thermometer(), Hygrometer()
    display(sensor=thermo)
    assert display.shown == 20.0
    thermo(offset=1.5)
    display()
    assert display.shown == 21.5
    display(sensor=hygro)
    assert display.shown == 55.0
    assert display.sensor == hygro
    with pytest.raises(PlcException, match="null interface reference"):
        display(sensor=None)
    assert not display.sensor
    assert display.shown == 55.0


def test_an_interface_variable_rejects_a_block_that_does_not_implement_it() -> None:
    with pytest.raises(TypeError, match=r"Display\.sensor: Motor does not implement ISensor"):
        Display()(sensor=Motor())  # type: ignore[arg-type]


def test_query_interface_success_failure_and_null() -> None:
    thermo = Thermometer()
    display = Display()
    display(sensor=thermo)
    diag = query_interface(display.sensor, IDiagnosable)
    assert diag is not None and diag == thermo
    assert diag.error_code() == 0
    assert query_interface(Hygrometer(), IDiagnosable) is None
    assert query_interface(Display().sensor, IDiagnosable) is None
    sensor = query_interface(diag, ISensor)
    assert sensor is not None and sensor.read(1) == 10.0


def test_query_interface_needs_iqueryinterface_c0239() -> None:
    with pytest.raises(DefinitionError, match=r"Interface IPlain does not extend __System\.IQueryInterface \(C0239\)"):
        query_interface(Hygrometer(), IPlain)
    with pytest.raises(TypeError, match="is not an INTERFACE"):
        query_interface(Hygrometer(), Motor)


def test_query_pointer_gives_the_instance_behind_an_interface() -> None:
    thermo = Thermometer()
    display = Display()
    display(sensor=thermo)
    pointer = query_pointer(display.sensor)
    assert pointer == adr(thermo)
    assert pointer.deref == thermo
    thermo(offset=3.0)
    assert pointer.deref.offset == 3.0
    null = query_pointer(Display().sensor)
    assert not null and null == 0


def test_query_pointer_on_a_block_without_iqueryinterface_is_c0239() -> None:
    with pytest.raises(DefinitionError, match=r"__QUERYPOINTER: Motor does not implement __System\.IQueryInterface \(C0239\)"):
        query_pointer(Motor())


# ---------------------------------------------------------------------------
# Fast mode (IECOOP_CHECKS=0 is read at import, so it runs in its own interpreter)
# ---------------------------------------------------------------------------

_FAST_MODE_SCRIPT = '''
from iecoop import _config, BOOL, INT, FunctionBlock, VAR, VAR_OUTPUT, PRIVATE, PROTECTED, AccessError, method, prop

assert _config.CHECKS is False


class Motor(FunctionBlock):
    speed: INT = VAR(0)
    running: BOOL = VAR_OUTPUT(False)

    @method(PRIVATE)
    def limit(self) -> INT:
        return 100

    @method(PROTECTED)
    def ramp(self) -> INT:
        return 10

    @method
    def start(self) -> INT:
        return self.limit() + self.ramp()

    @prop
    def rpm(self) -> INT:
        return self.speed

    @rpm.setter
    @method(PRIVATE)
    def rpm(self, value: INT) -> None:
        self.speed = value

    @method
    def set_rpm(self, value: INT) -> None:
        self.rpm = value


class Servo(Motor):
    @method
    def use_limit(self) -> INT:
        return self.limit()


motor = Motor()
for call in (motor.limit, motor.ramp, Servo().use_limit):
    try:
        call()
    except AccessError as exc:
        print("denied:", exc)
    else:
        raise SystemExit(f"{call.__name__} was allowed in fast mode")
try:
    motor.rpm = 5
except AccessError as exc:
    print("denied:", exc)
else:
    raise SystemExit("private setter was allowed in fast mode")
assert motor.start() == 110
motor.set_rpm(9)
assert motor.rpm == 9
motor.running = True
motor.speed = 4
print("outside writes:", motor.running, motor.speed)
'''


def test_fast_mode_keeps_method_access_rules_and_drops_outside_write_checks() -> None:
    env = {**os.environ, "IECOOP_CHECKS": "0"}
    result = subprocess.run(
        [sys.executable, "-c", _FAST_MODE_SCRIPT], env=env, cwd=ROOT, capture_output=True, text=True, timeout=60, check=False
    )
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert [line.split(" cannot")[0] for line in lines[:4]] == [
        "denied: PRIVATE METHOD Motor.limit",
        "denied: PROTECTED METHOD Motor.ramp",
        "denied: PRIVATE METHOD Motor.limit",
        "denied: PRIVATE PROPERTY Motor.rpm (Set)",
    ]
    assert "Servo.use_limit" in lines[2]
    assert lines[4] == "outside writes: True 4"


# ---------------------------------------------------------------------------
# PROTECTED overrides called from base code; forward references in signatures
# ---------------------------------------------------------------------------


class StepChain(FunctionBlock, abstract=True):
    """The Template Method shape: a FINAL base method calling PROTECTED steps that derived blocks override."""

    trace: INT = VAR(0)

    @method(FINAL)
    def run(self) -> INT:
        return self.first() * 10 + self.second()

    @method(PROTECTED | ABSTRACT)
    def first(self) -> INT:
        raise NotImplementedError

    @method(PROTECTED)
    def second(self) -> INT:
        return 1

    def body(self) -> None:
        self.trace = self.run()


class TwoStep(StepChain):
    @method(PROTECTED)
    def first(self) -> INT:
        return 4

    @method(PROTECTED)
    def second(self) -> INT:
        return super().second() + 1


def test_base_code_calls_a_protected_override() -> None:
    chain = TwoStep()
    assert chain.run() == 42
    chain()
    assert chain.trace == 42


def test_a_protected_override_is_still_closed_to_outside_callers() -> None:
    with pytest.raises(AccessError, match=r"PROTECTED METHOD TwoStep\.first cannot be called from .*only inside StepChain and its derived blocks"):
        TwoStep().first()


class ILink(Interface):
    @method
    def set_next(self, link: ILink) -> BOOL:
        raise NotImplementedError

    @method
    def clone(self) -> ILink | None:
        raise NotImplementedError

    @method
    def visit(self, device: LaterDevice) -> None: ...


class LaterDevice(FunctionBlock):
    pass


class Link(FunctionBlock, ILink):
    follower: ILink = VAR()

    @method
    def set_next(self, link: ILink) -> BOOL:
        self.follower = link
        return True

    @method
    def clone(self) -> ILink | None:
        return self

    @method
    def visit(self, device: LaterDevice) -> None: ...


class SelfReturning(FunctionBlock):
    @method
    def me(self) -> SelfReturning:
        return self


class SelfReturningChild(SelfReturning):
    @method
    def me(self) -> SelfReturning:
        return self


def test_signatures_naming_the_interface_itself_or_a_later_class_match() -> None:
    a, b = Link(), Link()
    assert a.set_next(b) and a.clone() is a
    assert SelfReturningChild().me() is not None


def test_a_really_different_forward_reference_is_still_refused() -> None:
    with pytest.raises(DefinitionError, match=r"set_next does not match interface ILink: interface \(link: ILink\) -> BOOL, here \(link: LaterDevice\) -> BOOL"):

        class WrongLink(FunctionBlock, ILink):
            @method
            def set_next(self, link: LaterDevice) -> BOOL:  # type: ignore[override]  # the rule under test
                return True

            @method
            def clone(self) -> ILink | None:
                return None

            @method
            def visit(self, device: LaterDevice) -> None: ...


# ---------------------------------------------------------------------------
# Writing through a member or element of another block's local / output / CONSTANT
# ---------------------------------------------------------------------------


class RecipeData(Struct):
    speed: REAL = 50.0
    steps: ARRAY[INT] = VAR(bounds=(1, 3))


class RecipeEditor(FunctionBlock):
    working: RecipeData = VAR()
    result: RecipeData = VAR_OUTPUT()
    request: RecipeData = VAR_INPUT()
    table: ARRAY[INT] = VAR(bounds=(1, 3))
    LIMITS: ARRAY[INT] = VAR([1, 2, 3], bounds=(1, 3), constant=True)

    @method
    def edit(self) -> None:
        self.working.speed = 60.0
        self.working.steps[2] = 7
        self.table[1] = 5
        self.result.steps[3] = 9


class DerivedEditor(RecipeEditor):
    @method
    def tune(self) -> None:
        self.working.speed = 70.0  # a derived block's own code writes the base's locals


@checked_only
def test_members_and_elements_of_a_blocks_locals_are_written_only_by_its_code() -> None:
    editor = DerivedEditor()
    editor.edit()
    editor.tune()
    assert (editor.working.speed, editor.working.steps[2], editor.table[1], editor.result.steps[3]) == (70.0, 7, 5, 9)
    with pytest.raises(AccessError, match=r"VAR RecipeEditor\.working cannot be written from .*only DerivedEditor's own code"):
        editor.working.speed = 999.0
    with pytest.raises(AccessError, match=r"VAR RecipeEditor\.working cannot be written"):
        editor.working.steps[1] = 9  # an element of a member: the mark follows the view
    with pytest.raises(AccessError, match=r"VAR RecipeEditor\.table cannot be written"):
        editor.table[1] = 9
    with pytest.raises(AccessError, match=r"VAR_OUTPUT RecipeEditor\.result cannot be written"):
        editor.result.speed = 1.0
    with pytest.raises(AccessError, match=r"RecipeEditor\.LIMITS is CONSTANT and cannot be written"):
        editor.LIMITS[1] = 5
    assert editor.working.speed == 70.0 and list(editor.LIMITS) == [1, 2, 3]
    editor.request.speed = 3.0  # an input's members are the caller's to set
    assert editor.request.speed == 3.0


def test_super_set_writes_the_base_property_and_names_what_is_missing() -> None:
    from iecoop import AccessError, INT, VAR, FunctionBlock, prop, super_set

    class FB_Base(FunctionBlock):
        _n: INT = VAR(0)

        @prop
        def n(self) -> INT:
            return self._n

        @n.setter
        def n(self, value: INT) -> None:
            self._n = value

        @prop
        def fixed(self) -> INT:
            return 1

    class FB_Derived(FB_Base):
        def body(self) -> None:
            super_set(super(), "n", self._n + 2)  # SUPER^.n := SUPER^.n + 2;

        def write_fixed(self) -> None:
            super_set(super(), "fixed", 2)

        def write_missing(self) -> None:
            super_set(super(), "nothing", 2)

    block = FB_Derived()
    block(); block()
    assert block.n == 4
    with pytest.raises(AttributeError, match=r"PROPERTY FB_Base\.fixed has no Set accessor: it is read-only"):
        block.write_fixed()
    with pytest.raises(AccessError, match=r"SUPER\^\.nothing := \.\.\.: no base of FB_Derived declares nothing"):
        block.write_missing()
    with pytest.raises(TypeError, match=r"the first argument is super\(\) inside a method"):
        super_set(block, "n", 1)  # type: ignore[arg-type]


def test_a_program_is_read_through_its_instance_and_is_not_a_member_type() -> None:
    from iecoop import INT, REFERENCE_TO, VAR, DefinitionError, Program

    class P_Count(Program):
        counter: INT = VAR(0)

        def body(self) -> None:
            self.counter += 1

    p_count = P_Count()

    class P_Main(Program):
        seen: INT = VAR(0)

        def body(self) -> None:
            self.seen = p_count.counter * 10  # ST: nSeen := P_Count.counter * 10;

    main = P_Main()
    p_count(); main(); p_count(); main()
    assert main.seen == 20
    for annotation in ("P_Count", "REFERENCE_TO[P_Count]"):
        with pytest.raises(DefinitionError, match=r"Holder\.other: PROGRAM P_Count is not a data type .* as ST reads P_Count\.x"):
            exec(f"class Holder(Program):\n    other: {annotation} = VAR()\n",
                 {"Program": Program, "VAR": VAR, "REFERENCE_TO": REFERENCE_TO, "P_Count": P_Count})
