"""Timers TON, TOF, TP (TIME, ms) and LTON, LTOF, LTP (LTIME, ns).

Each follows the IEC 61131-3 reference state machine (matiec ``timer.txt``),
with the internal variables under matiec's names: ``STATE`` (0 idle,
1 timing, 2 expired), ``PREV_IN`` (IN at the previous call) and ``START_TIME``.
The time is ``current_clock()`` read at the call: the task's clock in a
runtime, the default ``VirtualClock`` in a plain test.

What a user should know (IEC 61131-3:2013, timer function blocks; Beckhoff
Tc2_Standard and CODESYS Standard "TON", "TOF", "TP"):

* A rising or falling edge only *starts* timing; the expiry is seen at a
  later call. So with ``PT = T#0s`` a TON's Q (or the end of a TOF / TP
  pulse) comes one call after the edge.
* PT is read at every call; changing it while timing takes effect at once.
  An expired TON stays expired when PT is raised (STATE 2 is kept).
* TP is not retriggerable, and its Q lasts PT whatever IN does. After the
  pulse, ET holds PT while IN is TRUE and drops to 0 when IN is FALSE
  (profile ``tp_et_after_pulse="reset_when_in_false"``, the IEC reference)
  or holds PT until the next pulse starts (``"hold_until_next_pulse"``, the
  old Beckhoff text).
* Elapsed time is ``(now - START_TIME)`` modulo 2^32 ms (2^64 ns for the
  L-timers), as TIME arithmetic on the PLC: timing across the TIME wrap at
  49d17h is exact.

Outputs are written only when they change, so an idle timer's call is a few
C-level reads.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from iecoop.declarations import VAR, VAR_INPUT, VAR_OUTPUT
from iecoop.pou import FunctionBlock
from iecoop.profiles import active_profile
from iecoop.runtime.clock import task_clock
from iecoop.types import BOOL, LTIME, SINT, TIME

__all__ = ["LTOF", "LTON", "LTP", "TOF", "TON", "TP"]

# The calling thread's task clock; the bound ``get`` is read as fast as a list index.
_now = task_clock.get
_MS = 1_000_000
_TIME_MASK = 0xFFFF_FFFF
_LTIME_MASK = 0xFFFF_FFFF_FFFF_FFFF


class _Timer(FunctionBlock, abstract=True):
    """What TON, TOF and TP share with their LTIME forms: the pins, read in one unit.

    TIME pins count ms (elapsed time modulo 2^32), LTIME pins ns (modulo 2^64).
    Each state machine is written once, by a function that takes the unit
    (clock nanoseconds per tick) and the wrap mask; the two hold them as
    closure variables, so a call reads them as fast as locals.
    """

    if TYPE_CHECKING:
        IN: bool
        PT: int
        Q: bool
        ET: int
        STATE: int
        PREV_IN: bool
        START_TIME: int


def _on_delay(tick: int, mask: int) -> Callable[[_Timer], None]:
    """The TON / LTON state machine for pins counted in ``tick`` ns, wrapping at ``mask``."""

    def body(self: _Timer) -> None:
        if self.IN:
            prev = self.PREV_IN
            state = self.STATE
            if state == 0:
                if not prev:
                    self.STATE = 1
                    if self.Q:
                        self.Q = False
                    self.START_TIME = (_now().now_ns() // tick) & mask
            elif state == 1:
                elapsed = (_now().now_ns() // tick - self.START_TIME) & mask
                pt = self.PT
                if elapsed >= pt:
                    self.STATE = 2
                    self.Q = True
                    self.ET = pt
                else:
                    self.ET = elapsed
            if not prev:
                self.PREV_IN = True
        elif self.PREV_IN:
            # IN fell since the last call: reset the rest. Every call with IN TRUE ends with PREV_IN TRUE and
            # this branch resets all four, so while IN stays FALSE nothing is left to reset (one read a call).
            self.PREV_IN = False
            if self.STATE:
                self.STATE = 0
            if self.Q:
                self.Q = False
            if self.ET:
                self.ET = 0

    return body


def _off_delay(tick: int, mask: int) -> Callable[[_Timer], None]:
    """The TOF / LTOF state machine for pins counted in ``tick`` ns, wrapping at ``mask``."""

    def body(self: _Timer) -> None:
        prev = self.PREV_IN
        state = self.STATE
        if self.IN:
            if self.ET:
                self.ET = 0
            if state:
                self.STATE = 0
            if not prev:
                self.PREV_IN = True
            q = True
        else:
            if state == 0:
                if prev:
                    self.STATE = state = 1
                    self.START_TIME = (_now().now_ns() // tick) & mask
            elif state == 1:
                elapsed = (_now().now_ns() // tick - self.START_TIME) & mask
                pt = self.PT
                if elapsed >= pt:
                    self.STATE = state = 2
                    self.ET = pt
                else:
                    self.ET = elapsed
            if prev:
                self.PREV_IN = False
            q = state == 1
        if q != self.Q:
            self.Q = q

    return body


def _pulse(tick: int, mask: int) -> Callable[[_Timer], None]:
    """The TP / LTP state machine for pins counted in ``tick`` ns, wrapping at ``mask``."""

    def body(self: _Timer) -> None:
        in_ = self.IN
        prev = self.PREV_IN
        state = self.STATE
        if state == 0:
            if in_ and not prev:
                self.STATE = state = 1
                self.Q = True
                # Zero already unless the profile held ET after the last pulse.
                if self.ET:
                    self.ET = 0
                self.START_TIME = (_now().now_ns() // tick) & mask
        elif state == 1:
            elapsed = (_now().now_ns() // tick - self.START_TIME) & mask
            pt = self.PT
            if elapsed >= pt:
                self.STATE = state = 2
                self.Q = False
                self.ET = pt
            else:
                self.ET = elapsed
        if state == 2 and not in_:
            if active_profile().tp_et_after_pulse == "reset_when_in_false":
                self.ET = 0
            self.STATE = 0
        if in_ != prev:
            self.PREV_IN = in_

    return body


class TON(_Timer):
    """TON, on-delay timer: Q is TRUE once IN has been TRUE for PT.

    ST::

        FUNCTION_BLOCK TON
        VAR_INPUT  IN : BOOL; PT : TIME; END_VAR
        VAR_OUTPUT Q : BOOL; ET : TIME; END_VAR

    >>> from iecoop import T, LTIME
    >>> from iecoop.runtime.clock import default_clock
    >>> clock = default_clock(); clock.set(0)
    >>> delay = TON()
    >>> delay(IN=True, PT=T("2s"))
    >>> clock.advance(LTIME("1500ms")); delay(IN=True, PT=T("2s"))
    >>> delay.Q, delay.ET
    (False, 1500)
    >>> clock.advance(LTIME("500ms")); delay(IN=True, PT=T("2s"))
    >>> delay.Q, delay.ET
    (True, 2000)
    >>> delay(IN=False)
    >>> delay.Q, delay.ET
    (False, 0)
    """

    IN: BOOL = VAR_INPUT(False)
    PT: TIME = VAR_INPUT(0)
    Q: BOOL = VAR_OUTPUT(False)
    ET: TIME = VAR_OUTPUT(0)
    STATE: SINT = VAR(0)
    PREV_IN: BOOL = VAR(False)
    START_TIME: TIME = VAR(0)

    body = _on_delay(_MS, _TIME_MASK)


class LTON(_Timer):
    """LTON: TON with LTIME (ns) PT and ET.

    ST: ``VAR_INPUT IN : BOOL; PT : LTIME; END_VAR  VAR_OUTPUT Q : BOOL; ET : LTIME; END_VAR``

    >>> from iecoop import LTIME
    >>> from iecoop.runtime.clock import default_clock
    >>> clock = default_clock(); clock.set(0)
    >>> delay = LTON()
    >>> delay(IN=True, PT=LTIME("1ms"))
    >>> clock.advance(LTIME("999us")); delay(IN=True, PT=LTIME("1ms"))
    >>> delay.Q, delay.ET
    (False, 999000)
    >>> clock.advance(1_000); delay(IN=True, PT=LTIME("1ms"))
    >>> delay.Q, delay.ET
    (True, 1000000)
    """

    IN: BOOL = VAR_INPUT(False)
    PT: LTIME = VAR_INPUT(0)
    Q: BOOL = VAR_OUTPUT(False)
    ET: LTIME = VAR_OUTPUT(0)
    STATE: SINT = VAR(0)
    PREV_IN: BOOL = VAR(False)
    START_TIME: LTIME = VAR(0)

    body = _on_delay(1, _LTIME_MASK)


class TOF(_Timer):
    """TOF, off-delay timer: Q follows IN up and stays TRUE for PT after IN falls.

    ST::

        FUNCTION_BLOCK TOF
        VAR_INPUT  IN : BOOL; PT : TIME; END_VAR
        VAR_OUTPUT Q : BOOL; ET : TIME; END_VAR

    A first call with IN = FALSE is no falling edge: Q stays FALSE.

    >>> from iecoop import T, LTIME
    >>> from iecoop.runtime.clock import default_clock
    >>> clock = default_clock(); clock.set(0)
    >>> fan = TOF()
    >>> fan(IN=True, PT=T("10s")); fan.Q
    True
    >>> fan(IN=False); fan.Q, fan.ET
    (True, 0)
    >>> clock.advance(LTIME("9s")); fan(IN=False); fan.Q, fan.ET
    (True, 9000)
    >>> clock.advance(LTIME("1s")); fan(IN=False); fan.Q, fan.ET
    (False, 10000)
    """

    IN: BOOL = VAR_INPUT(False)
    PT: TIME = VAR_INPUT(0)
    Q: BOOL = VAR_OUTPUT(False)
    ET: TIME = VAR_OUTPUT(0)
    STATE: SINT = VAR(0)
    PREV_IN: BOOL = VAR(False)
    START_TIME: TIME = VAR(0)

    body = _off_delay(_MS, _TIME_MASK)


class LTOF(_Timer):
    """LTOF: TOF with LTIME (ns) PT and ET.

    ST: ``VAR_INPUT IN : BOOL; PT : LTIME; END_VAR  VAR_OUTPUT Q : BOOL; ET : LTIME; END_VAR``

    >>> from iecoop import LTIME
    >>> from iecoop.runtime.clock import default_clock
    >>> clock = default_clock(); clock.set(0)
    >>> hold = LTOF()
    >>> hold(IN=True, PT=LTIME("5us")); hold(IN=False)
    >>> clock.advance(4_999); hold(IN=False); hold.Q
    True
    >>> clock.advance(1); hold(IN=False); hold.Q, hold.ET
    (False, 5000)
    """

    IN: BOOL = VAR_INPUT(False)
    PT: LTIME = VAR_INPUT(0)
    Q: BOOL = VAR_OUTPUT(False)
    ET: LTIME = VAR_OUTPUT(0)
    STATE: SINT = VAR(0)
    PREV_IN: BOOL = VAR(False)
    START_TIME: LTIME = VAR(0)

    body = _off_delay(1, _LTIME_MASK)


class TP(_Timer):
    """TP, pulse timer: a rising edge of IN gives a pulse of exactly PT on Q.

    ST::

        FUNCTION_BLOCK TP
        VAR_INPUT  IN : BOOL; PT : TIME; END_VAR
        VAR_OUTPUT Q : BOOL; ET : TIME; END_VAR

    Not retriggerable; what ET does after the pulse is the profile switch
    ``tp_et_after_pulse`` (see the module docstring).

    >>> from iecoop import T, LTIME
    >>> from iecoop.runtime.clock import default_clock
    >>> clock = default_clock(); clock.set(0)
    >>> pulse = TP()
    >>> pulse(IN=True, PT=T("1s")); pulse(IN=False); pulse.Q
    True
    >>> clock.advance(LTIME("1s")); pulse(IN=False); pulse.Q, pulse.ET
    (False, 0)
    """

    IN: BOOL = VAR_INPUT(False)
    PT: TIME = VAR_INPUT(0)
    Q: BOOL = VAR_OUTPUT(False)
    ET: TIME = VAR_OUTPUT(0)
    STATE: SINT = VAR(0)
    PREV_IN: BOOL = VAR(False)
    START_TIME: TIME = VAR(0)

    body = _pulse(_MS, _TIME_MASK)


class LTP(_Timer):
    """LTP: TP with LTIME (ns) PT and ET.

    ST: ``VAR_INPUT IN : BOOL; PT : LTIME; END_VAR  VAR_OUTPUT Q : BOOL; ET : LTIME; END_VAR``

    >>> from iecoop import LTIME
    >>> from iecoop.runtime.clock import default_clock
    >>> clock = default_clock(); clock.set(0)
    >>> pulse = LTP()
    >>> pulse(IN=True, PT=LTIME("2us")); clock.advance(1_500); pulse(IN=True); pulse.Q, pulse.ET
    (True, 1500)
    >>> clock.advance(500); pulse(IN=True); pulse.Q, pulse.ET
    (False, 2000)
    """

    IN: BOOL = VAR_INPUT(False)
    PT: LTIME = VAR_INPUT(0)
    Q: BOOL = VAR_OUTPUT(False)
    ET: LTIME = VAR_OUTPUT(0)
    STATE: SINT = VAR(0)
    PREV_IN: BOOL = VAR(False)
    START_TIME: LTIME = VAR(0)

    body = _pulse(1, _LTIME_MASK)
