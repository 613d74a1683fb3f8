"""Memento: recipe snapshots on the HMI and the PERSISTENT last good recipe across resets and restarts."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import BOOL, AccessError, Program, T, VAR
from iecoop.runtime import Runtime, Task
from patterns.behavioral.memento import (
    SNAPSHOT_SLOTS,
    Recipe,
    RecipeEditor,
    RecipeMemento,
    RecipeSnapshots,
    RecipeStation,
    describe,
)
from tests import checked_only

Fields = tuple[str, float, float, int]
DEFAULT: Fields = ("", 100.0, 50.0, 30_000)


def _fields(recipe: Recipe) -> Fields:
    return (recipe.name, recipe.dose_litres, recipe.pump_speed, recipe.mix_time)


def _station(store: str | Path = ":memory:", profile: str = "twincat") -> tuple[RecipeStation, Runtime]:
    station = RecipeStation()
    rt = Runtime(store=store, profile=profile)
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), station)
    rt.run(cycles=1)
    return station, rt


def _press(rt: Runtime, station: RecipeStation, button: str, held: int = 3) -> str:
    setattr(station, button, True)
    rt.run(cycles=held)
    setattr(station, button, False)
    rt.run(cycles=1)
    return station.message


def _edit(
    editor: RecipeEditor, name: str = "Base", dose: float = 120.0, speed: float = 60.0, mix: int = 45_000
) -> None:
    assert editor.rename(name) and editor.set_dose(dose) and editor.set_pump_speed(speed) and editor.set_mix_time(mix)


# ---------------------------------------------------------------------------
# Snapshot / restore on the HMI, across cycles
# ---------------------------------------------------------------------------


def test_a_held_snapshot_button_takes_one_snapshot_and_restore_brings_it_back() -> None:
    station, rt = _station()
    editor = station.editor
    _edit(editor)
    station.label = "before trial"
    assert _press(rt, station, "snapshot_button", held=5) == "snapshot 1 'before trial' at 10 ms"
    assert station.snapshots.used == 1
    assert editor.set_pump_speed(95.0) and editor.set_dose(300.0)
    station.slot = 1
    assert _press(rt, station, "restore_button") == "restored snapshot 1"
    assert _fields(editor.working) == ("Base", 120.0, 60.0, 45_000)


def test_snapshots_are_independent_copies() -> None:
    station, rt = _station()
    editor = station.editor
    speeds = (40.0, 55.0, 70.0)
    for speed in speeds:
        assert editor.set_pump_speed(speed)
        _press(rt, station, "snapshot_button", held=1)
    assert editor.set_pump_speed(99.0)
    for slot, speed in enumerate(speeds, start=1):
        station.snapshots.restore(editor, slot)
        assert editor.working.pump_speed == speed
    assert [station.snapshots.label(slot) for slot in (1, 2, 3)] == ["", "", ""]
    assert [station.snapshots.taken_at(slot) for slot in (1, 2, 3)] == [10, 30, 50]


def test_edits_outside_the_limits_are_refused_and_change_nothing() -> None:
    editor = RecipeEditor()
    _edit(editor)
    assert editor.rename("   ") is False
    assert editor.rename("x" * 21) is False
    assert editor.set_dose(0.5) is False
    assert editor.set_dose(501.0) is False
    assert editor.set_pump_speed(9.9) is False
    assert editor.set_mix_time(T("11m")) is False
    assert _fields(editor.working) == ("Base", 120.0, 60.0, 45_000)


def test_a_recipe_without_a_name_cannot_be_committed() -> None:
    station, rt = _station()
    assert _press(rt, station, "commit_button") == "commit refused: no name"
    assert station.editor.has_last_good is False
    assert station.editor.rename("Base")
    assert _press(rt, station, "commit_button") == "committed as last good"
    assert _fields(station.editor.last_good)[0] == "Base"


def test_a_full_pool_and_unused_slots_are_refused_in_code_and_answered_on_the_hmi() -> None:
    station, rt = _station()
    for _ in range(SNAPSHOT_SLOTS):
        _press(rt, station, "snapshot_button", held=1)
    assert station.snapshots.full
    assert _press(rt, station, "snapshot_button") == f"no free snapshot slot ({SNAPSHOT_SLOTS} in use)"
    assert station.snapshots.take(station.editor, "one more") == 0
    assert station.snapshots.used == SNAPSHOT_SLOTS
    assert station.snapshots.label(SNAPSHOT_SLOTS) != "one more"
    assert station.snapshots.drop_newest() is True
    station.slot = SNAPSHOT_SLOTS
    assert _press(rt, station, "restore_button") == f"no snapshot {SNAPSHOT_SLOTS}"
    station.editor.set_dose(250.0)
    for slot in (0, -1, SNAPSHOT_SLOTS, SNAPSHOT_SLOTS + 1):
        assert station.snapshots.in_use(slot) is False
        assert station.snapshots.restore(station.editor, slot) is False
        assert (station.snapshots.label(slot), station.snapshots.taken_at(slot)) == ("", 0)
    assert station.editor.working.dose_litres == 250.0
    assert station.snapshots.used == SNAPSHOT_SLOTS - 1
    # A freed slot takes the next snapshot.
    assert station.snapshots.take(station.editor, "again") == SNAPSHOT_SLOTS
    assert station.snapshots.label(SNAPSHOT_SLOTS) == "again"


def test_the_memento_content_is_sealed_from_outside_the_library() -> None:
    snapshots, editor = RecipeSnapshots(), RecipeEditor()
    _edit(editor)
    snapshots.take(editor, "kept")
    memento: RecipeMemento = snapshots.slots[1]
    assert (memento.label, memento.valid) == ("kept", True)
    with pytest.raises(AccessError, match=r"INTERNAL METHOD RecipeMemento\.capture cannot be called"):
        memento.capture(editor.working, "forged")
    with pytest.raises(AccessError, match=r"INTERNAL METHOD RecipeMemento\.restore_into cannot be called"):
        memento.restore_into(editor.working)
    with pytest.raises(AccessError, match=r"INTERNAL FUNCTION_BLOCK RecipeMemento cannot be instantiated"):
        RecipeMemento()
    assert memento.label == "kept"


@checked_only
def test_the_memento_and_editor_variables_cannot_be_assigned_from_outside() -> None:
    snapshots, editor = RecipeSnapshots(), RecipeEditor()
    _edit(editor)
    snapshots.take(editor, "kept")
    memento: RecipeMemento = snapshots.slots[1]
    with pytest.raises(AccessError, match=r"VAR RecipeMemento\.content cannot be written from"):
        memento.content = Recipe(name="forged")
    with pytest.raises(AccessError, match=r"VAR RecipeEditor\.last_good cannot be written from"):
        editor.last_good = Recipe(name="forged")
    assert (memento.content.name, editor.has_last_good) == ("Base", False)


def test_restoring_from_an_empty_memento_is_refused() -> None:
    snapshots, editor = RecipeSnapshots(), RecipeEditor()
    _edit(editor)
    assert editor.restore_from(snapshots.slots[2]) is False
    assert _fields(editor.working) == ("Base", 120.0, 60.0, 45_000)


# ---------------------------------------------------------------------------
# The last good recipe: PERSISTENT across resets and restarts
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("profile", ["twincat", "codesys"])
def test_reset_cold_restores_the_last_good_recipe_and_clears_the_snapshots(profile: str) -> None:
    station, rt = _station(profile=profile)
    editor = station.editor
    _edit(editor)
    _press(rt, station, "commit_button")
    assert editor.set_pump_speed(90.0)
    _press(rt, station, "snapshot_button")
    rt.reset_cold()
    assert _fields(editor.working) == DEFAULT  # re-initialised; the first scan loads the last good recipe
    rt.run(cycles=1)
    assert _fields(editor.working) == ("Base", 120.0, 60.0, 45_000)
    assert editor.loaded_at_start is True
    assert station.snapshots.used == 0


def test_reset_origin_loses_the_last_good_recipe() -> None:
    station, rt = _station()
    editor = station.editor
    _edit(editor)
    _press(rt, station, "commit_button")
    rt.reset_origin()
    rt.run(cycles=3)
    assert (_fields(editor.working), editor.has_last_good, editor.loaded_at_start) == (DEFAULT, False, False)
    rt.reset_cold()
    rt.run(cycles=1)
    assert _fields(editor.working) == DEFAULT


class RetainedCopy(Program):
    """The same recipe kept twice: RETAIN beside the editor's PERSISTENT last good."""

    editor: RecipeEditor = VAR()
    retained: Recipe = VAR(retain=True)
    kept: BOOL = VAR(False, retain=True)

    def body(self) -> None:
        self.editor()
        if self.editor.has_last_good and not self.kept:
            self.retained = self.editor.last_good
            self.kept = True


@pytest.mark.parametrize("event", ["reset_cold", "download"])
def test_a_retain_copy_would_not_survive_where_persistent_does(event: str) -> None:
    program = RetainedCopy()
    rt = Runtime(store=":memory:", profile="codesys")
    rt.add_task(Task("PlcTask", interval=T("10ms")), program)
    _edit(program.editor)
    assert program.editor.commit()
    rt.run(cycles=2)
    assert program.retained.name == "Base"
    getattr(rt, event)()
    assert (program.retained.name, program.kept) == ("", False)
    assert program.editor.last_good.name == "Base"


def test_a_restart_on_the_same_store_loads_the_saved_last_good_recipe(tmp_path: Path) -> None:
    store = tmp_path / "plant.retain"
    station, rt = _station(store)
    _edit(station.editor, name="Night", dose=80.0)
    _press(rt, station, "commit_button")
    del rt  # the process dies before any save; the store's lock goes with it
    unsaved, rt_unsaved = _station(store)
    # PERSISTENT data is written on stop or on request, not every cycle.
    assert (_fields(unsaved.editor.working), unsaved.editor.loaded_at_start) == (DEFAULT, False)
    _edit(unsaved.editor, name="Night", dose=80.0)
    _press(rt_unsaved, unsaved, "commit_button")
    rt_unsaved.save_persistent()
    del rt_unsaved  # dies again, after the save this time
    restarted, rt_restarted = _station(store)
    assert _fields(restarted.editor.working) == ("Night", 80.0, 60.0, 45_000)
    assert restarted.editor.loaded_at_start is True
    rt_restarted.stop()


def test_after_a_reset_origin_a_restart_finds_no_last_good_recipe(tmp_path: Path) -> None:
    store = tmp_path / "plant.retain"
    station, rt = _station(store)
    _edit(station.editor)
    _press(rt, station, "commit_button")
    rt.save_persistent()
    rt.reset_origin()
    rt.stop()
    restarted, _rt = _station(store)
    assert (_fields(restarted.editor.working), restarted.editor.has_last_good) == (DEFAULT, False)


# ---------------------------------------------------------------------------
# Invariants
# ---------------------------------------------------------------------------

EDITS = st.lists(
    st.one_of(
        st.tuples(st.just("rename"), st.text("ABCxyz 09", min_size=0, max_size=24)),
        st.tuples(st.just("set_dose"), st.floats(-10.0, 600.0, width=32)),
        st.tuples(st.just("set_pump_speed"), st.floats(0.0, 120.0, width=32)),
        st.tuples(st.just("set_mix_time"), st.integers(0, 700_000)),
    ),
    max_size=12,
)


@settings(max_examples=60, deadline=None)
@given(before=EDITS, after=EDITS)
def test_restore_gives_back_exactly_the_snapshot_whatever_was_edited_since(
    before: list[tuple[str, object]], after: list[tuple[str, object]]
) -> None:
    snapshots, editor = RecipeSnapshots(), RecipeEditor()
    for name, value in before:
        getattr(editor, name)(value)
    taken = _fields(editor.working)
    slot = snapshots.take(editor, "t")
    for name, value in after:
        getattr(editor, name)(value)
    snapshots.restore(editor, slot)
    assert _fields(editor.working) == taken


@settings(max_examples=25, deadline=None)
@given(edits=EDITS)
def test_whatever_was_committed_is_the_working_recipe_after_a_reset_cold(edits: list[tuple[str, object]]) -> None:
    station, rt = _station()
    editor = station.editor
    assert editor.rename("R")
    for name, value in edits:
        getattr(editor, name)(value)
    committed = _fields(editor.working)
    assert editor.commit() is True  # rename() never accepts a blank name, so there is always one
    assert editor.set_dose(1.0)
    rt.reset_cold()
    assert _fields(editor.working) == DEFAULT
    rt.run(cycles=1)
    assert _fields(editor.working) == committed
    assert describe(editor.working).startswith(repr(committed[0]))
