"""A program loaded from Structured Text against the same program written by hand in iecoop Python, in one run.

The program is the scan of ``bench_scan.py`` written in ST: a line of 1,000
stations, each an R_TRIG turning its part sensor's rising edge into a pulse,
a CTU counting the pulses and a TON flagging a jam after 200 ms. The line
computes each station's sensor from the cycle count (a part for 3 cycles in
every 17, shifted by the station's index; every 50th station holds its part
for 30 cycles in 60, so its jam timer expires).

Cases, each a PROGRAM on a 10 ms task of a ``Runtime``, run for the same cycles:

(a) ``st.load(SOURCE).Line``: the ST below, translated and compiled by iecoop.st;
(b) ``Line``: the same program written by hand with the forms of the Rosetta
    table (``self.arrived(CLK=self.sensor)``, ``MOD`` for ST's MOD, a loop
    variable that is a VAR of the program, as in the ST).

Before timing, both sides run 200 cycles and must agree at every station. The
script then times the cases turn about and reports the median time per cycle
and the ratio a/b; it exits with status 1 when a/b is above 1.2.

    IECOOP_CHECKS=0 python benchmarks/bench_st.py
    python benchmarks/bench_st.py
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from iecoop import ARRAY, BOOL, DINT, INT, VAR, VAR_INPUT, VAR_OUTPUT, WORD, FunctionBlock, Program, T, _config, st  # noqa: E402
from iecoop.conversions import MOD  # noqa: E402
from iecoop.runtime import Runtime, Task  # noqa: E402
from iecoop.stdlib import CTU, R_TRIG, TON  # noqa: E402

TARGET = 1.2
STATIONS = 1_000

SOURCE = """
FUNCTION_BLOCK FB_Station
VAR_INPUT bSensor : BOOL; END_VAR
VAR_OUTPUT nParts : WORD; bJammed : BOOL; END_VAR
VAR fbArrived : R_TRIG; fbCounter : CTU; fbJam : TON; END_VAR
fbArrived(CLK := bSensor);
fbCounter(CU := fbArrived.Q, PV := 60000);
fbJam(IN := bSensor, PT := T#200MS);
nParts := fbCounter.CV;
bJammed := fbJam.Q;
END_FUNCTION_BLOCK

PROGRAM Line
VAR
    aStations : ARRAY[1..1000] OF FB_Station;
    nTick : DINT;
    i : INT;
END_VAR
FOR i := 1 TO 1000 DO
    IF i MOD 50 = 0 THEN
        aStations[i](bSensor := (nTick + i) MOD 60 < 30);
    ELSE
        aStations[i](bSensor := (nTick + i) MOD 17 < 3);
    END_IF
END_FOR
nTick := nTick + 1;
END_PROGRAM
"""


class Station(FunctionBlock):
    """FB_Station, by hand."""

    bSensor: BOOL = VAR_INPUT()
    nParts: WORD = VAR_OUTPUT()
    bJammed: BOOL = VAR_OUTPUT()
    fbArrived: R_TRIG = VAR()
    fbCounter: CTU = VAR()
    fbJam: TON = VAR()

    def body(self) -> None:
        self.fbArrived(CLK=self.bSensor)
        self.fbCounter(CU=self.fbArrived.Q, PV=60000)
        self.fbJam(IN=self.bSensor, PT=T("200ms"))
        self.nParts = self.fbCounter.CV
        self.bJammed = self.fbJam.Q


class Line(Program):
    """PROGRAM Line, by hand."""

    aStations: ARRAY[Station] = VAR(bounds=(1, STATIONS))
    nTick: DINT = VAR()
    i: INT = VAR()

    def body(self) -> None:
        for self.i in range(1, STATIONS + 1):
            if MOD(self.i, 50) == 0:
                self.aStations[self.i](bSensor=MOD(self.nTick + self.i, 60) < 30)
            else:
                self.aStations[self.i](bSensor=MOD(self.nTick + self.i, 17) < 3)
        self.nTick += 1


def on_task(program: Any) -> Runtime:
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    return runtime


def per_cycle(run: Callable[[int], None], cycles: int) -> float:
    start = time.perf_counter()
    run(cycles)
    return (time.perf_counter() - start) / cycles


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--cycles", type=int, default=20, help="cycles per timing (default 20)")
    parser.add_argument("--repeat", type=int, default=7, help="timings per case; the median is reported (default 7)")
    args = parser.parse_args(argv)

    loaded, written = st.load(SOURCE).Line, Line()
    rt_a, rt_b = on_task(loaded), on_task(written)
    rt_a.run(cycles=200)
    rt_b.run(cycles=200)
    seen_a = [(loaded.aStations[i].nParts, loaded.aStations[i].bJammed) for i in range(1, STATIONS + 1)]
    seen_b = [(written.aStations[i].nParts, written.aStations[i].bJammed) for i in range(1, STATIONS + 1)]
    assert seen_a == seen_b, "the loaded program and the hand-written one disagree"
    a: list[float] = []
    b: list[float] = []
    for _ in range(args.repeat):
        a.append(per_cycle(lambda n: rt_a.run(cycles=n), args.cycles))
        b.append(per_cycle(lambda n: rt_b.run(cycles=n), args.cycles))
    ma, mb = statistics.median(a), statistics.median(b)
    ratio = ma / mb
    mode = "fast mode (IECOOP_CHECKS=0)" if not _config.CHECKS else "checked mode (the default)"
    print(f"iecoop.st benchmark, {mode}, Python {sys.version.split()[0]}")
    print(f"{STATIONS} stations; both sides counted {sum(p for p, _ in seen_a)} parts in 200 cycles")
    print(f"median of {args.repeat} timings of {args.cycles} cycles, ms per cycle")
    for label, value in (("a  loaded from ST", ma), ("b  written by hand", mb)):
        print(f"{label:24} {value * 1e3:9.3f}")
    print(f"a/b = {ratio:.2f} (target <= {TARGET:.1f})")
    if ratio > TARGET:
        print("FAILED: a/b above target")
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
