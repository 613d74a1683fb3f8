"""Tc2_Standard: Beckhoff's library of the IEC 61131-3 standard function blocks and string functions.

TwinCAT 3 projects reference it (``<PlaceholderReference Include="Tc2_Standard">``) and call its
names plain (``TON``) or qualified (``Tc2_Standard.TON``). Each name here is iecoop's implementation
of the standard block or function (``iecoop.stdlib``, ``iecoop.functions``); the vendor's page is
https://infosys.beckhoff.com/english.php?content=../content/1033/tcplclib_tc2_standard/index.html

ST::

    fbDelay : Tc2_Standard.TON;

>>> from iecoop.libraries.tc2_standard import TON
>>> from iecoop.stdlib import TON as standard_TON
>>> TON is standard_TON
True
"""

from __future__ import annotations

from iecoop.functions import CONCAT, DELETE, FIND, INSERT, LEFT, LEN, MID, REPLACE, RIGHT
from iecoop.stdlib import CTD, CTU, CTUD, F_TRIG, LTOF, LTON, LTP, R_TRIG, RS, SR, TOF, TON, TP

__all__ = [
    "CONCAT", "CTD", "CTU", "CTUD", "DELETE", "FIND", "F_TRIG", "INSERT", "LEFT", "LEN", "LTOF", "LTON", "LTP",
    "MID", "REPLACE", "RIGHT", "RS", "R_TRIG", "SR", "TOF", "TON", "TP",
]
