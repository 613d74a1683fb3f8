"""blark tree -> a readable Python module that uses only iecoop's public API.

Two passes. The first collects every declared name (POUs, data types, GVLs,
their members, methods and properties) into a symbol table, so the second can
resolve ST's case-insensitive names to their declared spelling, type each
expression (``/`` on integers is DIV, ``AND`` on BOOL is ``and``, ``w.3`` is a
bit of a WORD) and order the classes so a class exists before it is used.
Whatever cannot be translated faithfully raises ``StUnsupportedError`` naming
the file, line and construct; nothing is dropped silently.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator, Sequence

import blark.transform as tf

from iecoop.st.language import is_reserved
from iecoop.st.read.parse import Unit
from iecoop.st.read.pous import Pous
from iecoop.st.read.libraries import bind, collapse_namespaces, rename_shadowed
from iecoop.st.read.lookup import BoundLibrary
from iecoop.st.read.pywriter import origin_of
from iecoop.st.read.prototypes import align_prototype_names
from iecoop.st.read.table import Decl

_QUALIFIED_ONLY = re.compile(r"\{\s*attribute\s+'qualified_only'\s*\}", re.IGNORECASE)


class Translator(Pous):
    """The whole translation: pass 1, then each declaration in dependency order."""

    def _refuse_keyword_names(self) -> None:
        """FUNCTION_BLOCK INT is refused, as TwinCAT refuses it: it would stand beside iecoop's INT, and plc.INT name the type."""
        for decl in self.decls.values():
            if not decl.library and decl.kind != "stdfb" and is_reserved(decl.st):
                keyword = {"fb": "FUNCTION_BLOCK", "gvl": "GVL", "alias": "TYPE"}.get(decl.kind, decl.kind.upper())
                self.unit = decl.unit
                raise self.fail(f"{keyword} {decl.st}: {decl.st.upper()} is an ST keyword, which no POU, type or GVL may be named",
                                decl.item if decl.kind != "gvl" else decl.node[0])

    def _built_from(self, decl: Decl) -> Iterator[Decl]:
        """What ``decl`` is made of before its own class exists: what it EXTENDS, or the type it is an alias of."""
        names = list(decl.bases)
        if decl.kind == "alias" and isinstance(decl.node, tf.SimpleTypeDeclaration):
            names.append(str(decl.node.init.spec))  # TYPE T_A : T_B (a POINTER TO or REFERENCE TO stays a name of its own)
        found = (self.decls.get(name.lower()) for name in names)
        yield from (d for d in found if d is not None and not d.library)

    def _refuse_self_built(self) -> None:
        """EXTENDS or an alias that comes back to where it started is refused at its line, naming the chain.

        (FB_A EXTENDS FB_B and FB_B EXTENDS FB_A; TYPE T_A : T_B and TYPE T_B : T_A.) A walk with a stack of
        its own, as a chain may be as long as the source is.
        """
        done: set[int] = set()
        for start in self.decls.values():
            path: list[Decl] = []
            stack: list[tuple[Decl, Iterator[Decl]]] = [(start, self._built_from(start))]
            path.append(start)
            while stack:
                decl, below = stack[-1]
                step = next(below, None)
                if step is None:
                    done.add(id(decl))
                    stack.pop()
                    path.pop()
                    continue
                if id(step) in done:
                    continue
                if any(step is d for d in path):
                    chain = path[next(i for i, d in enumerate(path) if d is step):] + [step]
                    keyword = {"fb": "FUNCTION_BLOCK", "alias": "TYPE"}.get(step.kind, step.kind.upper())
                    self.unit = step.unit
                    raise self.fail(f"{keyword} {step.st} is built from itself: {' -> '.join(d.st for d in chain)} "
                                    "(EXTENDS and aliases may not come back to the type they start from)", step.node)
                path.append(step)
                stack.append((step, self._built_from(step)))

    def ordered(self) -> list[Decl]:
        """User declarations, each after the ones it needs at class creation."""
        order: list[Decl] = []
        state: dict[str, int] = {}

        def needs(decl: Decl) -> Iterator[Decl | None]:
            yield from (self.decls.get(b.lower()) for b in decl.bases)
            yield from (self.decls.get(i.lower()) for i in decl.implements)
            members = [m.type for m in decl.members.values()]
            members += [p.type for p in decl.props.values()] + [m.returns for m in decl.methods.values()]
            members += [p.type for m in decl.methods.values() for p in m.params]
            # a method's ARRAY and VAR_STAT locals live in classes made before the block's
            members += [m.type for node in decl.method_nodes for block in node.declarations
                        if isinstance(block, (tf.VariableDeclarations, tf.StaticDeclarations)) for m in self._block_members(block)]
            for type_ in members:
                while type_ is not None and type_.kind in ("array", "pointer", "reference"):
                    # ARRAY[1..GVL_Param.cMax]: the bound reads the list's constant when the class is made
                    yield from (d for d in map(self.decls.get, sorted(type_.bound_names)) if d is not None and d.kind == "gvl")
                    type_ = type_.of
                if type_ is not None and type_.kind == "user":
                    yield self.by_python.get(type_.name)
            if decl.alias_of is not None and decl.alias_of.kind == "user":
                yield self.by_python.get(decl.alias_of.name)
            for member in decl.members.values():  # a VAR_EXTERNAL binds to its global when the class is made
                if member.section == "VAR_EXTERNAL" and member.st.lower() in self.globals:
                    yield self.by_python.get(self.globals[member.st.lower()][0])

        def visit(decl: Decl) -> None:
            key = decl.name
            if state.get(key) == 2 or decl.kind == "stdfb" or decl.library:
                return
            if state.get(key) == 1:
                return  # a cycle through a pointer or interface: annotations are strings, order does not matter
            state[key] = 1
            for dep in needs(decl):
                if dep is not None and dep is not decl:
                    visit(dep)
            state[key] = 2
            order.append(decl)

        for decl in self.decls.values():
            visit(decl)
        return order

    def translate(self) -> str:
        bind(self, self.libraries)
        collapse_namespaces(self.units, self.decls, self.globals)
        self.collect()
        self._refuse_keyword_names()
        self._refuse_self_built()
        rename_shadowed(self)
        self.resolve_members()
        align_prototype_names(self.decls)
        self.collect_named_programs()
        self.freeze()
        body: list[str] = []
        for decl in self.ordered():
            self.unit = decl.unit
            self.out = []
            self.preamble = []
            self.enter(decl.item)
            _WRITERS[decl.kind](self, decl)
            body.extend(self.preamble + ["", ""] + self.out)
        if self.named_programs:
            # P_Count.counter from another POU names the program's instance, as in ST: one per PROGRAM. A class
            # decorator makes it (as @gvl does), which mypy accepts where rebinding the class name is refused;
            # _emit_program writes it, since pass 1 knows these programs.
            self.need("typing", "TypeVar")
            body[:0] = ["", "", '_P = TypeVar("_P", bound=Program)', "", "",
                        "def _program_instance(cls: type[_P]) -> _P:",
                        '    """A PROGRAM other POUs read by name (P_Count.counter): as in ST, the name is its one instance."""',
                        "    return cls()"]
        header = ['"""Generated by iecoop.st from Structured Text; edit freely, it is plain iecoop code."""', "",
                  "from __future__ import annotations", ""]
        standard = [m for m in ("math", "typing") if m in self.imports]
        if "math" in self.imports:
            header.append("import math")
        if "typing" in self.imports:
            header.append(f"from typing import {', '.join(sorted(self.imports['typing']))}")
        if standard:
            header.append("")
        for module in sorted(m for m in self.imports if m not in standard):
            names = sorted(self.imports[module])
            line = f"from {module} import {', '.join(names)}"
            if len(line) > 110:
                header.append(f"from {module} import (")
                chunk = ""
                for name in names:
                    if len(chunk) + len(name) > 100:
                        header.append(f"    {chunk.rstrip()}")
                        chunk = ""
                    chunk += f"{name}, "
                header.append(f"    {chunk.rstrip()}")
                header.append(")")
            else:
                header.append(line)
        lines = header + body
        #: per line of the text, the ST (file, line) it was written for, or None
        self.origins = [origin_of(line) for line in lines for _ in line.split("\n")]
        return "\n".join(lines) + "\n"


#: Each kind of declaration -> the pass 2 writer of its class (or alias, or function).
_WRITERS: dict[str, Callable[[Translator, Decl], None]] = {
    "fb": Pous._emit_fb, "program": Pous._emit_program, "function": Pous._emit_function,
    "interface": Pous._emit_interface, "gvl": Pous._emit_gvl, "struct": Pous._emit_struct,
    "union": Pous._emit_union, "enum": Pous._emit_enum, "alias": Pous._emit_alias,
}


def translate_mapped(
    units: Sequence[Unit],
    externals: Sequence[str] = (),
    libraries: Sequence[BoundLibrary] = (),
    qualified_only: set[str] | None = None,
) -> tuple[str, list[tuple[str, str]], list[tuple[str, int] | None]]:
    """``translate`` and, per line of the text, the ST ``(file, line)`` it was written for (None: iecoop's own lines)."""
    translator = Translator(units, externals, libraries)
    text = translator.translate()
    names = [(d.kind, d.name) for d in translator.decls.values() if d.kind != "stdfb" and not d.library]
    if qualified_only is not None:
        qualified_only.update(d.st for d in translator.decls.values() if d.kind in ("gvl", "enum") and not d.library
                              and any(_QUALIFIED_ONLY.fullmatch(p) for p in _pragmas(translator, d)))
    return text, names, translator.origins


def translate(
    units: Sequence[Unit],
    externals: Sequence[str] = (),
    libraries: Sequence[BoundLibrary] = (),
    qualified_only: set[str] | None = None,
) -> tuple[str, list[tuple[str, str]]]:
    """The Python module text for ``units`` and the ``(kind, name)`` of each top-level ST name.

    ``libraries``: the libraries the source uses, their names resolved plain and qualified.
    ``qualified_only`` gets the ST names of the GVLs and enumerations marked ``{attribute 'qualified_only'}``
    (what a project using this source as a library must qualify).
    """
    text, names, _ = translate_mapped(units, externals, libraries, qualified_only)
    return text, names


def _pragmas(translator: Translator, decl: Decl) -> list[str]:
    """The pragmas of a declaration; a GVL's are those right above any of its VAR_GLOBAL blocks."""
    if decl.kind != "gvl":
        return translator._decl_pragmas(decl)
    found = []
    for block in decl.node:
        unit = decl.units.get(id(block), decl.unit)
        expected = block.meta.line if block.meta else None
        for token in sorted((t for t in unit.comments if expected is not None and t.line <= expected) if unit else (),
                            key=lambda t: -t.line):
            if expected is None or token.line < expected - 1 or not str(token).strip().startswith("{"):
                break
            found.append(str(token).strip())
            expected = token.line
    return found
