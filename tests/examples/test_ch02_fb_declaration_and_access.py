"""Chapter 2: the VAR sections of FB_Pump and the access-specifier table of FB_Access."""

from __future__ import annotations

import importlib
import sys
import uuid
from collections.abc import Callable, Iterator
from types import ModuleType

import pytest

from iecoop_examples.ch02_fb_declaration_and_access import (
    MEMBERS,
    Access,
    AccessChild,
    Main,
    PlantGlobals,
    Pump,
    access_table,
    main,
)
from iecoop import STRING, UDINT, VAR, VAR_IN_OUT, AccessError, DefinitionError, FunctionBlock, Program, T, adr
from iecoop.runtime import Runtime, Task
from tests import checked_only


class Owner(Program):
    """A second caller with its own counter and tag."""

    count: UDINT = VAR(0)
    tag: STRING = VAR("P-202")


def _call(pump: Pump, owner: Owner, **inputs: bool) -> None:
    pump(starts=adr(owner, "count"), tag=adr(owner, "tag"), **inputs)


def test_each_start_edge_counts_once_in_the_callers_variable() -> None:
    program = Main()
    program(start=True)
    program(start=True)  # held: no new edge
    assert (program.pump.running, program.pump_starts, program.pump.status) == (True, 1, "P-101 running")
    program(start=False, stop=True)
    assert (program.pump.running, program.pump_starts, program.pump.status) == (False, 1, "P-101 stopped")
    program(start=True, stop=True)  # an edge while stopped does not start
    assert (program.pump.running, program.pump_starts) == (False, 1)
    program(start=False, stop=False)
    program(start=True)
    assert (program.pump.running, program.pump_starts, program.pump.run_cycles) == (True, 2, 3)


def test_the_in_outs_are_whichever_variables_the_call_binds() -> None:
    pump, owner = Pump(), Owner()
    _call(pump, owner, start=True)
    assert (owner.count, pump.starts, pump.status) == (1, 1, "P-202 running")


def test_a_var_in_out_must_be_bound_at_every_call() -> None:
    with pytest.raises(TypeError, match=r"VAR_IN_OUT 'starts' must be assigned at every call"):
        Pump()(start=True)  # type: ignore[call-arg]


def test_the_constant_caps_the_starts() -> None:
    pump, owner = Pump(), Owner()
    for _ in range(5):
        _call(pump, owner, start=True, stop=False)
        _call(pump, owner, start=False, stop=True)
    assert (owner.count, pump.starts_retain, pump.max_starts) == (3, 3, 3)


def test_var_stat_is_shared_by_every_instance() -> None:
    first, second, owner = Pump(), Pump(), Owner()
    before = first.all_pump_starts
    _call(first, owner, start=True)
    _call(second, owner, start=True)
    assert first.all_pump_starts == second.all_pump_starts == before + 2


def test_var_external_reads_the_global_of_the_gvl() -> None:
    pump, owner = Pump(), Owner()
    _call(pump, owner, start=True)
    try:
        PlantGlobals.pumps_enabled = False
        _call(pump, owner)
        assert (pump.pumps_enabled, pump.running) == (False, False)
        _call(pump, owner, start=False)
        _call(pump, owner, start=True)
        assert pump.running is False  # no start while the plant disables the pumps
    finally:
        PlantGlobals.pumps_enabled = True
    _call(pump, owner, start=False)
    _call(pump, owner, start=True)
    assert pump.running is True


def test_reset_cold_keeps_the_remanent_variables() -> None:
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    program.start = True
    rt.run(cycles=5)
    assert (program.pump_starts, program.pump.starts_retain, program.pump.run_cycles) == (1, 1, 5)
    rt.reset_cold()
    assert (program.pump_starts, program.pump.running) == (0, False)
    assert (program.pump.starts_retain, program.pump.run_cycles) == (1, 5)  # TwinCAT profile
    rt.reset_origin()
    assert (program.pump.starts_retain, program.pump.run_cycles) == (0, 0)


def test_the_temp_holds_only_this_calls_start_decision() -> None:
    program = Main()
    program(start=True)
    assert program.pump.start_now is True
    program(start=True)
    assert program.pump.start_now is False


@checked_only
def test_outputs_locals_and_constants_are_not_written_from_outside() -> None:
    pump = Pump()
    with pytest.raises(AccessError, match=r"VAR_OUTPUT Pump\.running cannot be written from .*only Pump's own code"):
        pump.running = True
    with pytest.raises(AccessError, match=r"VAR_TEMP Pump\.start_now cannot be written from"):
        pump.start_now = True
    with pytest.raises(AccessError, match=r"Pump\.max_starts is CONSTANT and cannot be written"):
        pump.max_starts = 10
    pump.start = True  # an input: the caller writes it
    assert pump.start is True


@checked_only
def test_a_var_in_out_constant_is_read_only_inside() -> None:
    class Renamer(FunctionBlock):
        tag: STRING = VAR_IN_OUT(constant=True)

        def body(self) -> None:
            self.tag = "renamed"

    owner = Owner()
    with pytest.raises(AccessError, match=r"Renamer\.tag is CONSTANT and cannot be written"):
        Renamer()(tag=adr(owner, "tag"))
    assert owner.tag == "P-202"


def test_the_access_table_inside_derived_and_outside() -> None:
    assert access_table() == {
        "PUBLIC": ("1", "1", "1"),
        "PRIVATE": ("2", "denied", "denied"),
        "PROTECTED": ("3", "3", "denied"),
        "INTERNAL": ("4", "4", "4"),
    }


@pytest.mark.parametrize(
    ("specifier", "rule"),
    [
        ("PRIVATE", "PRIVATE members are callable only inside Access"),
        ("PROTECTED", "PROTECTED members are callable only inside Access and its derived blocks"),
    ],
)
def test_the_refusal_names_member_caller_and_rule(specifier: str, rule: str) -> None:
    name = MEMBERS[specifier]
    with pytest.raises(AccessError, match=rf"{specifier} METHOD Access\.{name} cannot be called from .*: {rule}"):
        getattr(Access(), name)()


def test_private_stays_private_in_the_derived_block() -> None:
    with pytest.raises(AccessError, match=r"PRIVATE METHOD Access\.m_private cannot be called from AccessChild"):
        AccessChild().call_derived("m_private")


def test_a_name_the_block_has_not_calls_nothing_and_gives_0() -> None:
    assert (Access().call_inside("m_missing"), AccessChild().call_derived("")) == (0, 0)
    assert [Access().call_inside(name) for name in MEMBERS.values()] == [1, 2, 3, 4]


_OTHER_NAMESPACE = '''
from iecoop import method


def call(block, name):
    return getattr(block, name)()


def derive(base):
    class ForeignChild(base):
        @method
        def call_derived(self, name: str):
            return getattr(self, name)()

    return ForeignChild
'''


@pytest.fixture(scope="module")
def other_namespace(tmp_path_factory: pytest.TempPathFactory) -> Iterator[ModuleType]:
    """A second top-level package, i.e. another namespace (a library) for INTERNAL."""
    root = tmp_path_factory.mktemp("namespace")
    name = f"otherlib_{uuid.uuid4().hex[:8]}"
    (root / name).mkdir()
    (root / name / "__init__.py").write_text(_OTHER_NAMESPACE)
    sys.path.insert(0, str(root))
    try:
        yield importlib.import_module(name)
    finally:
        sys.path.remove(str(root))
        sys.modules.pop(name, None)


@pytest.mark.parametrize(
    ("specifier", "derived_elsewhere", "other_namespace_call"),
    [("PUBLIC", True, True), ("PRIVATE", False, False), ("PROTECTED", True, False), ("INTERNAL", False, False)],
)
def test_the_access_table_from_another_namespace(
    specifier: str, derived_elsewhere: bool, other_namespace_call: bool, other_namespace: ModuleType
) -> None:
    name = MEMBERS[specifier]
    expected = list(MEMBERS).index(specifier) + 1
    foreign_child = other_namespace.derive(Access)()
    calls: list[tuple[bool, Callable[[], object]]] = [
        (derived_elsewhere, lambda: foreign_child.call_derived(name)),
        (other_namespace_call, lambda: other_namespace.call(Access(), name)),
    ]
    for allowed, call in calls:
        if allowed:
            assert call() == expected
        else:
            with pytest.raises(AccessError, match=rf"{specifier} METHOD Access\.{name} cannot be called from"):
                call()


def test_a_final_block_cannot_be_extended() -> None:
    with pytest.raises(DefinitionError, match=r"FUNCTION_BLOCK BigPump cannot EXTEND Pump: Pump is FINAL"):

        class BigPump(Pump):
            pass


def test_a_final_block_still_works_as_a_member() -> None:
    class Station(FunctionBlock):
        pump: Pump = VAR()

    assert Station().pump.running is False


def test_main_prints_the_pump_the_table_and_both_errors(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    out = capsys.readouterr().out
    assert "MAIN.nPumpStarts=2, nStartsRetain=2, nRunCycles=2" in out
    assert "PROTECTED  3       3        denied" in out
    assert "AccessError: PRIVATE METHOD Access.m_private cannot be called from main" in out
    assert "DefinitionError: FUNCTION_BLOCK BigPump cannot EXTEND Pump: Pump is FINAL" in out
