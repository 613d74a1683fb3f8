"""Tc3_Module: Beckhoff's TcCOM module library, which every TwinCAT 3 project template references.

Most of its names (``TcBaseModuleRegistered``, ``FW_ObjMgr_CreateInstance``,
``ITComObject``...) talk to TwinCAT's TcCOM object server, which iecoop's
virtual PLC does not have: a project that uses one of them is refused at
load, naming that name. What this module declares is the part plain PLC code
uses, written from Beckhoff's documentation (Infosys, "TwinCAT 3 PLC Lib:
Tc3_Module"): the status type ``HRESULT`` (a DINT whose negative values are
errors), the object-id type ``OTCID``, the GVL constants (``S_OK``,
``S_FALSE``, ``S_PENDING``, ``S_WATCHDOG_TIMEOUT`` and the ``OTCID_*`` ids)
and the checks ``SUCCEEDED`` and ``FAILED``.

>>> SUCCEEDED(S_PENDING), FAILED(S_OK), FAILED(-2147467259)
(True, False, True)
"""

from __future__ import annotations

from typing import Annotated

from iecoop.memory import Alias
from iecoop.types import BOOL, DINT, UDINT

__all__ = [
    "FAILED", "HRESULT", "OTCID", "OTCID_CreateNewId", "OTCID_FirstFreeId", "OTCID_LastFreeId", "SUCCEEDED",
    "S_FALSE", "S_OK", "S_PENDING", "S_WATCHDOG_TIMEOUT",
]

#: ``TYPE HRESULT : DINT``: a status code; negative (bit 31 set) is an error, 0 and above success.
HRESULT = Annotated[DINT, Alias("HRESULT")]
#: ``TYPE OTCID : UDINT``: the id of a TcCOM object.
OTCID = Annotated[UDINT, Alias("OTCID")]

S_OK = 0  #: processed without error
S_FALSE = 1  #: processed, with a negative or incomplete result
S_PENDING = 0x203  #: processed, no result yet
S_WATCHDOG_TIMEOUT = 0x256  #: processed, a timeout occurred
OTCID_CreateNewId = 0xFFFF_FFFF  #: asks for a new object id
OTCID_FirstFreeId = 0x7101_0000  #: the first object id free for an application
OTCID_LastFreeId = 0x710F_FFFF  #: the last one


def SUCCEEDED(hr: DINT) -> BOOL:  # noqa: N802 - the ST name
    """``SUCCEEDED(hr)``: TRUE when the HRESULT ``hr`` is no error (0 or above)."""
    return hr >= 0


def FAILED(hr: DINT) -> BOOL:  # noqa: N802 - the ST name
    """``FAILED(hr)``: TRUE when the HRESULT ``hr`` is an error (negative)."""
    return hr < 0
