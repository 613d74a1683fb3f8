"""A runtime's resets, download and online change: the application re-initialised per the vendor table.

Functions over a ``Runtime`` (its program blocks, GVLs and VAR_STAT blocks); the Runtime's methods call them.
"""

from __future__ import annotations

import ctypes
import traceback
import typing
from typing import TYPE_CHECKING, Any

from iecoop.exceptions import PlcException
from iecoop.lifecycle import finalise, heap_blocks, initialise, reinitialise
from iecoop.memory.allocations import allocation_for_handle, free, handle_of, registered_allocation, resolve
from iecoop.metadata import Kind, kind_of
from iecoop.profiles import use_profile
from iecoop.runtime import remanence
from iecoop.runtime.remanence import Entry
from iecoop.runtime.clock import use_clock
from iecoop.runtime.variables import PERSISTENT, PLAIN, RETAIN, copy_matching, handle_offsets, nodes, translate_offset

if TYPE_CHECKING:
    from iecoop.runtime.runtime import Runtime


def snapshot(runtime: Runtime, entry: Entry) -> bytes:
    return ctypes.string_at(ctypes.addressof(entry.program), ctypes.sizeof(entry.program))


def reinit(runtime: Runtime, operation: str, kept: set[int], init_retains: bool) -> None:
    """Re-initialise the whole application (programs, GVLs, VAR_STAT blocks), keeping ``kept`` classes.

    If an FB_exit or FB_init raises, the reset stops there: every block it
    reached gets its RETAIN and PERSISTENT data back (a failed reset loses
    no remanent data, and the store is not touched), and the runtime
    enters the exception state with that exception.
    """
    runtime._check_not_stopped(operation)
    with runtime._exclusive(operation), use_profile(runtime.profile), use_clock(runtime._clock):
        entries = runtime._all_entries()
        saved: list[bytes] = []
        try:
            for entry in entries:
                saved.append(snapshot(runtime, entry))
                finalise(entry.program, in_copy_code=False)
                # The instance's declaration (constructor) FB_init inputs hold on every re-initialisation.
                args = entry.program.__dict__.get("_iec_init_args_")
                initialise(entry.program, init_retains=init_retains, in_copy_code=False, args=args, zero=True)
                if kept:
                    copy_matching(saved[-1], entry.leaves, entry.program, entry.leaves, kept)
        except BaseException as exc:
            for entry, image in zip(entries, saved):
                copy_matching(image, entry.leaves, entry.program, entry.leaves, {RETAIN, PERSISTENT})
            if isinstance(exc, (KeyboardInterrupt, SystemExit)):
                raise
            failed = entries[len(saved) - 1].path if saved else "(start)"
            runtime._enter_operation_fault(operation, failed, exc)
    runtime.fault = None
    for task in runtime.tasks:
        task.info.FirstCycle = True
        task.info.CycleCount = 0
        task._overruns = 0
    if RETAIN not in kept and runtime._started:
        # The store must not bring back RETAIN values this reset has re-initialised.
        remanence.capture_retain(runtime)


def reset_cold(runtime: Runtime) -> None:
    """Reset cold: plain variables re-initialised; RETAIN per profile; PERSISTENT kept."""
    kept = {PERSISTENT}
    if runtime.profile.retain_on_reset_cold:
        kept.add(RETAIN)
    reinit(runtime, "reset_cold", kept, init_retains=RETAIN not in kept)


def reset_warm(runtime: Runtime) -> None:
    """Reset warm (CODESYS only): plain variables re-initialised, RETAIN and PERSISTENT kept."""
    if not runtime.profile.has_reset_warm:
        raise RuntimeError(f"the {runtime.profile.name} profile has no reset warm (TwinCAT 3 offers reset cold and reset origin)")
    reinit(runtime, "reset_warm", {RETAIN, PERSISTENT}, init_retains=False)


def reset_origin(runtime: Runtime) -> None:
    """Reset origin: everything re-initialised, the store cleared."""
    reinit(runtime, "reset_origin", set(), init_retains=True)
    # Only a store that exists holds anything to clear; do not create one for it.
    exists = runtime._store is not None or (runtime._store_path is not None and runtime._store_path.exists())
    store = remanence.store_or_none(runtime) if exists else None
    if store is not None:
        store.clear_retain()
        store.clear_persistent()


def download(runtime: Runtime) -> None:
    """A (re-)download of the project: plain re-initialised; RETAIN per profile; PERSISTENT kept."""
    kept = {PERSISTENT}
    if runtime.profile.retain_on_download:
        kept.add(RETAIN)
    reinit(runtime, "download", kept, init_retains=RETAIN not in kept)


def retarget(runtime: Runtime, old: Any, new: Any) -> None:
    """Online change: pointers, references and interfaces into the old instance now designate the new one.

    Every address held by the application's programs, GVLs and VAR_STAT
    blocks, and by every block ``new()`` created, is adjusted by instance
    path; one whose target is gone becomes 0. The old instance's memory is
    then released, so an address nobody could adjust (a ``Pointer`` kept
    by Python) faults with RTSEXCPT_ACCESS_VIOLATION instead of writing
    into the orphan.
    """
    old_alloc = registered_allocation(old)
    if old_alloc is None or old is new:
        return  # nobody took an address of the old instance, or it was not replaced
    old_nodes, new_nodes = nodes(type(old)), nodes(type(new))
    blocks = [entry.program for entry in runtime._all_entries()] + heap_blocks()
    for block in blocks:
        for offset in handle_offsets(type(block)):
            cell = ctypes.c_uint64.from_buffer(block, offset)
            handle = cell.value
            if not handle or allocation_for_handle(handle) is not old_alloc:
                continue
            try:
                _, position = resolve(handle, 0, "online change")
            except PlcException:
                moved = None  # moved outside its block by pointer arithmetic: designates no variable
            else:
                moved = translate_offset(old_nodes, new_nodes, position)
            cell.value = 0 if moved is None else handle_of(new, moved)
    free(old_alloc)


def online_change(runtime: Runtime, replace: dict[str, Any] | None = None) -> None:
    """An online change: every variable kept.

    Without ``replace`` it is a code-only change (no FB_exit / FB_init /
    FB_reinit). ``replace`` maps instance paths (``"PlcTask.Main"``) to the
    changed declaration: a program class (the runtime creates the new
    instance, whose only FB_init is the online change's), or an instance
    already built (its constructor ran FB_init(TRUE, FALSE) first). The old
    instance gets FB_exit(TRUE), the new one FB_init(FALSE, TRUE), the data
    is copied by path and type, then FB_reinit runs.
    """
    runtime._check_not_stopped("online_change")
    if not replace:
        return
    with runtime._exclusive("online_change"), use_profile(runtime.profile), use_clock(runtime._clock):
        for path, replacement in replace.items():
            entry = next((e for e in runtime._entries if e.path == path), None)
            if entry is None:
                raise KeyError(f"online change: no program at {path!r} (known: {', '.join(runtime.programs())})")
            if isinstance(replacement, type):
                if kind_of(replacement) not in (Kind.FUNCTION_BLOCK, Kind.PROGRAM):
                    raise TypeError(f"online change: {replacement.__name__} is not a Program class")
                new_program: Any = typing.cast(Any, replacement).__new__(replacement)
            else:
                new_program = replacement
            saved = snapshot(runtime, entry)
            finalise(entry.program, in_copy_code=True)
            initialise(new_program, init_retains=False, in_copy_code=True, zero=True)
            new_entry = Entry(path, new_program)
            copy_matching(saved, entry.leaves, new_program, new_entry.leaves, {PLAIN, RETAIN, PERSISTENT})
            index = runtime._entries.index(entry)
            runtime._entries[index] = new_entry
            retarget(runtime, entry.program, new_program)
            reinitialise(new_program)
            for task in runtime.tasks:
                task._set_programs((p, new_program if p == path else prog) for p, prog in task.programs)
    runtime._retain_plan = None
