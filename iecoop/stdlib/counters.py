"""Counters: CTU (up), CTD (down), CTUD (up/down), in vendor and IEC form.

CU and CD count on their rising edges; the IEC reference (matiec
``counter.txt``) feeds them through R_TRIG instances ``CU_T`` / ``CD_T``. Here
the edge memory of those R_TRIGs is inlined as the BOOL variables ``CU_M`` /
``CD_M`` (matiec's ``CU_T.M`` / ``CD_T.M``), so a counter call is one body.
The edge memory is updated at every call, also while R / LD act, so a CU
edge that arrives during a reset is consumed, not counted later.

TwinCAT 3 (Tc2_Standard) and CODESYS (Standard) name the reset and load pins
``RESET`` / ``LOAD`` and make PV and CV a WORD; IEC 61131-3 names them ``R`` /
``LD`` with INT. A variable has one name and one type, so both forms exist:

=============  ===================================================  ============
class          ST declaration                                       PV / CV
=============  ===================================================  ============
``CTU``        ``CTU(CU, RESET, PV) -> Q, CV``       (TC, CODESYS)   WORD
``CTD``        ``CTD(CD, LOAD, PV) -> Q, CV``        (TC, CODESYS)   WORD
``CTUD``       ``CTUD(CU, CD, RESET, LOAD, PV) -> QU, QD, CV``       WORD
``CTU_INT``    ``CTU(CU, R, PV) -> Q, CV``           (IEC)           INT
``CTD_INT``    ``CTD(CD, LD, PV) -> Q, CV``          (IEC)           INT
``CTUD_INT``   ``CTUD(CU, CD, R, LD, PV) -> QU, QD, CV`` (IEC)       INT
``CTU_DINT``   ``CTU_DINT(CU, R, PV) -> Q, CV``      (IEC)           DINT
``CTU_UDINT``  ``CTU_UDINT(CU, R, PV) -> Q, CV``     (IEC)           UDINT
=============  ===================================================  ============

Rules (IEC 61131-3:2013, counter function blocks, as matiec ``counter.txt``
implements them; Beckhoff Tc2_Standard and CODESYS Standard "CTU", "CTD", "CTUD"):

* R / RESET has priority over LD / LOAD (CTUD).
* CTUD: rising edges of CU and CD in the same call do not count.
* Counting down stops at 0 (``CV > 0`` is required to decrement), so CTD /
  CTUD never go below 0 by counting; LD can still load a negative INT PV.
* Counting up stops at PV (profile ``ctu_limit="pv"``, the IEC reference)
  or at the largest value of the CV type (``ctu_limit="type_max"``). The
  switch applies to CTU and to CTUD's up-counting, and is read at the call.
"""

from __future__ import annotations

import operator
from collections.abc import Callable
from typing import Any

from iecoop.declarations import VAR, VAR_INPUT, VAR_OUTPUT
from iecoop.pou import FunctionBlock
from iecoop.profiles import active_profile
from iecoop.types import BOOL, DINT, INT, UDINT, WORD

__all__ = ["CTD", "CTD_INT", "CTU", "CTUD", "CTUD_INT", "CTU_DINT", "CTU_INT", "CTU_UDINT"]

_WORD_MAX = 0xFFFF
_INT_MAX = 0x7FFF
_DINT_MAX = 0x7FFF_FFFF
_UDINT_MAX = 0xFFFF_FFFF


def _up_counter(cv_max: int, reset_pin: str) -> Callable[[Any], None]:
    """The CTU state machine, given the reset pin's name and the CV type's largest value.

    The TwinCAT / CODESYS form (``RESET``, WORD) and the IEC forms (``R``,
    INT / DINT / UDINT) share it; the pin is read through a C-level getter.
    """
    reset = operator.attrgetter(reset_pin)

    def body(self: Any) -> None:
        cu = self.CU
        m = self.CU_M
        if cu != m:
            self.CU_M = cu
        cv = self.CV
        if reset(self):
            if cv:
                self.CV = cv = 0
        elif cu and not m:
            limit = self.PV if active_profile().ctu_limit == "pv" else cv_max
            if cv < limit:
                self.CV = cv = cv + 1
        q = cv >= self.PV
        if q != self.Q:
            self.Q = q

    return body


def _down_counter(load_pin: str) -> Callable[[Any], None]:
    """The CTD state machine, given the load pin's name (``LOAD`` or ``LD``)."""
    load = operator.attrgetter(load_pin)

    def body(self: Any) -> None:
        cd = self.CD
        m = self.CD_M
        if cd != m:
            self.CD_M = cd
        cv = self.CV
        if load(self):
            pv = self.PV
            if cv != pv:
                self.CV = cv = pv
        elif cd and not m and cv > 0:
            self.CV = cv = cv - 1
        q = cv <= 0
        if q != self.Q:
            self.Q = q

    return body


def _up_down_counter(cv_max: int, reset_pin: str, load_pin: str) -> Callable[[Any], None]:
    """The CTUD state machine, given the reset and load pins' names and the CV type's largest value."""
    reset = operator.attrgetter(reset_pin)
    load = operator.attrgetter(load_pin)

    def body(self: Any) -> None:
        cu = self.CU
        cu_m = self.CU_M
        if cu != cu_m:
            self.CU_M = cu
        cd = self.CD
        cd_m = self.CD_M
        if cd != cd_m:
            self.CD_M = cd
        up = cu and not cu_m
        down = cd and not cd_m
        cv = self.CV
        pv = self.PV
        if reset(self):
            if cv:
                self.CV = cv = 0
        elif load(self):
            if cv != pv:
                self.CV = cv = pv
        elif up != down:
            if up:
                if cv < (pv if active_profile().ctu_limit == "pv" else cv_max):
                    self.CV = cv = cv + 1
            elif cv > 0:
                self.CV = cv = cv - 1
        qu = cv >= pv
        if qu != self.QU:
            self.QU = qu
        qd = cv <= 0
        if qd != self.QD:
            self.QD = qd

    return body


class CTU(FunctionBlock):
    """CTU, up counter (TwinCAT / CODESYS form): CV counts rising edges of CU; Q := CV >= PV.

    ST::

        FUNCTION_BLOCK CTU
        VAR_INPUT  CU : BOOL; RESET : BOOL; PV : WORD; END_VAR
        VAR_OUTPUT Q : BOOL; CV : WORD; END_VAR

    >>> parts = CTU()
    >>> for cu in (True, False, True, True, False, True):
    ...     parts(CU=cu, PV=3)
    >>> parts.CV, parts.Q
    (3, True)
    >>> parts(RESET=True); parts.CV, parts.Q
    (0, False)
    """

    CU: BOOL = VAR_INPUT(False)
    RESET: BOOL = VAR_INPUT(False)
    PV: WORD = VAR_INPUT(0)
    Q: BOOL = VAR_OUTPUT(False)
    CV: WORD = VAR_OUTPUT(0)
    CU_M: BOOL = VAR(False)

    body = _up_counter(_WORD_MAX, "RESET")



class CTU_INT(FunctionBlock):  # noqa: N801 - IEC name
    """CTU in the IEC form: pins R and PV / CV of type INT.

    ST::

        FUNCTION_BLOCK CTU
        VAR_INPUT  CU : BOOL; R : BOOL; PV : INT; END_VAR
        VAR_OUTPUT Q : BOOL; CV : INT; END_VAR

    >>> parts = CTU_INT()
    >>> for cu in (True, False, True):
    ...     parts(CU=cu, PV=2)
    >>> parts.CV, parts.Q
    (2, True)
    """

    CU: BOOL = VAR_INPUT(False)
    R: BOOL = VAR_INPUT(False)
    PV: INT = VAR_INPUT(0)
    Q: BOOL = VAR_OUTPUT(False)
    CV: INT = VAR_OUTPUT(0)
    CU_M: BOOL = VAR(False)

    body = _up_counter(_INT_MAX, "R")


class CTU_DINT(FunctionBlock):  # noqa: N801 - IEC name
    """CTU_DINT: the IEC up counter with PV / CV of type DINT.

    ST::

        FUNCTION_BLOCK CTU_DINT
        VAR_INPUT  CU : BOOL; R : BOOL; PV : DINT; END_VAR
        VAR_OUTPUT Q : BOOL; CV : DINT; END_VAR

    >>> big = CTU_DINT()
    >>> big(CU=True, PV=100_000); big.CV, big.Q
    (1, False)
    """

    CU: BOOL = VAR_INPUT(False)
    R: BOOL = VAR_INPUT(False)
    PV: DINT = VAR_INPUT(0)
    Q: BOOL = VAR_OUTPUT(False)
    CV: DINT = VAR_OUTPUT(0)
    CU_M: BOOL = VAR(False)

    body = _up_counter(_DINT_MAX, "R")


class CTU_UDINT(FunctionBlock):  # noqa: N801 - IEC name
    """CTU_UDINT: the IEC up counter with PV / CV of type UDINT.

    ST::

        FUNCTION_BLOCK CTU_UDINT
        VAR_INPUT  CU : BOOL; R : BOOL; PV : UDINT; END_VAR
        VAR_OUTPUT Q : BOOL; CV : UDINT; END_VAR

    >>> big = CTU_UDINT()
    >>> big(CU=True, PV=1); big.CV, big.Q
    (1, True)
    """

    CU: BOOL = VAR_INPUT(False)
    R: BOOL = VAR_INPUT(False)
    PV: UDINT = VAR_INPUT(0)
    Q: BOOL = VAR_OUTPUT(False)
    CV: UDINT = VAR_OUTPUT(0)
    CU_M: BOOL = VAR(False)

    body = _up_counter(_UDINT_MAX, "R")


class CTD(FunctionBlock):
    """CTD, down counter (TwinCAT / CODESYS form): LOAD sets CV := PV; CD edges count down to 0.

    ST::

        FUNCTION_BLOCK CTD
        VAR_INPUT  CD : BOOL; LOAD : BOOL; PV : WORD; END_VAR
        VAR_OUTPUT Q : BOOL; CV : WORD; END_VAR

    ``Q := CV <= 0``.

    >>> left = CTD()
    >>> left(LOAD=True, PV=2); left.CV
    2
    >>> for cd in (True, False, True, False, True):
    ...     left(CD=cd, LOAD=False)
    >>> left.CV, left.Q
    (0, True)
    """

    CD: BOOL = VAR_INPUT(False)
    LOAD: BOOL = VAR_INPUT(False)
    PV: WORD = VAR_INPUT(0)
    Q: BOOL = VAR_OUTPUT(False)
    CV: WORD = VAR_OUTPUT(0)
    CD_M: BOOL = VAR(False)

    body = _down_counter("LOAD")



class CTD_INT(FunctionBlock):  # noqa: N801 - IEC name
    """CTD in the IEC form: pins LD and PV / CV of type INT.

    ST::

        FUNCTION_BLOCK CTD
        VAR_INPUT  CD : BOOL; LD : BOOL; PV : INT; END_VAR
        VAR_OUTPUT Q : BOOL; CV : INT; END_VAR

    >>> left = CTD_INT()
    >>> left(LD=True, PV=1); left(CD=True, LD=False); left.CV, left.Q
    (0, True)
    """

    CD: BOOL = VAR_INPUT(False)
    LD: BOOL = VAR_INPUT(False)
    PV: INT = VAR_INPUT(0)
    Q: BOOL = VAR_OUTPUT(False)
    CV: INT = VAR_OUTPUT(0)
    CD_M: BOOL = VAR(False)

    body = _down_counter("LD")



class CTUD(FunctionBlock):
    """CTUD, up/down counter (TwinCAT / CODESYS form).

    ST::

        FUNCTION_BLOCK CTUD
        VAR_INPUT  CU : BOOL; CD : BOOL; RESET : BOOL; LOAD : BOOL; PV : WORD; END_VAR
        VAR_OUTPUT QU : BOOL; QD : BOOL; CV : WORD; END_VAR

    ``QU := CV >= PV``, ``QD := CV <= 0``; RESET beats LOAD; simultaneous CU
    and CD edges do not count.

    >>> level = CTUD()
    >>> level(CU=True, PV=2); level(CU=False); level(CU=True); level.CV, level.QU
    (2, True)
    >>> level(CU=False, CD=True); level.CV, level.QU, level.QD
    (1, False, False)
    """

    CU: BOOL = VAR_INPUT(False)
    CD: BOOL = VAR_INPUT(False)
    RESET: BOOL = VAR_INPUT(False)
    LOAD: BOOL = VAR_INPUT(False)
    PV: WORD = VAR_INPUT(0)
    QU: BOOL = VAR_OUTPUT(False)
    QD: BOOL = VAR_OUTPUT(False)
    CV: WORD = VAR_OUTPUT(0)
    CU_M: BOOL = VAR(False)
    CD_M: BOOL = VAR(False)

    body = _up_down_counter(_WORD_MAX, "RESET", "LOAD")



class CTUD_INT(FunctionBlock):  # noqa: N801 - IEC name
    """CTUD in the IEC form: pins R, LD and PV / CV of type INT.

    ST::

        FUNCTION_BLOCK CTUD
        VAR_INPUT  CU : BOOL; CD : BOOL; R : BOOL; LD : BOOL; PV : INT; END_VAR
        VAR_OUTPUT QU : BOOL; QD : BOOL; CV : INT; END_VAR

    >>> level = CTUD_INT()
    >>> level(LD=True, PV=5); level.CV, level.QU
    (5, True)
    >>> level(LD=False, CU=True, CD=True); level.CV
    5
    """

    CU: BOOL = VAR_INPUT(False)
    CD: BOOL = VAR_INPUT(False)
    R: BOOL = VAR_INPUT(False)
    LD: BOOL = VAR_INPUT(False)
    PV: INT = VAR_INPUT(0)
    QU: BOOL = VAR_OUTPUT(False)
    QD: BOOL = VAR_OUTPUT(False)
    CV: INT = VAR_OUTPUT(0)
    CU_M: BOOL = VAR(False)
    CD_M: BOOL = VAR(False)

    body = _up_down_counter(_INT_MAX, "R", "LD")


