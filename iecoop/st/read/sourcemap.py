"""Source maps: the Python generated from Structured Text runs under the ST file's name and line numbers.

The translator marks each generated line with the ST file and line it was
written for. ``compile_mapped`` parses the generated text, gives every node
the line of its ST statement and compiles each top-level class or function
under the name of its ST file (as the user gave it), so a traceback,
``linecache``, pytest's report, ``pdb`` and coverage show the ``.TcPOU`` /
``.st`` file and its ST text. ST given as text is registered in ``linecache``
as ``<st text #N>``. The readable Python (``st.to_python``,
``StModule.__python__``) is unchanged; iecoop's own lines (imports, helpers)
keep the generated module's name.

>>> import linecache
>>> text = "x = 1\\ny = 1 // 0\\n"
>>> codes = compile_mapped(text, [("plc.st", 7), ("plc.st", 9)], "<generated>", {})
>>> [code.co_filename for code in codes]
['plc.st']
>>> try:
...     exec(codes[0], {})
... except ZeroDivisionError as exc:
...     tb = exc.__traceback__
...     while tb.tb_next is not None:
...         tb = tb.tb_next
...     print(tb.tb_frame.f_code.co_filename, tb.tb_lineno)
plc.st 9
"""

from __future__ import annotations

import __future__
import ast
import linecache
import types
from collections.abc import Iterator, Mapping, Sequence

from iecoop._codegen import register_definition
from iecoop.exceptions import register_st_file

__all__ = ["Origin", "compile_mapped", "register_text"]

#: An ST file (as the user named it) and a line in it.
Origin = tuple[str, int]

#: A column wider than any ST line: a traceback then underlines no part of the ST line it shows.
_WHOLE_LINE = 1000
_FLAGS = __future__.annotations.compiler_flag


def register_text(name: str, text: str) -> None:
    """Put ST given as text into ``linecache`` as the file ``name`` (``<st text #N>``), for tracebacks and pdb."""
    linecache.cache[name] = (len(text), None, text.splitlines(True), name)
    register_st_file(name)


def compile_mapped(
    text: str, origins: Sequence[Origin | None], generated: str, rename: Mapping[str, str]
) -> list[types.CodeType]:
    """The code objects to run in order, in one namespace, for the generated module ``text``.

    ``origins[i]`` is the ST file and line of line ``i + 1`` of ``text``; a
    top-level statement with no ST line (an import, a helper) is compiled
    under ``generated`` at its own line. ``rename`` maps a unit's file name
    to the name it is shown under (``<st>`` -> ``<st text #3>``).
    """
    tree = ast.parse(text, generated)
    lines = text.splitlines(True)
    for node in _definitions(tree.body):
        # iecoop's ST writer reads a def's Python (to export it): kept before its lines become ST lines
        first = min([node.lineno, *(d.lineno for d in node.decorator_list)])
        setattr(node, "iecoop_python", "".join(lines[first - 1:node.end_lineno]))
    groups: list[tuple[str, list[ast.stmt]]] = []
    for statement in tree.body:
        file = _map_statement(statement, origins, rename) or generated
        if groups and groups[-1][0] == file:
            groups[-1][1].append(statement)
        else:
            groups.append((file, [statement]))
    codes = []
    for file, body in groups:
        module = ast.Module(body=body, type_ignores=[])
        code = compile(module, file, "exec", flags=_FLAGS, dont_inherit=True)
        if file != generated:
            register_st_file(file)
            # iecoop reads a method's definition from its source (has_body, the inlined call): the generated one.
            for function, node in _pair_definitions(code, body):
                register_definition(function, node, text)
        codes.append(code)
    return codes


def _map_statement(statement: ast.stmt, origins: Sequence[Origin | None], rename: Mapping[str, str]) -> str | None:
    """Give ``statement``'s nodes their ST lines; its ST file, or None when none of its lines has one."""
    decorators = getattr(statement, "decorator_list", [])
    first = min([statement.lineno, *(d.lineno for d in decorators)])
    last = statement.end_lineno or statement.lineno
    span = [origins[line - 1] if line - 1 < len(origins) else None for line in range(first, last + 1)]
    file = next((origin[0] for origin in span if origin is not None), None)
    if file is None:
        return None
    lines = _st_lines(span, file, first)
    shown = rename.get(file, file)
    columns: dict[int, tuple[int, int]] = {}
    for node in ast.walk(statement):
        if "lineno" not in node._attributes:
            continue
        start = lines.get(getattr(node, "lineno", first), lines[first])
        end = max(start, lines.get(getattr(node, "end_lineno", None) or first, start))
        if start not in columns:
            columns[start] = _columns(shown, start)
        node.lineno, node.end_lineno = start, end  # type: ignore[attr-defined]
        node.col_offset = columns[start][0]  # type: ignore[attr-defined]
        node.end_col_offset = columns[start][1] if end == start else _WHOLE_LINE  # type: ignore[attr-defined]
    _start_at_first_lines(statement)
    return shown


def _st_lines(span: Sequence[Origin | None], file: str, first: int) -> dict[int, int]:
    """Python line -> ST line over a statement's span; a line of iecoop's own (a field added to a class)
    takes the ST line before it."""
    lines: dict[int, int] = {}
    current = next(origin[1] for origin in span if origin is not None and origin[0] == file)
    for offset, origin in enumerate(span):
        if origin is not None and origin[0] == file:
            current = origin[1]
        lines[first + offset] = current
    return lines


def _start_at_first_lines(node: ast.AST) -> int:
    """A ``def`` (or ``class``) in ``node`` starts no later than its first ST line: pytest and inspect read its
    lines from there. The first line of ``node``'s nodes, found in one pass.

    ``def body`` is written after the block's METHODs, so its own line would be the last METHOD's.
    """
    own: int | None = getattr(node, "lineno", None) if "lineno" in node._attributes else None
    first = own
    for child in ast.iter_child_nodes(node):
        below = _start_at_first_lines(child)
        if below and (first is None or below < first):
            first = below
    if first is not None and isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
        for n in [node, *(d for decorator in node.decorator_list for d in ast.walk(decorator))]:
            if "lineno" in n._attributes and n.lineno > first:  # type: ignore[attr-defined]
                n.lineno = first  # type: ignore[attr-defined]
                n.col_offset = 0  # type: ignore[attr-defined]
    return first or 0


def _columns(file: str, line: int) -> tuple[int, int]:
    """The whole ST line, from its first character to its last: a traceback then underlines none of it."""
    text = linecache.getline(file, line).rstrip().encode()
    if not text:
        return 0, _WHOLE_LINE
    return len(text) - len(text.lstrip()), len(text)


def _definitions(body: Sequence[ast.AST]) -> Iterator[ast.FunctionDef | ast.AsyncFunctionDef]:
    """The ``def`` nodes in source order, depth first (the order the compiler stores their code).

    Only statement lists are searched: a ``def`` is a statement (a ``lambda`` is not one).
    """
    for node in body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            yield node
        for name in ("body", "orelse", "finalbody", "handlers", "cases"):
            inner = getattr(node, name, None)
            if isinstance(inner, list):
                yield from _definitions(inner)


def _codes(code: types.CodeType) -> Iterator[types.CodeType]:
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            yield const
            yield from _codes(const)


def _pair_definitions(
    code: types.CodeType, body: Sequence[ast.stmt]
) -> Iterator[tuple[types.CodeType, ast.FunctionDef | ast.AsyncFunctionDef]]:
    """Each function's code with its ``def`` node, matched by name and first line, in source order."""
    waiting: dict[tuple[str, int], list[ast.FunctionDef | ast.AsyncFunctionDef]] = {}
    for node in _definitions(body):
        first = min([node.lineno, *(d.lineno for d in node.decorator_list)])
        waiting.setdefault((node.name, first), []).append(node)
    for function in _codes(code):
        nodes = waiting.get((function.co_name, function.co_firstlineno))
        if nodes:
            yield function, nodes.pop(0)
