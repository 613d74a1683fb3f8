"""Measures for the layout guards of the ST bridge's wings: file, class and function sizes, read with ``ast``."""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

#: The nodes that add a path through a function, as radon counts them (McCabe's cyclomatic complexity).
_BRANCHES = (ast.If, ast.IfExp, ast.For, ast.AsyncFor, ast.While, ast.ExceptHandler, ast.Assert, ast.comprehension,
             ast.match_case)


def oversized(room: Path, *, module_lines: int, class_lines: int) -> list[str]:
    """What in ``room`` is longer than the bounds: the module, or a class in it."""
    text = room.read_text(encoding="utf-8")
    found = []
    if len(text.splitlines()) > module_lines:
        found.append(f"{room.name} has {len(text.splitlines())} lines")
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.ClassDef):
            size = (node.end_lineno or node.lineno) - node.lineno + 1
            if size > class_lines:
                found.append(f"{room.name}: class {node.name} has {size} lines")
    return found


def complexity(function: ast.FunctionDef | ast.AsyncFunctionDef) -> int:
    """1 + the branches of ``function`` (its nested functions count on their own), as radon's ``cc``."""
    score = 1
    for node in _own_nodes(function):
        if isinstance(node, _BRANCHES):
            score += 1 + (len(node.ifs) if isinstance(node, ast.comprehension) else 0)
        elif isinstance(node, ast.BoolOp):
            score += len(node.values) - 1
        elif isinstance(node, (ast.Try, ast.TryStar)) and node.orelse:
            score += 1
    return score


def _own_nodes(function: ast.AST) -> Iterator[ast.AST]:
    for child in ast.iter_child_nodes(function):
        if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
            continue
        yield child
        yield from _own_nodes(child)


def functions(room: Path) -> Iterator[tuple[str, int]]:
    """``(qualified name, complexity)`` of every function and method in ``room``."""
    tree = ast.parse(room.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.ClassDef):
            for item in node.body:
                if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    yield f"{node.name}.{item.name}", complexity(item)
        elif isinstance(node, ast.Module):
            for item in node.body:
                if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    yield item.name, complexity(item)
