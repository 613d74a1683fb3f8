"""The process ``test_runtime_kill`` kills: a Runtime cycling a program with RETAIN data.

    python _runtime_cycler.py STORE_DIRECTORY

Every cycle sets each RETAIN variable (in the program, in a nested FB and in
every element of an ARRAY of FBs) to the cycle's number, so a torn mix of two cycles' images shows as two different numbers.
The process restores from the store, prints ``ready <n>`` with the number it
restored, then prints ``n`` each time ``run(cycles=1)`` has returned, i.e.
after cycle ``n`` ended and its RETAIN image was written.
"""

from __future__ import annotations

import sys

from iecoop import ARRAY, DINT, LINT, FunctionBlock, Program, T, VAR, method
from iecoop.runtime import Runtime, Task


class Station(FunctionBlock):
    """A block with a RETAIN member: instance path PlcTask.Cell.stations[i].count."""

    count: LINT = VAR(retain=True)
    scratch: DINT = VAR()

    @method
    def mark(self, n: LINT) -> None:
        self.count = n
        self.scratch = n % 1000


class Cell(Program):
    """The fast task's program: three places that must always agree."""

    cycle: LINT = VAR(retain=True)
    nested: Station = VAR()
    stations: ARRAY[Station] = VAR(bounds=(1, 64))

    def body(self) -> None:
        n = self.cycle + 1
        self.cycle = n
        self.nested.mark(n)
        for i in range(1, 65):
            self.stations[i].mark(n)


def build(store: str) -> tuple[Runtime, Cell]:
    cell = Cell()
    runtime = Runtime(store=store)
    runtime.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    return runtime, cell


def values(cell: Cell) -> set[int]:
    """Every RETAIN number of the cell: one element when the image is consistent."""
    return {cell.cycle, cell.nested.count, *(cell.stations[i].count for i in range(1, 65))}


def main() -> None:
    runtime, cell = build(sys.argv[1])
    runtime.run(cycles=0)  # restore the store before the first cycle
    restored = values(cell)
    print("ready", *sorted(restored), flush=True)
    while True:
        runtime.run(cycles=1)
        print(cell.cycle, flush=True)


if __name__ == "__main__":
    main()
