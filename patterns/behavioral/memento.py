"""Memento: recipe editing with snapshot / restore and a persistent "last good" recipe.

Intent
------

Capture the state of an object in a memento without exposing that state, so
the object can be put back to it later; only the object that made the memento
can read it.

The PLC problem
---------------

An operator edits the dosing recipe on the HMI: name, dose, pump speed, mixing
time. Before trying a change they take a snapshot, and restore it if the batch
does not behave. A recipe that produced a good batch is committed as the
**last good recipe**, which must outlive the shift:

- it survives a **reset cold** (and a download and a restart of the runtime):
  on the first scan after one, the editor loads it as the working recipe;
- it is lost on a **reset origin**, which returns the machine to its delivery
  state.

That is the life of a ``VAR PERSISTENT`` variable in both vendor tables:
reset cold and download keep it, reset origin re-initialises it, and it is
written on an orderly stop or on request (TwinCAT ``FB_WritePersistentData``,
here ``Runtime.save_persistent()``). ``VAR RETAIN`` would not do: it is made
to survive a power failure and is written at the end of every cycle, and what
happens to it on a reset cold depends on the vendor. CODESYS and Beckhoff's
current remanent-variables page re-initialise RETAIN on a reset cold and on a
download (iecoop's CODESYS profile does so; its TwinCAT profile follows the
older table the course teaches, which keeps it). A last good recipe kept in
RETAIN would silently vanish on a CODESYS reset cold or download.

The snapshots themselves are editing scratch: plain ``VAR``, lost on every
reset.

Roles
-----

- Memento → ``RecipeMemento`` (``FB_RecipeMemento``): the copied recipe, a
  label and a time. Its content is read and written only through INTERNAL
  methods, so only code of the library that defines the editor can use it;
  an HMI program outside sees ``label``, ``taken_at`` and ``valid``.
- Originator → ``RecipeEditor`` (``FB_RecipeEditor``) implementing
  ``IRecipeEditor`` (``I_RecipeEditor``): the working recipe, validated
  edits, ``save_to`` / ``restore_from`` and the persistent last good recipe.
- Caretaker → ``RecipeSnapshots`` (``FB_RecipeSnapshots``): a fixed pool of
  memento slots, explicit failure when full.
- The recipe → ``Recipe`` (``ST_Recipe``), copied as a whole struct.
- Client → ``RecipeStation`` (``PRG_RecipeStation``).

IEC 61131-3 mapping
-------------------

::

    TYPE ST_Recipe : STRUCT
        sName : STRING(20); rDoseLitres : REAL; rPumpSpeed : REAL; tMix : TIME;
    END_STRUCT END_TYPE

    FUNCTION_BLOCK INTERNAL FB_RecipeMemento
        VAR stContent : ST_Recipe; sLabel : STRING(20);
            tTaken : TIME; bValid : BOOL; END_VAR
        METHOD INTERNAL Capture  VAR_INPUT stRecipe : ST_Recipe; sLabel : STRING(20); END_VAR
        METHOD INTERNAL RestoreInto
            VAR_IN_OUT stRecipe : ST_Recipe; END_VAR
        PROPERTY Label : STRING(20)          // Get only

    INTERFACE I_RecipeEditor
        METHOD Rename       : BOOL  VAR_INPUT sName : STRING(20); END_VAR
        METHOD SetDose      : BOOL  VAR_INPUT rLitres : REAL; END_VAR
        METHOD SetPumpSpeed : BOOL  VAR_INPUT rPercent : REAL; END_VAR
        METHOD SetMixTime   : BOOL  VAR_INPUT tMix : TIME; END_VAR
        METHOD Commit       : BOOL

    FUNCTION_BLOCK FB_RecipeEditor IMPLEMENTS I_RecipeEditor
        VAR_OUTPUT stWorking : ST_Recipe; bLoadedAtStart : BOOL; END_VAR
        VAR PERSISTENT stLastGood : ST_Recipe; bHasLastGood : BOOL; END_VAR
        METHOD SaveTo
            VAR_INPUT fbMemento : REFERENCE TO FB_RecipeMemento; sLabel : STRING(20); END_VAR
        METHOD RestoreFrom : BOOL
            VAR_INPUT fbMemento : REFERENCE TO FB_RecipeMemento; END_VAR

    FUNCTION_BLOCK FB_RecipeSnapshots
        VAR aSlots : ARRAY[1..SNAPSHOT_SLOTS] OF FB_RecipeMemento; END_VAR
        VAR_OUTPUT nUsed : INT; END_VAR
        METHOD Take : INT       // the slot taken; 0 when all are in use
            VAR_INPUT fbEditor : REFERENCE TO FB_RecipeEditor; sLabel : STRING(20); END_VAR
        METHOD Restore : BOOL   // FALSE for a slot not in use
            VAR_INPUT fbEditor : REFERENCE TO FB_RecipeEditor; nSlot : INT; END_VAR

When not to use it on a PLC
---------------------------

When the data to keep is one or two values, a second variable is simpler than
a memento. Do not snapshot large structures every scan (a struct copy costs
cycle time); snapshot on an operator action. And a memento is no recipe
database: recipes that must be managed, versioned or shared between machines
belong in a recipe manager or a file, not in PLC memory.

References
----------

- Gamma, Helm, Johnson, Vlissides: *Design Patterns*, Addison-Wesley 1994,
  "Memento".
- IEC 61131-3:2013 (3rd edition): structured data types, ``VAR RETAIN`` and
  ``VAR PERSISTENT``, the ``INTERNAL`` access specifier.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Remanent variables - PERSISTENT, RETAIN",
  "Data persistence", "FB_WritePersistentData".
- CODESYS Online Help: "Reset Cold", "Reset Origin", "Persistent Variables",
  "Preserving Data with Retain Variables".
- ISA-TR88.00.02 (PackML), for where recipe parameters sit in a unit's data.
"""

from __future__ import annotations

from iecoop import (
    ARRAY,
    BOOL,
    DINT,
    INT,
    INTERNAL,
    REAL,
    STRING,
    TIME,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    Interface,
    Program,
    Struct,
    T,
    adr,
    memcpy,
    method,
    prop,
    sizeof,
)
from iecoop.conversions import TIME_TO_DINT
from iecoop.functions import MID
from iecoop.runtime import Runtime, Task, now_ms
from iecoop.stdlib import R_TRIG
from patterns.showcase.entry import Column, Scenario, Showcase

__all__ = [
    "SNAPSHOT_SLOTS",
    "IRecipeEditor",
    "Recipe",
    "RecipeEditor",
    "RecipeMemento",
    "RecipeSnapshots",
    "RecipeStation",
    "describe",
    "main",
]

#: Memento slots in the snapshot pool.
SNAPSHOT_SLOTS = 4


class Recipe(Struct):
    """The dosing recipe. ST: ``TYPE ST_Recipe : STRUCT``."""

    name: STRING = VAR("", length=20)
    dose_litres: REAL = 100.0
    pump_speed: REAL = 50.0
    mix_time: TIME = T("30s")


def describe(recipe: Recipe) -> str:
    """One line for the HMI: ``'Base' 100 l at 50 % mix 30 s``."""
    return f"{recipe.name!r} {recipe.dose_litres:g} l at {recipe.pump_speed:g} % mix {recipe.mix_time // 1000} s"


class RecipeMemento(FunctionBlock, internal=True):
    """A saved copy of a recipe; only the editor's library reads or writes it.

    ST: ``FUNCTION_BLOCK FB_RecipeMemento`` with INTERNAL ``Capture`` /
    ``RestoreInto``. Its variables are locals (VAR), so nothing outside the
    block assigns them.
    """

    content: Recipe = VAR()
    tag: STRING = VAR("", length=20)
    stamp: TIME = VAR(0)
    filled: BOOL = VAR(False)

    @prop
    def label(self) -> STRING:
        return self.tag

    @prop
    def taken_at(self) -> TIME:
        return self.stamp

    @prop
    def valid(self) -> BOOL:
        return self.filled

    @method(INTERNAL)
    def capture(self, recipe: Recipe, label: STRING) -> None:
        self.content = recipe
        self.tag = label
        self.stamp = now_ms()
        self.filled = True

    @method(INTERNAL)
    def restore_into(self, recipe: Recipe) -> BOOL:
        if not self.filled:
            return False
        memcpy(adr(recipe), adr(self, "content"), sizeof(Recipe))
        return True

    @method(INTERNAL)
    def clear(self) -> None:
        self.filled = False
        self.tag = ""


class IRecipeEditor(Interface):
    """What the HMI may do with a recipe. ST: ``INTERFACE I_RecipeEditor``."""

    @method
    def rename(self, name: STRING) -> BOOL:
        raise NotImplementedError

    @method
    def set_dose(self, litres: REAL) -> BOOL:
        raise NotImplementedError

    @method
    def set_pump_speed(self, percent: REAL) -> BOOL:
        raise NotImplementedError

    @method
    def set_mix_time(self, mix_time: TIME) -> BOOL:
        raise NotImplementedError

    @method
    def commit(self) -> BOOL:
        raise NotImplementedError


class RecipeEditor(FunctionBlock, IRecipeEditor):
    """The originator: the working recipe, validated edits and the PERSISTENT last good recipe.

    ST: ``FUNCTION_BLOCK FB_RecipeEditor IMPLEMENTS I_RecipeEditor``. Edits
    outside the limits are refused (FALSE) and change nothing. On the first
    scan after a start or a reset the body loads the last good recipe, if
    there is one, into the working recipe.
    """

    working: Recipe = VAR_OUTPUT()
    loaded_at_start: BOOL = VAR_OUTPUT(False)
    last_good: Recipe = VAR(persistent=True)
    has_last_good: BOOL = VAR(False, persistent=True)
    started: BOOL = VAR(False)

    def body(self) -> None:
        # ``started`` is a plain VAR: every reset clears it, so this runs on the first scan after one.
        if not self.started:
            self.started = True
            if self.has_last_good:
                self.working = self.last_good
                self.loaded_at_start = True

    @method
    def rename(self, name: STRING) -> BOOL:
        """FALSE for a name longer than STRING(20) or one of blanks only."""
        if len(name) > 20:
            return False
        for i in range(1, len(name) + 1):
            if MID(name, 1, i) != " ":
                self.working.name = name
                return True
        return False

    @method
    def set_dose(self, litres: REAL) -> BOOL:
        if not 1.0 <= litres <= 500.0:
            return False
        self.working.dose_litres = litres
        return True

    @method
    def set_pump_speed(self, percent: REAL) -> BOOL:
        if not 10.0 <= percent <= 100.0:
            return False
        self.working.pump_speed = percent
        return True

    @method
    def set_mix_time(self, mix_time: TIME) -> BOOL:
        if not T("5s") <= mix_time <= T("10m"):
            return False
        self.working.mix_time = mix_time
        return True

    @method
    def commit(self) -> BOOL:
        """Keep the working recipe as the last good one; refused while it has no name."""
        if not self.working.name:
            return False
        self.last_good = self.working
        self.has_last_good = True
        return True

    @method
    def revert_to_last_good(self) -> BOOL:
        if not self.has_last_good:
            return False
        self.working = self.last_good
        return True

    @method
    def save_to(self, memento: RecipeMemento, label: STRING) -> None:
        memento.capture(self.working, label)

    @method
    def restore_from(self, memento: RecipeMemento) -> BOOL:
        """Put the working recipe back to ``memento``; FALSE (nothing changed) for an empty memento."""
        return memento.restore_into(self.working)


class RecipeSnapshots(FunctionBlock):
    """The caretaker: a fixed pool of mementos; it stores them and never looks inside.

    ST: ``FUNCTION_BLOCK FB_RecipeSnapshots``. ``take`` on a full pool
    answers 0 and keeps nothing; ``restore`` answers FALSE, and ``label`` /
    ``taken_at`` an empty value, for a slot number outside ``1..used``. An
    HMI checks ``full`` before offering "snapshot".
    """

    slots: ARRAY[RecipeMemento] = VAR(bounds=(1, SNAPSHOT_SLOTS))
    used: INT = VAR_OUTPUT(0)

    @prop
    def full(self) -> BOOL:
        return self.used == SNAPSHOT_SLOTS

    @method
    def take(self, editor: RecipeEditor, label: STRING) -> INT:
        """Snapshot the editor's working recipe into the next free slot; return the slot number, 0 when all are in use."""
        if self.full:
            return 0
        self.used += 1
        editor.save_to(self.slots[self.used], label)
        return self.used

    @method
    def restore(self, editor: RecipeEditor, slot: INT) -> BOOL:
        """Put snapshot ``slot`` back into the editor; FALSE, nothing changed, for a slot not in use."""
        if not self.in_use(slot):
            return False
        return editor.restore_from(self.slots[slot])

    @method
    def label(self, slot: INT) -> STRING:
        """The label of snapshot ``slot``; '' for a slot not in use."""
        if not self.in_use(slot):
            return ""
        label: STRING = self.slots[slot].label
        return label

    @method
    def taken_at(self, slot: INT) -> TIME:
        """When snapshot ``slot`` was taken; T#0s for a slot not in use."""
        if not self.in_use(slot):
            return T("0s")
        taken_at: TIME = self.slots[slot].taken_at
        return taken_at

    @method
    def drop_newest(self) -> BOOL:
        if self.used == 0:
            return False
        self.slots[self.used].clear()
        self.used -= 1
        return True

    @method
    def in_use(self, slot: INT) -> BOOL:
        """TRUE when ``slot`` holds a snapshot (slots ``1..used``)."""
        return 1 <= slot <= self.used


class RecipeStation(Program):
    """The recipe station behind the HMI page. ST: ``PROGRAM PRG_RecipeStation``.

    Edits go straight to the editor's methods; the snapshot, restore and
    commit buttons act on their rising edge inside the cycle, so a snapshot
    carries the task-clock time. The program checks ``full`` and the slot
    number through the answers of ``take`` and ``restore`` and says what
    happened in ``message``.
    """

    snapshot_button: BOOL = VAR_INPUT(False)
    restore_button: BOOL = VAR_INPUT(False)
    commit_button: BOOL = VAR_INPUT(False)
    slot: INT = VAR_INPUT(1)
    label: STRING = VAR_INPUT("", length=20)
    message: STRING = VAR_OUTPUT("", length=60)
    edges: ARRAY[R_TRIG] = VAR(bounds=(1, 3))
    editor: RecipeEditor = VAR()
    snapshots: RecipeSnapshots = VAR()

    def body(self) -> None:
        self.editor()
        self.edges[1](CLK=self.snapshot_button)
        self.edges[2](CLK=self.restore_button)
        self.edges[3](CLK=self.commit_button)
        if self.edges[1].Q:
            taken = self.snapshots.take(self.editor, self.label)
            if taken == 0:
                self.message = f"no free snapshot slot ({SNAPSHOT_SLOTS} in use)"
            else:
                at_ms: DINT = TIME_TO_DINT(self.snapshots.taken_at(taken))
                self.message = f"snapshot {taken} '{self.label}' at {at_ms} ms"
        if self.edges[2].Q:
            if self.snapshots.restore(self.editor, self.slot):
                self.message = f"restored snapshot {self.slot}"
            else:
                self.message = f"no snapshot {self.slot}"
        if self.edges[3].Q:
            self.message = "committed as last good" if self.editor.commit() else "commit refused: no name"


def main() -> None:
    """Edit, snapshot, restore and commit a recipe on the HMI, then reset cold and reset origin.

    >>> main()
    edited:       'Base' 120 l at 60 % mix 45 s
    t=  10 ms  snapshot 1 'before speed trial' at 10 ms
    edited:       'Base' 120 l at 95 % mix 45 s
    t=  30 ms  restored snapshot 1
    working:      'Base' 120 l at 60 % mix 45 s
    t=  50 ms  committed as last good
    reset cold:   'Base' 120 l at 60 % mix 45 s, loaded from last good: True
    reset origin: '' 100 l at 50 % mix 30 s, loaded from last good: False
    """
    station = RecipeStation()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), station)
    editor = station.editor
    rt.run(cycles=1)

    def press(button: str) -> None:
        at = rt.time_ms
        setattr(station, button, True)
        rt.run(cycles=1)
        setattr(station, button, False)
        rt.run(cycles=1)
        print(f"t={at:4d} ms  {station.message}")

    editor.rename("Base")
    editor.set_dose(120.0)
    editor.set_pump_speed(60.0)
    editor.set_mix_time(T("45s"))
    print(f"edited:       {describe(editor.working)}")
    station.label = "before speed trial"
    press("snapshot_button")
    editor.set_pump_speed(95.0)
    print(f"edited:       {describe(editor.working)}")
    press("restore_button")
    print(f"working:      {describe(editor.working)}")
    press("commit_button")
    for name, reset in (("reset cold:", rt.reset_cold), ("reset origin:", rt.reset_origin)):
        reset()
        rt.run(cycles=1)
        print(f"{name:<13} {describe(editor.working)}, loaded from last good: {editor.loaded_at_start}")


def _recipe(scenario: Scenario, cycle: int) -> None:
    station = scenario.program
    editor = station.editor
    if cycle == 2:
        editor.rename("Base")
        editor.set_dose(120.0)
        editor.set_pump_speed(60.0)
        editor.set_mix_time(T("45s"))
        station.label = "before speed trial"
    if cycle == 5:
        editor.set_pump_speed(95.0)
    station.snapshot_button = cycle == 3
    station.restore_button = cycle == 7
    station.commit_button = cycle == 9


SHOWCASE = Showcase(
    use_when="an operator edits a data set and must be able to return to a snapshot or the last good one",
    columns=(
        Column("recipe", lambda p: p.editor.working.name, repr),
        Column("dose l", lambda p: p.editor.working.dose_litres, ".0f"),
        Column("pump %", lambda p: p.editor.working.pump_speed, ".0f"),
        Column("snapshots", lambda p: p.snapshots.used),
        Column("message", lambda p: p.message),
    ),
    script=_recipe,
    cycles=12,
    tour_cycles=12,
)
