"""FB_init arguments naming a variable declared beside the member: ``fbUser : FB_User(fbCounter);``.

Dependency injection as TwinCAT and CODESYS projects write it: a block's
member receives, through its FB_init, a REFERENCE TO, an interface or the
ADR of another member of the same block, or the value of one. Each instance
passes its own variable, on creation and on every reset.
"""

from __future__ import annotations

import pytest

from iecoop import (
    BOOL, INT, POINTER_TO, REFERENCE_TO, VAR, VAR_OUTPUT, ARRAY, DefinitionError, FunctionBlock, Interface,
    Pointer, Program, adr, adr_of, method, ref_assign, sibling,
)
from iecoop.runtime import Runtime, Task


class ICount(Interface):
    @method
    def bump(self) -> None: ...


class Counter(FunctionBlock, ICount):
    count: INT = VAR_OUTPUT(0)

    @method
    def bump(self) -> None:
        self.count = self.count + 1

    def body(self) -> None:
        self.count = self.count + 1


class ByReference(FunctionBlock):
    """``_counter REF= counter;`` in FB_init, the counter called each cycle."""

    counter: REFERENCE_TO[Counter] = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, counter: REFERENCE_TO[Counter]) -> BOOL:
        ref_assign(self, "counter", adr(counter))
        return True

    def body(self) -> None:
        self.counter()


class ByInterface(FunctionBlock):
    target: ICount = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, target: ICount) -> BOOL:
        self.target = target
        return True

    def body(self) -> None:
        self.target.bump()


class ByPointer(FunctionBlock):
    target: POINTER_TO[Counter] = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, target: POINTER_TO[Counter]) -> BOOL:
        self.target = target
        return True

    def body(self) -> None:
        self.target.deref.bump()


class ByValue(FunctionBlock):
    start: INT = VAR_OUTPUT(0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, start: INT) -> BOOL:
        self.start = start
        return True


class Cell(Program):
    counter: Counter = VAR()
    user: ByReference = VAR(fb_init={"counter": sibling("counter")})
    caller: ByInterface = VAR(fb_init={"target": sibling("counter")})
    pointing: ByPointer = VAR(fb_init={"target": adr_of("counter")})
    counters: ARRAY[Counter] = VAR(bounds=(1, 3))
    second: ByReference = VAR(fb_init={"counter": sibling("counters", 2)})
    limit: INT = VAR(7)
    copied: ByValue = VAR(fb_init={"start": sibling("limit")})

    def body(self) -> None:
        self.user()
        self.caller()
        self.pointing()
        self.second()


def test_each_argument_reaches_the_variable_beside_it_over_cycles() -> None:
    cell = Cell()
    for _ in range(4):
        cell()
    # three users of the one counter, each bumping it once a cycle
    assert cell.counter.count == 12
    assert [cell.counters[i].count for i in (1, 2, 3)] == [0, 4, 0]
    assert cell.copied.start == 7


def test_every_instance_passes_its_own_variable() -> None:
    a, b = Cell(), Cell()
    a()
    a()
    b()
    assert (a.counter.count, b.counter.count) == (6, 3)
    assert adr(a.user.counter) == adr(a, "counter")
    assert adr(b.user.counter) == adr(b, "counter")
    assert isinstance(a.pointing.target, Pointer) and a.pointing.target == adr(a, "counter")


def test_a_cold_reset_passes_the_variables_again() -> None:
    cell = Cell()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=10, priority=20), cell)
    rt.run(cycles=3)
    assert cell.counter.count == 9
    rt.reset_cold()
    assert cell.counter.count == 0 and adr(cell.user.counter) == adr(cell, "counter")
    rt.run(cycles=2)
    assert cell.counter.count == 6
    assert cell.counters[2].count == 2


def test_a_list_per_element_takes_each_its_own_sibling() -> None:
    class Bank(Program):
        a: Counter = VAR()
        b: Counter = VAR()
        users: ARRAY[ByReference] = VAR(bounds=(1, 2), fb_init=[{"counter": sibling("a")}, {"counter": sibling("b")}])

        def body(self) -> None:
            self.users[1]()
            self.users[2]()
            self.users[2]()

    bank = Bank()
    bank()
    assert (bank.a.count, bank.b.count) == (1, 2)


def test_a_variable_the_block_does_not_declare_is_refused_at_definition() -> None:
    with pytest.raises(DefinitionError) as caught:
        class Typo(Program):
            counter: Counter = VAR()
            user: ByReference = VAR(fb_init={"counter": sibling("countr")})
    message = str(caught.value)
    assert "Typo.user" in message and "sibling('countr')" in message and "names no variable" in message


def test_an_index_into_a_variable_that_is_no_array_is_refused() -> None:
    with pytest.raises(DefinitionError, match=r"Flat\.user: .*needs an ARRAY, counter is Counter"):
        class Flat(Program):
            counter: Counter = VAR()
            user: ByReference = VAR(fb_init={"counter": sibling("counter", 2)})


def test_a_member_given_itself_is_refused() -> None:
    with pytest.raises(DefinitionError, match=r"Loop\.user: .*names the member it initialises"):
        class Loop(Program):
            user: ByReference = VAR(fb_init={"counter": adr_of("user")})


def test_the_name_must_be_a_string() -> None:
    with pytest.raises(TypeError, match="variable name"):
        sibling(Counter)  # type: ignore[arg-type]
