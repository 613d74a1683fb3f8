"""Edge detection: R_TRIG (rising edge) and F_TRIG (falling edge).

The IEC 61131-3 definitions (matiec ``edge_detection.txt``), with the edge
memory ``M`` starting FALSE. A consequence users meet: on its very first call
R_TRIG reports an edge if CLK is already TRUE, and F_TRIG reports one if CLK
is FALSE (IEC 61131-3:2013, edge detection function blocks; Beckhoff
Tc2_Standard and CODESYS Standard "R_TRIG", "F_TRIG").
"""

from __future__ import annotations

from iecoop.declarations import VAR, VAR_INPUT, VAR_OUTPUT
from iecoop.pou import FunctionBlock
from iecoop.types import BOOL

__all__ = ["F_TRIG", "R_TRIG"]


class R_TRIG(FunctionBlock):  # noqa: N801 - IEC name
    """R_TRIG: Q is TRUE for the one call in which CLK goes from FALSE to TRUE.

    ST::

        FUNCTION_BLOCK R_TRIG
        VAR_INPUT  CLK : BOOL; END_VAR
        VAR_OUTPUT Q : BOOL; END_VAR
        VAR        M : BOOL; END_VAR
        Q := CLK AND NOT M;
        M := CLK;

    >>> start = R_TRIG()
    >>> [(start(CLK=clk), start.Q)[1] for clk in (False, True, True, False, True)]
    [False, True, False, False, True]
    """

    CLK: BOOL = VAR_INPUT(False)
    Q: BOOL = VAR_OUTPUT(False)
    M: BOOL = VAR(False)

    def body(self) -> None:
        clk = self.CLK
        m = self.M
        q = clk and not m
        if q != self.Q:
            self.Q = q
        if clk != m:
            self.M = clk


class F_TRIG(FunctionBlock):  # noqa: N801 - IEC name
    """F_TRIG: Q is TRUE for the one call in which CLK goes from TRUE to FALSE.

    ST::

        FUNCTION_BLOCK F_TRIG
        VAR_INPUT  CLK : BOOL; END_VAR
        VAR_OUTPUT Q : BOOL; END_VAR
        VAR        M : BOOL; END_VAR
        Q := NOT CLK AND NOT M;
        M := NOT CLK;

    The first call with CLK = FALSE counts as a falling edge, as in the IEC
    definition:

    >>> stop = F_TRIG()
    >>> [(stop(CLK=clk), stop.Q)[1] for clk in (False, False, True, False, False)]
    [True, False, False, True, False]
    """

    CLK: BOOL = VAR_INPUT(False)
    Q: BOOL = VAR_OUTPUT(False)
    M: BOOL = VAR(False)

    def body(self) -> None:
        not_clk = not self.CLK
        m = self.M
        q = not_clk and not m
        if q != self.Q:
            self.Q = q
        if not_clk != m:
            self.M = not_clk
