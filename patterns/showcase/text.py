"""reStructuredText docstrings as plain text for a terminal (``iecoop show``).

Only what the modules' docstrings use is rendered, without docutils (it is
not a dependency of the command): inline literals and roles lose their
markup, a paragraph ending in ``::`` ends in ``:`` and its literal block (the
Structured Text of the *IEC 61131-3 mapping*) stays indented as written, a
``code-block`` directive keeps only its indented body.

>>> print(render_rst('''Delegates to ``I_PackMLState``; see :class:`~iecoop.stdlib.TON`.
...
... ST::
...
...     METHOD Command : BOOL  // ``cmd`` unchanged here
...
... *Done*.'''))
Delegates to I_PackMLState; see TON.
<BLANKLINE>
ST:
<BLANKLINE>
    METHOD Command : BOOL  // ``cmd`` unchanged here
<BLANKLINE>
Done.
"""

from __future__ import annotations

import re

__all__ = ["render_inline", "render_rst"]

# Inline markup may run over a line break, as in running text.
_ROLE = re.compile(r":[a-z]+(?::[a-z]+)?:`([^`]+)`")
_LITERAL = re.compile(r"``(.+?)``", re.S)
_LINK = re.compile(r"`([^`<]+?)\s*<([^`>]+)>`__?")
_STRONG = re.compile(r"\*\*(\S(?:.*?\S)?)\*\*", re.S)
_EMPHASIS = re.compile(r"(?<![\w*])\*(\S(?:.*?\S)?)\*(?![\w*])", re.S)
_DIRECTIVE = re.compile(r"^(\s*)\.\. ([a-z-]+)::\s*(.*)$")
_ADMONITIONS = {"note": "Note", "warning": "Warning", "tip": "Tip", "important": "Important", "seealso": "See also"}


def _role(match: re.Match[str]) -> str:
    text = match.group(1)
    shown = re.match(r"(.+?)\s*<[^>]+>$", text)
    if shown:
        return shown.group(1)
    return text.rsplit(".", 1)[-1] if text.startswith("~") else text


def render_inline(line: str) -> str:
    """Running text (one line or a paragraph) without its inline markup."""
    line = _ROLE.sub(_role, line)
    line = _LINK.sub(r"\1 (\2)", line)
    line = _LITERAL.sub(r"\1", line)
    line = _STRONG.sub(r"\1", line)
    return _EMPHASIS.sub(r"\1", line)


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip())


def render_rst(text: str) -> str:
    """A docstring's reStructuredText as terminal text; literal blocks are kept verbatim."""
    out: list[str] = []
    prose: list[str] = []  # running text waiting for its inline markup to be rendered

    def emit(line: str, literal: bool = False) -> None:
        if literal:
            if prose:
                out.extend(render_inline("\n".join(prose)).split("\n"))
                prose.clear()
            out.append(line)
        else:
            prose.append(line)

    literal_above: int | None = None  # the indentation a literal block must exceed, while in one
    for line in text.splitlines():
        if literal_above is not None:
            if not line.strip() or _indent(line) > literal_above:
                emit(line, literal=True)
                continue
            literal_above = None
        directive = _DIRECTIVE.match(line)
        if directive:
            indent, name, argument = directive.groups()
            if name in ("code-block", "code", "sourcecode"):
                literal_above = len(indent)
            elif name in _ADMONITIONS:
                emit(f"{indent}{_ADMONITIONS[name]}: {argument}".rstrip())
            continue  # other directives (targets, comments) have nothing to show
        stripped = line.rstrip()
        if stripped.endswith("::"):
            literal_above = _indent(line)
            head = stripped[:-2].rstrip()
            if not head.strip():
                literal_above = _indent(line)
                emit("", literal=True)
                continue  # a bare "::" introduces the block and shows nothing
            line = head + ":" if not stripped[:-2].endswith(" ") else head
        emit(line)
    emit("", literal=True)
    text = "\n".join(out)
    return re.sub(r"\n{3,}", "\n\n", text).strip("\n")
