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
    stations in an ``ARRAY[1..1000] OF Station``, the standard FBs of
    ``iecoop.stdlib`` reading the task clock;
(b) plain Python: the same program written with plain classes: ``__slots__``,
    a TON / R_TRIG / CTU written out with the same pins, called the same way
    (keyword arguments, inputs kept between calls as an FB keeps them), a
    clock variable set per cycle, WORD wrap, the stations in a list;
(c) iecoop with RETAIN: each station also keeps a ``RETAIN`` part total, the
    runtime writes the retain image to a store on disk at the end of every
    cycle; (c) - (a) is what capturing RETAIN costs per cycle.

Before timing, the script checks that (a) and (b) count the same parts and
flag the same jams. It then times the cases turn about (CPU time of the
process, so waiting for a core on a loaded machine does not count), reports
the median time per cycle, cycles per second, and the ratio a/b of the
medians with its range over the timings; it exits with status 1 when a/b
is above the target of its mode: 2.0 in fast mode
(``IECOOP_CHECKS=0``), 4.0 in checked mode. The station writes its TON's
preset as a literal in the body (``PT=T("200ms")``), as the docs teach.

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
from pathlib import Path

# Runs from a checkout without installing the package.
ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from iecoop import ARRAY, BOOL, DINT, VAR, VAR_INPUT, VAR_OUTPUT, WORD, FunctionBlock, Program, T, _config  # noqa: E402
from iecoop.runtime import Runtime, Task  # noqa: E402
from iecoop.stdlib import CTU, R_TRIG, TON  # noqa: E402

FAST_MODE_TARGET = 2.0
CHECKED_MODE_TARGET = 4.0
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


def scan(stations: ARRAY[Station] | ARRAY[RetainStation], tick: int) -> None:
    """One cycle over the stations: ``FOR i := 1 TO 1000 DO stations[i](sensor := ...); END_FOR``."""
    for i in range(1, STATIONS + 1):
        stations[i](sensor=sensor_pattern(tick, i))


class Line(Program):
    """PROGRAM Line: one cycle calls every station with its sensor."""

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
        scan(self.stations, self.tick)
        self.tick += 1


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

def iecoop_line(store: str | Path = ":memory:", retain: bool = False) -> tuple[Runtime, Line | RetainLine]:
    line: Line | RetainLine = RetainLine() if retain else Line()
    rt = Runtime(store=store)
    rt.add_task(Task("PlcTask", interval=INTERVAL, priority=20), line)
    return rt, line


def check_same_work(cycles: int) -> tuple[int, int]:
    """Run both sides; they must count the same parts and see the same jams at every station."""
    rt, line = iecoop_line()
    plain = PlainLine()
    jams = 0
    for _ in range(cycles):
        rt.run(cycles=1)
        plain.run(1)
        jams += sum(1 for s in plain.stations if s.jammed)
    mine = [(line.stations[i].parts, line.stations[i].jammed) for i in range(1, STATIONS + 1)]
    theirs = [(s.parts, s.jammed) for s in plain.stations]
    assert mine == theirs, "the iecoop line and the plain line disagree"
    return sum(p for p, _ in theirs), jams


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

    parts, jams = check_same_work(200)
    rt, _ = iecoop_line()
    plain = PlainLine()
    with tempfile.TemporaryDirectory() as folder:
        rt_retain, _ = iecoop_line(Path(folder) / "store", retain=True)
        a: list[float] = []
        b: list[float] = []
        c: list[float] = []
        for _ in range(args.repeat):
            a.append(per_cycle(lambda n: rt.run(cycles=n), args.cycles))
            b.append(per_cycle(plain.run, args.cycles))
            c.append(per_cycle(lambda n: rt_retain.run(cycles=n), args.cycles))
        rt_retain.stop()
    ma, mb, mc = statistics.median(a), statistics.median(b), statistics.median(c)
    ratio = ma / mb
    ratios = [x / y for x, y in zip(a, b)]
    fast = not _config.CHECKS
    mode = "fast mode (IECOOP_CHECKS=0)" if fast else "checked mode (the default)"
    print(f"iecoop scan benchmark, {mode}, Python {sys.version.split()[0]}")
    print(f"{STATIONS} stations (TON + R_TRIG + CTU each); both sides counted {parts} parts in 200 cycles, "
          f"{jams} station-cycles jammed")
    print(f"median of {args.repeat} timings of {args.cycles} cycles, ms per cycle")
    print(f"{'case':44} {'ms/cycle':>9} {'cycles/s':>9}")
    for label, value in (
        ("a  iecoop Line on a Runtime task", ma),
        ("b  plain Python, same logic", mb),
        ("c  iecoop Line with RETAIN, store on disk", mc),
    ):
        print(f"{label:44} {value * 1e3:9.3f} {1 / value:9.0f}")
    target = FAST_MODE_TARGET if fast else CHECKED_MODE_TARGET
    print(f"a/b = {ratio:.2f}, per timing {min(ratios):.2f} to {max(ratios):.2f} (target in this mode: <= {target:.1f})")
    print(f"RETAIN capture + write, per cycle: {(mc - ma) * 1e3:.3f} ms ({(mc / ma - 1) * 100:.0f}% of a cycle)")
    if ratio > target:
        print("FAILED: a/b above target")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
