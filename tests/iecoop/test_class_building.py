"""How a class statement becomes a block, a STRUCT, a GVL or an INTERFACE.

The builder works in phases: the fields and the OOP rules are read from the
class body before the class exists, the ctypes layout is assigned once ctypes
has initialised the class. These tests pin what a user sees: slips that would
silently do nothing are rejected with what to write instead, interface bodies
are judged from the source, and a class nothing holds any more is collected
together with what the library recorded about it.
"""

from __future__ import annotations

import gc
import linecache
import re
import textwrap
import weakref
from collections.abc import Callable
from typing import Any

import pytest

from iecoop import (
    BOOL,
    INT,
    REAL,
    VAR,
    VAR_EXTERNAL,
    VAR_INPUT,
    VAR_OUTPUT,
    VAR_STAT,
    DefinitionError,
    FunctionBlock,
    GlobalVariables,
    Interface,
    IQueryInterface,
    Program,
    Struct,
    gvl,
    method,
    new,
    delete,
    PROTECTED,
    query_interface,
    sizeof,
)
from iecoop import members as members_module
from iecoop.gvl import global_lists
from iecoop.interfaces import interface_members
from iecoop.memory._aggregates import class_for_tag
from iecoop.stdlib import TON

# ---------------------------------------------------------------------------
# Definition slips: rejected, saying what to write instead
# ---------------------------------------------------------------------------


def test_an_unannotated_input_names_the_annotation_to_write() -> None:
    with pytest.raises(DefinitionError, match=r"FUNCTION_BLOCK Unit: x = VAR_INPUT\(0\) has no type.*annotate it: x: INT = VAR_INPUT\(0\)"):

        class Unit(FunctionBlock):
            x = VAR_INPUT(0)


@pytest.mark.parametrize(
    ("declare", "advice"),
    [
        (lambda: VAR_OUTPUT(False), "done: BOOL = VAR_OUTPUT(False)"),
        (lambda: VAR(1.5, retain=True), "done: LREAL = VAR(1.5, retain=True)"),
        (lambda: VAR("", length=20), "done: STRING = VAR('', length=20)"),
        (lambda: VAR_STAT(0), "done: INT = VAR_STAT(0)"),
        (lambda: VAR([1, 2], bounds=(1, 2)), "done: ARRAY[INT] = VAR([1, 2], bounds=(1, 2))"),
        (lambda: VAR_OUTPUT(), "done: <type> = VAR_OUTPUT()"),
    ],
)
def test_every_unannotated_section_is_rejected(declare: Callable[[], Any], advice: str) -> None:
    with pytest.raises(DefinitionError, match="annotate it: " + re.escape(advice)):
        type("Unit", (FunctionBlock,), {"__module__": __name__, "done": declare()})


def test_an_unannotated_struct_member_and_global_are_rejected() -> None:
    with pytest.raises(DefinitionError, match=r"STRUCT Point: y = VAR\(2.0\) has no type.*annotate it: y: LREAL = VAR\(2.0\)"):

        class Point(Struct):
            x: REAL = 0.0
            y = VAR(2.0)

    with pytest.raises(DefinitionError, match=r"GVL GVL_Slip: level = VAR\(3\) has no type.*annotate it: level: INT"):

        class GVL_Slip(GlobalVariables):
            level = VAR(3)


@pytest.mark.parametrize("spelling", ["Body", "BODY", "bOdY"])
def test_a_body_spelled_in_another_case_is_rejected(spelling: str) -> None:
    def wrong(self: Any) -> None:
        raise AssertionError("never runs as the body")

    with pytest.raises(DefinitionError, match=rf"FUNCTION_BLOCK Pump: {spelling} is not body .*rename it to body"):
        type("Pump", (FunctionBlock,), {"__module__": __name__, spelling: wrong})


def test_the_lifecycle_methods_spelled_as_in_st_are_rejected() -> None:
    with pytest.raises(DefinitionError, match=r"PROGRAM Main: FB_init is not fb_init .*rename it to fb_init"):

        class Main(Program):
            def FB_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
                return True

    with pytest.raises(DefinitionError, match=r"FUNCTION_BLOCK Axis: FB_Exit is not fb_exit"):

        class Axis(FunctionBlock):
            def FB_Exit(self, in_copy_code: BOOL) -> BOOL:
                return True


def test_a_variable_spelled_like_body_is_a_variable() -> None:
    class Gauge(FunctionBlock):
        Body: INT = VAR_OUTPUT(4)

    assert Gauge().Body == 4


def test_overriding_the_call_is_rejected() -> None:
    with pytest.raises(DefinitionError, match=r"FUNCTION_BLOCK Valve: __call__ cannot be overridden.*def body\(self\) -> None"):

        class Valve(FunctionBlock):
            def __call__(self, **inputs: Any) -> None:
                pass

    with pytest.raises(DefinitionError, match=r"PROGRAM Cell: __call__ cannot be overridden"):

        class Cell(Program):
            def __call__(self) -> None:  # type: ignore[override]
                pass


def test_the_correct_spellings_run() -> None:
    class Counter(FunctionBlock):
        step: INT = VAR_INPUT(1)
        count: INT = VAR_OUTPUT(0)

        def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
            self.count = 10
            return True

        def body(self) -> None:
            self.count += self.step

    counter = Counter()
    for _ in range(3):
        counter(step=2)
    assert counter.count == 16


# ---------------------------------------------------------------------------
# Phases: the layout a class gets, on every supported Python
# ---------------------------------------------------------------------------


def test_a_derived_block_lays_out_after_its_base_with_its_own_descriptors() -> None:
    class Base(FunctionBlock):
        a: INT = VAR_INPUT(1)

    class Derived(Base):
        b: REAL = VAR_OUTPUT(2.5)

    layout = Derived._iec_layout_
    assert layout is not None
    assert [(f.name, f.owner) for f in layout.fields] == [("a", "Base"), ("b", "Derived")]
    assert layout.by_name["b"].offset > layout.by_name["a"].offset
    assert sizeof(Derived) > sizeof(Base)
    assert "_iec_builder_" not in vars(Derived)
    d = Derived()
    d(a=7)
    assert (d.a, d.b) == (7, 2.5)


def test_a_struct_member_value_is_stored_not_left_as_a_class_attribute() -> None:
    class Recipe(Struct):
        speed: REAL = 1.5

    assert not isinstance(vars(Recipe)["speed"], float)
    assert Recipe().speed == 1.5


# ---------------------------------------------------------------------------
# Interface bodies, judged from the source
# ---------------------------------------------------------------------------

_BODY_SOURCE = textwrap.dedent(
    """
    class IExec(Interface):
        @method
        def ping(self) -> BOOL:
            return True
    """
)


def _run_registered(source: str, filename: str) -> dict[str, Any]:
    """Run ``source`` as code generated at run time that registers its lines with linecache, as attrs does."""
    linecache.cache[filename] = (len(source), None, source.splitlines(True), filename)
    namespace: dict[str, Any] = {"Interface": Interface, "method": method, "BOOL": BOOL, "INT": INT}
    try:
        exec(compile(source, filename, "exec"), namespace)
    finally:
        del linecache.cache[filename]
    return namespace


def _level_prototype(body: str) -> str:
    return "class IForm(Interface):\n    @method\n    def level(self) -> INT:\n" + textwrap.indent(body, " " * 8) + "\n"


def test_an_interface_body_is_found_in_source_registered_with_linecache() -> None:
    with pytest.raises(DefinitionError, match=r"INTERFACE IExec: ping has a body"):
        _run_registered(_BODY_SOURCE, "<iecoop test: interface with a body>")


def test_an_interface_without_source_is_accepted_unchecked() -> None:
    # exec'd code that no linecache entry describes: the body cannot be read, so it is taken as a prototype
    namespace: dict[str, Any] = {"Interface": Interface, "method": method, "BOOL": BOOL}
    exec(compile(_BODY_SOURCE, "<iecoop test: no source>", "exec"), namespace)
    assert list(interface_members(namespace["IExec"])) == ["ping"]


@pytest.mark.parametrize(
    "body",
    [
        "...",
        "pass",
        '"""Docstring."""',
        '"""Docstring."""\n...',
        "raise NotImplementedError",
        'raise NotImplementedError("prototype")',
    ],
)
def test_interface_prototype_forms(body: str) -> None:
    namespace = _run_registered(_level_prototype(body), f"<iecoop test: prototype {body!r}>")
    assert "level" in interface_members(namespace["IForm"])


@pytest.mark.parametrize(
    "body",
    ["return 0", "x = 1", '"""Docstring."""\nreturn 0', "raise ValueError", "print()\nraise NotImplementedError"],
)
def test_interface_bodies_that_do_something(body: str) -> None:
    with pytest.raises(DefinitionError, match=r"INTERFACE IForm: level has a body"):
        _run_registered(_level_prototype(body), f"<iecoop test: body {body!r}>")


# ---------------------------------------------------------------------------
# Lifetime: a class nothing holds is collected, with its registry entries
# ---------------------------------------------------------------------------


def _collect() -> None:
    for _ in range(3):  # a class and its ctypes types die over more than one pass
        gc.collect()


def _define_and_use() -> tuple[list[weakref.ref[type]], int]:
    class IPing(IQueryInterface):
        @method
        def ping(self) -> INT:
            raise NotImplementedError

    class Point(Struct):
        x: REAL = 0.0

    @gvl
    class GVL_Lifetime(GlobalVariables):
        lifetime_level: INT = 5

    class Inner(FunctionBlock):
        n: INT = VAR_INPUT(0)

        def body(self) -> None:
            self.n += 1

    class Outer(FunctionBlock, IPing):
        enable: BOOL = VAR_INPUT(False)
        count: INT = VAR_OUTPUT(0)
        origin: Point = VAR()
        inner: Inner = VAR()
        timer: TON = VAR()
        me: IPing = VAR()
        calls: INT = VAR_STAT(0)
        lifetime_level: INT = VAR_EXTERNAL()

        @method(PROTECTED)
        def step(self) -> INT:
            return 1

        @method
        def ping(self) -> INT:
            return self.count + self.step()

        def body(self) -> None:
            self.inner(n=1)
            self.me = self
            self.calls += 1
            if self.enable:
                self.count += self.lifetime_level

    outer = Outer()
    for _ in range(2):
        outer(enable=True)
    seen = query_interface(outer.me, IPing)
    assert seen is not None and seen.ping() == 11
    pointer = new(Inner)
    delete(pointer)
    assert "GVL_Lifetime" in global_lists()
    return [weakref.ref(c) for c in (IPing, Point, Inner, Outer, type(GVL_Lifetime))], getattr(Outer, "_iec_tag_value_")


def test_classes_defined_in_a_function_are_collected_with_their_registry_entries() -> None:
    _collect()
    owners_before = len(members_module._code_owners)
    refs, tag = _define_and_use()
    _collect()
    assert [r() for r in refs] == [None] * len(refs)
    assert class_for_tag(tag) is None
    assert "GVL_Lifetime" not in global_lists()
    assert len(members_module._code_owners) <= owners_before


def test_a_class_that_is_held_stays_registered() -> None:
    refs, tag = _define_and_use()
    outer = refs[3]()
    assert outer is not None
    _collect()
    assert class_for_tag(tag) is outer
    block = outer()
    block(enable=True)
    assert block.count == 5
