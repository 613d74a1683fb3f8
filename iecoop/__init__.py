"""iecoop: IEC 61131-3 object-oriented PLC code as type-checked Python."""

from iecoop.declarations import VAR, VAR_EXTERNAL, VAR_IN_OUT, VAR_INPUT, VAR_INST, VAR_OUTPUT, VAR_STAT, VAR_TEMP
from iecoop.gvl import GlobalVariables, gvl
from iecoop.interfaces import NULL, Interface, IQueryInterface, null, query_interface, query_pointer
from iecoop.lifecycle import delete, new
from iecoop.parameters import function
from iecoop.generics import ANY, ANY_BIT, ANY_DATE, ANY_ELEMENTARY, ANY_INT, ANY_NUM, ANY_REAL, ANY_STRING, AnyType
from iecoop.members import ABSTRACT, FINAL, INTERNAL, PRIVATE, PROTECTED, PUBLIC, Access, call_after_init, method, prop, super_set
from iecoop.pou import FunctionBlock, Program
from iecoop.stdlib import CriticalSection, test_and_set
from iecoop.exceptions import AccessError, DefinitionError, ExceptionCode, PlcException, try_catch
from iecoop.literals import D, T
from iecoop.memory import (
    ARRAY, POINTER_TO, REFERENCE_TO, TYPE_CLASS, Alias, IecEnum, NullInterface, Pointer, Struct, Union, VarInfo,
    adr, adr_of, is_valid_ref, memcmp, memcpy, memset, ref_assign, sibling, sizeof, var_info,
)
from iecoop.profiles import Profile, active_profile, use_profile
from iecoop.types import (
    BOOL, BYTE, DATE, DINT, DT, DWORD, INT, LINT, LREAL, LTIME, LWORD, REAL, SINT, STRING, TIME, TOD,
    UDINT, UINT, ULINT, USINT, WORD, WSTRING,
)

__all__ = [
    "ANY", "ANY_BIT", "ANY_DATE", "ANY_ELEMENTARY", "ANY_INT", "ANY_NUM", "ANY_REAL", "ANY_STRING", "AnyType",
    "ABSTRACT", "Access", "FINAL", "NULL", "FunctionBlock", "GlobalVariables", "INTERNAL", "IQueryInterface", "Interface",
    "PRIVATE", "PROTECTED", "PUBLIC", "Program", "call_after_init", "delete", "function", "gvl", "method", "new", "prop",
    "null", "query_interface", "query_pointer", "super_set", "CriticalSection", "test_and_set",
    "ARRAY", "Alias", "D", "IecEnum", "NullInterface", "POINTER_TO", "Pointer", "REFERENCE_TO", "Struct", "T",
    "TYPE_CLASS", "Union", "VAR", "VAR_EXTERNAL", "VAR_INPUT", "VAR_INST", "VAR_IN_OUT", "VAR_OUTPUT", "VAR_STAT",
    "VAR_TEMP", "VarInfo", "adr", "adr_of", "is_valid_ref", "memcmp", "memcpy", "memset", "ref_assign", "sibling", "sizeof", "var_info",
    "AccessError", "BOOL", "BYTE", "DATE", "DINT", "DT", "DWORD", "DefinitionError", "ExceptionCode",
    "INT", "LINT", "LREAL", "LTIME", "LWORD", "PlcException", "Profile", "REAL", "SINT", "STRING",
    "TIME", "TOD", "UDINT", "UINT", "ULINT", "USINT", "WORD", "WSTRING", "active_profile",
    "try_catch", "use_profile",
]
