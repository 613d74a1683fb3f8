"""A runtime's remanent data: RETAIN and PERSISTENT images restored at start, written at each cycle and on request.

Functions over a ``Runtime`` (its store and its program blocks); the Runtime's methods call them.
"""

from __future__ import annotations

import ctypes
import warnings
from typing import TYPE_CHECKING, Any

from iecoop.runtime.store import ImageLayout, RemanentStore
from iecoop.runtime.variables import PERSISTENT, PLAIN, RETAIN, Leaf, copy_matching, format_directory, leaves, parse_directory

if TYPE_CHECKING:
    from iecoop.runtime.runtime import Runtime


class Entry:
    """One program instance in a task, with its instance path and variable directory."""

    __slots__ = ("path", "program", "leaves", "remanent")

    def __init__(self, path: str, program: Any) -> None:
        self.path = path
        self.program = program
        self.leaves: list[Leaf] = leaves(type(program))
        self.remanent = any(leaf.remanence != PLAIN for leaf in self.leaves)


def store_or_none(runtime: Runtime) -> RemanentStore | None:
    if runtime._store_path is None:
        return None
    if runtime._store is None:
        runtime._store = RemanentStore(runtime._store_path, durability=runtime._durability)
    return runtime._store


def start(runtime: Runtime) -> None:
    """Controller start: restore RETAIN and PERSISTENT data that still match.

    Addresses (POINTER, REFERENCE, interface variables) inside restored
    data are not restored: they keep what initialisation gave them.
    """
    if not any(e.remanent for e in runtime._all_entries()):
        runtime._started = True
        return
    # Opening the store takes its lock; if that fails the runtime has not started.
    store = store_or_none(runtime)
    runtime._started = True
    if store is None:
        return
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        retain = store.load_retain()
        persistent = store.load_persistent()
    runtime.boot_report = [str(w.message) for w in caught]
    for message in runtime.boot_report:
        warnings.warn(message, RuntimeWarning, stacklevel=3)
    if retain is not None:
        apply_image(runtime, retain.values(), {RETAIN})
    if persistent is not None:
        apply_image(runtime, persistent.values(), {PERSISTENT})


def apply_image(runtime: Runtime, values: dict[str, tuple[str, bytes]], classes: set[int]) -> None:
    for entry in runtime._all_entries():
        stored = values.get(entry.path)
        if stored is None:
            continue
        directory, data = stored
        try:
            old_leaves = parse_directory(directory)
        except ValueError as exc:
            runtime.boot_report.append(f"{entry.path}: stored directory rejected ({exc})")
            continue
        copy_matching(data, old_leaves, entry.program, entry.leaves, classes, addresses=False)


def plan(runtime: Runtime, classes: set[int]) -> tuple[ImageLayout, list[Any]]:
    """The layout of an image of the given classes and the program blocks it copies."""
    entries = []
    blocks = []
    for entry in runtime._all_entries():
        kept = [leaf for leaf in entry.leaves if leaf.remanence in classes]
        if kept:
            entries.append((entry.path, format_directory(kept), ctypes.sizeof(entry.program)))
            blocks.append(entry.program)
    return ImageLayout(tuple(entries)), blocks


def gather(blocks: list[Any]) -> bytes:
    """One C-level copy per program block: the image data."""
    return b"".join(ctypes.string_at(ctypes.addressof(b), ctypes.sizeof(b)) for b in blocks)


def capture_retain(runtime: Runtime) -> None:
    if runtime._retain_plan is None:
        runtime._retain_plan = plan(runtime, {RETAIN})
    layout, blocks = runtime._retain_plan
    if not blocks:
        return
    store = store_or_none(runtime)
    if store is not None:
        store.write_retain(layout, gather(blocks))


def save_persistent(runtime: Runtime) -> None:
    """Write the PERSISTENT image now (TwinCAT ``FB_WritePersistentData``)."""
    runtime._check_not_stopped("save_persistent")
    layout, blocks = plan(runtime, {PERSISTENT})
    store = store_or_none(runtime) if blocks else None
    if store is not None:
        store.write_persistent(layout, gather(blocks))
