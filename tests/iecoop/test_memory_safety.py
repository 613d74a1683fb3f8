"""No read or write outside a live block, also under threads, huge offsets, forged tags and misuse.

The cases that could take the interpreter down (a C call on freed memory)
run in a child process bounded in time; a signal there is a failure.
"""

from __future__ import annotations

import gc
import os
import signal
import subprocess
import sys
import threading
import weakref
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest

from iecoop import (
    ARRAY, BOOL, INT, LINT, LREAL, POINTER_TO, REFERENCE_TO, VAR, VAR_INPUT, VAR_OUTPUT, DefinitionError,
    ExceptionCode, FunctionBlock, Interface, PlcException, Pointer, Program, Struct, T, adr, delete, memcpy,
    method, new, ref_assign, sizeof,
)
from iecoop.memory._handles import MAX_BLOCK_SIZE
from iecoop.runtime import Runtime, Task
from tests import checked_only

AV = ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
CHILD = Path(__file__).with_name("_memory_child.py")
ROOT = Path(__file__).resolve().parents[2]


@contextmanager
def access_violation(match: str) -> Iterator[None]:
    with pytest.raises(PlcException, match=match) as info:
        yield
    assert info.value.code == AV


# ---------------------------------------------------------------------------
# MEMCPY / MEMSET / MEMCMP hold their blocks; the allocation table is thread-safe
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("case", ["memset", "memcpy", "memcmp", "handle"])
def test_memory_operators_never_touch_a_block_freed_meanwhile(case: str) -> None:
    # memset / memcpy / memcmp race a thread that creates and deletes 2 MiB blocks;
    # "handle": a Pointer subclass whose handle property deletes the copy's destination.
    environment = {**os.environ, "PYTHONPATH": str(ROOT)}  # the iecoop of this tree
    done = subprocess.run(
        [sys.executable, str(CHILD), case, "2"], cwd=ROOT, env=environment, capture_output=True, text=True, timeout=60
    )
    if done.returncode < 0:
        pytest.fail(f"{case}: the interpreter died of {signal.Signals(-done.returncode).name}\n{done.stderr[-2000:]}")
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.startswith("done "), done.stdout


class Cell(Struct):
    a: INT = 0
    b: LINT = 0


def test_adr_and_dereference_from_four_threads() -> None:
    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)
    errors: list[BaseException] = []
    stop = threading.Event()

    def work(seed: int) -> None:
        try:
            while not stop.is_set():
                cells = [Cell(a=seed, b=i) for i in range(20)]
                for i, cell in enumerate(cells):
                    p = adr(cell, "b")
                    assert p.deref == i
                    assert adr(cell, "a").deref == seed
                del cells
        except BaseException as exc:  # any error in the table fails the test
            errors.append(exc)
            stop.set()

    threads = [threading.Thread(target=work, args=(n,)) for n in range(4)]
    try:
        for thread in threads:
            thread.start()
        stop.wait(1.5)
    finally:
        stop.set()
        for thread in threads:
            thread.join()
        sys.setswitchinterval(interval)
    assert errors == []
    # And the table is still whole for a single thread afterwards.
    cells = [Cell(a=7, b=i) for i in range(50)]
    assert [adr(c, "b").deref for c in cells] == list(range(50))


# ---------------------------------------------------------------------------
# Offsets at full width; block sizes
# ---------------------------------------------------------------------------


class Pair(Struct):
    first: LINT = 11
    second: LINT = 22


@pytest.mark.parametrize("delta", [2**32, -(2**32), 2**33, 2**64, 2**31])
def test_a_pointer_moved_far_away_never_wraps_into_its_block(delta: int) -> None:
    pair = Pair()
    p = adr(pair, "first")
    moved = p + delta
    with access_violation("outside its 16-byte block"):
        _ = moved.deref
    with access_violation("outside its 16-byte block"):
        moved.deref = 5
    # Moving it back does not revive it: the address left the representable range.
    with access_violation("an address moved outside its block"):
        _ = (moved - delta).deref
    assert pair.first == 11 and pair.second == 22


def test_a_pointer_below_its_block_and_back_is_the_same_address() -> None:
    pair = Pair()
    p = adr(pair, "second")
    below = p - 100
    assert below - p == -100
    with access_violation("address -92"):
        _ = below.deref
    assert (below + 100).deref == 22


def test_a_block_larger_than_a_handle_can_address_is_refused_at_definition() -> None:
    with pytest.raises(DefinitionError, match=r"Huge.*larger than the largest memory block"):

        class Huge(Struct):
            head: ARRAY[LINT] = VAR(bounds=(0, 2**27))  # 1 GiB + 8
            body: ARRAY[LINT] = VAR(bounds=(0, 2**27))
            tail: INT = 0

    with pytest.raises(DefinitionError, match=r"Wide\.cells: ARRAY of 4611686018427387904 LINT"):

        class Wide(Struct):
            cells: ARRAY[LINT] = VAR(bounds=((-(2**31), 2**31 - 1), (0, 2**30 - 1)))

    class Largest(Struct):
        data: ARRAY[BOOL] = VAR(bounds=(1, MAX_BLOCK_SIZE))

    assert sizeof(Largest) == MAX_BLOCK_SIZE


# ---------------------------------------------------------------------------
# Type tags checked against the block's real class
# ---------------------------------------------------------------------------


class IMachine(Interface):
    @method
    def kind(self) -> INT: ...  # a prototype's body is '...'


class Pump(FunctionBlock, IMachine):
    @method
    def kind(self) -> INT:
        return 1


class Valve(FunctionBlock, IMachine):
    opened: LREAL = VAR(0.0)
    spare: ARRAY[LINT] = VAR(bounds=(1, 64))

    @method
    def kind(self) -> INT:
        return 2


class Line(FunctionBlock):
    machine: IMachine = VAR_INPUT()
    pump_ptr: POINTER_TO[Pump] = VAR_INPUT()
    result: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.result = self.machine.kind()


def test_a_forged_type_tag_faults_instead_of_calling_another_class() -> None:
    pump, valve, line = Pump(), Valve(), Line()
    line(machine=pump)
    assert line.result == 1
    memcpy(adr(pump), adr(valve), 8)  # the header now claims to be a Valve
    with access_violation("type tag .* was overwritten"):
        line()
    with access_violation("type tag .* was overwritten"):
        line.machine.kind()
    assert valve.kind() == 2


def test_a_larger_blocks_header_copied_in_faults_instead_of_a_buffer_error() -> None:
    pump, valve, line = Pump(), Valve(), Line()
    line(machine=pump)
    memcpy(adr(pump), adr(valve), 8)  # a 528-byte Valve's header on an 8-byte Pump
    with access_violation("matching type"):
        line()


class BigPump(Pump):
    stages: ARRAY[LREAL] = VAR(bounds=(1, 8))


class Skid(Struct):
    pump: Pump = VAR()
    neighbour: ARRAY[LINT] = VAR(bounds=(1, 8))


def test_a_forged_derived_tag_faults_through_a_pointer_to_the_base() -> None:
    # The tag of a class derived from the pointer's type: without the real-class check the
    # dereference would make a BigPump view reaching into the neighbour's memory.
    skid, line, big = Skid(), Line(), BigPump()
    line.pump_ptr = adr(skid, "pump")
    assert line.pump_ptr.deref.kind() == 1
    memcpy(adr(skid, "pump"), adr(big), 8)
    with access_violation("matching type"):
        _ = line.pump_ptr.deref
    assert list(skid.neighbour) == [0] * 8


exits: list[str] = []


class Motor(FunctionBlock):
    speed: INT = VAR(0)
    me: POINTER_TO[Motor] = VAR_INPUT()

    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        exits.append("Motor")
        delete(self.me)  # an FB_exit that deletes its own instance
        return True

    def body(self) -> None:
        self.speed += 1


class Conveyor(FunctionBlock):
    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        exits.append("Conveyor")
        return True


def test_delete_through_a_pointer_to_an_unrelated_type_is_refused() -> None:
    exits.clear()
    p = new(Motor)
    with access_violation("__DELETE through POINTER TO Conveyor of a Motor instance"):
        delete(p.typed(Conveyor))
    assert exits == []
    p.deref()
    assert p.deref.speed == 1  # still alive
    delete(p)
    assert exits == ["Motor"]


def test_an_fb_exit_that_deletes_its_own_instance_runs_once() -> None:
    exits.clear()
    p = new(Motor)
    p.deref.me = p
    delete(p)
    assert exits == ["Motor"]
    assert not p
    delete(p)  # deleting the null pointer again is harmless
    assert exits == ["Motor"]


# ---------------------------------------------------------------------------
# List and dict writes are all or nothing
# ---------------------------------------------------------------------------


class Point(Struct):
    x: LREAL = 0.0
    y: LREAL = 0.0


class Plotter(FunctionBlock):
    values: ARRAY[INT] = VAR_INPUT(bounds=(1, 3))
    at: Point = VAR_INPUT()
    points: ARRAY[Point] = VAR_INPUT(bounds=(1, 2))


def test_a_list_written_into_an_array_is_all_or_nothing() -> None:
    plotter = Plotter()
    plotter(values=[1, 2, 3])
    with pytest.raises(TypeError, match=r"Plotter\.values\[3\]: cannot store str 'x'"):
        plotter(values=[7, 8, "x"])
    assert list(plotter.values) == [1, 2, 3]
    with pytest.raises(TypeError, match=r"4 values for ARRAY\[1\.\.3\] OF INT"):
        plotter(values=[7, 8, 9, 10])
    assert list(plotter.values) == [1, 2, 3]


def test_a_dict_written_into_a_struct_is_all_or_nothing() -> None:
    plotter = Plotter()
    plotter(at={"x": 1.5, "y": 2.5})
    with pytest.raises(TypeError, match=r"Plotter\.at\.y: cannot store str"):
        plotter(at={"x": 9.0, "y": "far"})
    with pytest.raises(TypeError, match=r"Plotter\.at: Point has no member 'z'"):
        plotter(at={"x": 9.0, "z": 1.0})
    assert (plotter.at.x, plotter.at.y) == (1.5, 2.5)
    with pytest.raises(TypeError, match=r"Plotter\.points\[2\]\.x: cannot store str"):
        plotter(points=[{"x": 1.0}, {"x": "no"}])
    assert [(p.x, p.y) for p in plotter.points] == [(0.0, 0.0), (0.0, 0.0)]
    pointer = adr(plotter, "values")
    with pytest.raises(TypeError, match=r"\[2\]: cannot store float"):
        pointer.deref = [4, 5.5]
    assert list(plotter.values) == [0, 0, 0]


# ---------------------------------------------------------------------------
# Use after delete() through a view Python kept
# ---------------------------------------------------------------------------


def test_a_view_kept_after_delete_faults_on_write_call_and_read() -> None:
    p = new(Motor)
    inst = p.deref
    inst()
    delete(p)
    with access_violation("'speed' written of a deleted Motor"):
        inst.speed = 3
    with access_violation("call of a deleted Motor"):
        inst()
    with access_violation("'speed' read of a deleted Motor"):
        _ = inst.speed
    with access_violation("deleted Motor"):
        inst.fb_exit(False)
    assert repr(inst) == "<deleted Motor>"


def test_an_interface_value_kept_after_delete_faults() -> None:
    p = new(Pump)
    line = Line()
    line(machine=p.deref)
    kept = line.machine
    delete(p)
    with access_violation("deleted Pump"):
        kept.kind()
    with access_violation("deleted or no longer exists"):
        line()


# ---------------------------------------------------------------------------
# LREAL range in checked mode
# ---------------------------------------------------------------------------


class Gauge(Struct):
    value: LREAL = 0.0


def test_the_largest_integers_an_lreal_holds_are_stored() -> None:
    gauge = Gauge()
    gauge.value = 2**1023
    assert gauge.value == float(2**1023)
    gauge.value = -(2**1023)
    assert gauge.value == -float(2**1023)


@checked_only
def test_an_integer_beyond_lreal_names_the_variable() -> None:
    gauge = Gauge()
    with pytest.raises(ValueError, match=r"Gauge\.value: an integer of 1329 bits is outside the range of LREAL"):
        gauge.value = 10**400
    assert gauge.value == 0.0


# ---------------------------------------------------------------------------
# Lifetime: a block holding an instance's address keeps it alive
# ---------------------------------------------------------------------------


class DolMotor(FunctionBlock, IMachine):
    starts: INT = VAR(0)

    @method
    def kind(self) -> INT:
        self.starts += 1
        return 3


class Station(FunctionBlock):
    machine: IMachine = VAR_INPUT()
    motor_ptr: POINTER_TO[DolMotor] = VAR_INPUT()
    motor_ref: REFERENCE_TO[DolMotor] = VAR_INPUT()
    result: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.result = self.machine.kind()


def test_an_instance_held_by_an_interface_variable_lives_while_held() -> None:
    station = Station()
    station.machine = DolMotor()
    gc.collect()
    station()
    station()
    assert station.result == 3
    assert station.machine.starts == 2
    watch = weakref.ref(station.machine)
    station.machine = Pump()  # overwritten: the old one is no longer kept
    gc.collect()
    assert watch() is None


def test_an_instance_held_by_a_pointer_or_reference_lives_while_held() -> None:
    station = Station()
    station.motor_ptr = adr(DolMotor())
    ref_assign(station, "motor_ref", DolMotor())
    gc.collect()
    assert station.motor_ptr.deref.kind() == 3
    assert station.motor_ref.kind() == 3
    watch = weakref.ref(station.motor_ptr.deref)
    station.motor_ptr = Pointer()  # NULL
    gc.collect()
    assert watch() is None


def test_a_pointer_from_adr_keeps_its_instance_alive() -> None:
    p = adr(DolMotor(), "starts")
    gc.collect()
    p.deref = 4
    assert p.deref == 4


class Peer(FunctionBlock, IMachine):
    peer: IMachine = VAR_INPUT()

    @method
    def kind(self) -> INT:
        return 4


def test_blocks_holding_each_other_are_collected_together() -> None:
    first, second = Peer(), Peer()
    first.peer, second.peer = second, first
    first.peer = first  # a block holding itself keeps nothing extra
    first.peer = second
    watch = [weakref.ref(first), weakref.ref(second)]
    del first, second
    gc.collect()
    assert [w() for w in watch] == [None, None]


def test_delete_still_ends_a_new_instance_held_by_a_block() -> None:
    station = Station()
    p = new(DolMotor)
    station.machine = p.deref
    station()
    delete(p)
    with access_violation("deleted or no longer exists"):
        station()


class Plant(Struct):
    stations: ARRAY[Station] = VAR(bounds=(1, 2))


def test_an_instance_held_through_an_array_element_view_lives_while_held() -> None:
    # An element of an ARRAY OF block is a view made over the array's memory:
    # the instance is kept by the plant's block, not by that short-lived view.
    plant = Plant()
    plant.stations[2].machine = DolMotor()
    gc.collect()
    plant.stations[2]()
    assert plant.stations[2].result == 3


class Cell2(Program):
    machine: IMachine = VAR_INPUT()


def test_a_reset_that_clears_a_block_lets_go_of_what_it_held() -> None:
    cell = Cell2()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    cell.machine = DolMotor()
    watch = weakref.ref(cell.machine)
    rt.run(cycles=1)
    gc.collect()
    assert watch() is not None
    rt.reset_cold()
    gc.collect()
    assert watch() is None
    assert not cell.machine
