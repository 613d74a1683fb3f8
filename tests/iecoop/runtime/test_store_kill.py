"""``kill -9`` of a process writing the remanent store, at random instants.

After each kill the store must hold exactly the image of the last write that
had returned (the child prints its number right after), or of the one write
that was under way: never a torn mix, never anything older.
"""

from __future__ import annotations

import random
import sys
import time
import warnings
from pathlib import Path
from typing import Literal

import pytest

from iecoop.runtime.store import LoadedImage, RemanentStore, StoreWarning

from ._child import TIMEOUT, ReportingChild
from ._store_writer import counter_of, image_for

WRITER = Path(__file__).with_name("_store_writer.py")

Kind = Literal["retain", "persistent"]


def writer(directory: Path, kind: Kind, durability: str, large: bool, lines_wanted: int) -> ReportingChild:
    """The writer process, with a thread collecting the numbers it reports."""
    argv = [sys.executable, str(WRITER), str(directory), kind, durability, "large" if large else "small"]
    return ReportingChild(argv, lines_wanted)


def load(directory: Path, kind: Kind) -> LoadedImage | None:
    # A write torn by the kill is reported as a StoreWarning: expected here.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", StoreWarning)
        with RemanentStore(directory) as store:
            return store.load_retain() if kind == "retain" else store.load_persistent()


def kill_repeatedly(tmp_path: Path, kind: Kind, iterations: int) -> None:
    directory = tmp_path / "store-0"
    large = False
    previous: LoadedImage | None = None
    in_flight = torn = 0
    for iteration in range(iterations):
        rng = random.Random(f"{kind}-{iteration}")
        if iteration and rng.random() < 0.25:
            # A fresh store: its first writes create and grow the file.
            directory = tmp_path / f"store-{iteration}"
            large = rng.random() < 0.4
            previous = None
        durability = "power" if rng.random() < 0.25 else "process"
        # A large image's writer spends its first tens of milliseconds reading
        # the store; it is killed once it has settled into writing.
        by_time = not large and rng.random() < 0.5
        # Fewer lines when every write waits for the disk.
        lines_wanted = (1 << 30 if by_time else rng.randint(1, 4) if large
                        else rng.randint(0, 40 if durability == "process" else 5))
        child = writer(directory, kind, durability, large, lines_wanted)
        try:
            assert child.ready.wait(TIMEOUT), "the writer did not start"
            if by_time:
                time.sleep(rng.uniform(0.0, 0.030))
            else:
                assert child.enough.wait(TIMEOUT), "the writer stalled"
                # Right after a line the writer is building its next image;
                # a little later it may be inside the pwrite.
                time.sleep(rng.uniform(0.0, 0.008 if large else 0.004))
        finally:
            child.kill("the writer")

        image = load(directory, kind)
        where = (f"iteration {iteration} ({kind}, {durability}, {'large' if large else 'small'}, {directory.name}, "
                 f"reported {child.reported[-3:]})")
        completed = child.reported[-1] if child.reported else (None if previous is None else counter_of(previous))
        if image is None:
            assert completed is None, f"{where}: no image, but write {completed} had completed"
        else:
            counter = counter_of(image)
            assert len({entry for _, entry in image.values().values()}) == 1, f"{where}: entries disagree"
            layout, data = image_for(counter, large)
            assert image.layout == layout and image.data == data, f"{where}: image {counter} is a torn mix"
            low = 1 if completed is None else completed
            assert low <= counter <= low + 1, f"{where}: loaded image {counter}, last completed write {completed}"
            if previous is not None:
                assert image.sequence >= previous.sequence, f"{where}: the sequence went back"
            in_flight += counter != completed
            torn += image.from_backup
        previous = image
    # Not asserted (timing decides), only shown with -s: whether kills landed inside writes.
    print(f"{kind}: {iterations} kills; {in_flight} left the write under way complete, {torn} tore a record")


@pytest.mark.slow  # seconds each: once, in the slow gate
def test_kill_during_retain_writes(tmp_path: Path) -> None:
    kill_repeatedly(tmp_path, "retain", 64)


@pytest.mark.slow  # seconds each: once, in the slow gate
def test_kill_during_persistent_writes(tmp_path: Path) -> None:
    kill_repeatedly(tmp_path, "persistent", 32)
