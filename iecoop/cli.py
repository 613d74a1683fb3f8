"""The ``iecoop`` command: runs a small plant on the cyclic runtime and prints its trace.

``iecoop`` (no arguments) runs the demo: a filling line whose program counts
bottles with an edge trigger and stops the conveyor at a batch size, on a
10 ms task in virtual time. ``iecoop --cycles N`` sets the cycle count.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from iecoop import BOOL, INT, FunctionBlock, Program, T, VAR, VAR_INPUT, VAR_OUTPUT
from iecoop.runtime import Runtime, Task

__all__ = ["main"]


class BottleCounter(FunctionBlock):
    """Counts rising edges of a photo-eye and reports when the batch is complete."""

    eye: BOOL = VAR_INPUT(False)
    batch: INT = VAR_INPUT(5)
    count: INT = VAR_OUTPUT(0)
    done: BOOL = VAR_OUTPUT(False)
    last_eye: BOOL = VAR(False)

    def body(self) -> None:
        eye = self.eye
        if eye and not self.last_eye:
            self.count += 1
        self.last_eye = eye
        self.done = self.count >= self.batch


class FillingLine(Program):
    """The demo PROGRAM: a bottle passes the eye every 3 cycles; the conveyor stops at the batch."""

    cycle: INT = VAR(0)
    conveyor: BOOL = VAR(True)
    counter: BottleCounter = VAR()

    def body(self) -> None:
        self.cycle += 1
        eye = self.conveyor and self.cycle % 3 == 0
        self.counter(eye=eye, batch=5)
        self.conveyor = not self.counter.done


def _demo(cycles: int) -> int:
    line = FillingLine()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), line)
    print("iecoop demo: a filling line on a 10 ms task (virtual time)")
    print(f"{'time':>8}  {'cycle':>5}  {'conveyor':>8}  {'bottles':>7}  {'done':>5}")
    for _ in range(cycles):
        rt.run(cycles=1)
        print(
            f"{rt.time_ms:>6}ms  {line.cycle:>5}  {str(line.conveyor):>8}  {line.counter.count:>7}  {str(line.counter.done):>5}"
        )
    print(f"batch of {line.counter.count} bottles complete: {line.counter.done}")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``iecoop`` command."""
    parser = argparse.ArgumentParser(prog="iecoop", description="Run the iecoop demo plant on the cyclic runtime.")
    parser.add_argument("--cycles", type=int, default=18, help="how many 10 ms cycles to run (default 18)")
    args = parser.parse_args(argv)
    if args.cycles <= 0:
        parser.error("--cycles must be a positive number")
    return _demo(args.cycles)


if __name__ == "__main__":
    sys.exit(main())
