"""What a typed PLC variable costs against plain Python, measured side by side in one run.

The statement is the same in every case, ``x := x + 1`` on an INT:

(a) an INT member of a Struct (a ctypes field: C does the load, the store and
    the wrap to 16 bits);
(b) a plain Python attribute doing the same work, wrap included:
    ``o.x = ((o.x + 1 + 32768) & 0xFFFF) - 32768``;
(c) a plain attribute without the wrap, for information (it computes a
    different thing once x passes 32767).

Run from the repository root::

    IECOOP_CHECKS=0 python benchmarks/bench_access.py    # fast mode
    python benchmarks/bench_access.py                    # checked mode (the default)

Each case is timed with ``timeit.repeat`` in several rounds, the cases taking
turns, so a burst of load on the machine hits all of them alike. The table
shows the median time per statement, raw and with the loop's own cost (an
empty statement, timed the same way) taken off, and the ratios of the net
medians. The script exits with status 1 when a/b exceeds the limit of its
mode: 3.0 in fast mode (``IECOOP_CHECKS=0``), 8.0 in checked mode.
Options: ``--number`` statements per timing, ``--repeat`` timings per round,
``--rounds`` rounds.
"""

from __future__ import annotations

import argparse
import dataclasses
import platform
import statistics
import sys
import time
import timeit
from collections.abc import Callable
from pathlib import Path

# Runs from a checkout without installing the package.
ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from iecoop import INT, Struct  # noqa: E402
from iecoop import _config  # noqa: E402

FAST_MODE_LIMIT = 3.0
CHECKED_MODE_LIMIT = 8.0


class Counter(Struct):
    x: INT = 0


class PlainCounter:
    def __init__(self) -> None:
        self.x = 0


@dataclasses.dataclass(frozen=True)
class Case:
    """One timed statement; ``make`` builds the namespace it runs in, fresh for each repeat."""

    key: str
    title: str
    stmt: str
    make: Callable[[], dict[str, object]]


def _struct_field() -> dict[str, object]:
    return {"s": Counter()}


def _plain() -> dict[str, object]:
    return {"o": PlainCounter()}


CASES: list[Case] = [
    Case("a", "INT member of a Struct: s.x = s.x + 1", "s.x = s.x + 1", _struct_field),
    Case("b", "plain attribute with the INT wrap", "o.x = ((o.x + 1 + 32768) & 0xFFFF) - 32768", _plain),
    Case("c", "plain attribute, no wrap", "o.x = o.x + 1", _plain),
    # Later: "d", an FB variable written inside a method (self.x = self.x + 1 in a FunctionBlock).
]

# (numerator, denominator) pairs reported as ratios.
RATIOS: list[tuple[str, str]] = [("a", "b"), ("a", "c"), ("b", "c")]


def check_same_work() -> None:
    """(a) and (b) must compute the same INT values, or the comparison means nothing."""
    typed, plain = Counter(), PlainCounter()
    for _ in range(40_000):  # passes 32767, so the wrap happens
        typed.x = typed.x + 1
        plain.x = ((plain.x + 1 + 32768) & 0xFFFF) - 32768
    if typed.x != plain.x or typed.x != 40_000 - 65_536:
        raise SystemExit(f"cases a and b disagree: {typed.x} != {plain.x}")


LOOP = Case("loop", "empty statement (the timing loop itself)", "pass", dict)


def median_ns(cases: list[Case], number: int, repeat: int, rounds: int) -> dict[str, float]:
    """Median nanoseconds per statement of each case, over ``rounds`` x ``repeat`` timings."""
    runs: dict[str, list[float]] = {case.key: [] for case in cases}
    for _ in range(rounds):
        for case in cases:
            # CPU time of the process: waiting for a core on a loaded machine is not counted.
            seconds = timeit.repeat(case.stmt, globals=case.make(), number=number, repeat=repeat, timer=time.process_time)
            runs[case.key].extend(t / number * 1e9 for t in seconds)
    return {key: statistics.median(values) for key, values in runs.items()}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--number", type=int, default=200_000, help="statements per timing")
    parser.add_argument("--repeat", type=int, default=3, help="timings per case in each round")
    parser.add_argument("--rounds", type=int, default=5, help="rounds; the median of all timings is reported")
    args = parser.parse_args(argv)

    check_same_work()
    mode = "checked mode (default)" if _config.CHECKS else "fast mode (IECOOP_CHECKS=0)"
    medians = median_ns([LOOP, *CASES], args.number, args.repeat, args.rounds)
    loop = medians.pop(LOOP.key)
    raw = medians
    net = {key: max(value - loop, 0.001) for key, value in raw.items()}

    timings = args.rounds * args.repeat
    print(f"iecoop access benchmark: {mode}")
    print(f"Python {platform.python_version()} on {platform.machine()}, {timings} timings x {args.number:,} statements")
    print(f"loop cost {loop:.1f} ns per statement, taken off below")
    print()
    print(f"{'case':<46} {'raw ns':>8} {'net ns':>8}")
    for case in CASES:
        print(f"{case.key}  {case.title:<43} {raw[case.key]:>8.1f} {net[case.key]:>8.1f}")
    print()
    for top, bottom in RATIOS:
        print(f"ratio {top}/{bottom} = {net[top] / net[bottom]:.2f}")

    ratio = net["a"] / net["b"]
    limit = CHECKED_MODE_LIMIT if _config.CHECKS else FAST_MODE_LIMIT
    if ratio > limit:
        print(f"FAIL: a/b = {ratio:.2f} exceeds {limit} in this mode")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
