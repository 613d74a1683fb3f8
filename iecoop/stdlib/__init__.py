"""The IEC 61131-3 standard function blocks, with their IEC pin names.

==========================  =====================================================
module                      blocks
==========================  =====================================================
``timers``                  TON TOF TP (TIME), LTON LTOF LTP (LTIME)
``triggers``                R_TRIG F_TRIG
``counters``                CTU CTD CTUD (TwinCAT / CODESYS: RESET, LOAD, WORD),
                            CTU_INT CTD_INT CTUD_INT (IEC: R, LD, INT),
                            CTU_DINT CTU_UDINT
``bistables``               SR RS
``sync``                    test_and_set, CriticalSection, S (``S=``), R (``R=``)
``heap``                    new_array (``__NEW(BYTE, n)``: n elements on the heap)
``calendar_text``           string_to_calendar (``STRING_TO_DT``, ``STRING_TO_DATE``, ``STRING_TO_TOD``)
==========================  =====================================================

Timers read ``iecoop.runtime.clock.current_clock()``: the task's clock in a
runtime, a ``VirtualClock`` you advance yourself in a plain test.

>>> from iecoop import T, LTIME
>>> from iecoop.runtime.clock import default_clock
>>> clock = default_clock(); clock.set(0)
>>> start, delay = R_TRIG(), TON()
>>> start(CLK=True); delay(IN=start.Q, PT=T("100ms")); delay.Q
False
"""

from iecoop.stdlib.bistables import RS, SR
from iecoop.stdlib.counters import CTD, CTD_INT, CTU, CTU_DINT, CTU_INT, CTU_UDINT, CTUD, CTUD_INT
from iecoop.stdlib.sync import CriticalSection, R, S, test_and_set
from iecoop.stdlib.timers import LTOF, LTON, LTP, TOF, TON, TP
from iecoop.stdlib.triggers import F_TRIG, R_TRIG

__all__ = [
    "CTD",
    "CTD_INT",
    "CTU",
    "CTUD",
    "CTUD_INT",
    "CTU_DINT",
    "CTU_INT",
    "CTU_UDINT",
    "CriticalSection",
    "F_TRIG",
    "LTOF",
    "LTON",
    "LTP",
    "R",
    "RS",
    "R_TRIG",
    "S",
    "SR",
    "TOF",
    "TON",
    "TP",
    "test_and_set",
]
