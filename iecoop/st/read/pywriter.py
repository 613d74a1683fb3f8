"""The Python text being produced: lines, indentation, imports, and the ST comments and pragmas carried over."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from iecoop.st.read.symbols import Symbols
from iecoop.st.read.table import SYSTEM_DECLS, TypeRef


class SourceLine(str):
    """One line of the generated Python, with the ST file and line it was written for (``origin``)."""

    origin: tuple[str, int] | None


def origin_of(line: str) -> tuple[str, int] | None:
    """The ST ``(file, line)`` a generated line was written for; None for lines of iecoop's own (imports, helpers)."""
    return getattr(line, "origin", None)


class PyWriter(Symbols):
    """Writes the module's Python lines and imports, with the ST comments kept in place."""

    def need(self, module: str, *names: str) -> None:
        self.imports.setdefault(module, set()).update(names)

    # --- pass 2: emission ---

    def emit(self, text: str, level: int) -> None:
        self.out.append(self.mapped("    " * level + text if text else ""))
        self.code_lines += bool(text)

    def at(self, node: Any) -> None:
        """The lines written next are for ``node``'s ST line (an ELSIF, a CASE label, the end of a FOR)."""
        line = getattr(getattr(node, "meta", None), "line", None)
        if line is not None:
            self.line = line

    def mapped(self, text: str) -> SourceLine:
        """``text`` marked with the ST file and line being translated (what a traceback and pdb will show)."""
        line = SourceLine(text)
        line.origin = None
        if self.unit is not None and self.line is not None:
            line.origin = self.unit.line_map.get(self.line, (self.unit.filename, self.line))
        return line

    def emit_comment(self, text: str, level: int) -> None:
        """A comment line: no code, so a body holding only comments still needs its ``pass``."""
        self.out.append("    " * level + f"# {text}".rstrip())

    def emit_def(self, name: str, params: Sequence[str], returns: str, level: int) -> None:
        """``def name(params) -> returns:``; one parameter per line when it would be longer than 110 characters."""
        text = f"def {name}({', '.join(params)}) -> {returns}:"
        if len(text) + 4 * level <= 110:
            self.emit(text, level)
            return
        self.emit(f"def {name}(", level)
        for param in params:
            self.emit(f"{param},", level + 1)
        self.emit(f") -> {returns}:", level)

    def enter(self, node: Any) -> None:
        """Comments are taken from the source lines of the top-level item ``node`` from now on."""
        unit = self.unit
        line = getattr(getattr(node, "meta", None), "line", None)
        self.window = (0, 0)
        if unit is None or line is None:
            return
        self.line = line
        previous_end = 0
        for item in unit.tree.items:
            meta = getattr(item, "meta", None)
            if item is node:
                self.window = (previous_end + 1, getattr(meta, "end_line", None) or line)
                return
            end = getattr(meta, "end_line", None)
            if end is not None and end < line:
                previous_end = max(previous_end, end)

    def comments(self, node: Any, level: int, inline: bool = False) -> str:
        """Emit the comments before ``node``; with ``inline``, return the one on its line, for the end of that line.

        Comments are placed by their line in the source (blark attaches some of them to a later
        statement), each once, within the lines of the item being written.
        """
        meta = getattr(node, "meta", None)
        line = getattr(meta, "line", None)
        trailing = ""
        if line is None or self.unit is None:
            return ""
        low, high = self.window
        tokens = [
            t for t in self.unit.comments
            if low <= t.line <= min(line, high) and id(t) not in self.used_comments
        ]
        for token in tokens:
            text = str(token).strip()
            self.used_comments.add(id(token))
            if text.startswith("{"):
                continue  # pragmas are read where they matter (call_after_init)
            if text.startswith("//"):
                body = [text[2:].strip()]
            else:
                body = [part.strip() for part in text[2:-2].strip().splitlines()]
            if inline and line is not None and getattr(token, "line", None) == line and len(body) == 1:
                trailing = body[0]
                continue
            for part in body:
                self.emit_comment(part, level)
        return trailing

    def trail(self, index: int, comment: str) -> None:
        """Put ``comment`` at the end of the line at ``index`` (an ST end-of-line comment)."""
        if comment and index < len(self.out):
            line = SourceLine(f"{self.out[index]}  # {comment}")
            line.origin = origin_of(self.out[index])
            self.out[index] = line

    def pragmas(self, node: Any, after: int | None = None) -> list[str]:
        """The pragmas (``{attribute 'x'}``) written before ``node``, within the current item's lines (after line ``after``)."""
        line = getattr(getattr(node, "meta", None), "line", None)
        if line is None or self.unit is None:
            return []
        low = self.window[0] if after is None else max(self.window[0], after + 1)
        return [str(t).strip() for t in self.unit.comments if low <= t.line <= line and str(t).strip().startswith("{")]

    def _need_type(self, type_: TypeRef | None) -> None:
        if type_ is None:
            return
        if type_.kind == "array":
            self.need("iecoop", "ARRAY")
        elif type_.kind == "pointer":
            self.need("iecoop", "POINTER_TO")
        elif type_.kind == "reference":
            self.need("iecoop", "REFERENCE_TO")
        elif type_.kind in ("elem", "string", "any"):
            self.need("iecoop", type_.name)
        elif type_.name == "ExceptionCode":
            self.need("iecoop", "ExceptionCode")
        elif getattr(self.by_python.get(type_.name), "kind", None) == "stdfb":
            self.need("iecoop.stdlib", type_.name)
        elif type_.kind == "user" and type_.name not in self.by_python and type_.name.lower() in SYSTEM_DECLS:
            self.need("iecoop", type_.name)
        if type_.of is not None:
            self._need_type(type_.of)
