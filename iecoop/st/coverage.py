"""A coverage.py plugin: line coverage of the Structured Text files ``st.load`` ran.

Loaded ST runs under the name and lines of its ``.TcPOU`` / ``.st`` file
(source maps), so the lines coverage.py records for it are ST lines. This
plugin claims those files: it reports their executable lines (the line of
each ST statement, read from the file's parse, which the translation cache
keeps) and their text, for the terminal, HTML and XML reports. Enable it in
the coverage configuration::

    [run]
    plugins = iecoop.st.coverage

(``[tool.coverage.run] plugins = ["iecoop.st.coverage"]`` in
``pyproject.toml``). The ST source of a line that declares variables, a
METHOD or a POU is not counted: it runs when the module is loaded, not when
the PLC runs.
"""

from __future__ import annotations

import os
import pathlib
from typing import Any

import coverage.plugin

from iecoop.st.read.parse import ST_SUFFIXES, TWINCAT_SUFFIXES

__all__ = ["StCoveragePlugin", "StFileReporter", "coverage_init", "executable_lines"]

_SUFFIXES = (*ST_SUFFIXES, *TWINCAT_SUFFIXES)


def _is_st_file(filename: str) -> bool:
    return os.path.splitext(filename)[1].lower() in _SUFFIXES


def executable_lines(filename: str) -> set[int]:
    """The lines of ``filename`` that run code: each ST statement, ELSIF and CASE label in a body.

    Bodies are those of POUs, METHODs, PROPERTY accessors and ACTIONs; the
    translator writes each of these lines' code at that line.
    """
    import blark.transform as tf

    from iecoop.st.read.parse import parse_sources

    path = pathlib.Path(filename)
    lines: set[int] = set()
    for unit in parse_sources(path):
        stack: list[Any] = [unit.tree]
        while stack:
            node = stack.pop()
            # A CASE runs its selector in its first label's test: the labels are its lines, not the CASE's.
            if isinstance(node, (tf.Statement, tf.ElseIfClause)) and not isinstance(node, tf.CaseStatement):
                meta = getattr(node, "meta", None)
                line = getattr(meta, "line", None)
                if isinstance(line, int):
                    file, real = unit.line_map.get(line, (unit.filename, line))
                    if os.path.abspath(file) == os.path.abspath(filename):
                        lines.add(real)
            stack.extend(_children(node))
    return lines


def _children(node: Any) -> list[Any]:
    """The blark nodes directly inside ``node`` (its dataclass fields, lists of them flattened)."""
    import dataclasses

    if not dataclasses.is_dataclass(node) or isinstance(node, type):
        return []
    found: list[Any] = []
    for field in dataclasses.fields(node):
        if field.name == "meta":
            continue
        value = getattr(node, field.name, None)
        items = value if isinstance(value, (list, tuple)) else [value]
        found.extend(item for item in items if dataclasses.is_dataclass(item) and not isinstance(item, type))
    return found


class _StFileTracer(coverage.plugin.FileTracer):
    """Code compiled under an ST file's name is that file's (its lines are already the ST lines)."""

    def __init__(self, filename: str) -> None:
        self._filename = filename

    def source_filename(self) -> str:
        return self._filename


class StFileReporter(coverage.plugin.FileReporter):
    """An ST file in a report: its statement lines and its text."""

    def lines(self) -> set[int]:
        try:
            return executable_lines(self.filename)
        except Exception:  # noqa: BLE001 - a file that no longer parses is reported with no statements
            return set()

    def source(self) -> str:
        return pathlib.Path(self.filename).read_text(encoding="utf-8", errors="replace")


class StCoveragePlugin(coverage.plugin.CoveragePlugin):
    """Claims ``.st``, ``.TcPOU``, ``.TcDUT``, ``.TcGVL`` and ``.TcIO`` files."""

    def file_tracer(self, filename: str) -> coverage.plugin.FileTracer | None:
        return _StFileTracer(filename) if _is_st_file(filename) else None

    def file_reporter(self, filename: str) -> coverage.plugin.FileReporter | str:
        return StFileReporter(filename)


def coverage_init(reg: Any, options: dict[str, Any]) -> None:
    """coverage.py's entry point for ``plugins = iecoop.st.coverage``."""
    reg.add_file_tracer(StCoveragePlugin())
