"""Standard: the CODESYS library of the IEC 61131-3 standard function blocks and string functions.

CODESYS projects reference it (the placeholder ``Standard``) and call its
names plain (``TON``) or qualified (``Standard.TON``). Each name here is iecoop's implementation
of the standard block or function (``iecoop.stdlib``, ``iecoop.functions``); the vendor's page is
https://content.helpme-codesys.com/en/libs/Standard/Current/index.html

ST::

    fbDelay : Standard.TON;

>>> from iecoop.libraries.codesys_standard import TON
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
