"""The memory model: C-compatible layouts, checked pointers and references.

Instances of structs, unions, arrays and POUs are real ctypes memory blocks
laid out like a TwinCAT 3 x64 target. Pointers, references and interface
variables hold checked handles, so a bad address raises
RTSEXCPT_ACCESS_VIOLATION instead of crashing the interpreter.
"""

from iecoop.memory.aliases import Alias
from iecoop.memory.interface_references import NullInterface
from iecoop.memory.references import REFERENCE_TO
from iecoop.memory.arrays import ARRAY
from iecoop.memory.pointers import POINTER_TO, Pointer
from iecoop.memory.datatypes import IecEnum, Struct, Union
from iecoop.memory.operators import (
    TYPE_CLASS,
    VarInfo,
    adr,
    adr_of,
    is_valid_ref,
    memcmp,
    memcpy,
    memset,
    ref_assign,
    sibling,
    sizeof,
    var_info,
)

__all__ = [
    "ARRAY",
    "Alias",
    "IecEnum",
    "NullInterface",
    "POINTER_TO",
    "Pointer",
    "REFERENCE_TO",
    "Struct",
    "TYPE_CLASS",
    "Union",
    "VarInfo",
    "adr",
    "adr_of",
    "is_valid_ref",
    "memcmp",
    "memcpy",
    "memset",
    "ref_assign",
    "sibling",
    "sizeof",
    "var_info",
]
