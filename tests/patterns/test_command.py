"""Command: the dosing-skid HMI panel, its undo history, macros and audit trail, across PLC cycles."""

from __future__ import annotations

from dataclasses import dataclass

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import NULL, AccessError, T, delete, new
from iecoop.runtime import Runtime, Task, default_clock
from patterns.behavioral.command import (
    AUDIT_DEPTH,
    BUTTONS,
    HISTORY_DEPTH,
    MACRO_CAPACITY,
    AuditAction,
    AuditTrail,
    CommandError,
    CommandHistory,
    CommandPanel,
    DosingPump,
    DosingSkid,
    DosingValve,
    ICommand,
    MacroCommand,
    Mixer,
    OpenValveCommand,
    ReceiverCommand,
    SetPumpSpeedCommand,
    StartMixerCommand,
    UndoRecord,
    speed_text,
)

State = tuple[bool, float, bool]


def _skid() -> tuple[DosingSkid, Runtime]:
    skid = DosingSkid()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), skid)
    return skid, rt


def _state(skid: DosingSkid) -> State:
    return (skid.inlet.is_open, skid.pump.speed, skid.mixer.running)


def _actions(panel: CommandPanel) -> list[tuple[str, str]]:
    lines = (panel.audit.entry(i) for i in range(1, panel.audit.count + 1))
    return [(AuditAction(line.outcome).name, line.command) for line in lines]


def _press(rt: Runtime, panel: CommandPanel, button: int, held: int = 3) -> None:
    panel.buttons[button] = True
    rt.run(cycles=held)
    panel.buttons[button] = False
    rt.run(cycles=1)


def _undo(rt: Runtime, panel: CommandPanel, held: int = 2) -> None:
    panel.undo_button = True
    rt.run(cycles=held)
    panel.undo_button = False
    rt.run(cycles=1)


# ---------------------------------------------------------------------------
# The panel across cycles
# ---------------------------------------------------------------------------


def test_a_held_button_executes_its_command_once_per_press() -> None:
    skid, rt = _skid()
    skid.panel.buttons[2] = True
    rt.run(cycles=10)
    assert skid.pump.speed == 60.0
    assert (skid.panel.history.count, skid.panel.audit.total) == (1, 1)
    skid.panel.buttons[2] = False
    rt.run(cycles=2)
    skid.panel.buttons[2] = True
    rt.run(cycles=1)
    assert (skid.panel.history.count, skid.panel.audit.total) == (2, 2)


def test_undo_button_takes_back_the_requests_newest_first() -> None:
    skid, rt = _skid()
    panel = skid.panel
    _press(rt, panel, 2)
    _press(rt, panel, 3)
    _press(rt, panel, 1)
    assert _state(skid) == (True, 60.0, True)
    seen = []
    for _ in range(3):
        _undo(rt, panel)
        seen.append(_state(skid))
    assert seen == [(False, 60.0, True), (False, 60.0, False), (False, 0.0, False)]
    assert panel.history.count == 0


def test_the_macro_runs_as_one_history_entry_and_is_undone_as_one() -> None:
    skid, rt = _skid()
    panel = skid.panel
    _press(rt, panel, 2)
    _press(rt, panel, 4)
    assert _state(skid) == (True, 25.0, True)
    assert panel.history.count == 2
    _undo(rt, panel)
    assert _state(skid) == (False, 60.0, False)
    assert _actions(panel) == [("EXECUTED", "P201 to 60 %"), ("EXECUTED", "prime skid"), ("UNDONE", "prime skid")]


def test_audit_lines_carry_the_task_clock_time() -> None:
    skid, rt = _skid()
    rt.run(cycles=7)
    skid.panel.buttons[3] = True
    rt.run(cycles=1)  # the cycle starting at 70 ms sees the edge
    skid.panel.buttons[3] = False
    rt.run(cycles=5)
    skid.panel.undo_button = True
    rt.run(cycles=1)  # 130 ms
    line_1, line_2 = skid.panel.audit.entry(1), skid.panel.audit.entry(2)
    assert (line_1.stamp, AuditAction(line_1.outcome), line_1.command) == (70, AuditAction.EXECUTED, "start M301")
    assert (line_2.stamp, AuditAction(line_2.outcome)) == (130, AuditAction.UNDONE)
    assert rt.time_ms == 140


def test_unassigned_button_and_empty_undo_are_refused_and_logged_not_faults() -> None:
    panel = CommandPanel()
    default_clock().set(0)
    panel.buttons[3] = True
    panel()
    panel(undo_button=True)
    assert _actions(panel) == [("REFUSED", "button 3 unassigned"), ("REFUSED", "undo: history empty")]
    assert panel.history.count == 0


def test_a_full_history_drops_the_oldest_entry_and_logs_the_drop() -> None:
    skid, rt = _skid()
    panel = skid.panel
    for _ in range(HISTORY_DEPTH):
        _press(rt, panel, 1, held=1)
    _press(rt, panel, 2, held=1)
    assert (panel.history.count, panel.history.dropped) == (HISTORY_DEPTH, 1)
    assert _actions(panel)[-2:] == [("DROPPED", "open XV101"), ("EXECUTED", "P201 to 60 %")]
    for _ in range(HISTORY_DEPTH):
        _undo(rt, panel, held=1)
    # The first "open" lost its undo when it was dropped: the valve stays open.
    assert _state(skid) == (True, 0.0, False)
    _undo(rt, panel, held=1)
    assert _actions(panel)[-1] == ("REFUSED", "undo: history empty")


def test_a_reset_cold_rewires_the_panel_and_empties_the_history() -> None:
    skid, rt = _skid()
    _press(rt, skid.panel, 4)
    rt.reset_cold()
    assert _state(skid) == (False, 0.0, False)
    assert (skid.panel.history.count, skid.panel.audit.count) == (0, 0)
    _press(rt, skid.panel, 4)
    _undo(rt, skid.panel)
    assert _state(skid) == (False, 0.0, False)
    assert skid.prime.count == 3


# ---------------------------------------------------------------------------
# Commands, macros and the history as blocks
# ---------------------------------------------------------------------------


@dataclass
class Bench:
    """Receivers and commands outside a runtime, injected at FB_init."""

    valve: DosingValve
    pump: DosingPump
    mixer: Mixer
    prime: MacroCommand
    outer: MacroCommand
    commands: list[ICommand]

    def state(self) -> State:
        return (self.valve.is_open, self.pump.speed, self.mixer.running)


def _bench() -> Bench:
    valve, pump, mixer = DosingValve(tag="XV1"), DosingPump(tag="P1"), Mixer(tag="M1")
    open_valve = OpenValveCommand(valve=valve)
    slow, fast = SetPumpSpeedCommand(pump=pump, speed=30.0), SetPumpSpeedCommand(pump=pump, speed=75.0)
    start = StartMixerCommand(mixer=mixer)
    prime = MacroCommand(label="prime")
    for command in (slow, open_valve, start):
        prime.add(command)
    outer = MacroCommand(label="outer")
    outer.add(fast)
    outer.add(prime)
    return Bench(valve, pump, mixer, prime, outer, [open_valve, slow, fast, start, prime, outer])


def test_commands_injected_at_fb_init_execute_on_their_receivers() -> None:
    bench = _bench()
    record = UndoRecord()
    bench.commands[2].execute(record)
    bench.commands[3].execute(record)
    assert bench.state() == (False, 75.0, True)
    assert record.used == 2
    bench.commands[3].undo(record)
    bench.commands[2].undo(record)
    assert (bench.state(), record.used) == ((False, 0.0, False), 0)


def test_a_macro_is_undone_in_reverse_order() -> None:
    pump, valve = DosingPump(), DosingValve()
    macro = MacroCommand(label="fill")
    # Interface and REFERENCE TO variables do not keep their targets alive: the caller owns them.
    steps: list[ICommand] = [SetPumpSpeedCommand(pump=pump, speed=25.0), OpenValveCommand(valve=valve)]
    for step in steps:
        macro.add(step)
    pump.set_speed(10.0)
    record = UndoRecord()
    macro.execute(record)
    assert (pump.speed, valve.is_open, record.used) == (25.0, True, 2)
    macro.undo(record)
    # The record is a stack: undone in forward order, the pump would pop the valve's step.
    assert (pump.speed, valve.is_open, record.used) == (10.0, False, 0)


def test_the_same_command_pressed_twice_is_undone_twice() -> None:
    bench = _bench()
    history = CommandHistory()
    slow, fast = bench.commands[1], bench.commands[2]
    for command in (slow, fast, slow):
        history.execute(command)
    speeds = []
    while history.undo_last():
        speeds.append(bench.pump.speed)
    assert speeds == [75.0, 30.0, 0.0]


def test_a_command_without_its_receiver_is_refused_before_touching_the_history() -> None:
    history, pump = CommandHistory(), DosingPump()
    pump_40 = SetPumpSpeedCommand(pump=pump, speed=40.0)
    assert history.execute(pump_40) is True
    unbound: list[tuple[OpenValveCommand | SetPumpSpeedCommand | StartMixerCommand, str]] = [
        (OpenValveCommand(), "open valve"), (SetPumpSpeedCommand(speed=5.0), "pump to 5 %"),
        (StartMixerCommand(), "start mixer"),
    ]
    for command, name in unbound:
        assert history.execute(command) is False
        assert (command.error, command.name) == (CommandError.NO_RECEIVER, name)
        assert command.undo(UndoRecord()) is False
    assert (history.count, history.newest.name, pump.speed) == (1, "P to 40 %", 40.0)


def test_a_command_whose_receiver_was_deleted_refuses_instead_of_writing_freed_memory() -> None:
    p_valve = new(DosingValve, tag="XV9")
    command = OpenValveCommand(valve=p_valve.deref)
    record = UndoRecord()
    assert command.execute(record) is True
    assert (command.error, command.name) == (CommandError.NONE, "open XV9")
    delete(p_valve)
    assert command.undo(record) is False
    assert (command.error, command.name, record.used) == (CommandError.NO_RECEIVER, "open valve", 1)


def test_a_deleted_receiver_is_refused_on_the_panel_and_logged() -> None:
    panel = CommandPanel()
    p_mixer = new(Mixer, tag="M9")
    start = StartMixerCommand(mixer=p_mixer.deref)
    assert panel.assign(1, start) is True
    default_clock().set(0)
    panel.buttons[1] = True
    panel()
    panel.buttons[1] = False
    panel()
    delete(p_mixer)
    panel(undo_button=True)
    panel(undo_button=False)
    panel.buttons[1] = True
    panel()
    assert _actions(panel) == [("EXECUTED", "start M9"), ("REFUSED", "start mixer"), ("REFUSED", "start mixer")]
    assert (panel.history.count, start.error) == (0, CommandError.NO_RECEIVER)


def test_macro_add_refuses_a_full_macro_too_many_steps_nulls_and_cycles() -> None:
    bench = _bench()
    open_valve, slow, fast, start = bench.commands[:4]
    prime, outer = bench.prime, bench.outer
    full = MacroCommand(label="full")
    for command in (open_valve, slow, fast, start):
        assert full.add(command) is True
    assert (full.add(slow), full.error) == (False, CommandError.MACRO_FULL)
    big = MacroCommand(label="big")
    assert big.add(full) and big.add(open_valve)
    assert (big.add(prime), big.error) == (False, CommandError.TOO_MANY_STEPS)
    assert (big.add(CommandPanel().commands[1]), big.error) == (False, CommandError.NULL_COMMAND)
    assert (outer.add(outer), outer.error) == (False, CommandError.CONTAINS_ITSELF)
    assert (prime.add(outer), prime.error) == (False, CommandError.CONTAINS_ITSELF)
    assert (full.count, big.count, prime.count, outer.count) == (4, 2, 3, 2)
    # The refusals left no macro marked busy: they still count and run.
    assert (prime.undo_steps, outer.undo_steps, big.undo_steps) == (3, 4, 5)
    record = UndoRecord()
    assert (outer.execute(record), record.used, bench.state()) == (True, 4, (True, 30.0, True))
    assert (big.add(fast), big.error) == (True, CommandError.NONE)


def test_a_macro_is_all_or_nothing_when_a_command_refuses() -> None:
    pump, valve = DosingPump(), DosingValve()
    pump.set_speed(10.0)
    no_mixer = StartMixerCommand()
    macro = MacroCommand(label="fill")
    steps: list[ICommand] = [SetPumpSpeedCommand(pump=pump, speed=25.0), OpenValveCommand(valve=valve), no_mixer]
    for step in steps:
        assert macro.add(step) is True
    record = UndoRecord()
    assert macro.execute(record) is False
    assert (macro.error, no_mixer.error) == (CommandError.STEP_REFUSED, CommandError.NO_RECEIVER)
    # The pump and the valve were taken back, newest first; the record is empty again.
    assert (pump.speed, valve.is_open, record.used) == (10.0, False, 0)
    history = CommandHistory()
    assert (history.execute(macro), history.count) == (False, 0)


def test_a_macro_refuses_a_record_without_room_for_its_steps() -> None:
    bench = _bench()
    record = UndoRecord()
    for _ in range(4):
        assert bench.commands[0].execute(record) is True
    prime = bench.prime
    assert (prime.execute(record), prime.error, record.used) == (False, CommandError.RECORD_FULL, 4)
    assert bench.state() == (True, 0.0, False)
    for _ in range(2):
        assert bench.commands[1].execute(record) is True
    start = StartMixerCommand(mixer=bench.mixer)
    assert (start.execute(record), start.error, record.used) == (False, CommandError.RECORD_FULL, 6)
    assert bench.mixer.running is False


def test_panel_assign_checks_the_button_number_and_the_command() -> None:
    panel = CommandPanel()
    assert (panel.assign(BUTTONS + 1, MacroCommand()), panel.error) == (False, CommandError.NO_BUTTON)
    assert (panel.assign(0, MacroCommand()), panel.error) == (False, CommandError.NO_BUTTON)
    assert (panel.assign(1, panel.commands[2]), panel.error) == (False, CommandError.NULL_COMMAND)
    assert not panel.commands[1]
    assert (panel.assign(BUTTONS, MacroCommand()), panel.error) == (True, CommandError.NONE)


def test_history_ends_and_protected_steps_are_guarded() -> None:
    history = CommandHistory()
    assert (history.newest, history.oldest) == (NULL, NULL)
    assert history.undo_last() is False
    valve = DosingValve()
    command = OpenValveCommand(valve=valve)
    with pytest.raises(AccessError, match=r"PROTECTED METHOD ReceiverCommand\.pop_step cannot be called"):
        command.pop_step(UndoRecord())
    assert command.undo(UndoRecord()) is False
    assert command.error == CommandError.NOTHING_TO_UNDO
    with pytest.raises(TypeError, match="ABSTRACT"):
        ReceiverCommand()
    assert history.execute(command) and history.undo_last()
    # Undone back to empty: the ends are null again, not the stale entry.
    assert (history.count, history.newest, history.oldest) == (0, NULL, NULL)


def test_the_audit_trail_keeps_the_newest_lines() -> None:
    trail = AuditTrail()
    clock = default_clock()
    for n in range(AUDIT_DEPTH + 5):
        clock.set(n * 1_000_000)
        trail.log(AuditAction.EXECUTED, f"request {n}")
    assert (trail.count, trail.total) == (AUDIT_DEPTH, AUDIT_DEPTH + 5)
    assert (trail.entry(1).command, trail.entry(1).stamp) == ("request 5", 5)
    assert trail.entry(AUDIT_DEPTH).command == f"request {AUDIT_DEPTH + 4}"
    for index in (0, -1, AUDIT_DEPTH + 1):
        assert (trail.entry(index).command, trail.entry(index).stamp) == ("", 0)


@pytest.mark.parametrize(("percent", "text"), [(60.0, "60"), (25.0, "25"), (12.5, "12.5"), (0.0, "0"), (99.94, "99.9"), (-7.5, "-7.5"), (-0.04, "0")])
def test_speed_text_prints_like_the_hmi(percent: float, text: str) -> None:
    assert speed_text(percent) == text


# ---------------------------------------------------------------------------
# Invariant: executes followed by as many undos give back the original state
# ---------------------------------------------------------------------------

INITIAL = st.tuples(st.booleans(), st.sampled_from([0.0, 12.5, 30.0, 100.0]), st.booleans())


def _set(bench: Bench, state: State) -> None:
    bench.valve.open() if state[0] else bench.valve.close()
    bench.pump.set_speed(state[1])
    bench.mixer.start() if state[2] else bench.mixer.stop()


@settings(max_examples=60, deadline=None)
@given(initial=INITIAL, presses=st.lists(st.integers(0, 5), max_size=HISTORY_DEPTH))
def test_undoing_every_press_restores_the_receivers(initial: State, presses: list[int]) -> None:
    bench = _bench()
    _set(bench, initial)
    history = CommandHistory()
    for index in presses:
        history.execute(bench.commands[index])
    for _ in presses:
        assert history.undo_last() is True
    assert bench.state() == initial
    assert history.undo_last() is False


@settings(max_examples=40, deadline=None)
@given(initial=INITIAL, presses=st.lists(st.integers(0, 5), min_size=HISTORY_DEPTH + 1, max_size=3 * HISTORY_DEPTH))
def test_undo_reaches_back_exactly_history_depth_presses(initial: State, presses: list[int]) -> None:
    bench, model = _bench(), _bench()
    _set(bench, initial)
    _set(model, initial)
    history = CommandHistory()
    for index in presses:
        history.execute(bench.commands[index])
    kept = len(presses) - HISTORY_DEPTH
    record = UndoRecord()
    for index in presses[:kept]:
        model.commands[index].execute(record)
        record.used = 0
    while history.undo_last():
        pass
    assert history.dropped == kept
    assert bench.state() == model.state()
