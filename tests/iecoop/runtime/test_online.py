"""Online write and force by TwinCAT symbol path: once at the next cycle start, or held until released."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

import pytest

from iecoop import ARRAY, BOOL, INT, REAL, AccessError, FunctionBlock, GlobalVariables, Program, T, VAR, VAR_INPUT
from iecoop import STRING, VAR_OUTPUT, gvl
from iecoop.runtime import Runtime, Task


class Station(FunctionBlock):
    count: INT = VAR(0)
    full: BOOL = VAR_OUTPUT(False)

    def body(self) -> None:
        self.count += 1
        self.full = self.count >= 10


@gvl
class GVL_CommissioningIO(GlobalVariables):
    start_button: BOOL = False


class Main(Program):
    station: Station = VAR()
    enable: BOOL = VAR_INPUT(False)
    out: INT = VAR_OUTPUT(0)
    seen: INT = VAR(0)
    pressed: BOOL = VAR(False)
    speeds: ARRAY[REAL] = VAR(bounds=(1, 3))
    label: STRING = VAR("", length=5)

    def body(self) -> None:
        self.seen = self.out  # what the code reads at its start
        self.out = 7
        self.pressed = GVL_CommissioningIO.start_button
        self.station()


def _runtime() -> tuple[Runtime, Main]:
    main = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), main)
    return rt, main


def test_a_write_lands_once_at_the_next_cycle_start_even_into_internals_and_outputs() -> None:
    rt, main = _runtime()
    rt.write("MAIN.station.count", 100)
    rt.write("MAIN.out", 3)
    rt.write("GVL_CommissioningIO.start_button", True)
    assert main.station.count == 0  # not before the cycle
    rt.run(cycles=1)
    assert (main.station.count, main.station.full, main.seen, main.pressed) == (101, True, 3, True)
    rt.run(cycles=1)
    assert (main.station.count, main.seen) == (102, 7)  # written once: the code's own value is back


def test_paths_match_case_insensitively_and_by_instance_path() -> None:
    rt, main = _runtime()
    rt.write("main.STATION.Count", 5)
    rt.write("PlcTask.Main.speeds[2]", 1.5)
    rt.run(cycles=1)
    assert (main.station.count, list(main.speeds)) == (6, [0.0, 1.5, 0.0])
    assert rt.symbol("MAIN.speeds[2]").load() == 1.5


def test_a_forced_value_wins_over_the_code_at_every_cycle_start_and_after_it_until_released() -> None:
    rt, main = _runtime()
    rt.force("MAIN.out", 3)
    assert rt.forced == {"MAIN.out": 3}
    for _ in range(3):
        rt.run(cycles=1)
        # The code read the forced value, and its own assignment did not survive the cycle.
        assert (main.seen, main.out) == (3, 3)
    rt.release("MAIN.out")
    assert rt.forced == {}
    rt.run(cycles=1)
    assert (main.seen, main.out) == (3, 7)
    rt.run(cycles=1)
    assert main.seen == 7


def test_release_all_and_force_again_replaces_the_value() -> None:
    rt, main = _runtime()
    rt.force("MAIN.out", 3)
    rt.force("main.OUT", 4)
    rt.force("GVL_CommissioningIO.start_button", True)
    assert rt.forced == {"MAIN.out": 4, "GVL_CommissioningIO.start_button": True}
    rt.run(cycles=1)
    assert (main.seen, main.pressed) == (4, True)
    rt.release_all()
    GVL_CommissioningIO.start_button = False
    rt.run(cycles=2)
    assert (rt.forced, main.seen, main.pressed) == ({}, 7, False)


def test_a_forced_variable_overrides_a_plant_model_at_the_cycle_start() -> None:
    rt, main = _runtime()
    rt.on_cycle_start.append(lambda: setattr(main, "enable", False))
    rt.force("MAIN.enable", True)
    rt.run(cycles=1)
    assert main.enable is True


@pytest.mark.parametrize(
    ("path", "value", "words"),
    [
        ("MAIN.nothing", 1, ["MAIN.nothing", "Main has no member 'nothing'"]),
        ("NOPE.x", 1, ["NOPE.x", "no program or GVL named 'NOPE'"]),
        ("MAIN", 1, ["MAIN", "not a variable"]),
        ("MAIN.station", 1, ["MAIN.station", "elementary"]),
        ("MAIN.out.x", 1, ["MAIN.out.x", "has no member 'x'"]),
        ("MAIN.out[1]", 1, ["MAIN.out[1]", "not an ARRAY"]),
        ("MAIN.speeds[4]", 1.0, ["MAIN.speeds[4]", "outside the bounds 1..3"]),
        ("MAIN.speeds[a]", 1.0, ["MAIN.speeds[a]", "not a list of integers"]),
        ("MAIN.speeds[1,2]", 1.0, ["takes 1 indices"]),
        ("MAIN.out", 70_000, ["MAIN.out", "outside the range of INT (-32768..32767)"]),
        ("MAIN.out", "7", ["MAIN.out", "cannot store str"]),
        ("MAIN.enable", 1, ["MAIN.enable", "BOOL"]),
        ("MAIN.speeds[1]", 1e40, ["MAIN.speeds[1]", "outside the range of REAL"]),
        ("MAIN.label", "too long", ["MAIN.label", "8 characters do not fit STRING(5)"]),
        ("MAIN.label", "a\x00b", ["MAIN.label", "cannot hold the NUL character"]),
        ("MAIN.a-b", 1, ["'a-b' is not a member name"]),
        ("", 1, ["a symbol path is a dotted name"]),
    ],
)
def test_a_wrong_path_or_value_is_refused_at_the_call(path: str, value: object, words: list[str]) -> None:
    rt, main = _runtime()
    for call in (rt.write, rt.force):
        with pytest.raises(AccessError) as caught:
            call(path, value)
        for word in words:
            assert word in str(caught.value)
    rt.run(cycles=1)  # nothing was queued
    assert (main.out, list(main.speeds), main.label, rt.forced) == (7, [0.0, 0.0, 0.0], "", {})


def test_release_of_a_variable_not_forced_names_it() -> None:
    rt, _ = _runtime()
    with pytest.raises(AccessError, match="MAIN.out: is not forced"):
        rt.release("MAIN.out")


def _wait_for(condition: Callable[[], bool], timeout: float = 60.0) -> None:
    """Wait until ``condition`` holds; the bound is generous, the test never measures time."""
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, "condition not reached"
        time.sleep(0.001)


def test_writes_and_forces_from_another_thread_land_in_a_background_run() -> None:
    rt, main = _runtime()
    with rt.running(realtime=False):
        writer = threading.Thread(target=rt.force, args=("MAIN.out", 11))
        writer.start()
        writer.join()
        _wait_for(lambda: main.seen == 11)
        rt.write("MAIN.station.count", -1000)
        _wait_for(lambda: main.station.count < 0)
        rt.release("MAIN.out")
        _wait_for(lambda: main.seen == 7)
    assert rt.forced == {}


def test_a_release_keeps_the_forced_value_and_a_release_with_restore_puts_the_old_one_back() -> None:
    rt, main = _runtime()
    rt.write("MAIN.speeds[2]", 1.5)
    rt.run(cycles=1)
    rt.force("MAIN.enable", True)  # an input nothing assigns: the released value stays
    rt.force("MAIN.speeds[2]", 9.0)
    rt.run(cycles=2)
    rt.force("MAIN.speeds[2]", 8.0)  # forced again: the value from before the first force is kept
    rt.run(cycles=1)
    rt.release("MAIN.enable")  # TwinCAT's <Unforce>: the forced value stays until something assigns it
    rt.release("MAIN.speeds[2]", restore=True)  # <Unforce and restore>
    assert rt.symbol("MAIN.speeds[2]").load() == 8.0  # restored at the next cycle start, as a write
    rt.run(cycles=1)
    assert (main.enable, rt.symbol("MAIN.speeds[2]").load(), rt.forced) == (True, 1.5, {})
    rt.force("MAIN.label", "abc")
    rt.release_all(restore=True)  # released before any cycle applied it: nothing to restore
    rt.run(cycles=1)
    assert main.label == ""
    rt.force("MAIN.label", "abc")
    rt.run(cycles=1)
    rt.release_all(restore=True)
    rt.run(cycles=1)
    assert main.label == ""
