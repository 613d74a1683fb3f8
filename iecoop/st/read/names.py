"""ST names and the Python names they are written as (the naming rule, both ways)."""

from __future__ import annotations

import builtins
import functools
import keyword
import re
from typing import Any

from iecoop.st.language import is_reserved


# --- names -------------------------------------------------------------------------------------

#: The suffix and prefix of the naming rule (see ``python_name``).
NAME_SUFFIX = "_"
NAME_PREFIX = "st"
#: Names the generated code itself writes beside the user's: ``self``, a block's ``body``, FB_init's
#: PEP 8 inputs, a pointer's ``deref``, the modules it imports.
_GENERATED_NAMES = frozenset(("self", "cls", "body", "fb_init", "fb_reinit", "fb_exit", "init_retains", "in_copy_code",
                              "deref", "typed", "math", "copy", "typing", "iecoop", "Annotated", "TypeVar"))


@functools.cache
def reserved_names(attribute: bool = False) -> frozenset[str]:
    """Every Python name an ST name must not become: keywords, builtins and what the generated module uses.

    A name Python code reads bare (a POU, type, GVL or FUNCTION; a METHOD's or FUNCTION's input, output
    or local) must be none of Python's keywords and soft keywords, its builtins, the names the generated
    module may import (``iecoop``, ``iecoop.stdlib``, ``.functions``, ``.conversions``, ``.runtime``,
    ``iecoop.st.external``), the public attributes of iecoop's base classes and ``_GENERATED_NAMES``. A name read
    as an attribute (``self.x``: a variable of a block, STRUCT or GVL, a METHOD, PROPERTY or enumeration
    value) stands bare only in its class body, beside the section specifiers, types and literals
    of ``iecoop`` and ``iecoop.stdlib``: with ``attribute``, the builtins and the other modules stay
    free (a METHOD ``open``, a constant ``LIMIT``). Compared with case, as Python compares names:
    ``T`` is reserved (``T#5S``), ``t`` is not.
    """
    import iecoop
    import iecoop.conversions
    import iecoop.functions
    import iecoop.runtime
    import iecoop.stdlib

    names = {*keyword.kwlist, *_GENERATED_NAMES, *iecoop.__all__, *iecoop.stdlib.__all__}
    for base in (iecoop.FunctionBlock, iecoop.Program, iecoop.Struct, iecoop.Union, iecoop.GlobalVariables,
                 iecoop.Interface, iecoop.IecEnum):
        names.update(n for n in dir(base) if not n.startswith("_"))
    if not attribute:
        names.update(keyword.softkwlist, dir(builtins))
        for module in (iecoop.functions, iecoop.conversions, iecoop.runtime):
            names.update(module.__all__)
        names.add("external")  # iecoop.st's decorator of a FUNCTION without a body
    return frozenset(n for n in names if not n.startswith("_"))


_PREFIXED = re.compile(f"(?:{NAME_PREFIX})*_", re.IGNORECASE)


def python_name(name: str, attribute: bool = False) -> str:
    """The Python name of the ST name ``name``: itself, unless it could meet a Python or iecoop name.

    A name that is reserved (``reserved_names(attribute)``: ``attribute`` for a name only read as
    ``x.name``), or starts or ends with ``_``, gets ``_`` at its end,
    so it can be no keyword, builtin or generated name, and no other ST name's Python name (only these
    end with ``_``). If it starts with ``_`` (after any number of ``st``), it also gets ``st`` in front,
    so no ST name becomes a Python private (``_x``) or special (``__x__``) name. ``in`` is ``in_``,
    ``in_`` is ``in__``, ``_x`` is ``st_x_``, ``__del__`` is ``st__del___``; ``Speed`` is ``Speed``.

    One exception keeps the writer's names: ``TO_`` (how ``st.export`` writes a Python name that is an ST
    keyword) is ``TO`` again, since no ST name can be ``TO`` and no other name's image lacks the suffix.
    """
    stem = _keyword_stem(name, attribute)
    if stem is not None:
        return stem
    if name not in reserved_names(attribute) and not name.startswith("_") and not name.endswith("_"):
        return name
    return (NAME_PREFIX if _PREFIXED.match(name) else "") + name + NAME_SUFFIX


def field_name(name: str, type_: Any) -> str:
    """The Python name of a variable of a block or GVL: ``python_name``, with ``_`` at its end when it is the name
    of a type its own type's annotation names (``kitchen : kitchen;``), which the class body would read instead.
    ``type_`` is the variable's ``TypeRef`` (or None)."""
    python = python_name(name, attribute=True)
    annotation = type_.annotation() if type_ is not None else ""
    return python + NAME_SUFFIX if re.search(rf"(?<![\w.]){re.escape(python)}(?!\w)", annotation) else python


def _keyword_stem(name: str, attribute: bool) -> str | None:
    """``TO`` for ``TO_``: an ST keyword with one suffix, when the keyword itself is free in Python."""
    stem = name[: -len(NAME_SUFFIX)]
    if not name.endswith(NAME_SUFFIX) or not is_reserved(stem) or stem.endswith(NAME_SUFFIX) or stem.startswith("_"):
        return None
    return stem if stem not in reserved_names(attribute) else None


def st_keyword(st: str, python: str, comma: str = ", ") -> str:
    """``, st_name="in"`` where the naming rule renamed ``st`` to ``python``, else nothing."""
    return f'{comma}st_name="{st}"' if st != python else ""


def st_name_of(python: str) -> str:
    """The ST name whose Python name is ``python``: the inverse of ``python_name`` (only mapped names end with ``_``).

    ``in_`` is ``in``, ``st_x_`` is ``_x``, ``TO`` is ``TO_``, ``Speed`` is ``Speed``.
    """
    if not python.endswith(NAME_SUFFIX):
        return python + NAME_SUFFIX if is_reserved(python) else python
    name = python[: -len(NAME_SUFFIX)]
    if name[: len(NAME_PREFIX)].lower() == NAME_PREFIX and _PREFIXED.match(name, len(NAME_PREFIX)):
        return name[len(NAME_PREFIX):]
    return name


