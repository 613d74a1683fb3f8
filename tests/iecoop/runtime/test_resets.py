"""Resets, download, online change, restart and faults against the vendor tables.

docs/concepts/retain-persistent.md gives what each operation does to plain
VAR, VAR RETAIN and VAR PERSISTENT in each vendor profile (CODESYS 3.5's table;
for TwinCAT, RETAIN is kept on reset cold and download). docs/concepts/lifecycle.md
gives which of FB_init / FB_reinit / FB_exit run with which flags, the order
along the inheritance chain, the order of nested instances and where
declaration-site inputs and ``call_after_init`` come in.

Every table row is checked at every place a variable can live: the program
itself, a nested function block, the elements of an ARRAY OF FB, a GVL used
through VAR_EXTERNAL, and a VAR_STAT block (one per class).
"""

from __future__ import annotations

import ctypes
import struct
import typing
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest

from iecoop import (
    ARRAY,
    BOOL,
    DINT,
    INT,
    UINT,
    VAR,
    VAR_EXTERNAL,
    VAR_INPUT,
    VAR_STAT,
    ExceptionCode,
    FunctionBlock,
    GlobalVariables,
    Interface,
    PlcException,
    Program,
    call_after_init,
    gvl,
    method,
)
from iecoop.gvl import global_lists
from iecoop.pou import static_blocks
from iecoop.profiles import get_profile
from iecoop.runtime import Fault, Runtime, Task
from iecoop.runtime.store import ImageLayout, RemanentStore

PROFILES = ("twincat", "codesys")
PAGE = 4096
CYCLES = 3

# ---------------------------------------------------------------------------
# The application of the table tests: a program with its own, nested, array
# and global variables, each class plain / RETAIN / PERSISTENT.
# ---------------------------------------------------------------------------


class Cell(FunctionBlock):
    plain: INT = VAR(1)
    kept: INT = VAR(2, retain=True)
    saved: DINT = VAR(3, persistent=True)
    calls: DINT = VAR_STAT(100)

    def body(self) -> None:
        self.plain += 10
        self.kept += 10
        self.saved += 10
        self.calls += 1


@gvl
class GVL_ResetsPlant(GlobalVariables):
    rs_plain: INT = 1
    rs_kept: INT = VAR(2, retain=True)
    rs_saved: DINT = VAR(3, persistent=True)


class Cabinet(Program):
    plain: INT = VAR(1)
    kept: INT = VAR(2, retain=True)
    saved: DINT = VAR(3, persistent=True)
    unit: Cell = VAR()
    cells: ARRAY[Cell] = VAR(bounds=(1, 2))
    rs_plain: INT = VAR_EXTERNAL()
    rs_kept: INT = VAR_EXTERNAL()
    rs_saved: DINT = VAR_EXTERNAL()

    def body(self) -> None:
        self.plain += 10
        self.kept += 10
        self.saved += 10
        self.unit()
        for cell in self.cells:
            cell()
        self.rs_plain += 10
        self.rs_kept += 10
        self.rs_saved += 10


class CabinetV2(Cabinet):
    """The changed declaration of an online change: one variable added."""

    added: INT = VAR(7)


Triple = tuple[int, int, int]
INITIAL: Triple = (1, 2, 3)
RAN: Triple = (1 + 10 * CYCLES, 2 + 10 * CYCLES, 3 + 10 * CYCLES)
STAT_INITIAL, STAT_RAN = 100, 100 + 3 * CYCLES  # three Cell calls per cycle


def _triple(block: Any) -> Triple:
    return (block.plain, block.kept, block.saved)


def _places(program: Cabinet) -> dict[str, Triple]:
    return {
        "program": _triple(program),
        "nested FB": _triple(program.unit),
        "ARRAY OF FB [1]": _triple(program.cells[1]),
        "ARRAY OF FB [2]": _triple(program.cells[2]),
        "GVL": (GVL_ResetsPlant.rs_plain, GVL_ResetsPlant.rs_kept, GVL_ResetsPlant.rs_saved),
    }


def _var_stat(program: Cabinet) -> int:
    """Cell's VAR_STAT, one variable for every Cell instance."""
    shared = {program.unit.calls, program.cells[1].calls, program.cells[2].calls}
    assert len(shared) == 1
    return shared.pop()


def _fresh_process_globals() -> None:
    """What a new process starts with: every GVL and VAR_STAT block at its initial values."""
    Runtime(store=":memory:").reset_origin()


def _cabinet_runtime(store: Path | str, profile: str, program: Cabinet | None = None) -> tuple[Runtime, Cabinet]:
    program = Cabinet() if program is None else program
    rt = Runtime(store=store, profile=profile)
    rt.add_task(Task("PlcTask", interval=10, priority=20), program)
    return rt, program


# ---------------------------------------------------------------------------
# Lifecycle recording: every FB_init / FB_reinit / FB_exit / call_after_init
# with the instance it ran on (resolved to an instance path when asserted).
# ---------------------------------------------------------------------------

events: list[tuple[int, str]] = []


def _record(block: Any, text: str) -> None:
    events.append((ctypes.addressof(block), text))


class Part(FunctionBlock):
    n: INT = VAR(0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        _record(self, f"Part.FB_init({init_retains}, {in_copy_code}) n={self.n}")
        return False

    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        _record(self, f"Part.FB_exit({in_copy_code})")
        return False

    def fb_reinit(self) -> BOOL:
        _record(self, f"Part.FB_reinit n={self.n}")
        return False

    def body(self) -> None:
        self.n += 1


class AxisBase(FunctionBlock):
    brake: Part = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, axis_id: INT = 0) -> BOOL:
        _record(self, f"AxisBase.FB_init({init_retains}, {in_copy_code}) axis_id={axis_id}")
        return False

    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        _record(self, f"AxisBase.FB_exit({in_copy_code})")
        return False

    def fb_reinit(self) -> BOOL:
        _record(self, "AxisBase.FB_reinit")
        return False


class Axis(AxisBase):
    encoder: Part = VAR()
    speed: INT = VAR_INPUT(0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, axis_id: INT = 0) -> BOOL:
        _record(self, f"Axis.FB_init({init_retains}, {in_copy_code}) speed={self.speed}")
        return False

    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        _record(self, f"Axis.FB_exit({in_copy_code})")
        return False

    def fb_reinit(self) -> BOOL:  # does not call super().fb_reinit(): AxisBase.FB_reinit must not run
        _record(self, "Axis.FB_reinit")
        return False

    @call_after_init
    def ready(self) -> None:
        _record(self, f"Axis.call_after_init speed={self.speed}")

    def body(self) -> None:
        self.brake()
        self.encoder()


class Line(Program):
    x: Axis = VAR({"speed": 5}, fb_init={"axis_id": 7})
    cells: ARRAY[Part] = VAR(bounds=(1, 2))

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        _record(self, f"Line.FB_init({init_retains}, {in_copy_code})")
        return False

    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        _record(self, f"Line.FB_exit({in_copy_code})")
        return False

    def fb_reinit(self) -> BOOL:
        _record(self, "Line.FB_reinit")
        return False

    def body(self) -> None:
        self.x()
        for part in self.cells:
            part()


class LineV2(Line):
    extra: INT = VAR(0)


@gvl
class GVL_ResetsTracked(GlobalVariables):
    rs_tracked: Part = VAR()


class Station(FunctionBlock):
    shared: Part = VAR_STAT()


def _instance_paths(block: Any, path: str, into: dict[int, str], *, root: bool = True) -> dict[int, str]:
    """Address -> instance path of ``block`` and every FB instance inside it.

    A GVL or VAR_STAT block (``root=False``) has no type tag, so its first member
    shares its address; only its members are named.
    """
    if root:
        into[ctypes.addressof(block)] = path
    for found in type(block)._iec_children_:
        for child, label in zip(found.members(block), found.labels):
            _instance_paths(child, path + label, into)
    return into


def _global_paths() -> dict[int, str]:
    """The FB instances of every GVL and VAR_STAT block in the process, by path."""
    paths: dict[int, str] = {}
    for name, block in global_lists().items():
        _instance_paths(block, name, paths, root=False)
    for cls, block in static_blocks():
        _instance_paths(block, f"{cls.__qualname__}.VAR_STAT", paths, root=False)
    return paths


def _sequence(*roots: tuple[Any, str], prefix: str = "") -> list[str]:
    """The recorded events as ``"path: event"``, only those whose path starts with ``prefix``."""
    paths = _global_paths()
    for block, path in roots:
        _instance_paths(block, path, paths)
    rendered = [f"{paths.get(address, '?')}: {text}" for address, text in events]
    return [line for line in rendered if line.startswith(prefix)]


def _init_tree(path: str, init_retains: bool, in_copy_code: bool, *, n: int = 0) -> list[str]:
    """FB_init of a Line: members first in declaration order, each completely; base before derived."""
    flags = f"({init_retains}, {in_copy_code})"
    return [
        f"{path}.x.brake: Part.FB_init{flags} n={n}",
        f"{path}.x.encoder: Part.FB_init{flags} n={n}",
        f"{path}.x: AxisBase.FB_init{flags} axis_id=7",
        f"{path}.x: Axis.FB_init{flags} speed=0",  # the declaration-site input comes after FB_init
        f"{path}.x: Axis.call_after_init speed=5",
        f"{path}.cells[1]: Part.FB_init{flags} n={n}",
        f"{path}.cells[2]: Part.FB_init{flags} n={n}",
        f"{path}: Line.FB_init{flags}",
    ]


def _exit_tree(path: str, in_copy_code: bool) -> list[str]:
    """FB_exit of a Line: the block itself derived first, then base; then its members in reverse."""
    return [
        f"{path}: Line.FB_exit({in_copy_code})",
        f"{path}.cells[2]: Part.FB_exit({in_copy_code})",
        f"{path}.cells[1]: Part.FB_exit({in_copy_code})",
        f"{path}.x: Axis.FB_exit({in_copy_code})",
        f"{path}.x: AxisBase.FB_exit({in_copy_code})",
        f"{path}.x.encoder: Part.FB_exit({in_copy_code})",
        f"{path}.x.brake: Part.FB_exit({in_copy_code})",
    ]


def _reinit_tree(path: str, n: int) -> list[str]:
    """FB_reinit after the copy: members first, only the most derived FB_reinit; the copied data is visible."""
    return [
        f"{path}.x.brake: Part.FB_reinit n={n}",
        f"{path}.x.encoder: Part.FB_reinit n={n}",
        f"{path}.x: Axis.FB_reinit",
        f"{path}.cells[1]: Part.FB_reinit n={n}",
        f"{path}.cells[2]: Part.FB_reinit n={n}",
        f"{path}: Line.FB_reinit",
    ]


def _global_reinit(init_retains: bool) -> list[str]:
    return [
        "GVL_ResetsTracked.rs_tracked: Part.FB_exit(False)",
        f"GVL_ResetsTracked.rs_tracked: Part.FB_init({init_retains}, False) n=0",
    ]


def _static_reinit(init_retains: bool) -> list[str]:
    return [
        "Station.VAR_STAT.shared: Part.FB_exit(False)",
        f"Station.VAR_STAT.shared: Part.FB_init({init_retains}, False) n=0",
    ]


def _line_runtime(profile: str = "twincat") -> tuple[Runtime, Line]:
    line = Line()
    rt = Runtime(store=":memory:", profile=profile)
    rt.add_task(Task("PlcTask", interval=10), line)
    return rt, line


@pytest.fixture(autouse=True)
def _fresh_application() -> Iterator[None]:
    _fresh_process_globals()
    events.clear()
    yield
    events.clear()


@contextmanager
def _recorded_warnings() -> Iterator[list[warnings.WarningMessage]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield caught


def _flip(path: Path, offset: int) -> None:
    raw = bytearray(path.read_bytes())
    raw[offset] ^= 0x40
    path.write_bytes(bytes(raw))


# ---------------------------------------------------------------------------
# The tables: every operation x every variable class x every place
# ---------------------------------------------------------------------------

INIT, KEPT = "reinit", "kept"
Row = tuple[str, str, str]  # plain VAR, VAR RETAIN, VAR PERSISTENT

TABLE: dict[tuple[str, str], Row] = {
    # TwinCAT 3: RETAIN kept on reset cold and download (docs/concepts/retain-persistent.md).
    ("twincat", "reset_cold"): (INIT, KEPT, KEPT),
    ("twincat", "reset_origin"): (INIT, INIT, INIT),
    ("twincat", "download"): (INIT, KEPT, KEPT),
    ("twincat", "online_change"): (KEPT, KEPT, KEPT),
    ("twincat", "online_change_class"): (KEPT, KEPT, KEPT),
    ("twincat", "online_change_instance"): (KEPT, KEPT, KEPT),
    ("twincat", "restart"): (INIT, KEPT, KEPT),
    # CODESYS 3.5: the CODESYS table of docs/concepts/retain-persistent.md.
    ("codesys", "reset_warm"): (INIT, KEPT, KEPT),
    ("codesys", "reset_cold"): (INIT, INIT, KEPT),
    ("codesys", "reset_origin"): (INIT, INIT, INIT),
    ("codesys", "download"): (INIT, INIT, KEPT),
    ("codesys", "online_change"): (KEPT, KEPT, KEPT),
    ("codesys", "online_change_class"): (KEPT, KEPT, KEPT),
    ("codesys", "online_change_instance"): (KEPT, KEPT, KEPT),
    ("codesys", "restart"): (INIT, KEPT, KEPT),
}


def _apply(operation: str, rt: Runtime, program: Cabinet, store: Path, profile: str) -> tuple[Runtime, Cabinet]:
    """Do ``operation``; return the runtime and program instance that run afterwards."""
    if operation == "online_change":
        rt.online_change()
    elif operation == "online_change_class":
        rt.online_change(replace={"PlcTask.Cabinet": CabinetV2})
    elif operation == "online_change_instance":
        rt.online_change(replace={"PlcTask.Cabinet": CabinetV2()})
    elif operation == "restart":
        rt.stop()
        _fresh_process_globals()
        rt, program = _cabinet_runtime(store, profile)
        rt.run(cycles=0)
        return rt, program
    else:
        getattr(rt, operation)()
    replaced = rt.programs()["PlcTask.Cabinet"]
    assert isinstance(replaced, Cabinet)
    return rt, replaced


@pytest.mark.parametrize(("profile", "operation"), list(TABLE), ids=[f"{p}-{o}" for p, o in TABLE])
def test_every_table_row_at_every_place(tmp_path: Path, profile: str, operation: str) -> None:
    rt, program = _cabinet_runtime(tmp_path, profile)
    rt.run(cycles=CYCLES)
    assert _places(program) == dict.fromkeys(_places(program), RAN)
    rt, program = _apply(operation, rt, program, tmp_path, profile)
    expected = tuple(
        ran if what == KEPT else initial for what, ran, initial in zip(TABLE[profile, operation], RAN, INITIAL)
    )
    assert _places(program) == dict.fromkeys(_places(program), expected)
    # The cycles go on from there.
    rt.run(cycles=1)
    assert _places(program)["program"] == tuple(v + 10 for v in expected)
    rt.stop()


@pytest.mark.parametrize(
    ("profile", "operation", "kept"),
    [
        (profile, operation, operation.startswith("online_change"))
        for profile, operation in TABLE
        if operation != "restart"
    ],
)
def test_var_stat_is_plain_data_of_the_application(tmp_path: Path, profile: str, operation: str, kept: bool) -> None:
    rt, program = _cabinet_runtime(tmp_path, profile)
    rt.run(cycles=CYCLES)
    assert _var_stat(program) == STAT_RAN
    rt, program = _apply(operation, rt, program, tmp_path, profile)
    assert _var_stat(program) == (STAT_RAN if kept else STAT_INITIAL)


def test_reset_warm_is_not_offered_by_the_twincat_profile(tmp_path: Path) -> None:
    rt, program = _cabinet_runtime(tmp_path, "twincat")
    rt.run(cycles=CYCLES)
    with pytest.raises(RuntimeError, match=r"^the twincat profile has no reset warm \(TwinCAT 3 offers reset cold"):
        rt.reset_warm()
    assert _places(program) == dict.fromkeys(_places(program), RAN)
    assert _var_stat(program) == STAT_RAN
    rt.run(cycles=1)  # the runtime is not left in a fault or half-reset state
    assert _triple(program) == tuple(v + 10 for v in RAN)


def test_the_profile_flags_match_the_tables() -> None:
    twincat, codesys = get_profile("twincat"), get_profile("codesys")
    assert (twincat.has_reset_warm, twincat.retain_on_reset_cold, twincat.retain_on_download) == (False, True, True)
    assert (codesys.has_reset_warm, codesys.retain_on_reset_cold, codesys.retain_on_download) == (True, False, False)
    assert Runtime(store=":memory:", profile="CODESYS").profile is codesys
    with pytest.raises(ValueError, match=r"unknown vendor profile 'beckhoff'; known profiles: codesys, twincat"):
        Runtime(store=":memory:", profile="beckhoff")


@pytest.mark.parametrize("profile", PROFILES)
def test_reset_origin_clears_the_store(tmp_path: Path, profile: str) -> None:
    rt, _ = _cabinet_runtime(tmp_path, profile)
    rt.run(cycles=CYCLES)
    rt.save_persistent()
    rt.reset_origin()
    # An uncontrolled termination right after the reset: nothing old may come back.
    assert not (tmp_path / "retain.dat").exists() and not (tmp_path / "persistent.dat").exists()
    del rt  # the store's lock goes with the process
    _fresh_process_globals()
    rt2, program = _cabinet_runtime(tmp_path, profile)
    rt2.run(cycles=0)
    assert _places(program) == dict.fromkeys(_places(program), INITIAL)
    rt2.stop()


@pytest.mark.parametrize("operation", ["reset_cold", "download"])
def test_a_codesys_retain_reinit_survives_a_restart(tmp_path: Path, operation: str) -> None:
    rt, program = _cabinet_runtime(tmp_path, "codesys")
    rt.run(cycles=CYCLES)
    getattr(rt, operation)()
    assert _triple(program) == (INITIAL[0], INITIAL[1], RAN[2])
    rt.stop()  # no cycle ran after the reset
    _fresh_process_globals()
    rt2, restarted = _cabinet_runtime(tmp_path, "codesys")
    rt2.run(cycles=0)
    # CODESYS 2.1: the reset re-initialised RETAIN; a restart must not bring the old values back.
    assert _triple(restarted) == (INITIAL[0], INITIAL[1], RAN[2])
    rt2.stop()


# ---------------------------------------------------------------------------
# Restart on the same store
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("profile", PROFILES)
def test_uncontrolled_termination_keeps_retain_of_the_last_cycle_and_the_last_saved_persistent(
    tmp_path: Path, profile: str
) -> None:
    rt, _ = _cabinet_runtime(tmp_path, profile)
    rt.run(cycles=CYCLES)
    rt.save_persistent()  # FB_WritePersistentData
    rt.run(cycles=2)
    # The process dies here: no stop(), so PERSISTENT is the image of save_persistent(),
    # and the store's lock goes with the process.
    del rt
    _fresh_process_globals()
    rt2, program = _cabinet_runtime(tmp_path, profile)
    rt2.run(cycles=0)
    assert rt2.boot_report == []
    expected = (INITIAL[0], RAN[1] + 20, RAN[2])
    assert _places(program) == dict.fromkeys(_places(program), expected)
    rt2.stop()


def test_a_memory_store_keeps_nothing_across_runtimes() -> None:
    rt, _ = _cabinet_runtime(":memory:", "twincat")
    rt.run(cycles=CYCLES)
    rt.stop()
    _fresh_process_globals()
    rt2, program = _cabinet_runtime(":memory:", "twincat")
    rt2.run(cycles=0)
    assert _places(program) == dict.fromkeys(_places(program), INITIAL)
    assert rt2.boot_report == []


class Drive(FunctionBlock):
    pos: DINT = VAR(0, persistent=True)
    homed: BOOL = VAR(False, retain=True)

    def body(self) -> None:
        self.pos += 100
        self.homed = True


class Servo(FunctionBlock):
    """Drive renamed: the same variables under another type name."""

    pos: DINT = VAR(0, persistent=True)
    homed: BOOL = VAR(False, retain=True)


class v1:  # noqa: N801 - the first version of the project
    class Machine(Program):
        count: INT = VAR(0, retain=True)
        removed: INT = VAR(0, retain=True)
        retyped: INT = VAR(0, retain=True)
        same_size: INT = VAR(0, retain=True)
        total: DINT = VAR(0, persistent=True)
        axis: Drive = VAR()
        spindle: Drive = VAR()
        slots: ARRAY[Drive] = VAR(bounds=(1, 2))
        plain: INT = VAR(0)

        def body(self) -> None:
            self.count += 1
            self.removed += 1
            self.retyped += 1
            self.same_size += 1
            self.total += 1000
            self.axis()
            self.spindle()
            for slot in self.slots:
                slot()
            self.plain += 1


class v2:  # noqa: N801 - the changed declaration, downloaded after a stop
    class Machine(Program):
        added: INT = VAR(5, retain=True)  # new, and declared first: every offset moves
        count: INT = VAR(0, retain=True)
        retyped: DINT = VAR(9, retain=True)  # INT -> DINT: another type
        same_size: UINT = VAR(8, retain=True)  # INT -> UINT: same size, still another type
        total: DINT = VAR(0, persistent=True)
        drive: Drive = VAR()  # the member axis renamed
        spindle: Servo = VAR()  # the member's type renamed, its variables unchanged
        slots: ARRAY[Drive] = VAR(bounds=(1, 3))  # one element more
        plain: INT = VAR(0)


def test_a_changed_declaration_keeps_what_still_matches_by_path_and_type(tmp_path: Path) -> None:
    old = v1.Machine()
    rt = Runtime(store=tmp_path)
    rt.add_task(Task("PlcTask"), old)
    rt.run(cycles=4)
    rt.stop()
    new = v2.Machine()
    rt2 = Runtime(store=tmp_path)
    rt2.add_task(Task("PlcTask"), new)
    rt2.run(cycles=0)
    assert rt2.boot_report == []
    assert (new.count, new.total, new.plain) == (4, 4000, 0)
    assert (new.added, new.retyped, new.same_size) == (5, 9, 8)
    assert (new.drive.pos, new.drive.homed) == (0, False)
    assert (new.spindle.pos, new.spindle.homed) == (400, True)
    assert [(s.pos, s.homed) for s in new.slots] == [(400, True), (400, True), (0, False)]
    rt2.stop()


def test_a_removed_program_leaves_the_others_restored(tmp_path: Path) -> None:
    rt = Runtime(store=tmp_path)
    rt.add_task(Task("PlcTask"), v1.Machine(), Cabinet())
    rt.run(cycles=CYCLES)
    rt.stop()
    _fresh_process_globals()
    rt2, program = _cabinet_runtime(tmp_path, "twincat")
    rt2.run(cycles=0)
    assert _triple(program) == (INITIAL[0], RAN[1], RAN[2])
    rt2.stop()


def test_a_program_in_another_task_is_another_instance_path(tmp_path: Path) -> None:
    rt, _ = _cabinet_runtime(tmp_path, "twincat")
    rt.run(cycles=CYCLES)
    rt.stop()
    program = Cabinet()
    rt2 = Runtime(store=tmp_path)
    rt2.add_task(Task("Other"), program)
    rt2.run(cycles=0)
    assert _triple(program) == INITIAL
    rt2.stop()


def test_a_damaged_persistent_file_is_not_loaded_and_is_reported(tmp_path: Path) -> None:
    rt, _ = _cabinet_runtime(tmp_path, "twincat")
    rt.run(cycles=CYCLES)
    rt.stop()
    _flip(tmp_path / "persistent.dat", 85)
    _fresh_process_globals()
    rt2, program = _cabinet_runtime(tmp_path, "twincat")
    with _recorded_warnings() as caught:
        rt2.run(cycles=0)
    assert [w.category for w in caught] == [RuntimeWarning]
    assert "persistent.dat: record checksum mismatch" in str(caught[0].message)
    assert str(caught[0].message).endswith("no valid PERSISTENT image; PERSISTENT variables start from their initial values")
    assert rt2.boot_report == [str(caught[0].message)]
    # RETAIN still comes from its own, undamaged file.
    assert _places(program) == dict.fromkeys(_places(program), (INITIAL[0], RAN[1], INITIAL[2]))
    rt2.stop()


def test_a_damaged_retain_file_is_not_loaded_and_is_reported(tmp_path: Path) -> None:
    rt, _ = _cabinet_runtime(tmp_path, "twincat")
    rt.run(cycles=CYCLES)
    rt.stop()
    _flip(tmp_path / "retain.dat", 90)
    _flip(tmp_path / "retain.dat", PAGE + 90)
    _fresh_process_globals()
    rt2, program = _cabinet_runtime(tmp_path, "twincat")
    with _recorded_warnings() as caught:
        rt2.run(cycles=0)
    messages = [str(w.message) for w in caught]
    assert [w.category for w in caught] == [RuntimeWarning]
    assert "retain.dat slot A: record checksum mismatch" in messages[0]
    assert "retain.dat slot B: record checksum mismatch" in messages[0]
    assert messages[0].endswith("no valid RETAIN image; RETAIN variables start from their initial values")
    assert rt2.boot_report == messages
    assert _places(program) == dict.fromkeys(_places(program), (INITIAL[0], INITIAL[1], RAN[2]))
    rt2.stop()


def test_a_damaged_newest_persistent_generation_falls_back_to_the_older_one(tmp_path: Path) -> None:
    rt, _ = _cabinet_runtime(tmp_path, "twincat")
    rt.run(cycles=CYCLES)
    rt.save_persistent()  # generation 1: saved = RAN
    rt.run(cycles=1)
    rt.stop()  # generation 2: saved = RAN + 10
    _flip(tmp_path / "persistent.dat", 85)
    _fresh_process_globals()
    rt2, program = _cabinet_runtime(tmp_path, "twincat")
    with _recorded_warnings() as caught:
        rt2.run(cycles=0)
    assert len(caught) == 1 and caught[0].category is RuntimeWarning
    assert "using the older generation persistent.dat.bak" in str(caught[0].message)
    assert rt2.boot_report == [str(caught[0].message)]
    assert _places(program) == dict.fromkeys(_places(program), (INITIAL[0], RAN[1] + 10, RAN[2]))
    rt2.stop()


def test_a_stored_directory_that_does_not_parse_is_rejected_in_the_boot_report(tmp_path: Path) -> None:
    size = ctypes.sizeof(typing.cast(Any, Cabinet))
    with RemanentStore(tmp_path) as store:
        store.write_persistent(ImageLayout((("PlcTask.Cabinet", "saved\tDINT", size),)), b"\x7f" * size)
    rt, program = _cabinet_runtime(tmp_path, "twincat")
    rt.run(cycles=0)
    assert rt.boot_report == ["PlcTask.Cabinet: stored directory rejected (directory line 1 has 2 fields, expected 5)"]
    assert _triple(program) == INITIAL
    rt.stop()


def test_the_stored_directory_locates_each_value_in_the_stored_block(tmp_path: Path) -> None:
    # A directory naming the right path and type, but another offset: the bytes at that offset are used.
    size = ctypes.sizeof(typing.cast(Any, Cabinet))
    data = bytearray(size)
    struct.pack_into("<i", data, 0, 1234)
    with RemanentStore(tmp_path) as store:
        store.write_persistent(ImageLayout((("PlcTask.Cabinet", "saved\tDINT\t0\t4\t2", size),)), bytes(data))
    rt, program = _cabinet_runtime(tmp_path, "twincat")
    rt.run(cycles=0)
    assert rt.boot_report == []
    assert _triple(program) == (INITIAL[0], INITIAL[1], 1234)
    rt.stop()


# ---------------------------------------------------------------------------
# Call sequences (docs/concepts/lifecycle.md)
# ---------------------------------------------------------------------------


def test_first_start_runs_fb_init_true_false_at_declaration_and_nothing_when_the_tasks_start() -> None:
    rt, line = _line_runtime()
    assert _sequence((line, "PlcTask.Line")) == _init_tree("PlcTask.Line", True, False)
    events.clear()
    rt.run(cycles=2)
    assert events == []
    assert (line.x.speed, line.x.brake.n, line.cells[2].n) == (5, 2, 2)


def test_global_fb_instances_get_fb_init_true_false_at_definition() -> None:
    @gvl
    class GVL_ResetsDefinition(GlobalVariables):
        rs_defined_a: Part = VAR()
        rs_defined_b: Part = VAR()

    assert GVL_ResetsDefinition.rs_defined_a.n == 0
    assert _sequence() == [
        "GVL_ResetsDefinition.rs_defined_a: Part.FB_init(True, False) n=0",
        "GVL_ResetsDefinition.rs_defined_b: Part.FB_init(True, False) n=0",
    ]


@pytest.mark.parametrize(
    ("profile", "operation", "init_retains"),
    [
        # bInitRetains is TRUE exactly when the operation re-initialises RETAIN (1.1 flag meaning, tables 2.1 / 2.2).
        ("twincat", "reset_cold", False),
        ("twincat", "reset_origin", True),
        ("twincat", "download", False),
        ("codesys", "reset_warm", False),
        ("codesys", "reset_cold", True),
        ("codesys", "reset_origin", True),
        ("codesys", "download", True),
    ],
)
def test_reset_and_download_run_fb_exit_false_then_fb_init(profile: str, operation: str, init_retains: bool) -> None:
    rt, line = _line_runtime(profile)
    rt.run(cycles=2)
    events.clear()
    getattr(rt, operation)()
    assert _sequence((line, "PlcTask.Line"), prefix="PlcTask.") == (
        _exit_tree("PlcTask.Line", False) + _init_tree("PlcTask.Line", init_retains, False)
    )
    # The application's global FB instances too: the GVL's and the VAR_STAT block's.
    assert _sequence(prefix="GVL_ResetsTracked.") == _global_reinit(init_retains)
    assert _sequence(prefix="Station.") == _static_reinit(init_retains)
    assert not [entry for entry in _sequence((line, "PlcTask.Line")) if entry.startswith("?")]
    assert (line.x.speed, line.x.brake.n) == (5, 0)


def test_reset_warm_in_the_twincat_profile_calls_nothing() -> None:
    rt, _ = _line_runtime("twincat")
    rt.run(cycles=1)
    events.clear()
    with pytest.raises(RuntimeError, match="twincat profile has no reset warm"):
        rt.reset_warm()
    assert events == []


def test_stop_runs_fb_exit_false_once() -> None:
    rt, line = _line_runtime()
    rt.run(cycles=1)
    events.clear()
    rt.stop()
    assert _sequence((line, "PlcTask.Line"), prefix="PlcTask.") == _exit_tree("PlcTask.Line", False)
    events.clear()
    rt.stop()  # a second stop does nothing
    assert events == []
    with pytest.raises(RuntimeError, match="the runtime was stopped; create a new Runtime on the same store"):
        rt.run(cycles=1)


def test_stop_runs_fb_exit_of_the_global_fb_instances_too() -> None:
    rt, _ = _line_runtime()
    rt.run(cycles=1)
    events.clear()
    rt.stop()
    # 1.2: FB_exit runs before the instance code is removed (Run -> Config), for every instance.
    assert _sequence(prefix="GVL_ResetsTracked.") == ["GVL_ResetsTracked.rs_tracked: Part.FB_exit(False)"]
    assert _sequence(prefix="Station.") == ["Station.VAR_STAT.shared: Part.FB_exit(False)"]


def test_code_only_online_change_calls_nothing_and_keeps_the_instance() -> None:
    rt, line = _line_runtime()
    rt.run(cycles=2)
    events.clear()
    rt.online_change()
    rt.online_change(replace={})
    assert events == []
    assert rt.programs() == {"PlcTask.Line": line}


def test_online_change_to_a_class() -> None:
    rt, old = _line_runtime()
    rt.run(cycles=2)
    events.clear()
    rt.online_change(replace={"PlcTask.Line": LineV2})
    new = rt.programs()["PlcTask.Line"]
    assert isinstance(new, LineV2)
    # Old FB_exit(TRUE); new FB_init(FALSE, TRUE) only (before the copy: n=0); copy; FB_reinit (after: n=2).
    assert _sequence((old, "old"), (new, "new")) == (
        _exit_tree("old", True) + _init_tree("new", False, True) + _reinit_tree("new", n=2)
    )
    assert (new.x.brake.n, new.cells[1].n, new.x.speed, new.extra) == (2, 2, 5, 0)
    events.clear()
    rt.run(cycles=1)
    assert (new.x.brake.n, old.x.brake.n) == (3, 2)  # the new instance runs, the old one no longer
    assert events == []


def test_online_change_to_an_instance_already_built() -> None:
    rt, old = _line_runtime()
    rt.run(cycles=2)
    events.clear()
    new = LineV2()
    rt.online_change(replace={"PlcTask.Line": new})
    assert rt.programs()["PlcTask.Line"] is new
    # Its constructor ran FB_init(TRUE, FALSE); the online change runs FB_init(FALSE, TRUE) again.
    assert _sequence((old, "old"), (new, "new")) == (
        _init_tree("new", True, False)
        + _exit_tree("old", True)
        + _init_tree("new", False, True)
        + _reinit_tree("new", n=2)
    )
    assert (new.x.brake.n, new.cells[2].n) == (2, 2)


def test_online_change_of_one_program_leaves_the_others_alone() -> None:
    rt, line = _line_runtime()
    other = Cabinet()
    rt.add_program("PlcTask", other)
    rt.run(cycles=2)
    events.clear()
    rt.online_change(replace={"PlcTask.Cabinet": CabinetV2})
    assert events == []
    assert rt.programs()["PlcTask.Line"] is line
    assert isinstance(rt.programs()["PlcTask.Cabinet"], CabinetV2)
    assert list(rt.programs()) == ["PlcTask.Line", "PlcTask.Cabinet"]


def test_online_change_of_an_unknown_path_names_the_known_ones() -> None:
    rt, _ = _line_runtime()
    events.clear()
    with pytest.raises(KeyError, match=r"online change: no program at 'PlcTask.Nope' \(known: PlcTask.Line\)"):
        rt.online_change(replace={"PlcTask.Nope": LineV2})
    assert events == []


class RecipeV1(Program):
    speed: INT = VAR(0)
    dropped: INT = VAR(0)
    width: INT = VAR(0, retain=True)
    stock: ARRAY[Part] = VAR(bounds=(1, 2))
    axis: Drive = VAR()
    motor: Drive = VAR()

    def body(self) -> None:
        self.speed += 1
        self.dropped += 1
        self.width += 2
        for part in self.stock:
            part()
        self.axis()
        self.motor()


class DriveV2(Drive):
    torque: INT = VAR(11)


class RecipeV2(Program):
    added: INT = VAR(42)
    speed: INT = VAR(0)
    width: DINT = VAR(-1, retain=True)  # retyped
    stock: ARRAY[Part] = VAR(bounds=(0, 2))  # one element added in front
    drive: Drive = VAR()  # axis renamed
    motor: DriveV2 = VAR()  # the member's type changed: a variable added


def test_online_change_copies_data_by_path_and_type(tmp_path: Path) -> None:
    old = RecipeV1()
    rt = Runtime(store=tmp_path)
    rt.add_task(Task("PlcTask"), old)
    rt.run(cycles=3)
    rt.online_change(replace={"PlcTask.RecipeV1": RecipeV2})
    new = rt.programs()["PlcTask.RecipeV1"]
    assert isinstance(new, RecipeV2)
    assert (new.added, new.speed, new.width) == (42, 3, -1)
    assert [p.n for p in new.stock] == [0, 3, 3]
    assert (new.drive.pos, new.drive.homed) == (0, False)
    assert (new.motor.pos, new.motor.homed, new.motor.torque) == (300, True, 11)
    # The store follows the new declaration from the next cycle on.
    rt.run(cycles=1)
    rt.stop()
    again = RecipeV2()
    rt2 = Runtime(store=tmp_path)
    rt2.add_task(Task("PlcTask"), again)
    rt2.run(cycles=0)
    assert again.width == -1 and rt2.boot_report == []
    rt2.stop()


class IStep(Interface):
    @method
    def step(self) -> INT: ...


class Stepper(FunctionBlock, IStep):
    count: INT = VAR(0)

    @method
    def step(self) -> INT:
        self.count += 1
        return self.count


class Sequencer(Program):
    stepper: Stepper = VAR()
    current: IStep = VAR()

    def body(self) -> None:
        if not self.current:
            self.current = self.stepper
        self.current.step()


class SequencerV2(Sequencer):
    extra: INT = VAR(0)


def test_online_change_adjusts_interface_variables_to_the_new_instance() -> None:
    old = Sequencer()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask"), old)
    rt.run(cycles=2)
    rt.online_change(replace={"PlcTask.Sequencer": SequencerV2})
    new = rt.programs()["PlcTask.Sequencer"]
    rt.run(cycles=1)
    # 1.2: "interface variables are adjusted by the compiler automatically" during the copy.
    assert (new.stepper.count, old.stepper.count) == (3, 2)


class Numbered(Program):
    number: INT = VAR(0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, number: INT = 1) -> BOOL:
        self.number = number
        return False


def test_a_reset_re_runs_fb_init_with_the_declaration_inputs() -> None:
    numbered = Numbered(number=4)
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask"), numbered)
    rt.run(cycles=1)
    rt.reset_cold()
    # 1.6: FB_init inputs are part of the declaration, so every re-initialisation passes them again.
    assert numbered.number == 4


class Plain(FunctionBlock):
    """No FB_init / FB_exit / FB_reinit of its own: only the implicit init runs."""

    value: INT = VAR(4)


class Holder(Program):
    plain: Plain = VAR()
    part: Part = VAR()

    def body(self) -> None:
        self.part()


def test_blocks_without_lifecycle_methods_are_reinitialised_silently() -> None:
    holder = Holder()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask"), holder)
    rt.run(cycles=1)
    events.clear()
    rt.reset_cold()
    assert _sequence((holder, "PlcTask.Holder"), prefix="PlcTask.") == [
        "PlcTask.Holder.part: Part.FB_exit(False)",
        "PlcTask.Holder.part: Part.FB_init(False, False) n=0",
    ]
    assert holder.plain.value == 4


# ---------------------------------------------------------------------------
# Faults: the exception state and the way out of it
# ---------------------------------------------------------------------------


class IValve(Interface):
    @method
    def open(self) -> BOOL: ...


class Faulty(Program):
    mode: INT = VAR_INPUT(0)  # 0 no fault, 1 division, 2 array bound, 3 null interface, 4 PlcException, 5 other
    n: INT = VAR(0)
    kept: INT = VAR(0, retain=True)
    table: ARRAY[INT] = VAR(bounds=(1, 3))
    valve: IValve = VAR()

    def body(self) -> None:
        self.n += 1
        self.kept += 1
        if self.n == 3:
            self._fail()

    def _fail(self) -> None:
        if self.mode == 1:
            self.n = self.n // (self.n - 3)
        elif self.mode == 2:
            self.table[self.n + 1] = 1
        elif self.mode == 3:
            self.valve.open()
        elif self.mode == 4:
            raise PlcException(ExceptionCode.RTSEXCPT_OVERFLOW, "counter overflow")
        elif self.mode == 5:
            raise ValueError("not a PLC fault")


def _faulty(mode: int, profile: str = "twincat") -> tuple[Runtime, Faulty]:
    faulty = Faulty()
    faulty.mode = mode
    rt = Runtime(store=":memory:", profile=profile)
    rt.add_task(Task("Fast", interval=2, priority=1), faulty)
    return rt, faulty


@pytest.mark.parametrize(
    ("mode", "code", "cause"),
    [
        (1, ExceptionCode.RTSEXCPT_DIVIDEBYZERO, "ZeroDivisionError"),
        (2, ExceptionCode.RTSEXCPT_ARRAYBOUNDS, "index 4 outside ARRAY[1..3] OF INT"),
        (3, ExceptionCode.RTSEXCPT_ACCESS_VIOLATION, "null interface"),
        (4, ExceptionCode.RTSEXCPT_OVERFLOW, "counter overflow"),
        (5, ExceptionCode.RTSEXCPT_UNKNOWN, "ValueError: not a PLC fault"),
    ],
    ids=["divide-by-zero", "array-bounds", "null-interface", "plc-exception", "other-exception"],
)
def test_a_fault_enters_the_exception_state_with_task_cycle_code_and_traceback(
    mode: int, code: ExceptionCode, cause: str
) -> None:
    rt, faulty = _faulty(mode)
    with pytest.raises(PlcException, match=rf"^{code.name} \(16#{int(code):X}\): task Fast stopped in cycle 3: ") as info:
        rt.run(cycles=10)
    assert info.value.code == code and cause in str(info.value)
    fault = rt.fault
    assert isinstance(fault, Fault)
    assert (fault.task, fault.cycle, fault.code, fault.exception.code) == ("Fast", 3, code, code)
    assert cause in fault.message and "_fail" in fault.traceback and "Traceback" in fault.traceback
    assert faulty.n == 3 and rt.time_ms == 4  # stopped in the third cycle, at t = 4 ms
    # run() keeps raising the same fault, and nothing runs.
    for _ in range(2):
        with pytest.raises(PlcException, match=f"task Fast stopped in cycle 3: {code.name}") as again:
            rt.run(cycles=1)
        assert again.value.code == code
    with pytest.raises(PlcException):
        rt.run(duration=10)
    assert faulty.n == 3 and rt.fault is fault


@pytest.mark.parametrize(
    ("profile", "operation", "kept"),
    [
        ("twincat", "reset_cold", 3),
        ("twincat", "reset_origin", 0),
        ("twincat", "download", 3),
        ("codesys", "reset_warm", 3),
        ("codesys", "reset_cold", 0),
        ("codesys", "reset_origin", 0),
        ("codesys", "download", 0),
    ],
)
def test_every_reset_kind_leaves_the_exception_state(profile: str, operation: str, kept: int) -> None:
    rt, faulty = _faulty(1, profile)
    with pytest.raises(PlcException):
        rt.run(cycles=10)
    getattr(rt, operation)()
    assert rt.fault is None
    assert (faulty.mode, faulty.n, faulty.kept) == (0, 0, kept)  # the input is re-initialised: no second fault
    info = rt.tasks[0].info
    assert (info.CycleCount, info.FirstCycle) == (0, True)
    rt.run(cycles=5)
    assert (faulty.n, faulty.kept, info.CycleCount, info.FirstCycle) == (5, kept + 5, 5, False)


def test_an_online_change_does_not_leave_the_exception_state() -> None:
    rt, _ = _faulty(1)
    with pytest.raises(PlcException):
        rt.run(cycles=10)
    rt.online_change()
    with pytest.raises(PlcException, match="DIVIDEBYZERO"):
        rt.run(cycles=1)


def test_a_fault_in_a_higher_priority_task_stops_the_tick() -> None:
    rt, faulty = _faulty(1)
    later = Faulty()
    rt.add_task(Task("Slow", interval=2, priority=5), later)
    with pytest.raises(PlcException, match="task Fast stopped in cycle 3"):
        rt.run(cycles=10)
    assert (faulty.n, later.n) == (3, 2)
    assert rt.tasks[1].info.CycleCount == 2


def test_the_fault_state_is_per_runtime() -> None:
    rt, _ = _faulty(1)
    with pytest.raises(PlcException):
        rt.run(cycles=10)
    healthy, program = _faulty(0)
    healthy.run(cycles=5)
    assert healthy.fault is None and program.n == 5

