"""Util: the CODESYS utility library's signal, monitor, controller and function blocks.

Written from the CODESYS documentation (CODESYS Online Help, library "Util":
Signals, Analog Monitors, Controller, Function Manipulators, Mathematical
Functions); the "Util" library page lists each name with what is simulated.
Time comes from the task clock (``iecoop.runtime.clock.current_clock()``), so
in virtual time every block is exact and instant; DERIVATIVE and INTEGRAL take
the time since their last call as their TM input, as CODESYS documents.

>>> from iecoop import T
>>> from iecoop.runtime.clock import default_clock
>>> clock = default_clock(); clock.set(0)
>>> blink = BLINK()
>>> states = []
>>> for _ in range(6):
...     blink(ENABLE=True, TIMEHIGH=T("200ms"), TIMELOW=T("100ms")); states.append(blink.OUT)
...     clock.advance(100_000_000)
>>> states
[True, True, False, True, True, False]
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from iecoop.declarations import VAR, VAR_IN_OUT, VAR_INPUT, VAR_OUTPUT
from iecoop.memory import ARRAY, Struct
from iecoop.pou import FunctionBlock
from iecoop.runtime.clock import current_clock
from iecoop.types import BOOL, BYTE, DWORD, INT, LREAL, REAL, TIME, ULINT

__all__ = [
    "BLINK", "CHARCURVE", "DERIVATIVE", "HYSTERESIS", "INTEGRAL", "LIMITALARM", "PD", "PID", "POINT", "RAMP_INT",
    "RAMP_REAL",
]

_REAL_MAX = 3.402823466e38


def _now_ms() -> int:
    return current_clock().now_ns() // 1_000_000


class _Clocked(FunctionBlock, abstract=True):
    """What the timed blocks share: the task clock at their last call, and the time since it."""

    LAST_NS: ULINT = VAR(0)
    STARTED: BOOL = VAR(False)

    def elapsed_s(self) -> float:
        """Seconds since the last call (0.0 at the first call), and remember this call's time."""
        now = current_clock().now_ns()
        elapsed = (now - self.LAST_NS) / 1e9 if self.STARTED else 0.0
        self.LAST_NS, self.STARTED = now, True
        return max(elapsed, 0.0)


# --- signals and monitors -----------------------------------------------------------------------


class BLINK(FunctionBlock):
    """``BLINK``: while ENABLE, OUT is TRUE for TIMEHIGH, then FALSE for TIMELOW, and again.

    ST: ``VAR_INPUT ENABLE : BOOL; TIMELOW : TIME; TIMEHIGH : TIME; END_VAR  VAR_OUTPUT OUT : BOOL; END_VAR``.
    When ENABLE falls, OUT keeps its value (CODESYS: use ``OUT AND ENABLE``
    for FALSE); a new ENABLE starts again with the TRUE phase.
    """

    ENABLE: BOOL = VAR_INPUT(False)
    TIMELOW: TIME = VAR_INPUT(0)
    TIMEHIGH: TIME = VAR_INPUT(0)
    OUT: BOOL = VAR_OUTPUT(False)
    RUNNING: BOOL = VAR(False)
    START_TIME: TIME = VAR(0)

    def body(self) -> None:
        if not self.ENABLE:
            self.RUNNING = False
            return
        now = _now_ms() & 0xFFFF_FFFF
        if not self.RUNNING:
            self.RUNNING, self.OUT, self.START_TIME = True, True, now
            return
        phase = self.TIMEHIGH if self.OUT else self.TIMELOW
        if (now - self.START_TIME) & 0xFFFF_FFFF >= phase:
            self.OUT = not self.OUT
            self.START_TIME = now


class HYSTERESIS(FunctionBlock):
    """``HYSTERESIS``: OUT becomes TRUE when IN falls below LOW and FALSE when IN rises above HIGH.

    ST: ``VAR_INPUT IN, HIGH, LOW : INT; END_VAR  VAR_OUTPUT OUT : BOOL; END_VAR`` (between LOW and HIGH OUT keeps its value).
    """

    IN: INT = VAR_INPUT(0)
    HIGH: INT = VAR_INPUT(0)
    LOW: INT = VAR_INPUT(0)
    OUT: BOOL = VAR_OUTPUT(False)

    def body(self) -> None:
        if self.IN < self.LOW:
            self.OUT = True
        elif self.IN > self.HIGH:
            self.OUT = False


class LIMITALARM(FunctionBlock):
    """``LIMITALARM``: O when IN is above HIGH, U when below LOW, IL when LOW <= IN <= HIGH.

    ST: ``VAR_INPUT IN, HIGH, LOW : INT; END_VAR  VAR_OUTPUT O, U, IL : BOOL; END_VAR``
    """

    IN: INT = VAR_INPUT(0)
    HIGH: INT = VAR_INPUT(0)
    LOW: INT = VAR_INPUT(0)
    O: BOOL = VAR_OUTPUT(False)
    U: BOOL = VAR_OUTPUT(False)
    IL: BOOL = VAR_OUTPUT(False)

    def body(self) -> None:
        self.O = self.IN > self.HIGH
        self.U = self.IN < self.LOW
        self.IL = not (self.O or self.U)


# --- function manipulators ----------------------------------------------------------------------


class _Ramp(_Clocked, abstract=True):
    """What RAMP_REAL and RAMP_INT share: the ramp's value (kept as LREAL) and its step."""

    VALUE: LREAL = VAR(0.0)
    RAMPING: BOOL = VAR(False)

    if TYPE_CHECKING:
        IN: float
        ASCEND: float
        DESCEND: float
        TIMEBASE: int
        RESET: bool

    def step(self) -> float:
        """Move VALUE toward IN by at most ASCEND / DESCEND per TIMEBASE (per call at T#0s); the new VALUE."""
        elapsed_s = self.elapsed_s()
        target = float(self.IN)
        if self.RESET or not self.RAMPING:
            self.RAMPING = True
            self.VALUE = target
            return target
        share = 1.0 if self.TIMEBASE <= 0 else elapsed_s * 1000.0 / self.TIMEBASE
        current = float(self.VALUE)
        if target > current:
            self.VALUE = min(target, current + abs(float(self.ASCEND)) * share)
        else:
            self.VALUE = max(target, current - abs(float(self.DESCEND)) * share)
        return float(self.VALUE)


class RAMP_REAL(_Ramp):  # noqa: N801 - the ST name
    """``RAMP_REAL``: OUT follows IN, rising at most ASCEND and falling at most DESCEND per TIMEBASE.

    ST: ``VAR_INPUT IN, ASCEND, DESCEND : REAL; TIMEBASE : TIME; RESET : BOOL; END_VAR
    VAR_OUTPUT OUT : REAL; END_VAR``. TIMEBASE T#0s: the limits are per call.
    The first call and RESET set OUT to IN.
    """

    IN: REAL = VAR_INPUT(0.0)
    ASCEND: REAL = VAR_INPUT(0.0)
    DESCEND: REAL = VAR_INPUT(0.0)
    TIMEBASE: TIME = VAR_INPUT(0)
    RESET: BOOL = VAR_INPUT(False)
    OUT: REAL = VAR_OUTPUT(0.0)

    def body(self) -> None:
        self.OUT = self.step()


class RAMP_INT(_Ramp):  # noqa: N801 - the ST name
    """``RAMP_INT``: RAMP_REAL for INT values; OUT is the ramp's value rounded toward zero.

    ST: ``VAR_INPUT IN, ASCEND, DESCEND : INT; TIMEBASE : TIME; RESET : BOOL; END_VAR  VAR_OUTPUT OUT : INT; END_VAR``
    """

    IN: INT = VAR_INPUT(0)
    ASCEND: INT = VAR_INPUT(0)
    DESCEND: INT = VAR_INPUT(0)
    TIMEBASE: TIME = VAR_INPUT(0)
    RESET: BOOL = VAR_INPUT(False)
    OUT: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.OUT = int(self.step())


class POINT(Struct):
    """``POINT``: one point of a CHARCURVE characteristic (X, Y : INT)."""

    X: INT = 0
    Y: INT = 0


class CHARCURVE(FunctionBlock):
    """``CHARCURVE``: OUT is IN mapped through the line P[0]..P[N-1], linear between points.

    ST: ``VAR_INPUT IN : INT; N : BYTE; END_VAR  VAR_IN_OUT P : ARRAY[0..10] OF POINT; END_VAR
    VAR_OUTPUT OUT : INT; ERR : BYTE; END_VAR``. ERR 1: the X values are not
    ascending; 2: IN is outside P[0].X..P[N-1].X (OUT is the end point's Y);
    4: N is not 2..11. The result is rounded toward zero, as INT division.
    """

    IN: INT = VAR_INPUT(0)
    N: BYTE = VAR_INPUT(0)
    P: ARRAY[POINT] = VAR_IN_OUT(bounds=(0, 10))
    OUT: INT = VAR_OUTPUT(0)
    ERR: BYTE = VAR_OUTPUT(0)

    def body(self) -> None:
        n = self.N
        if not 2 <= n <= 11:
            self.ERR = 4
            return
        points = [(self.P[i].X, self.P[i].Y) for i in range(n)]
        if any(points[i][0] >= points[i + 1][0] for i in range(n - 1)):
            self.ERR = 1
            return
        x = self.IN
        if x < points[0][0] or x > points[-1][0]:
            self.ERR = 2
            self.OUT = points[0][1] if x < points[0][0] else points[-1][1]
            return
        self.ERR = 0
        for (x0, y0), (x1, y1) in zip(points, points[1:]):
            if x <= x1:
                num = (y1 - y0) * (x - x0)
                den = x1 - x0
                quotient = abs(num) // den
                self.OUT = y0 + (quotient if num >= 0 else -quotient)
                return


# --- mathematical functions ---------------------------------------------------------------------


class INTEGRAL(FunctionBlock):
    """``INTEGRAL``: OUT sums IN × TM (TM: ms since the last call), in seconds; OVERFLOW locks it until RESET.

    ST: ``VAR_INPUT IN : REAL; TM : DWORD; RESET : BOOL; END_VAR  VAR_OUTPUT OUT : REAL; OVERFLOW : BOOL; END_VAR``.
    OVERFLOW: the sum left the REAL range (±3.4E38).
    """

    IN: REAL = VAR_INPUT(0.0)
    TM: DWORD = VAR_INPUT(0)
    RESET: BOOL = VAR_INPUT(False)
    OUT: REAL = VAR_OUTPUT(0.0)
    OVERFLOW: BOOL = VAR_OUTPUT(False)
    SUM: LREAL = VAR(0.0)

    def body(self) -> None:
        if self.RESET:
            self.SUM, self.OUT, self.OVERFLOW = 0.0, 0.0, False
            return
        if self.OVERFLOW:
            return
        total = self.SUM + self.IN * self.TM / 1000.0
        if abs(total) > _REAL_MAX:
            self.OVERFLOW = True
            return
        self.SUM = total
        self.OUT = total


class DERIVATIVE(FunctionBlock):
    """``DERIVATIVE``: OUT is the slope of IN per second, from its last four values (less noise than two).

    ST: ``VAR_INPUT IN : REAL; TM : DWORD; RESET : BOOL; END_VAR  VAR_OUTPUT OUT : REAL; END_VAR``.
    With x0 = IN and x1..x3 the values of the three calls before, and T the
    mean of the last three TM (s): OUT = (x0 + 3·x1 − 3·x2 − x3) / (6·T),
    exact for a straight line. The first call and RESET fill the history
    with IN (OUT 0.0).
    """

    IN: REAL = VAR_INPUT(0.0)
    TM: DWORD = VAR_INPUT(0)
    RESET: BOOL = VAR_INPUT(False)
    OUT: REAL = VAR_OUTPUT(0.0)
    X1: LREAL = VAR(0.0)
    X2: LREAL = VAR(0.0)
    X3: LREAL = VAR(0.0)
    T1: DWORD = VAR(0)
    T2: DWORD = VAR(0)
    FILLED: BOOL = VAR(False)

    def body(self) -> None:
        x0 = float(self.IN)
        if self.RESET or not self.FILLED:
            self.X1 = self.X2 = self.X3 = x0
            self.T1 = self.T2 = self.TM
            self.FILLED = True
            self.OUT = 0.0
            return
        period = (self.TM + self.T1 + self.T2) / 3000.0
        self.OUT = (x0 + 3 * self.X1 - 3 * self.X2 - self.X3) / (6 * period) if period > 0 else 0.0
        self.X3, self.X2, self.X1 = self.X2, self.X1, x0
        self.T2, self.T1 = self.T1, self.TM


# --- controllers --------------------------------------------------------------------------------


class PD(_Clocked):
    """``PD``: Y = KP · (e + TV · de/dt) + Y_OFFSET, e = SET_POINT − ACTUAL, limited to Y_MIN..Y_MAX.

    ST: ``VAR_INPUT ACTUAL, SET_POINT, KP, TV, Y_MANUAL, Y_OFFSET, Y_MIN, Y_MAX : REAL;
    MANUAL, RESET : BOOL; END_VAR  VAR_OUTPUT Y : REAL; LIMITS_ACTIVE : BOOL; END_VAR``.
    TV in seconds; de/dt is the change of e since the last call over the task
    clock's time between them (0 at the first call). The limits apply when
    Y_MIN < Y_MAX. MANUAL: Y is Y_MANUAL; RESET: Y is Y_OFFSET.
    """

    ACTUAL: REAL = VAR_INPUT(0.0)
    SET_POINT: REAL = VAR_INPUT(0.0)
    KP: REAL = VAR_INPUT(1.0)
    TV: REAL = VAR_INPUT(0.0)
    Y_MANUAL: REAL = VAR_INPUT(0.0)
    Y_OFFSET: REAL = VAR_INPUT(0.0)
    Y_MIN: REAL = VAR_INPUT(0.0)
    Y_MAX: REAL = VAR_INPUT(0.0)
    MANUAL: BOOL = VAR_INPUT(False)
    RESET: BOOL = VAR_INPUT(False)
    Y: REAL = VAR_OUTPUT(0.0)
    LIMITS_ACTIVE: BOOL = VAR_OUTPUT(False)
    E_PREV: LREAL = VAR(0.0)
    HAVE_E: BOOL = VAR(False)
    I_SUM: LREAL = VAR(0.0)

    def body(self) -> None:
        self.Y, self.LIMITS_ACTIVE = self.control(integral_time=0.0)

    def control(self, integral_time: float) -> tuple[float, bool]:
        """Y and LIMITS_ACTIVE for this call; ``integral_time`` TN in s (0: no I part)."""
        dt = self.elapsed_s()
        e = float(self.SET_POINT) - float(self.ACTUAL)
        if self.RESET or self.MANUAL:
            self.I_SUM, self.HAVE_E, self.E_PREV = 0.0, True, e
            return (float(self.Y_MANUAL) if self.MANUAL and not self.RESET else float(self.Y_OFFSET)), False
        de = (e - self.E_PREV) / dt if self.HAVE_E and dt > 0 else 0.0
        self.E_PREV, self.HAVE_E = e, True
        step = e * dt
        i_sum = self.I_SUM + step
        i_part = i_sum / integral_time if integral_time > 0 else 0.0
        y = self.KP * (e + i_part + self.TV * de) + self.Y_OFFSET
        low, high = float(self.Y_MIN), float(self.Y_MAX)
        if low < high and not low < y < high:
            # Anti-windup: at a limit the integrator stops where it was.
            return (high if y >= high else low), True
        self.I_SUM = i_sum
        return y, False


class PID(PD):
    """``PID``: Y = KP · (e + 1/TN · ∫e dt + TV · de/dt) + Y_OFFSET, limited to Y_MIN..Y_MAX.

    ST: ``VAR_INPUT ACTUAL, SET_POINT, KP, TN, TV, Y_MANUAL, Y_OFFSET, Y_MIN, Y_MAX : REAL;
    MANUAL, RESET : BOOL; END_VAR  VAR_OUTPUT Y : REAL; LIMITS_ACTIVE, OVERFLOW : BOOL; END_VAR``.
    TN and TV in seconds; TN = 0 leaves the I part out. ∫e dt sums e times
    the task clock's time since the last call. At a limit the integrator
    stops (anti-windup); MANUAL and RESET clear it. OVERFLOW: the integral
    left the REAL range; Y is then Y_OFFSET until RESET.
    """

    TN: REAL = VAR_INPUT(0.0)
    OVERFLOW: BOOL = VAR_OUTPUT(False)

    def body(self) -> None:
        if self.RESET:
            self.OVERFLOW = False
        if self.OVERFLOW:
            self.Y, self.LIMITS_ACTIVE = float(self.Y_OFFSET), False
            return
        self.Y, self.LIMITS_ACTIVE = self.control(integral_time=float(self.TN))
        if abs(self.I_SUM) > _REAL_MAX:
            self.OVERFLOW, self.I_SUM = True, 0.0
