"""The words of Structured Text, listed once: the ST writer keeps them out of names, the ST lexer colours them.

TwinCAT 3 and CODESYS reserve them whatever their case (``then``, ``Then``
and ``THEN`` are one keyword), so none of them can name a variable, a
METHOD, a type or a POU.
"""

from __future__ import annotations

__all__ = ["KEYWORDS", "RESERVED", "TYPES", "WORD_OPERATORS"]

#: Declarations, sections, qualifiers and statements.
KEYWORDS = (
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
WORD_OPERATORS = ("AND_THEN", "OR_ELSE", "AND", "OR", "XOR", "NOT", "MOD")
#: Elementary and generic types.
TYPES = (
    "BOOL", "SINT", "INT", "DINT", "LINT", "USINT", "UINT", "UDINT", "ULINT", "BYTE", "WORD", "DWORD", "LWORD",
    "REAL", "LREAL", "STRING", "WSTRING", "CHAR", "WCHAR", "TIME", "LTIME", "DATE", "LDATE", "TIME_OF_DAY",
    "TOD", "LTOD", "DATE_AND_TIME", "DT", "LDT", "ANY", "ANY_NUM", "ANY_INT", "ANY_REAL", "ANY_BIT",
    "ANY_STRING", "ANY_DATE", "ANY_ELEMENTARY", "ANY_MAGNITUDE", "ANY_DERIVED", "__XINT", "__UXINT",
    "__XWORD", "PVOID", "BIT",
)
#: Operators written like a FUNCTION call (``ADR(x)``): not words of the grammar, so they stay usable as names.
_CALLED = frozenset(("REF", "ADR", "SIZEOF"))
#: Every reserved word, in capitals: compare ``name.upper()``.
RESERVED = frozenset((*KEYWORDS, *WORD_OPERATORS, *TYPES, "TRUE", "FALSE", "NULL")) - _CALLED
