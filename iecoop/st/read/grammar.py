"""The grammars ST is parsed with: blark's own, and blark's with what the vendors accept beyond it.

``GRAMMAR_OVERLAY`` adds the vendors' exception handling to blark's grammar
with Lark's ``%extend``, and ``dialect.DIALECT_OVERLAY`` the dialect's forms;
only a source that uses them is parsed with the extended grammar (an Earley
parser of blark's size takes a while to build, and parses no faster).
"""

from __future__ import annotations

import functools
import re
from collections.abc import Sequence
from typing import Any

__all__ = ["GRAMMAR_OVERLAY", "build_grammars", "grammar_of", "needs_overlay", "overlay_parser"]


#: What blark's grammar lacks and the vendors accept, added to it with Lark's ``%extend``
#: (kept small and self-contained, so it could go upstream as is). Only a source that
#: uses one of these words is parsed with the extended grammar.
GRAMMAR_OVERLAY = r"""
%extend _statement: try_statement
%extend _case_element_statement: try_statement
try_statement: _TRY [ statement_list ] [ catch_clause ] [ finally_clause ] _ENDTRY ";"*
catch_clause: _CATCH "(" _variable ")" [ statement_list ]
finally_clause: _FINALLY [ statement_list ]
_TRY.2: /\b__TRY\b/i
_CATCH.2: /\b__CATCH\b/i
_FINALLY.2: /\b__FINALLY\b/i
_ENDTRY.2: /\b__ENDTRY\b/i
"""
_OVERLAY_WORDS = re.compile(r"\b__(TRY|CATCH|FINALLY|ENDTRY)\b", re.IGNORECASE)


@functools.lru_cache(maxsize=1)
def overlay_parser() -> Any:
    """blark's own grammar (read from the installed package) with ``GRAMMAR_OVERLAY`` added."""
    import importlib.resources

    import blark
    import lark
    from blark.parse import BlarkStartingRule

    from iecoop.st.read.dialect import DIALECT_OVERLAY

    grammar = importlib.resources.files(blark).joinpath(blark.GRAMMAR_FILENAME.name).read_text()
    return lark.Lark(
        grammar + GRAMMAR_OVERLAY + DIALECT_OVERLAY,
        parser="earley",
        maybe_placeholders=True,
        propagate_positions=True,
        start=[rule.name for rule in BlarkStartingRule],
    )


def build_grammars(texts: Sequence[str]) -> None:
    """Build the Earley parsers ``texts`` need (blark's, and the overlay's if one needs it): each takes a while."""
    import blark.parse

    names = {grammar_of(text) for text in texts}
    if "blark" in names:
        blark.parse.get_parser()
    if names - {"blark"}:
        overlay_parser()


def needs_overlay(text: str) -> bool:
    """Whether ``text`` uses a word of ``GRAMMAR_OVERLAY`` or a form of the dialect: then it is parsed with them."""
    from iecoop.st.read.dialect import needs_dialect

    return bool(_OVERLAY_WORDS.search(text)) or needs_dialect(text)


def grammar_of(text: str) -> str:
    """The grammar ``text`` is parsed with: blark's, or blark's with iecoop's overlay and dialect (named by
    their hash, with the dialect's tree rewrite, whose result the cache keeps)."""
    return _overlay_name() if needs_overlay(text) else "blark"


@functools.cache
def _overlay_name() -> str:
    import hashlib
    import inspect

    from iecoop.st.read import dialect

    overlay = GRAMMAR_OVERLAY + dialect.DIALECT_OVERLAY + inspect.getsource(dialect)
    return "overlay-" + hashlib.sha256(overlay.encode()).hexdigest()[:16]
