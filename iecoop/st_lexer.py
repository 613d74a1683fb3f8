"""A Pygments lexer for IEC 61131-3 Structured Text, as TwinCAT 3 and CODESYS write it.

Needs Pygments (installed with Sphinx, or ``pip install pygments``); nothing
else in iecoop imports this module. The docs register it for the ``st`` and
``iecst`` code blocks; elsewhere ``pygments.highlight(code, IecStLexer(), ...)``.

It knows the keywords (case-insensitive, as in ST), the elementary types,
typed and based literals (``INT#5``, ``16#FF``, ``2#1010_0101``,
``T#1s500ms``, ``DT#2024-01-28-12:00:00``, ``BOOL#TRUE``), strings with
their ``$`` escapes, ``(* *)`` comments (nested, as TwinCAT and CODESYS
allow), ``/* */`` and ``//`` comments, pragmas (``{attribute
'qualified_only'}``), direct addresses (``%IX0.1``, ``AT %I*``) and the
operators, including ``:=``, ``=>``, ``S=`` / ``R=`` and ``REF=``.

>>> from pygments.token import Comment, Keyword
>>> tokens = list(IecStLexer().get_tokens("IF bRun THEN // while and\\n"))
>>> tokens[0], tokens[-2]
((Token.Keyword, 'IF'), (Token.Comment.Single, '// while and'))

``(Token.Error)`` never comes out of well-formed ST; :func:`looks_like_st`
tells ST from Python in a literal block.
"""

from __future__ import annotations

import re

from pygments.lexer import RegexLexer, include, words
from pygments.token import (
    Comment,
    Keyword,
    Name,
    Number,
    Operator,
    Punctuation,
    String,
    Whitespace,
)

from iecoop.st.language import KEYWORDS, TYPE_NAMES, WORD_OPERATORS

__all__ = ["IecStLexer", "looks_like_st"]

_TIME_PREFIX = r"(?:LTIME|LT|TIME|T)#"
_DATE_PREFIX = r"(?:LDATE_AND_TIME|DATE_AND_TIME|LDT|DT|LTIME_OF_DAY|TIME_OF_DAY|LTOD|TOD|LDATE|DATE|LD|D)#"
_TYPED = r"(?:" + "|".join(sorted((t for t in TYPE_NAMES if not t.startswith(("ANY", "__"))), key=len, reverse=True)) + r")#"


class IecStLexer(RegexLexer):
    """IEC 61131-3 Structured Text (TwinCAT 3 / CODESYS)."""

    name = "IEC 61131-3 Structured Text"
    aliases = ["iecst", "iec-st", "structured-text"]
    filenames = ["*.st", "*.TcPOU", "*.TcDUT", "*.TcGVL", "*.TcIO"]
    mimetypes = ["text/x-iecst"]
    flags = re.IGNORECASE | re.MULTILINE

    tokens = {
        "root": [
            (r"\s+", Whitespace),
            include("comments"),
            (r"\{[^}]*\}", Comment.Preproc),  # pragmas: {attribute 'x'}, {warning '...'}, {IF defined(...)}
            include("literals"),
            (r"%[IQM]\*", Name.Builtin),  # AT %I* : the address given by the I/O configuration
            (r"%[IQM][XBWDL]?\d+(?:\.\d+)*", Name.Builtin),
            (r"(?<=\s)(?:REF|S|R)=(?=\s)", Operator),  # x REF= y; ExST x S= cond, x R= cond
            (words(KEYWORDS, prefix=r"(?<![\w#])", suffix=r"\b"), Keyword),
            (words(WORD_OPERATORS, prefix=r"(?<![\w#])", suffix=r"\b"), Operator.Word),
            (words(("TRUE", "FALSE", "NULL"), prefix=r"(?<!\w)", suffix=r"\b"), Keyword.Constant),
            (words(TYPE_NAMES, prefix=r"(?<![\w#])", suffix=r"\b"), Keyword.Type),
            # E_Mode#Auto: the enumeration, then its value
            (r"[A-Za-z_]\w*(?=#[A-Za-z_])", Name.Class),
            (r"#(?=[A-Za-z_])", Operator),
            (r"(?<=#)[A-Za-z_]\w*", Name.Constant),
            (r"[A-Za-z_]\w*(?=\s*\()", Name.Function),
            (r"[A-Za-z_]\w*", Name),
            (r":=|=>|<>|<=|>=|\*\*|[-+*/=<>&^]", Operator),
            (r"[;:,.()\[\]]", Punctuation),
        ],
        "comments": [
            (r"//.*?$", Comment.Single),
            (r"\(\*", Comment.Multiline, "comment"),
            (r"/\*", Comment.Multiline, "c-comment"),
        ],
        "comment": [
            (r"\(\*", Comment.Multiline, "#push"),  # TwinCAT and CODESYS nest (* *) comments
            (r"\*\)", Comment.Multiline, "#pop"),
            (r"[^(*]+", Comment.Multiline),
            (r"[(*]", Comment.Multiline),
        ],
        "c-comment": [
            (r"\*/", Comment.Multiline, "#pop"),
            (r"[^*]+", Comment.Multiline),
            (r"\*", Comment.Multiline),
        ],
        "literals": [
            (r"'", String.Single, "string"),
            (r'"', String.Double, "wstring"),
            (_TIME_PREFIX + r"[-+]?(?:\d[\d_]*(?:\.\d+)?(?:d|h|ms|m|s|us|ns)_?)+", Number.Other),
            (_DATE_PREFIX + r"\d[\d:.\-]*", Number.Other),
            (r"(" + _TYPED + r")(?=[-+\d'\"]|TRUE|FALSE|16#|8#|2#)", Keyword.Type),  # INT#5 : the type, then 5
            (r"16#[0-9A-F][0-9A-F_]*", Number.Hex),
            (r"8#[0-7][0-7_]*", Number.Oct),
            (r"2#[01][01_]*", Number.Bin),
            (r"\d[\d_]*\.\d[\d_]*(?:E[-+]?\d+)?", Number.Float),
            (r"\d[\d_]*E[-+]?\d+", Number.Float),
            (r"\d[\d_]*", Number.Integer),
        ],
        "string": [
            (r"\$(?:[0-9A-F]{2}|[$'LNPRT\"])", String.Escape),
            (r"'", String.Single, "#pop"),
            (r"[^$']+", String.Single),
            (r"\$", String.Single),
        ],
        "wstring": [
            (r"\$(?:[0-9A-F]{4}|[$\"LNPRT'])", String.Escape),
            (r'"', String.Double, "#pop"),
            (r'[^$"]+', String.Double),
            (r"\$", String.Double),
        ],
    }

    @staticmethod
    def analyse_text(text: str) -> float:
        return 0.6 if looks_like_st(text) else 0.0


_ST_LINE = re.compile(
    r"^\s*(?:FUNCTION_BLOCK|FUNCTION|PROGRAM|METHOD|PROPERTY|INTERFACE|TYPE|STRUCT|VAR(?:_\w+)?|END_\w+|"
    r"IF|ELSIF|CASE|FOR|WHILE|REPEAT)\b",
    re.MULTILINE,
)


def looks_like_st(text: str) -> bool:
    """True for Structured Text: a line opens with an ST keyword (in capitals) and no ``>>>`` prompt."""
    return ">>>" not in text and _ST_LINE.search(text) is not None
