"""Cost of an FB call and of a typed-variable write, as ratios to plain Python measured in the same run.

Case 1: ``fb(enable=True)`` on FB_Counter (one BOOL input, an INT count
incremented when enabled) against a plain callable object doing the same work:
set the input if given, increment with INT wrap-around. Beside it, for
information, the same statements the block's generated call runs, on a bare
``ctypes.Structure``: the floor of case 1 while a block's memory is ctypes'.

Case 2: ``self.x = self.x + 1`` on an INT variable, in a loop inside an FB
METHOD (so the call overhead does not dominate), against a plain object doing
the same with INT wrap-around.

Case 3, for information: the same loop calling a METHOD each pass, whose
fields every pass then reads and writes in memory (in fast mode a loop that
calls nothing keeps ``x`` in a local while it runs; see "How it works").

All are timed interleaved (one iecoop repeat, one plain repeat, ...) so a
change of CPU clock or of the machine's load affects both sides; the figures
are the median time per operation of each side and the median of the ratios
of the timings taken in the same round. Each mode has its targets (fast mode ``IECOOP_CHECKS=0``: call
1.3, variable 1.1; checked mode, the default: 1.6 and 3.0); the script exits
with status 1 if a ratio is above the target of its mode.

    python benchmarks/bench_call.py
    IECOOP_CHECKS=0 python benchmarks/bench_call.py
"""

from __future__ import annotations

import argparse
import ctypes
import statistics
import sys
import time
import timeit
from dataclasses import dataclass
from typing import Any

from iecoop import BOOL, DINT, INT, VAR, VAR_INPUT, VAR_OUTPUT, FunctionBlock, _config, method

#: Ratio targets per mode: fast mode (IECOOP_CHECKS=0), checked mode (the default).
TARGETS = {True: {"call": 1.3, "variable": 1.1}, False: {"call": 1.6, "variable": 3.0}}


class Counter(FunctionBlock):
    """FB_Counter: ``IF enable THEN count := count + 1; END_IF``."""

    enable: BOOL = VAR_INPUT(False)
    count: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self.enable:
            self.count += 1


class PlainCounter:
    """The same work in plain Python: the input kept between calls, INT wrap on store."""

    __slots__ = ("count", "enable")

    def __init__(self) -> None:
        self.enable = False
        self.count = 0

    def __call__(self, enable: bool | None = None) -> None:
        if enable is not None:
            self.enable = enable
        if self.enable:
            self.count = ((self.count + 1 + 0x8000) & 0xFFFF) - 0x8000


class BareCounter(ctypes.Structure):
    """For information: the statements of FB_Counter's generated call (fast mode) on a bare ctypes.Structure.

    What a call costs with the block's memory in ctypes fields and nothing of
    iecoop's around it: the floor of case 1 while the memory is ctypes'.
    """

    _fields_ = [("enable", ctypes.c_bool), ("count", ctypes.c_int16)]
    enable: bool
    count: int

    def __call__(self, *, enable: bool | None = None) -> None:
        if enable is not None and enable is not self.enable:
            self.enable = enable
        if enable is True or (enable is not False and self.enable):
            self.count += 1


class Accumulator(FunctionBlock):
    x: INT = VAR(0)
    notes: DINT = VAR(0)

    @method
    def run(self, n: DINT) -> None:
        for _ in range(n):
            self.x = self.x + 1

    @method
    def run_noting(self, n: DINT) -> None:
        """The same loop calling a METHOD each pass: every pass reads and writes the fields (for information)."""
        for _ in range(n):
            self.x = self.x + 1
            self.note()

    @method
    def note(self) -> None:
        self.notes = self.notes + 1


class PlainAccumulator:
    __slots__ = ("notes", "x")

    def __init__(self) -> None:
        self.x = 0
        self.notes = 0

    def run(self, n: int) -> None:
        for _ in range(n):
            self.x = ((self.x + 1 + 0x8000) & 0xFFFF) - 0x8000

    def run_noting(self, n: int) -> None:
        for _ in range(n):
            self.x = ((self.x + 1 + 0x8000) & 0xFFFF) - 0x8000
            self.note()

    def note(self) -> None:
        self.notes = ((self.notes + 1 + 0x8000_0000) & 0xFFFF_FFFF) - 0x8000_0000


@dataclass(frozen=True)
class Result:
    name: str
    iecoop_ns: float
    plain_ns: float
    #: The median of the ratios of the two timings taken in each round.
    ratio: float


def interleaved(
    iecoop_stmt: str, plain_stmt: str, namespace: dict[str, Any], number: int, repeat: int, per_call: int
) -> tuple[float, float, float]:
    """Median ns per operation of each statement, the two timed turn about, and the median ratio of a round's timings."""
    # CPU time of this process: on a shared machine, time spent waiting for a core is not counted.
    iecoop_timer = timeit.Timer(iecoop_stmt, globals=namespace, timer=time.process_time)
    plain_timer = timeit.Timer(plain_stmt, globals=namespace, timer=time.process_time)
    iecoop_times: list[float] = []
    plain_times: list[float] = []
    for _ in range(repeat):
        iecoop_times.extend(iecoop_timer.repeat(repeat=1, number=number))
        plain_times.extend(plain_timer.repeat(repeat=1, number=number))
    scale = 1e9 / (number * per_call)
    ratio = statistics.median(x / y for x, y in zip(iecoop_times, plain_times))
    return statistics.median(iecoop_times) * scale, statistics.median(plain_times) * scale, ratio


def check_same_work() -> None:
    """Both sides of each case compute the same values, wrap-around included."""
    fb, plain, bare = Counter(), PlainCounter(), BareCounter()
    for i in range(70_000):
        enable = i % 3 != 0
        fb(enable=enable)
        plain(enable=enable)
        bare(enable=enable)
    assert fb.count == plain.count == bare.count, (fb.count, plain.count, bare.count)
    acc, plain_acc = Accumulator(), PlainAccumulator()
    acc.run(40_000)
    plain_acc.run(40_000)
    assert acc.x == plain_acc.x == 40_000 - 65_536, (acc.x, plain_acc.x)
    acc.run_noting(30_000)
    plain_acc.run_noting(30_000)
    assert (acc.x, acc.notes) == (plain_acc.x, plain_acc.notes) == (70_000 - 65_536, 30_000), (acc.x, plain_acc.x)


def run(number: int, repeat: int, loop: int) -> list[Result]:
    namespace: dict[str, Any] = {
        "fb": Counter(),
        "plain": PlainCounter(),
        "bare": BareCounter(),
        "acc": Accumulator(),
        "plain_acc": PlainAccumulator(),
        "loop": loop,
    }
    call = interleaved("fb(enable=True)", "plain(enable=True)", namespace, number, repeat, 1)
    floor = interleaved("bare(enable=True)", "plain(enable=True)", namespace, number, repeat, 1)
    variable = interleaved("acc.run(loop)", "plain_acc.run(loop)", namespace, max(1, number // loop), repeat, loop)
    noting = interleaved(
        "acc.run_noting(loop)", "plain_acc.run_noting(loop)", namespace, max(1, number // loop // 4), repeat, loop,
    )
    return [
        Result("call", *call),
        Result("floor", *floor),
        Result("variable", *variable),
        Result("noting", *noting),
    ]


LABELS = {
    "call": "fb(enable=True) vs plain callable",
    "floor": "the same on a bare ctypes.Structure",
    "variable": "self.x = self.x + 1 in a METHOD loop",
    "noting": "the same, a METHOD called each pass",
}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--number", type=int, default=100_000, help="operations per timing (default 100000)")
    parser.add_argument("--repeat", type=int, default=7, help="timings per side; the median is reported (default 7)")
    parser.add_argument("--loop", type=int, default=1_000, help="writes per METHOD call in case 2 (default 1000)")
    args = parser.parse_args(argv)

    check_same_work()
    results = run(args.number, args.repeat, args.loop)
    fast = not _config.CHECKS
    mode = "fast mode (IECOOP_CHECKS=0)" if fast else "checked mode (the default)"
    print(f"iecoop call benchmark, {mode}, Python {sys.version.split()[0]}")
    print(f"median of {args.repeat} interleaved timings, ns per operation")
    print(f"{'case':40} {'iecoop':>9} {'plain':>9} {'ratio':>7}  target (this mode)")
    failed = []
    targets = TARGETS[fast]
    for result in results:
        target = targets.get(result.name)
        if target is None:
            verdict = "(for information)"
        else:
            verdict = f"<= {target:.1f} " + ("ok" if result.ratio <= target else "ABOVE TARGET")
            if result.ratio > target:
                failed.append(result.name)
        print(f"{LABELS[result.name]:40} {result.iecoop_ns:9.1f} {result.plain_ns:9.1f} {result.ratio:7.2f}  {verdict}")
    if failed:
        print(f"FAILED: ratio above target for {', '.join(failed)}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
