"""A whole scan: 1,000 station FBs on a 10 ms task against the same logic in plain Python, in one run.

Each station watches a part sensor: an R_TRIG turns the sensor's rising edge
into a one-cycle pulse, a CTU counts those pulses, and a TON flags a jam when
the sensor stays on longer than 200 ms. The line program calls the 1,000
stations every cycle with the sensor pattern of a moving conveyor (each
station sees a part for 3 cycles in every 17, shifted by its index; every
50th station holds its part for 30 cycles, so its jam timer expires).

ST of one station::

    FUNCTION_BLOCK FB_Station
    VAR_INPUT  sensor : BOOL; END_VAR
    VAR_OUTPUT parts : WORD; jammed : BOOL; END_VAR
    VAR arrived : R_TRIG; counter : CTU; jam : TON; END_VAR
    arrived(CLK := sensor);
    counter(CU := arrived.Q, PV := 60000);
    jam(IN := sensor, PT := T#200MS);
    parts := counter.CV;
    jammed := jam.Q;

Cases, each run for the same number of cycles:

(a) iecoop: the ``Line`` program on a ``Runtime`` task (``rt.run(cycles=n)``),
    the loop written in its body as users write it
    (``for i in range(1, N + 1): self.stations[i](sensor=...)``), stations in
    an ``ARRAY[1..1000] OF Station``, the standard FBs of ``iecoop.stdlib``
    reading the task clock, the TON's preset a literal in the body
    (``PT=T("200ms")``);
(s) the same station and program in Structured Text, ``st.load(SOURCE)``;
    s/a is what the scan costs when it is loaded from ST rather than
    written in Python as users write it (target 1.1);
(p) for information, the ST's statements written in Python (``i`` a VAR,
    ``MOD``): what (s) is compiled from, so s/p is what the loading itself
    costs, and p/a what those statements cost against the Python loop;
(h) for information, (a) hand-optimised: the array read once per cycle and
    handed to a helper holding the loop;
(b) plain Python: the same program written with plain classes: ``__slots__``,
    a TON / R_TRIG / CTU written out with the same pins, called the same way
    (keyword arguments, inputs kept between calls as an FB keeps them), a
    clock variable set per cycle, WORD wrap, the stations in a list;
(c) iecoop with RETAIN: each station also keeps a ``RETAIN`` part total, the
    runtime writes the retain image to a store on disk at the end of every
    cycle; (c) - (a) is what capturing RETAIN costs per cycle.

Before timing, the script checks that every side counts the same parts and
flags the same jams. It then times the cases turn about (CPU time of the
process, so waiting for a core on a loaded machine does not count), reports
the median time per cycle and the median of the ratios of timings taken in
the same round; it exits with status 1 when a/b is above the target of its
mode (1.5 in fast mode, ``IECOOP_CHECKS=0``; 2.0 in checked mode) or s/a
above 1.1.

    IECOOP_CHECKS=0 python benchmarks/bench_scan.py
    python benchmarks/bench_scan.py
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from typing import Any
from pathlib import Path

# Runs from a checkout without installing the package.
ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from iecoop import ARRAY, BOOL, DINT, VAR, VAR_INPUT, VAR_OUTPUT, WORD, FunctionBlock, Program, T, _config, st  # noqa: E402
from iecoop.conversions import MOD  # noqa: E402
from iecoop.runtime import Runtime, Task  # noqa: E402
from iecoop.stdlib import CTU, R_TRIG, TON  # noqa: E402

FAST_MODE_TARGET = 1.5
CHECKED_MODE_TARGET = 2.0
#: The scan loaded from ST against the scan written in Python as users write it (s/a).
ST_TARGET = 1.1
STATIONS = 1_000
PERIOD, ON, JAM_ON = 17, 3, 30
JAM_PT = T("200ms")
INTERVAL = T("10ms")


def sensor_pattern(tick: int, index: int) -> bool:
    """What station ``index`` (1-based) sees at cycle ``tick``; the same for both sides."""
    if index % 50 == 0:
        return (tick + index) % 60 < JAM_ON
    return (tick + index) % PERIOD < ON


class Station(FunctionBlock):
    """FB_Station: counts parts on the sensor's rising edge and flags a jam after 200 ms."""

    sensor: BOOL = VAR_INPUT()
    parts: WORD = VAR_OUTPUT()
    jammed: BOOL = VAR_OUTPUT()
    arrived: R_TRIG = VAR()
    counter: CTU = VAR()
    jam: TON = VAR()

    def body(self) -> None:
        self.arrived(CLK=self.sensor)
        self.counter(CU=self.arrived.Q, PV=60000)
        self.jam(IN=self.sensor, PT=T("200ms"))  # the literal in the body, as the docs write it
        self.parts = self.counter.CV
        self.jammed = self.jam.Q


class RetainStation(Station):
    """FB_Station with a RETAIN total of parts ever seen (survives a power loss)."""

    total: DINT = VAR(retain=True)

    def body(self) -> None:
        super().body()
        if self.arrived.Q:
            self.total += 1


def scan(stations: ARRAY[Station], tick: int) -> None:
    """The hand-optimised cycle: the array read once and handed to a helper (for information)."""
    for i in range(1, STATIONS + 1):
        stations[i](sensor=sensor_pattern(tick, i))


class Line(Program):
    """PROGRAM Line: ``FOR i := 1 TO 1000 DO stations[i](sensor := ...); END_FOR``, written in the body as users write it."""

    stations: ARRAY[Station] = VAR(bounds=(1, STATIONS))
    tick: DINT = VAR()

    def body(self) -> None:
        for i in range(1, STATIONS + 1):
            self.stations[i](sensor=sensor_pattern(self.tick, i))
        self.tick += 1


class HelperLine(Program):
    """PROGRAM Line with the array read once per cycle and the loop in a helper."""

    stations: ARRAY[Station] = VAR(bounds=(1, STATIONS))
    tick: DINT = VAR()

    def body(self) -> None:
        scan(self.stations, self.tick)
        self.tick += 1


class RetainLine(Program):
    """PROGRAM Line with the RETAIN stations."""

    stations: ARRAY[RetainStation] = VAR(bounds=(1, STATIONS))
    tick: DINT = VAR()

    def body(self) -> None:
        for i in range(1, STATIONS + 1):
            self.stations[i](sensor=sensor_pattern(self.tick, i))
        self.tick += 1


class StLine(Program):
    """PROGRAM Line written in Python statement for statement as its ST below (``i`` a VAR, ``MOD``)."""

    stations: ARRAY[Station] = VAR(bounds=(1, STATIONS))
    tick: DINT = VAR()
    i: DINT = VAR()

    def body(self) -> None:
        for self.i in range(1, STATIONS + 1):
            if MOD(self.i, 50) == 0:
                self.stations[self.i](sensor=MOD(self.tick + self.i, 60) < JAM_ON)
            else:
                self.stations[self.i](sensor=MOD(self.tick + self.i, PERIOD) < ON)
        self.tick = self.tick + 1


#: The same station and line in Structured Text, loaded with ``st.load``.
SOURCE = f"""
FUNCTION_BLOCK FB_Station
VAR_INPUT sensor : BOOL; END_VAR
VAR_OUTPUT parts : WORD; jammed : BOOL; END_VAR
VAR arrived : R_TRIG; counter : CTU; jam : TON; END_VAR
arrived(CLK := sensor);
counter(CU := arrived.Q, PV := 60000);
jam(IN := sensor, PT := T#200MS);
parts := counter.CV;
jammed := jam.Q;
END_FUNCTION_BLOCK

PROGRAM Line
VAR
    stations : ARRAY[1..{STATIONS}] OF FB_Station;
    tick : DINT;
    i : DINT;
END_VAR
FOR i := 1 TO {STATIONS} DO
    IF i MOD 50 = 0 THEN
        stations[i](sensor := (tick + i) MOD 60 < {JAM_ON});
    ELSE
        stations[i](sensor := (tick + i) MOD {PERIOD} < {ON});
    END_IF
END_FOR
tick := tick + 1;
END_PROGRAM
"""


# -- the same logic in plain Python -------------------------------------------

class Clock:
    __slots__ = ("now_ms",)

    def __init__(self) -> None:
        self.now_ms = 0


class PlainRTrig:
    __slots__ = ("CLK", "M", "Q")

    def __init__(self) -> None:
        self.CLK = False
        self.M = False
        self.Q = False

    def __call__(self, CLK: bool | None = None) -> None:  # noqa: N803 - the FB's pin names
        if CLK is not None:
            self.CLK = CLK
        self.Q = self.CLK and not self.M
        self.M = self.CLK


class PlainCtu:
    __slots__ = ("CU", "CU_M", "CV", "PV", "Q", "RESET")

    def __init__(self) -> None:
        self.CU = False
        self.RESET = False
        self.PV = 0
        self.CU_M = False
        self.CV = 0
        self.Q = False

    def __call__(self, CU: bool | None = None, RESET: bool | None = None, PV: int | None = None) -> None:  # noqa: N803
        if CU is not None:
            self.CU = CU
        if RESET is not None:
            self.RESET = RESET
        if PV is not None:
            self.PV = PV & 0xFFFF
        if self.RESET:
            self.CV = 0
        elif self.CU and not self.CU_M and self.CV < self.PV:
            self.CV = (self.CV + 1) & 0xFFFF
        self.CU_M = self.CU
        self.Q = self.CV >= self.PV


class PlainTon:
    __slots__ = ("ET", "IN", "PREV_IN", "PT", "Q", "START_TIME", "STATE", "clock")

    def __init__(self, clock: Clock) -> None:
        self.clock = clock
        self.IN = False
        self.PT = 0
        self.STATE = 0
        self.PREV_IN = False
        self.START_TIME = 0
        self.Q = False
        self.ET = 0

    def __call__(self, IN: bool | None = None, PT: int | None = None) -> None:  # noqa: N803
        if IN is not None:
            self.IN = IN
        if PT is not None:
            self.PT = PT & 0xFFFF_FFFF
        if self.IN:
            if self.STATE == 0:
                if not self.PREV_IN:
                    self.STATE = 1
                    self.Q = False
                    self.START_TIME = self.clock.now_ms
            elif self.STATE == 1:
                elapsed = (self.clock.now_ms - self.START_TIME) & 0xFFFF_FFFF
                if elapsed >= self.PT:
                    self.STATE = 2
                    self.Q = True
                    self.ET = self.PT
                else:
                    self.ET = elapsed
            self.PREV_IN = True
        else:
            self.STATE = 0
            self.Q = False
            self.ET = 0
            self.PREV_IN = False


class PlainStation:
    __slots__ = ("arrived", "counter", "jam", "jammed", "parts", "sensor")

    def __init__(self, clock: Clock) -> None:
        self.sensor = False
        self.parts = 0
        self.jammed = False
        self.arrived = PlainRTrig()
        self.counter = PlainCtu()
        self.jam = PlainTon(clock)

    def __call__(self, sensor: bool | None = None) -> None:
        if sensor is not None:
            self.sensor = sensor
        self.arrived(CLK=self.sensor)
        self.counter(CU=self.arrived.Q, PV=60000)
        self.jam(IN=self.sensor, PT=JAM_PT)
        self.parts = self.counter.CV
        self.jammed = self.jam.Q


class PlainLine:
    __slots__ = ("clock", "stations", "tick")

    def __init__(self) -> None:
        self.clock = Clock()
        self.stations = [PlainStation(self.clock) for _ in range(STATIONS)]
        self.tick = 0

    def run(self, cycles: int) -> None:
        for _ in range(cycles):
            self.clock.now_ms = self.tick * INTERVAL
            tick = self.tick
            for i, station in enumerate(self.stations, 1):
                station(sensor=sensor_pattern(tick, i))
            self.tick = tick + 1


# -- measuring ------------------------------------------------------------------

def iecoop_line(store: str | Path = ":memory:", program: Any = None) -> tuple[Runtime, Any]:
    line = Line() if program is None else program
    rt = Runtime(store=store)
    rt.add_task(Task("PlcTask", interval=INTERVAL, priority=20), line)
    return rt, line


def check_same_work(cycles: int, loaded: Any) -> tuple[int, int]:
    """Run every side; they must count the same parts and see the same jams at every station."""
    lines = [iecoop_line(program=p) for p in (Line(), HelperLine(), StLine(), loaded)]
    plain = PlainLine()
    jams = 0
    for _ in range(cycles):
        for rt, _line in lines:
            rt.run(cycles=1)
        plain.run(1)
        jams += sum(1 for s in plain.stations if s.jammed)
    theirs = [(s.parts, s.jammed) for s in plain.stations]
    for _rt, line in lines:
        mine = [(line.stations[i].parts, line.stations[i].jammed) for i in range(1, STATIONS + 1)]
        assert mine == theirs, f"the iecoop {type(line).__name__} and the plain line disagree"
    return sum(p for p, _ in theirs), jams


def cycles_of(rt: Runtime) -> Callable[[int], None]:
    def run(n: int) -> None:
        rt.run(cycles=n)

    return run


def per_cycle(run: Callable[[int], None], cycles: int) -> float:
    # CPU time of this process: on a shared machine, time spent waiting for a core is not counted.
    start = time.process_time()
    run(cycles)
    return (time.process_time() - start) / cycles


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--cycles", type=int, default=20, help="cycles per timing (default 20)")
    parser.add_argument("--repeat", type=int, default=7, help="timings per case; the median is reported (default 7)")
    args = parser.parse_args(argv)

    parts, jams = check_same_work(200, st.load(SOURCE).Line)
    plain = PlainLine()
    with tempfile.TemporaryDirectory() as folder:
        cases: dict[str, tuple[str, Callable[[int], None]]] = {}
        for key, label, program, store in (
            ("a", "iecoop Line, the loop in the body", Line(), ":memory:"),
            ("s", "the same Line loaded from ST", st.load(SOURCE).Line, ":memory:"),
            ("p", "the ST's statements written in Python", StLine(), ":memory:"),
            ("h", "iecoop Line, array read once (helper)", HelperLine(), ":memory:"),
            ("c", "iecoop Line with RETAIN, store on disk", RetainLine(), Path(folder) / "store"),
        ):
            rt, _ = iecoop_line(store, program)
            cases[key] = (label, cycles_of(rt))
        cases["b"] = ("plain Python, same logic", plain.run)
        times: dict[str, list[float]] = {key: [] for key in cases}
        for _ in range(args.repeat):
            for key, (_label, run) in cases.items():
                times[key].append(per_cycle(run, args.cycles))
    median = {key: statistics.median(values) for key, values in times.items()}
    # Ratios of timings taken in the same round, so a busy spell weighs on both sides alike.
    ratios = {
        pair: [x / y for x, y in zip(times[pair[0]], times[pair[1]])]
        for pair in (("a", "b"), ("h", "b"), ("s", "a"), ("s", "p"), ("p", "a"))
    }
    fast = not _config.CHECKS
    mode = "fast mode (IECOOP_CHECKS=0)" if fast else "checked mode (the default)"
    print(f"iecoop scan benchmark, {mode}, Python {sys.version.split()[0]}")
    print(f"{STATIONS} stations (TON + R_TRIG + CTU each); every side counted {parts} parts in 200 cycles, "
          f"{jams} station-cycles jammed")
    print(f"median of {args.repeat} timings of {args.cycles} cycles, ms per cycle")
    print(f"{'case':44} {'ms/cycle':>9} {'cycles/s':>9}")
    for key in ("a", "s", "p", "h", "b", "c"):
        label = f"{key}  {cases[key][0]}"
        print(f"{label:44} {median[key] * 1e3:9.3f} {1 / median[key]:9.0f}")
    target = FAST_MODE_TARGET if fast else CHECKED_MODE_TARGET
    failed = False
    for (x, y), limit in ((("a", "b"), target), (("h", "b"), None), (("s", "a"), ST_TARGET), (("s", "p"), None), (("p", "a"), None)):
        values = ratios[(x, y)]
        ratio = statistics.median(values)
        goal = f" (target <= {limit:.2f})" if limit is not None else ""
        print(f"{x}/{y} = {ratio:.2f}, per round {min(values):.2f} to {max(values):.2f}{goal}")
        if limit is not None and ratio > limit:
            print(f"FAILED: {x}/{y} above target")
            failed = True
    print(f"RETAIN capture + write, per cycle: {(median['c'] - median['a']) * 1e3:.3f} ms "
          f"({(median['c'] / median['a'] - 1) * 100:.0f}% of a cycle)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
