"""Bound libraries: what a library module declares, as the declarations pass 1 uses.

A library is a Python module of iecoop classes whose ``__all__`` lists its ST names (iecoop's shipped
libraries, a user's module, or a folder of ST loaded with ``st.load``). Its names resolve plain
(``TON``) and qualified by the namespace the project gives it (``Tc2_Standard.TON``), ST's way:
case-insensitively, the project's own names first. A name two libraries both declare is ambiguous
when used plain; ``{attribute 'qualified_only'}`` (or ``QUALIFIED_ONLY = True`` in a Python module)
refuses the plain use. The generated Python imports what it uses from the library's module.
"""

from __future__ import annotations

import copy
import dataclasses
import enum
import inspect
import keyword
import os
import pathlib
import types
import typing
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import Any

import blark.transform as tf

from iecoop.exceptions import DefinitionError
from iecoop.metadata import Kind, iec_class, kind_of
from iecoop.parameters import parameter_sections
from iecoop.st.read.names import python_name
from iecoop.st.read.lookup import BoundLibrary, Lookup
from iecoop.st.read.parse import LibraryReference, Unit
from iecoop.st.read.symbols import Symbols
from iecoop.st.read.table import Callable_, Decl, Member, TypeRef
from iecoop.st.read.trees import signature

__all__ = ["bind", "collapse_namespaces", "library_folders", "rename_shadowed", "resolve"]

#: the ``st.load`` keyword and environment variable an unresolved reference's message points at
HOW_TO_RESOLVE = ("pass libraries={name: folder, .plcproj or module}, library_path=[folder, ...] "
                  "or set IECOOP_LIBRARY_PATH to folders holding <name>/ or <name>.plcproj")


# --- a module's declarations ---------------------------------------------------------------------

_KINDS = {Kind.FUNCTION_BLOCK: "fb", Kind.PROGRAM: "program", Kind.STRUCT: "struct", Kind.UNION: "union",
          Kind.INTERFACE: "interface", Kind.ENUM: "enum"}


def _kind(value: Any) -> str | None:
    """The Decl kind of what a library module lists, or None for what ST cannot name."""
    if isinstance(value, type):
        kind = kind_of(value)
        return _KINDS.get(kind) if kind is not None else None
    kind = kind_of(type(value))
    if kind is Kind.GVL:
        return "gvl"
    if kind is Kind.PROGRAM:
        return "program"
    if typing.get_origin(value) is typing.Annotated and any(type(m).__name__ == "Alias" for m in value.__metadata__):
        return "alias"
    if callable(value) and not isinstance(value, type):
        return "function"
    return None


class _Binder:
    """Makes the Decls of the bound libraries and registers their names in the symbol table."""

    def __init__(self, symbols: Symbols, libraries: Sequence[BoundLibrary]) -> None:
        self.symbols = symbols
        self.libraries = libraries
        #: id of a library class -> its Decl (types of members resolve through it)
        self.by_object: dict[int, Decl] = {}
        self.standard: dict[int, Decl] = {}
        #: namespace -> the declaration standing for a Python module's constants; plain name -> its namespace
        self.constants: dict[str, Decl] = {}
        self.constant_of: dict[str, str] = {}

    def run(self) -> None:
        import iecoop.functions as functions
        import iecoop.stdlib as stdlib


        symbols = self.symbols
        for decl in list(symbols.decls.values()):
            if decl.kind == "stdfb":
                self.standard[id(getattr(stdlib, decl.name))] = decl
        plain: dict[str, list[tuple[BoundLibrary, Decl]]] = {}
        made: list[tuple[BoundLibrary, Decl, Any]] = []
        for library in self.libraries:
            symbols.decls.namespaces.add(library.namespace.lower())
            for st_name in library.names():
                value = getattr(library.module, st_name, None)
                kind = _kind(value)
                if isinstance(value, (bool, int, float, str)) and not isinstance(value, enum.Enum):
                    self._constant(library, st_name, value)
                    continue
                if value is None or kind is None:
                    continue
                if kind == "function" and getattr(functions, st_name.upper(), None) is value:
                    # the translator writes the standard functions itself (typed by their operands)
                    symbols.decls.builtin[f"{library.namespace}.{st_name}".lower()] = st_name.upper()
                    continue
                found = self.standard.get(id(value)) or self.by_object.get(id(value))
                if found is not None:
                    decl = found
                else:
                    decl = Decl(kind, python_name(st_name), st=st_name)
                    decl.library = library.import_from
                    symbols.decls.namespace_of[id(decl)] = library.namespace
                    self.by_object[id(value)] = decl
                    made.append((library, decl, value))
                self._register(f"{library.namespace}.{st_name}".lower(), decl)
                plain.setdefault(st_name.lower(), []).append((library, decl))
        self._python_names(made)
        for _library, decl, value in made:
            self._fill(decl, value)
        for key, candidates in plain.items():
            self._plain(key, candidates)

    def _constant(self, library: BoundLibrary, st_name: str, value: bool | int | float | str) -> None:
        """A module-level constant (``cMaxAxes = 8``): a global read as ``<module>.cMaxAxes``, plain or qualified."""

        package, _, leaf = library.import_from.rpartition(".")
        if not package:
            raise DefinitionError(f"library {library.namespace}: the constant {st_name} of module {library.import_from}, "
                                  "which is in no package, cannot be imported by name (move the module into a package, "
                                  "or the constant into a GVL)")
        holder = self.constants.get(library.namespace)
        if holder is None:
            holder = self.constants[library.namespace] = Decl("gvl", f"lib_{library.namespace}", st=library.namespace)
            holder.library, holder.import_spec = package, f"{leaf} as lib_{library.namespace}"
        type_ = (TypeRef("elem", "BOOL") if isinstance(value, bool) else TypeRef("elem", "LINT") if isinstance(value, int)
                 else TypeRef("elem", "LREAL") if isinstance(value, float) else TypeRef("string", "STRING", length=str(max(len(value), 1))))
        member = Member(st_name, type_, "VAR_GLOBAL", st=st_name)
        globals_ = self.symbols.globals
        globals_.bind(f"{library.namespace}.{st_name}".lower(), (holder.name, member), holder)
        key = st_name.lower()
        if library.qualified_only:
            globals_.refuse(key, f"{st_name} needs its namespace: library {library.namespace} is qualified_only "
                                 f"(write {library.namespace}.{st_name})")
        elif key in self.constant_of and self.constant_of[key] != library.namespace:
            globals_.refuse(key, f"{st_name} is ambiguous: {self.constant_of[key]}.{st_name} and {library.namespace}.{st_name} "
                                 "both declare it (qualify it with the library's namespace)")
        else:
            self.constant_of[key] = library.namespace
            globals_.bind(key, (holder.name, member), holder)

    def _register(self, key: str, decl: Decl) -> None:
        if decl.library:
            self.symbols.decls.bind(key, decl, decl)
        else:
            dict.__setitem__(self.symbols.decls, key, decl)

    def _python_names(self, made: list[tuple[BoundLibrary, Decl, Any]]) -> None:
        """Two libraries' declarations of one name get their namespace in front (``TCU_FB_TestSuite``)."""
        counts: dict[str, int] = {}
        for _library, decl, _value in made:
            counts[decl.name] = counts.get(decl.name, 0) + 1
        for library, decl, value in made:
            if counts[decl.name] > 1 or decl.name in self.symbols.by_python:
                decl.name = f"{library.namespace}_{decl.name}"
            self._import_as(decl, decl.st)
            self.symbols.by_python.bind(decl.name, decl, decl)

    @staticmethod
    def _import_as(decl: Decl, attribute: str) -> None:
        decl.import_spec = attribute if attribute == decl.name else f"{attribute} as {decl.name}"

    def _plain(self, key: str, found: list[tuple[BoundLibrary, Decl]]) -> None:
        """The plain name: one library's declaration, or refused (ambiguous, qualified only)."""
        decls = {id(d): (lib, d) for lib, d in found}
        if len(decls) > 1:
            names = " and ".join(f"{lib.namespace}.{d.st}" for lib, d in decls.values())
            self.symbols.decls.refuse(key, f"{found[0][1].st} is ambiguous: {names} both declare it "
                                           "(qualify it with the library's namespace)")
            return
        library, decl = found[0]
        if library.qualified_only:
            self.symbols.decls.refuse(key, f"{decl.st} needs its namespace: library {library.namespace} is "
                                           f"qualified_only (write {library.namespace}.{decl.st})")
            return
        self._register(key, decl)
        if decl.kind not in ("gvl", "enum"):
            return
        globals_, values = self.symbols.globals, self.symbols.enum_values
        for name in [m.st for m in decl.members.values()] if decl.kind == "gvl" else decl.values:
            if key in library.qualified:
                what = "GVL" if decl.kind == "gvl" else "enumeration"
                (globals_ if decl.kind == "gvl" else values).refuse(
                    name.lower(), f"{name} needs its {what}'s name: {what} {library.namespace}.{decl.st} "
                                  f"is qualified_only (write {decl.st}.{name})")
            elif decl.kind == "gvl":
                globals_.bind(name.lower(), (decl.name, decl.members[name.lower()]), decl)
            else:
                values.bind(name.lower(), (decl.name, python_name(name, attribute=True)), decl)

    # --- members ---

    def _fill(self, decl: Decl, value: Any) -> None:
        """What pass 1 knows of a library name: a FUNCTION's signature, an alias's target, an enumeration's
        values, or a class's lineage, variables, METHODs and PROPERTYs."""
        if decl.kind == "function":
            decl.methods["()"] = Callable_(decl.name, self._returns(value), self._params(value), st=decl.st)
        elif decl.kind == "alias":
            decl.alias_of = self._annotation_type(value)
        elif decl.kind == "enum":
            record = iec_class(value)
            spelled = dict(record.value_names) if record is not None else {}
            decl.values = [spelled.get(item.name, item.name) for item in value]
        else:
            cls = value if isinstance(value, type) else type(value)
            self._fill_lineage(decl, cls)
            self._fill_members(decl, cls)

    def _fill_lineage(self, decl: Decl, cls: type) -> None:
        """EXTENDS and IMPLEMENTS of a library class, from the library classes in its MRO."""
        for base in cls.__mro__[1:]:
            base_decl = self.by_object.get(id(base)) or self.standard.get(id(base))
            if base_decl is not None:
                # qualified, so a project name that hides the base's plain name does not change the lineage
                name = f"{self.symbols.decls.namespace_of[id(base_decl)]}.{base_decl.st}" if base_decl.library else base_decl.st
                (decl.implements if base_decl.kind == "interface" and decl.kind != "interface" else decl.bases).append(name)
                if base_decl.kind != "interface":
                    break

    def _fill_members(self, decl: Decl, cls: type) -> None:
        """The variables, METHODs and PROPERTYs of a library class, by their ST names."""
        record = iec_class(cls)
        if record is None:
            return
        for field in record.layout.fields if record.layout is not None else ():
            section = str(field.section.value if hasattr(field.section, "value") else field.section)
            decl.members[field.st_name.lower()] = Member(field.name, self._info_type(field.info), section, st=field.st_name)
        for name, member in record.members.items():
            st = member.st_name or name
            function = getattr(cls, name, None)
            if member.kind == "method" and function is not None:
                decl.methods[st.lower()] = Callable_(name, self._returns(function), self._params(function, skip_self=True), st=st)
            elif member.kind == "property":
                getter = getattr(inspect.getattr_static(cls, name, None), "fget", None)
                type_ = self._returns(getter) if getter is not None else None
                decl.props[st.lower()] = Member(name, type_, "PROPERTY", st=st)

    def _params(self, function: Any, skip_self: bool = False) -> list[Member]:

        sections = parameter_sections(function)
        hints = self._hints(function)
        members = []
        try:
            params = list(inspect.signature(inspect.unwrap(function)).parameters.values())
        except (TypeError, ValueError):
            return []
        for param in params[1 if skip_self else 0:]:
            if param.kind in (param.VAR_POSITIONAL, param.VAR_KEYWORD):
                continue
            spec = sections.get(param.name)
            section = str(spec.section.value) if spec is not None else "VAR_INPUT"
            annotation = hints.get(param.name)
            type_ = self._annotation_type(annotation) if annotation is not None else None
            if spec is not None and type_ is not None and type_.kind == "pointer" and type_.of is not None:
                type_ = type_.of  # an output or in-out reaches its variable through a pointer
            # A Python keyword is spelled with a trailing underscore (in_): ST calls it by its own name (in := ...).
            st = param.name[:-1] if param.name.endswith("_") and keyword.iskeyword(param.name[:-1]) else param.name
            members.append(Member(param.name, type_, section, st=st))
        return signature(members)

    def _returns(self, function: Any) -> TypeRef | None:
        annotation = self._hints(function).get("return")
        return self._annotation_type(annotation) if annotation is not None else None

    @staticmethod
    def _hints(function: Any) -> dict[str, Any]:
        try:
            return typing.get_type_hints(inspect.unwrap(function), include_extras=True)
        except Exception:  # an annotation the module cannot resolve: the parameter stays untyped
            return {}

    def _annotation_type(self, annotation: Any) -> TypeRef | None:
        from iecoop.memory.typeinfo import resolve_type

        try:
            info = resolve_type(annotation, "library")
        except (DefinitionError, TypeError, ValueError):
            return None
        return self._info_type(info)

    def _info_type(self, info: Any) -> TypeRef | None:

        for attribute in ("cls", "enum_cls", "iface"):
            target = getattr(info, attribute, None)
            if target is not None:
                decl = self.by_object.get(id(target)) or self.standard.get(id(target))
                return TypeRef("user", decl.name) if decl is not None else None
        record = getattr(info, "record", None)
        length = getattr(info, "length", None)
        if record is not None and length is not None:
            return TypeRef("string", str(record.name), length=str(length))
        if record is not None:
            return TypeRef("elem", str(record.name))
        inner = getattr(info, "target", None) or getattr(info, "element", None)
        for kind, name in (("pointer", "POINTER_TO"), ("reference", "REFERENCE_TO")):
            if type(info).__name__.lower().startswith(kind):
                of = self._info_type(inner) if inner is not None else None
                return TypeRef(kind, name, of=of) if of is not None else None
        return None


def bind(symbols: Symbols, libraries: Sequence[BoundLibrary]) -> None:
    """Register what ``libraries`` declare in ``symbols`` (qualified and plain), before the project's names."""
    for table in (symbols.decls, symbols.by_python, symbols.globals, symbols.enum_values):
        table.on_refused = symbols.fail
        table.imports = symbols.imports
    _Binder(symbols, libraries).run()


def rename_shadowed(symbols: Symbols) -> None:
    """A library declaration whose Python name the project's own declaration took gets its namespace in front."""
    for key, (value, _) in list(symbols.by_python.bound.items()):
        decl: Decl = value
        if dict.get(symbols.by_python, key) is decl:
            continue
        namespace = symbols.decls.namespace_of[id(decl)]
        attribute = decl.import_spec.split(" as ")[0]
        decl.name = f"{namespace}_{attribute}"
        _Binder._import_as(decl, attribute)
        symbols.by_python.bind(decl.name, decl, decl)
        for table in (symbols.globals, symbols.enum_values):
            for bound_key, (entry, owner) in list(table.bound.items()):
                if owner is decl:  # (list name, member) and (enum name, value) name the class
                    table.bind(bound_key, (value.name, entry[1]), decl)


# --- qualified names in expressions ------------------------------------------------------------------


def collapse_namespaces(units: Iterable[Unit], decls: Lookup[Any], globals_: Lookup[Any]) -> None:
    """``Lib.F_Add(1)``, ``Lib.GVL_C.cMax``: the namespace and the name it qualifies become one name, ``Lib.F_Add``.

    blark reads a qualified name in an expression as a variable ``Lib`` and its field; the symbol table
    knows the qualified name, so the two parts become one (a standard function the translator has built
    in, ``Tc2_Standard.LEN``, becomes ``LEN``). Only names a bound library declares are joined, so a
    variable named like a namespace keeps its fields.
    """
    namespaces: dict[str, dict[str, str | None]] = {}
    for key in [*decls.bound, *decls.builtin, *globals_.bound]:
        namespace, _, name = key.rpartition(".")
        if namespace:
            namespaces.setdefault(namespace, {})[name] = decls.builtin.get(key)
    if not namespaces:
        return
    for unit in units:
        if not any(_qualified(node, namespaces) for _, _, node in _slots(unit.tree)):
            continue
        unit.tree = copy.deepcopy(unit.tree)  # parsed trees are cached and shared: change a copy
        for holder, key, node in _slots(unit.tree):
            declared = _qualified(node, namespaces)
            if declared is None:
                continue
            head, field = node.name, node.elements[0].field
            token = head.name
            spelled = declared[str(field.name).lower()] or f"{head.name}.{field.name}"
            joined = token.update(value=spelled) if hasattr(token, "update") else spelled
            name = tf.SimpleVariable(name=joined, dereferenced=field.dereferenced)
            name.meta = head.meta
            if len(node.elements) == 1 and not node.dereferenced:
                if isinstance(holder, list):
                    holder[key] = name
                else:
                    setattr(holder, str(key), name)
            else:
                node.name = name
                node.elements = node.elements[1:]


def _qualified(node: Any, namespaces: dict[str, dict[str, str | None]]) -> dict[str, str | None] | None:
    """The names of the namespace ``node`` starts with, when it is ``Namespace.Name...`` of a bound library."""
    if not isinstance(node, tf.MultiElementVariable) or not node.elements:
        return None
    head, first = node.name, node.elements[0]
    if not isinstance(head, tf.SimpleVariable) or not isinstance(first, tf.FieldSelector):
        return None
    declared = namespaces.get(str(head.name).lower())
    field = first.field
    if declared is None or not isinstance(field, tf.SimpleVariable) or str(field.name).lower() not in declared:
        return None
    return declared


def _slots(tree: Any) -> Iterator[tuple[Any, Any, Any]]:
    """Every node below ``tree`` with the object that holds it and its field name or index there."""
    pending: list[tuple[Any, Any, Any]] = [(None, None, tree)]
    while pending:
        holder, key, current = pending.pop()
        yield holder, key, current
        if dataclasses.is_dataclass(current) and not isinstance(current, type):
            pending.extend((current, f.name, getattr(current, f.name)) for f in dataclasses.fields(current) if f.name != "meta")
        elif isinstance(current, list):
            pending.extend((current, index, item) for index, item in enumerate(current))


# --- resolving a project's references -----------------------------------------------------------------

#: what ``libraries=`` may map a name to: a folder or ``.plcproj`` of ST, or a module of iecoop classes
LibrarySource = typing.Union[str, "os.PathLike[str]", types.ModuleType]
#: loads a folder or ``.plcproj`` of ST as a library module (``st.load`` with the same search settings)
Loader = Callable[[pathlib.Path], types.ModuleType]


def library_folders(library_path: Iterable[str | os.PathLike[str]] | None) -> list[pathlib.Path]:
    """The folders searched for libraries: ``library_path``, then those of ``IECOOP_LIBRARY_PATH``."""
    folders = [pathlib.Path(p) for p in library_path or ()]
    folders += [pathlib.Path(p) for p in os.environ.get("IECOOP_LIBRARY_PATH", "").split(os.pathsep) if p]
    return folders


def _in_folder(folder: pathlib.Path, name: str) -> pathlib.Path | None:
    """``<name>.plcproj``, ``<name>/<name>.plcproj`` or the folder ``<name>/`` (names compared case-insensitively)."""
    if not folder.is_dir():
        return None
    lowered = name.lower()
    for child in sorted(folder.iterdir()):
        if child.name.lower() == f"{lowered}.plcproj" and child.is_file():
            return child
    for child in sorted(folder.iterdir()):
        if child.name.lower() == lowered and child.is_dir():
            inner = _in_folder(child, name)
            return inner if inner is not None and inner.suffix == ".plcproj" else child
    return None


def resolve(
    references: Sequence[LibraryReference],
    libraries: typing.Mapping[str, LibrarySource] | None,
    library_path: Iterable[str | os.PathLike[str]] | None,
    loader: Loader,
) -> list[BoundLibrary]:
    """The libraries a source uses: its references, and every entry of ``libraries=``, each found and loaded.

    A reference is looked up in ``libraries=`` (by title or namespace), then in ``library_path``, then in
    ``IECOOP_LIBRARY_PATH``, then among the libraries iecoop ships; one that is nowhere is a DefinitionError
    naming the ``.plcproj``, the title, version and company, and how to provide it.
    """
    from iecoop.libraries import known, module_of

    given = {str(key).lower(): value for key, value in (libraries or {}).items()}
    folders = library_folders(library_path)
    bound: list[BoundLibrary] = []
    used: set[str] = set()
    for reference in references:
        value = given.get(reference.name.lower())
        key = reference.name.lower()
        if value is None and reference.namespace.lower() in given:
            key = reference.namespace.lower()
            value = given[key]
        used.add(key)
        module: types.ModuleType | None = None
        if value is not None:
            module = _module(value, loader, reference.name)
        else:
            for folder in folders:
                found = _in_folder(folder, reference.name)
                if found is not None:
                    module = loader(found)
                    break
        if module is None:
            shipped = known(reference.name)
            if shipped is not None:
                try:
                    module = module_of(shipped)
                except ImportError:
                    module = None
        if module is None:
            version = f", version {reference.version}" if reference.version else ""
            company = f" ({reference.company})" if reference.company else ""
            raise DefinitionError(f"{reference.where}: library {reference.name}{version}{company} is not found: {HOW_TO_RESOLVE}")
        bound.append(_bound(reference.namespace, module, reference.name))
    for key, value in (libraries or {}).items():
        if str(key).lower() not in used:
            bound.append(_bound(str(key), _module(value, loader, str(key)), str(key)))
    return bound


def _module(value: LibrarySource, loader: Loader, name: str) -> types.ModuleType:
    if isinstance(value, types.ModuleType):
        return value
    if isinstance(value, (str, os.PathLike)):
        path = pathlib.Path(value)
        if not path.exists():
            raise DefinitionError(f"library {name}: {str(path)!r} does not exist (libraries= maps a name to a folder, "
                                  ".plcproj or module)")
        return loader(path)
    raise DefinitionError(f"library {name}: libraries= maps a name to a folder, .plcproj or module, got {type(value).__name__}")


def _bound(namespace: str, module: types.ModuleType, title: str) -> BoundLibrary:
    qualified = frozenset(str(n).lower() for n in getattr(module, "__qualified_only__", ()))
    return BoundLibrary(namespace, module, title, bool(getattr(module, "QUALIFIED_ONLY", False)), qualified)
