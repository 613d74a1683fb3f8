"""Bistables: SR (set dominant) and RS (reset dominant), level-sensitive.

The pin names are the TwinCAT / CODESYS ones (``SET1, RESET`` and ``SET,
RESET1``); IEC and matiec call them ``S1, R`` and ``S, R1``. There is no edge
detection: a TRUE level acts at every call (IEC 61131-3:2013, bistable function
blocks; Beckhoff Tc2_Standard and CODESYS Standard "SR", "RS").
"""

from __future__ import annotations

from iecoop.declarations import VAR_INPUT, VAR_OUTPUT
from iecoop.pou import FunctionBlock
from iecoop.types import BOOL

__all__ = ["RS", "SR"]


class SR(FunctionBlock):
    """SR, set-dominant bistable: ``Q1 := SET1 OR (NOT RESET AND Q1)``.

    ST::

        FUNCTION_BLOCK SR
        VAR_INPUT  SET1 : BOOL; RESET : BOOL; END_VAR
        VAR_OUTPUT Q1 : BOOL; END_VAR

    >>> latch = SR()
    >>> latch(SET1=True, RESET=True); latch.Q1
    True
    >>> latch(SET1=False, RESET=False); latch.Q1
    True
    >>> latch(RESET=True); latch.Q1
    False
    """

    SET1: BOOL = VAR_INPUT(False)
    RESET: BOOL = VAR_INPUT(False)
    Q1: BOOL = VAR_OUTPUT(False)

    def body(self) -> None:
        q1 = self.Q1
        q = self.SET1 or (q1 and not self.RESET)
        if q != q1:
            self.Q1 = q


class RS(FunctionBlock):
    """RS, reset-dominant bistable: ``Q1 := NOT RESET1 AND (SET OR Q1)``.

    ST::

        FUNCTION_BLOCK RS
        VAR_INPUT  SET : BOOL; RESET1 : BOOL; END_VAR
        VAR_OUTPUT Q1 : BOOL; END_VAR

    >>> latch = RS()
    >>> latch(SET=True, RESET1=True); latch.Q1
    False
    >>> latch(SET=True, RESET1=False); latch.Q1
    True
    >>> latch(SET=False); latch.Q1
    True
    """

    SET: BOOL = VAR_INPUT(False)
    RESET1: BOOL = VAR_INPUT(False)
    Q1: BOOL = VAR_OUTPUT(False)

    def body(self) -> None:
        q1 = self.Q1
        q = not self.RESET1 and (self.SET or q1)
        if q != q1:
            self.Q1 = q
