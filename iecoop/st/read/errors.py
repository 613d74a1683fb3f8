"""The two errors the ST reader raises: a source blark cannot parse, and a construct iecoop cannot translate.

Both are ``DefinitionError``s naming the file, the line and the construct; ``iecoop.st`` exports them.
"""

from __future__ import annotations

from iecoop.exceptions import DefinitionError

__all__ = ["StSyntaxError", "StUnsupportedError"]


class StSyntaxError(DefinitionError):
    """The source is not valid Structured Text (blark could not parse it); names the file and line."""

    __module__ = "iecoop.st"


class StUnsupportedError(DefinitionError):
    """A construct that iecoop cannot translate faithfully; names the file, line and construct."""

    __module__ = "iecoop.st"
