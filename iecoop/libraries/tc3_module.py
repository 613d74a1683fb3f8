"""Tc3_Module: Beckhoff's TcCOM module library, which every TwinCAT 3 project template references.

Its TcCOM names (``TcBaseModuleRegistered``, ``FW_ObjMgr_CreateInstance``,
``ITComObject``...) talk to TwinCAT's TcCOM object server, which iecoop's
virtual PLC does not have: this module declares none of them, and a project
that uses one of them is refused at load, naming that name. It declares the
``HRESULT`` type and its two checks, ``SUCCEEDED`` and ``FAILED``, which code
that reports results as HRESULT calls without any TcCOM object (Infosys:
Tc3_Module "SUCCEEDED", "FAILED").

>>> from iecoop.libraries import known
>>> known("Tc3_Module").module, __all__
('iecoop.libraries.tc3_module', ['FAILED', 'HRESULT', 'SUCCEEDED'])
>>> SUCCEEDED(0), SUCCEEDED(1), FAILED(-2147467259)  # S_OK, S_FALSE, E_FAIL (16#80004005)
(True, True, True)
"""

from __future__ import annotations

from typing import Annotated

from iecoop.memory import Alias
from iecoop.types import BOOL, DINT, DINT_T

__all__ = ["FAILED", "HRESULT", "SUCCEEDED"]

#: ``TYPE HRESULT : DINT``: an error is negative, success zero or positive (a warning or information).
HRESULT = Annotated[int, DINT_T, Alias("HRESULT")]


def SUCCEEDED(hr: DINT) -> BOOL:  # noqa: N802 - the ST name
    """``SUCCEEDED(hr)``: TRUE when the HRESULT ``hr`` reports no error (``hr >= 0``)."""
    return hr >= 0


def FAILED(hr: DINT) -> BOOL:  # noqa: N802 - the ST name
    """``FAILED(hr)``: TRUE when the HRESULT ``hr`` reports an error (``hr < 0``)."""
    return hr < 0
