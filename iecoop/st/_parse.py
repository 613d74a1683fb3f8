"""The blark front end: ST text, ``.st`` files, TwinCAT files, folders and ``.plcproj`` to blark trees.

Every source becomes *flat* Structured Text first: the form TwinCAT exports
and blark parses, where a METHOD or PROPERTY follows the FUNCTION_BLOCK or
INTERFACE it belongs to. A TwinCAT file is split by blark into its parts
(declaration, implementation, each method, each property accessor); they are
joined back here in that order, and a property accessor is renamed
``Name.Get`` / ``Name.Set`` (the plain-text form of a property with both
accessors). A map from each flat line to its file and line keeps error
messages pointing at the real source.
"""

from __future__ import annotations

import dataclasses
import functools
import os
import pathlib
import re
import xml.etree.ElementTree as ElementTree
from collections.abc import Iterator
from typing import Any

from iecoop.exceptions import DefinitionError

__all__ = ["StSyntaxError", "StUnsupportedError", "Unit", "parse_sources"]

#: The TwinCAT file kinds blark reads (POUs, data types, global and I/O lists).
TWINCAT_SUFFIXES = (".tcpou", ".tcdut", ".tcgvl", ".tcio")
ST_SUFFIXES = (".st",)

_PROPERTY_NAME = re.compile(
    r"^(\s*PROPERTY\s+(?:(?:PUBLIC|PRIVATE|PROTECTED|INTERNAL|ABSTRACT|FINAL)\s+)*)([A-Za-z_]\w*)", re.IGNORECASE | re.MULTILINE
)


class StSyntaxError(DefinitionError):
    """The source is not valid Structured Text (blark could not parse it); names the file and line."""

    __module__ = "iecoop.st"


class StUnsupportedError(DefinitionError):
    """A construct that iecoop cannot translate faithfully; names the file, line and construct."""

    __module__ = "iecoop.st"


@dataclasses.dataclass
class Unit:
    """One parsed flat source: the blark tree and where its lines came from."""

    tree: Any  # blark.transform.SourceCode
    filename: str
    #: flat line number -> (file, line) for sources joined from TwinCAT parts
    line_map: dict[int, tuple[str, int]] = dataclasses.field(default_factory=dict)
    #: every comment and pragma token of the source, in order (each has ``.line``)
    comments: tuple[Any, ...] = ()

    def where(self, line: int | None) -> str:
        """``file:line`` of a flat line."""
        if line is None:
            return self.filename
        file, real = self.line_map.get(line, (self.filename, line))
        return f"{file}:{real}"


def parse_sources(source: str | os.PathLike[str]) -> list[Unit]:
    """Parse ``source`` (ST text, a file, a folder or a ``.plcproj``) into flat units."""
    if isinstance(source, str) and ("\n" in source or ";" in source or not _looks_like_path(source)):
        return [_parse_text(source, "<st>", {})]
    path = pathlib.Path(source)
    if not path.exists():
        raise FileNotFoundError(f"ST source {str(path)!r} does not exist")
    return [_parse_text(text, name, line_map) for text, name, line_map in _flat_sources(path)]


def _looks_like_path(text: str) -> bool:
    return pathlib.Path(text).suffix.lower() in (*ST_SUFFIXES, *TWINCAT_SUFFIXES, ".plcproj") or pathlib.Path(text).is_dir()


def _flat_sources(path: pathlib.Path) -> Iterator[tuple[str, str, dict[int, tuple[str, int]]]]:
    if path.is_dir():
        for child in sorted(path.rglob("*")):
            if child.is_file() and child.suffix.lower() in (*ST_SUFFIXES, *TWINCAT_SUFFIXES):
                yield from _flat_sources(child)
        return
    suffix = path.suffix.lower()
    if suffix in ST_SUFFIXES:
        yield path.read_text(encoding="utf-8-sig"), str(path), {}
    elif suffix in TWINCAT_SUFFIXES:
        yield _flatten_twincat(path)
    elif suffix == ".plcproj":
        for included in _plcproj_files(path):
            yield from _flat_sources(included)
    else:
        raise StUnsupportedError(f"{path}: unsupported file kind {path.suffix!r} (use .st, .TcPOU, .TcDUT, .TcGVL, .TcIO, .plcproj or a folder)")


def _plcproj_files(path: pathlib.Path) -> list[pathlib.Path]:
    root = ElementTree.parse(path).getroot()
    files = []
    for element in root.iter():
        if element.tag.rsplit("}", 1)[-1] == "Compile":
            include = element.get("Include", "")
            candidate = path.parent / include.replace("\\", "/")
            if candidate.suffix.lower() in TWINCAT_SUFFIXES and candidate.exists():
                files.append(candidate)
    return files


def _flatten_twincat(path: pathlib.Path) -> tuple[str, str, dict[int, tuple[str, int]]]:
    from blark.input import BlarkCompositeSourceItem, load_file_by_name

    lines: list[str] = []
    line_map: dict[int, tuple[str, int]] = {}

    def add(code: str, inner: dict[int, int]) -> None:
        for offset, text in enumerate(code.split("\n"), start=1):
            lines.append(text)
            line_map[len(lines)] = (str(path), inner.get(offset, max(inner.values(), default=0)))

    def walk(item: Any) -> None:
        if isinstance(item, BlarkCompositeSourceItem):
            parts = list(item.parts)
            index = 0
            while index < len(parts):
                part = parts[index]
                if isinstance(part, BlarkCompositeSourceItem):
                    walk(part)
                    index += 1
                    continue
                code, inner = part.get_code_and_line_map(include_end=False)
                accessor = part.identifier.split("/")[0].rsplit(".", 1)[-1].lower()
                if part.type.name == "action":  # a TwinCAT <Action> holds only its code: the flat form names it
                    first = min(inner.values(), default=0)
                    add(f"ACTION {part.identifier.split('/')[0].rsplit('.', 1)[-1]}:", {1: first})
                    add(code, inner)
                    add("END_ACTION", {1: max(inner.values(), default=first)})
                    index += 1
                    continue
                if part.type.name in ("property_get", "property_set"):
                    code = _PROPERTY_NAME.sub(lambda m: f"{m.group(1)}{m.group(2)}.{accessor.capitalize()}", code, count=1)
                add(code, inner)
                end = part.implicit_end
                nxt = parts[index + 1] if index + 1 < len(parts) else None
                if (
                    nxt is not None
                    and not isinstance(nxt, BlarkCompositeSourceItem)
                    and nxt.identifier.endswith("/implementation")
                    and nxt.identifier.split("/")[0] == part.identifier.split("/")[0]
                ):
                    impl, impl_map = nxt.get_code_and_line_map(include_end=False)
                    if impl.strip():
                        add(impl, impl_map)
                    index += 1
                if end:
                    add(end, {1: max(inner.values(), default=0)})
                index += 1
        else:
            code, inner = item.get_code_and_line_map(include_end=True)
            add(code, inner)

    for item in load_file_by_name(path):
        walk(item)
    return "\n".join(lines) + "\n", str(path), line_map


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
def _overlay_parser() -> Any:
    """blark's own grammar (read from the installed package) with ``GRAMMAR_OVERLAY`` added."""
    import importlib.resources

    import blark
    import lark
    from blark.parse import BlarkStartingRule

    grammar = importlib.resources.files(blark).joinpath(blark.GRAMMAR_FILENAME.name).read_text()
    return lark.Lark(
        grammar + GRAMMAR_OVERLAY,
        parser="earley",
        maybe_placeholders=True,
        propagate_positions=True,
        start=[rule.name for rule in BlarkStartingRule],
    )


def _parse_text(text: str, filename: str, line_map: dict[int, tuple[str, int]]) -> Unit:
    tree, comments = _tree(text, filename, tuple(sorted(line_map.items())))
    return Unit(tree, filename, line_map, comments)


@functools.lru_cache(maxsize=128)
def _tree(text: str, filename: str, line_map_items: tuple[tuple[int, tuple[str, int]], ...]) -> Any:
    """blark's tree and comment tokens for ``text``; cached, because blark's Earley parser takes a while and a test loads one source often."""
    import blark
    import lark

    line_map = dict(line_map_items)
    parser = _overlay_parser() if _OVERLAY_WORDS.search(text) else None
    result = blark.parse_source_code(text, fn=filename, parser=parser)
    if result.exception is not None:
        exc = result.exception
        line = getattr(exc, "line", None)
        unit = Unit(None, filename, line_map)
        where = unit.where(line if isinstance(line, int) and line > 0 else None)
        detail = _syntax_detail(exc, text)
        raise StSyntaxError(f"{where}: Structured Text syntax error: {detail}") from None
    try:
        return result.transform(), tuple(result.comments)
    except (lark.LarkError, ValueError, TypeError) as exc:  # a tree blark cannot build
        raise StSyntaxError(f"{filename}: blark could not build the tree: {exc}") from None


def _syntax_detail(exc: Exception, text: str) -> str:
    token = getattr(exc, "token", None)
    line = getattr(exc, "line", None)
    source_line = ""
    if isinstance(line, int) and 0 < line <= len(text.splitlines()):
        source_line = text.splitlines()[line - 1].strip()
    if token is not None:
        return f"unexpected {str(token)!r} in {source_line!r}"
    return f"cannot parse {source_line!r}" if source_line else type(exc).__name__
