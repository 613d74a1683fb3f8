"""iecoop: IEC 61131-3 object-oriented PLC code as type-checked Python."""

from iecoop.exceptions import AccessError, DefinitionError, ExceptionCode, PlcException, try_catch
from iecoop.profiles import Profile, active_profile, use_profile
from iecoop.types import (
    BOOL, BYTE, DATE, DINT, DT, DWORD, INT, LINT, LREAL, LTIME, LWORD, REAL, SINT, STRING, TIME, TOD,
    UDINT, UINT, ULINT, USINT, WORD, WSTRING,
)

__all__ = [
    "AccessError", "BOOL", "BYTE", "DATE", "DINT", "DT", "DWORD", "DefinitionError", "ExceptionCode",
    "INT", "LINT", "LREAL", "LTIME", "LWORD", "PlcException", "Profile", "REAL", "SINT", "STRING",
    "TIME", "TOD", "UDINT", "UINT", "ULINT", "USINT", "WORD", "WSTRING", "active_profile",
    "try_catch", "use_profile",
]
