"""The symbol table's lookups of bound libraries' names: plain, qualified, refused, and the imports they need.

A name bound from a library (``TON``, ``Tc2_Standard.TON``) is imported by the generated module once a
lookup finds it and the project has not declared the name itself; a refused name (ambiguous, qualified
only) raises its rule where it is used.
"""

from __future__ import annotations

import dataclasses
import types
from collections.abc import Callable
from typing import Any, Protocol, TypeVar

from iecoop.exceptions import DefinitionError
from iecoop.st.read.table import FrozenTableError

__all__ = ["BoundLibrary", "Lookup", "unknown_name"]

_V = TypeVar("_V")


class _Imported(Protocol):
    """A library declaration: the module the generated code imports it from, and how (``TON``, ``X as Y``)."""

    library: str
    import_spec: str


@dataclasses.dataclass(frozen=True)
class BoundLibrary:
    """A library a project uses: its namespace (``Tc2_Standard``, or ``TCU`` for a renamed one) and its module.

    ``qualified_only``: every name needs the namespace; ``qualified``: the ST names (lower case) of the
    GVLs and enumerations marked ``{attribute 'qualified_only'}``, whose variables and values need it.
    """

    namespace: str
    module: types.ModuleType
    title: str = ""
    qualified_only: bool = False
    qualified: frozenset[str] = frozenset()

    @property
    def import_from(self) -> str:
        return self.module.__name__

    def names(self) -> list[str]:
        """The ST names the library declares (its module's ``__all__``)."""
        listed = getattr(self.module, "__all__", None)
        if listed is None:
            raise DefinitionError(f"library {self.namespace}: module {self.import_from} has no __all__ listing its ST names")
        return [str(name) for name in listed]


class Lookup(dict[str, _V]):
    """A table of ST names (lower case) that notes which library declaration a lookup resolved to.

    A name bound from a library is imported by the generated module once a lookup finds it (and the
    project has not declared the name itself); a refused name (ambiguous, qualified only) raises its
    rule when looked up, so each use is reported at its own line.
    """

    def __init__(self) -> None:
        super().__init__()
        self.frozen = False
        #: key -> (the value bound from a library, the library declaration the generated code imports for it)
        self.bound: dict[str, tuple[Any, _Imported]] = {}
        #: key -> the rule that refuses the plain name
        self.refused: dict[str, str] = {}
        self.on_refused: Callable[[str], Exception] = DefinitionError
        self.imports: dict[str, set[str]] = {}
        #: ``tc2_standard.concat`` -> ``CONCAT``: a library's name for a function the translator has built in
        self.builtin: dict[str, str] = {}
        #: the namespaces of the bound libraries (lower case)
        self.namespaces: set[str] = set()
        #: id of a library declaration -> its library's namespace as the project spells it
        self.namespace_of: dict[int, str] = {}

    def freeze(self) -> None:
        """End of pass 1: the names are all known; a write raises ``FrozenTableError`` (lookups still note imports)."""
        self.frozen = True

    def _check_open(self, key: str) -> None:
        if getattr(self, "frozen", False):
            raise FrozenTableError(f"the symbol table is frozen after pass 1: the entry {key!r} cannot be written")

    def bind(self, key: str, value: _V, decl: _Imported) -> None:
        self._check_open(key)
        dict.__setitem__(self, key, value)
        self.bound[key] = (value, decl)

    def refuse(self, key: str, rule: str) -> None:
        self._check_open(key)
        if dict.__contains__(self, key):
            dict.__delitem__(self, key)
        self.refused[key] = rule

    def _found(self, key: str) -> _V:
        value = dict.__getitem__(self, key)
        bound = self.bound.get(key)
        if bound is not None and bound[0] is value:
            self.imports.setdefault(bound[1].library, set()).add(bound[1].import_spec)
        return value

    def __setitem__(self, key: str, value: _V) -> None:
        self._check_open(key)
        self.refused.pop(key, None)  # the project's own name comes first
        dict.__setitem__(self, key, value)

    def setdefault(self, key: str, default: _V) -> _V:
        """The project's value unless the project set one already: a library's gives way to it."""
        bound = self.bound.get(key)
        if dict.__contains__(self, key) and (bound is None or dict.__getitem__(self, key) is not bound[0]):
            return dict.__getitem__(self, key)
        self[key] = default
        return default

    def __contains__(self, key: object) -> bool:
        return dict.__contains__(self, key) or key in self.refused

    def __getitem__(self, key: str) -> _V:
        if not dict.__contains__(self, key) and key in self.refused:
            raise self.on_refused(self.refused[key])
        return self._found(key)

    def get(self, key: str, default: Any = None) -> Any:
        if dict.__contains__(self, key):
            return self._found(key)
        if key in self.refused:
            raise self.on_refused(self.refused[key])
        return default


def unknown_name(what: str, name: str, decls: Lookup[Any]) -> str:
    """The message for an unknown ``what`` (type, ...) ``name``; a qualified name says whether its namespace is bound."""
    namespace, _, last = name.rpartition(".")
    if not namespace:
        return f"unknown {what} {name!r}"
    if namespace.lower() in decls.namespaces:
        return f"unknown {what} {name!r}: library {namespace} declares no {last}"
    return (f"unknown {what} {name!r}: {namespace!r} is no namespace of a bound library "
            f"(the project's references and libraries= name them)")


def add_global(globals_: Lookup[Any], lists_of: dict[str, list[str]], list_name: str, value: Any, name: str) -> None:
    """A global's plain name: its list's, or refused where two lists declare it (each is reached as ``GVL_A.name``,
    as TwinCAT takes two lists of one name, ``{attribute 'qualified_only'}`` or not)."""
    key = name.lower()
    lists = lists_of.setdefault(key, [])
    if list_name not in lists:
        lists.append(list_name)
    if len(lists) == 1:
        globals_[key] = value
    else:
        globals_.refuse(key, f"global {name} is declared in {' and '.join(lists)}: name its list ({lists[0]}.{name})")
