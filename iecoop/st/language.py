"""The Structured Text vocabulary, defined once.

Both wings of the ST bridge (``read``: ST to Python, ``write``: Python to ST),
the Pygments lexer and the hypothesis strategies take their words from here:
the reserved words, the elementary types with their widths (read from
iecoop's own type records, so a width is never written twice), the
operators, the standard functions with their Python names and result
types, the access specifiers and the lifecycle METHODs.

TwinCAT 3 and CODESYS read every word here in any case (``then``, ``Then``
and ``THEN`` are one keyword); the tables hold capitals, so look a word up
as ``word.upper()``.

>>> INTEGER_LAYOUT["UDINT"], INTEGER_LAYOUT["SINT"]
((32, False), (8, True))
>>> canonical_type("time_of_day")
'TOD'
>>> MATH_FUNCTIONS["LOG"], MATH_BY_PYTHON["log10"]
('log10', 'LOG')
>>> is_reserved("Then"), is_reserved("nSpeed")
(True, False)
"""

from __future__ import annotations

from typing import Final

from iecoop.types import ELEMENTARY_TYPES, ElementaryType

__all__ = [
    "ACCESS_SPECIFIERS",
    "BUILTIN_FUNCTIONS",
    "COMPARISONS",
    "ELEMENTARY",
    "GENERIC_TYPES",
    "INTEGER_LAYOUT",
    "INTEGER_TYPES",
    "KEYWORDS",
    "LIFECYCLE",
    "PLCOPEN_ST_DECLARATION",
    "MATH_BY_PYTHON",
    "MATH_FUNCTIONS",
    "OPERATOR_FUNCTIONS",
    "PLCOPEN_ELEMENTARY",
    "PRECEDENCE",
    "REAL_TYPES",
    "RESERVED",
    "SECTION_ORDER",
    "STANDARD_FBS",
    "STRING_FUNCTIONS",
    "SYSTEM_FUNCTIONS",
    "TASK_INFO_MEMBERS",
    "TYPE_NAMES",
    "TYPE_SYNONYMS",
    "VAR_INFO_MEMBERS",
    "WORD_OPERATORS",
    "canonical_type",
    "is_reserved",
]

# --- words ----------------------------------------------------------------------------------------

#: Declarations, sections, qualifiers and statements.
KEYWORDS: Final = (
    "PROGRAM", "END_PROGRAM", "FUNCTION", "END_FUNCTION", "FUNCTION_BLOCK", "END_FUNCTION_BLOCK",
    "METHOD", "END_METHOD", "PROPERTY", "END_PROPERTY", "INTERFACE", "END_INTERFACE", "ACTION", "END_ACTION",
    "TYPE", "END_TYPE", "STRUCT", "END_STRUCT", "UNION", "END_UNION", "NAMESPACE", "END_NAMESPACE",
    "VAR", "VAR_INPUT", "VAR_OUTPUT", "VAR_IN_OUT", "VAR_GLOBAL", "VAR_EXTERNAL", "VAR_TEMP", "VAR_STAT",
    "VAR_INST", "VAR_CONFIG", "VAR_ACCESS", "END_VAR", "CONSTANT", "RETAIN", "NON_RETAIN", "PERSISTENT", "AT",
    "EXTENDS", "IMPLEMENTS", "ABSTRACT", "FINAL", "PUBLIC", "PRIVATE", "PROTECTED", "INTERNAL",
    "READ_ONLY", "READ_WRITE",
    "ARRAY", "OF", "POINTER", "REFERENCE", "REF_TO", "TO", "BY", "DO",
    "IF", "THEN", "ELSIF", "ELSE", "END_IF", "CASE", "END_CASE", "FOR", "END_FOR", "WHILE", "END_WHILE",
    "REPEAT", "UNTIL", "END_REPEAT", "EXIT", "CONTINUE", "RETURN", "JMP",
    "THIS", "SUPER", "REF", "ADR", "SIZEOF", "__NEW", "__DELETE", "__QUERYINTERFACE", "__QUERYPOINTER",
    "__ISVALIDREF", "__TRY", "__CATCH", "__FINALLY", "__ENDTRY", "__VARINFO", "__POUNAME", "__POSITION",
    "TASK", "CONFIGURATION", "END_CONFIGURATION", "RESOURCE", "END_RESOURCE", "WITH", "ON",
)
#: Operators written as words.
WORD_OPERATORS: Final = ("AND_THEN", "OR_ELSE", "AND", "OR", "XOR", "NOT", "MOD")

# --- types ----------------------------------------------------------------------------------------

#: The elementary types iecoop stores, by IEC name (iecoop.types holds the records).
ELEMENTARY: Final = frozenset(ELEMENTARY_TYPES)
#: Long spellings and their short names.
TYPE_SYNONYMS: Final = {"TIME_OF_DAY": "TOD", "DATE_AND_TIME": "DT"}
#: Every integer-like type (TIME, LTIME and the dates are unsigned counters): name -> (bits, signed).
INTEGER_LAYOUT: Final[dict[str, tuple[int, bool]]] = {
    name: (record.bits, record.kind == "signed")
    for name, record in ELEMENTARY_TYPES.items()
    if isinstance(record, ElementaryType) and record.kind in ("signed", "unsigned", "time", "date")
}
REAL_TYPES: Final = frozenset(
    name for name, record in ELEMENTARY_TYPES.items() if isinstance(record, ElementaryType) and record.kind == "real"
)
#: Generic types (ANY and its families) and the spellings iecoop reads but does not store.
GENERIC_TYPES: Final = (
    "ANY", "ANY_NUM", "ANY_INT", "ANY_REAL", "ANY_BIT", "ANY_STRING", "ANY_DATE", "ANY_ELEMENTARY",
    "ANY_MAGNITUDE", "ANY_DERIVED", "__XINT", "__UXINT", "__XWORD", "PVOID", "BIT",
    "CHAR", "WCHAR", "LDATE", "LTOD", "LDT",
)
#: Every type name ST reserves.
TYPE_NAMES: Final = tuple(sorted(ELEMENTARY | set(TYPE_SYNONYMS))) + GENERIC_TYPES


def canonical_type(name: str) -> str:
    """The IEC name of an elementary type as iecoop spells it: ``time_of_day`` -> ``TOD``."""
    upper = name.upper()
    return TYPE_SYNONYMS.get(upper, upper)


#: The words no name may take. ADR, REF and SIZEOF are operators written like a call, not
#: words of the grammar, so they stay usable as names.
RESERVED: Final = frozenset((*KEYWORDS, *WORD_OPERATORS, *TYPE_NAMES, "TRUE", "FALSE", "NULL")) - {"REF", "ADR", "SIZEOF"}


def is_reserved(name: str) -> bool:
    """Whether ``name`` is an ST reserved word, in any case."""
    return name.upper() in RESERVED


# --- operators ------------------------------------------------------------------------------------

#: ST comparison -> Python comparison.
COMPARISONS: Final = {"=": "==", "<>": "!=", "<": "<", ">": ">", "<=": "<=", ">=": ">="}

# --- standard functions and blocks ----------------------------------------------------------------

#: The standard function blocks of iecoop.stdlib that ST code may instantiate.
STANDARD_FBS: Final = (
    "TON", "TOF", "TP", "LTON", "LTOF", "LTP", "R_TRIG", "F_TRIG", "CTU", "CTD", "CTUD", "CTU_INT",
    "CTD_INT", "CTUD_INT", "CTU_DINT", "CTU_UDINT", "SR", "RS",
)
#: Numeric functions of LREAL: ST name -> the name of Python's ``math`` function that computes the same.
MATH_FUNCTIONS: Final = {
    "SQRT": "sqrt", "LN": "log", "LOG": "log10", "EXP": "exp", "SIN": "sin", "COS": "cos", "TAN": "tan",
    "ASIN": "asin", "ACOS": "acos", "ATAN": "atan",
}
MATH_BY_PYTHON: Final = {python: st for st, python in MATH_FUNCTIONS.items()}
#: The string functions of IEC 61131-3.
STRING_FUNCTIONS: Final = frozenset(("LEN", "LEFT", "RIGHT", "MID", "CONCAT", "INSERT", "DELETE", "REPLACE", "FIND"))
#: TwinCAT's system functions TIME() and the Tc2_System memory functions, with their result types.
SYSTEM_FUNCTIONS: Final = {"TIME": "TIME", "MEMCPY": "UDINT", "MEMSET": "UDINT", "MEMCMP": "DINT"}
#: iecoop operators (Python name) and the ST operator of another spelling.
OPERATOR_FUNCTIONS: Final = {
    "adr": "ADR", "sizeof": "SIZEOF", "memcpy": "MEMCPY", "memset": "MEMSET", "memcmp": "MEMCMP",
    "new": "__NEW", "delete": "__DELETE", "test_and_set": "TestAndSet",
}
#: Python builtins and the IEC standard function that computes the same.
BUILTIN_FUNCTIONS: Final = {"min": "MIN", "max": "MAX", "abs": "ABS"}

# --- access and lifecycle -------------------------------------------------------------------------

#: Access specifiers and the other member qualifiers, as iecoop's flags spell them.
ACCESS_SPECIFIERS: Final = ("PUBLIC", "PRIVATE", "PROTECTED", "INTERNAL", "ABSTRACT", "FINAL")
#: The lifecycle METHODs: ST name (in capitals) -> iecoop's Python name.
LIFECYCLE: Final = {"FB_INIT": "fb_init", "FB_REINIT": "fb_reinit", "FB_EXIT": "fb_exit"}

# --- the write wing (Python to ST) ----------------------------------------------------------------
# What the writer needs beyond the words above: how tightly each operator binds, the order of the
# VAR sections, and the types PLCopen XML names by an element of their own.

#: ST operator precedence, loosest first (IEC 61131-3, "Operators of the ST language"): an operand
#: that binds looser than its operator is written in parentheses.
PRECEDENCE: Final = {
    "OR": 1, "OR_ELSE": 1, "XOR": 2, "AND": 3, "AND_THEN": 3, "&": 3, "=": 4, "<>": 4, "<": 5, "<=": 5, ">": 5, ">=": 5,
    "+": 6, "-": 6, "*": 7, "/": 7, "MOD": 7, "**": 8, "NOT": 9,
}
#: The integer types (not TIME or a date): those whose ``*_TO_STRING`` writes the digits Python writes.
INTEGER_TYPES: Final = frozenset(
    name for name, record in ELEMENTARY_TYPES.items()
    if isinstance(record, ElementaryType) and record.kind in ("signed", "unsigned")
)
#: The elementary types PLCopen XML (TC6 2.01) writes as an element of their own (``<INT/>``); it has no LTIME.
PLCOPEN_ELEMENTARY: Final = frozenset(
    name for name, record in ELEMENTARY_TYPES.items() if isinstance(record, ElementaryType)
) - {"LTIME"}
#: The VAR sections of a POU in the order its declaration lists them.
SECTION_ORDER: Final = ("VAR_INPUT", "VAR_OUTPUT", "VAR_IN_OUT", "VAR", "VAR_STAT", "VAR_INST", "VAR_EXTERNAL", "VAR_TEMP")

# --- system structures the read wing types ----------------------------------------------------------
# Kept here because they are TwinCAT vocabulary: ST code reads these members by name
# (``_TaskInfo[i].CycleCount``, ``__VARINFO(x).Symbol``) and the reader types each from this table.

#: The members of TwinCAT's PlcTaskSystemInfo that iecoop's TaskInfo also has (times in 100 ns), and their ST types.
TASK_INFO_MEMBERS: Final = {
    "CycleTime": "UDINT", "CycleCount": "UDINT", "LastExecTime": "UDINT", "Priority": "UINT",
    "FirstCycle": "BOOL", "CycleTimeExceeded": "BOOL", "TaskName": "STRING",
}
#: The members of TwinCAT's PlcAppSystemInfo (``_AppInfo``) that iecoop's AppInfo has, and their ST types.
APP_INFO_MEMBERS: Final = {"ProjectName": "STRING", "AppName": "STRING", "AdsPort": "UINT"}
#: The members of ``__SYSTEM.VAR_INFO`` (iecoop's VarInfo) and their ST types; TypeClass compares with TYPE_CLASS values.
VAR_INFO_MEMBERS: Final = {
    "Symbol": "STRING", "ByteAddress": "ULINT", "ByteOffset": "UDINT", "Area": "DINT", "BitNr": "UINT",
    "BitSize": "UDINT", "TypeClass": "DINT", "TypeName": "STRING", "NumElements": "UDINT",
    "ElemBitSize": "UDINT", "BaseTypeClass": "DINT",
}

#: The PLCopen XML addData block in which iecoop keeps a variable's ST declaration where TC6 has no form for it
#: (a VAR_STAT, a METHOD's VAR_INST, FB_init values): the writer writes it, the reader takes it.
PLCOPEN_ST_DECLARATION: Final = "urn:iecoop:st-declaration"
