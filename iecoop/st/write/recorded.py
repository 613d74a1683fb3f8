"""What a loaded object's declaration says that its Python class does not hold, so the writer keeps it.

A module made by ``st.load`` records the source of each object (:mod:`iecoop.st.read.origin`). An object
changed in Python, or exported in another format than it was read in, goes through the writer, which
works from the class: the class knows ``bounds=(1, 8)``, not that the ST said ``1..GVL_Param.cMaxAlarms``;
it holds no ``AT %I*``; an enumeration's ``{attribute 'strict'}`` is nothing in Python. :func:`recorded`
reads those facts once from the parse of the recorded source (blark's nodes, never the text) and hands
them to the writer as a :class:`Declared` per object.
"""

from __future__ import annotations

import dataclasses
import pathlib
import types
from collections.abc import Iterable, Mapping
from typing import Any

__all__ = ["Bound", "Declared", "recorded"]


@dataclasses.dataclass(frozen=True)
class Bound:
    """One dimension of an ARRAY as the source wrote it: the texts of its bounds and their values."""

    low: str
    high: str
    values: tuple[int, int]


@dataclasses.dataclass(frozen=True)
class Declared:
    """The pragmas and comments that head an object, and its variables' ``AT`` addresses and ARRAY bounds."""

    #: the pragmas and comments before the declaration, as written (``{attribute 'strict'}``, ``// ...``)
    head: tuple[str, ...] = ()
    #: the names of the attributes those pragmas set (``qualified_only``, ``strict``, ``to_string``...)
    attributes: frozenset[str] = frozenset()
    #: ``AT`` address by variable name in lower case (``%I*``, ``%QX0.1``)
    locations: Mapping[str, str] = dataclasses.field(default_factory=dict)
    #: ARRAY bounds by variable name in lower case, one :class:`Bound` per dimension
    bounds: Mapping[str, tuple[Bound, ...]] = dataclasses.field(default_factory=dict)
    #: read from an ST source (its head is the whole head), not from a Python class's own source
    from_st: bool = True
    #: by variable name in lower case: the pragmas and comments on the lines before its declaration, and the
    #: comment after it on its line (``{attribute 'TcLinkTo' := '...'}``, ``// the lamp``)
    notes: Mapping[str, tuple[tuple[str, ...], str]] = dataclasses.field(default_factory=dict)

    def dimensions(self, name: str, values: tuple[tuple[int, int], ...]) -> tuple[Bound, ...] | None:
        """The recorded bounds of variable ``name`` when they still give ``values`` (the class's), else None."""
        found = self.bounds.get(name.lower())
        return found if found is not None and tuple(b.values for b in found) == values else None


def recorded(module: types.ModuleType, names: Iterable[str]) -> dict[str, Declared]:
    """The :class:`Declared` of each object ``names`` (ST names) of a module ``st.load`` made, by lower-case
    name; an object whose source is no longer what was read (the file changed since) is left out."""
    sources: Mapping[str, Any] = getattr(module, "__st_sources__", None) or {}
    found: dict[str, Declared] = {}
    for name in names:
        origin = sources.get(name)
        item = _item(origin, name) if origin is not None else None
        if item is not None:
            found[name.lower()] = _declared(item, module)
    return found


def _item(origin: Any, name: str) -> Any:
    """blark's node of object ``name`` in its recorded source, or None."""
    from iecoop.st.read.origin import object_name
    from iecoop.st.read.parse import parse_sources

    if origin.format in ("twincat", "plcopen"):
        # a file of its own (TwinCAT XML, a PLCopen export): parsed again as the loader parsed it
        path = pathlib.Path(origin.file)
        if not path.is_file() or path.read_bytes() != origin.text:
            return None
        units = parse_sources(path)
    else:
        units = parse_sources(origin.text.decode("utf-8", "replace"))
    for unit in units:
        for item in getattr(unit.tree, "items", ()):
            if str(object_name(item) or "").lower() == name.lower():
                return item
    return None


def _declared(item: Any, module: types.ModuleType) -> Declared:
    # The reader's own mark of a global list's name in flat text (``// GVL GVL_IO``) is the writer's to write.
    from iecoop.st.read.origin import object_name

    mark = f"// GVL {object_name(item)}"
    head = tuple(str(token) for token in getattr(getattr(item, "meta", None), "comments", None) or () if str(token).strip() != mark)
    attributes = frozenset(name for token in getattr(getattr(item, "meta", None), "comments", None) or ()
                           if getattr(token, "type", "") == "PRAGMA" and (name := _attribute(str(token))))
    locations: dict[str, str] = {}
    bounds: dict[str, tuple[Bound, ...]] = {}
    notes: dict[str, tuple[tuple[str, ...], str]] = {}
    for names, location, init, node in _variables(item):
        found = _notes(node)
        if found != ((), "") and names:
            notes[names[0].lower()] = found
        for variable in names:
            if location is not None:
                locations[variable.lower()] = str(location)
            dims = _dimensions(init, module)
            if dims is not None:
                bounds[variable.lower()] = dims
    return Declared(head, attributes, locations, bounds, notes=notes)


def _notes(node: Any) -> tuple[tuple[str, ...], str]:
    """The pragmas and comments blark gave a declaration: those on lines before it, and the one on its last line."""
    meta = getattr(node, "meta", None)
    line, end = getattr(meta, "line", None), getattr(meta, "end_line", None)
    tokens = getattr(meta, "comments", None) or ()
    if not isinstance(line, int) or not isinstance(end, int):
        return (), ""
    before = tuple(str(t) for t in tokens if isinstance(getattr(t, "line", None), int) and t.line < line)
    after = [str(t) for t in tokens if getattr(t, "line", None) == end and getattr(t, "type", "") == "SINGLE_LINE_COMMENT"]
    return before, after[0] if len(after) == 1 else ""


def _attribute(pragma: str) -> str:
    """The name an ``{attribute 'name'}`` pragma (as the reader gave it) sets, or ``""`` for another pragma."""
    words = pragma.strip("{} \t").split(None, 1)
    if len(words) == 2 and words[0].lower() == "attribute":
        return words[1].split()[0].strip("'\"")
    return ""


def _variables(node: Any) -> Iterable[tuple[list[str], Any, Any, Any]]:
    """(names, location, init, declaration node) of every variable declared in ``node`` (a POU, a GVL, a
    STRUCT), not in its METHODs or body."""
    from blark import transform as tf

    if isinstance(node, (tf.StatementList, tf.Method, tf.Property, tf.Action)):
        return
    spec = getattr(node, "spec", None)
    if isinstance(node, tf.GlobalVariableDeclaration) and isinstance(spec, tf.GlobalVariableSpec):
        yield [str(v) for v in spec.variables], spec.location, node.init, node
        return
    declared = getattr(node, "variables", None)
    if isinstance(declared, list) and declared and all(isinstance(v, tf.DeclaredVariable) for v in declared):
        for index, variable in enumerate(declared):
            yield [str(variable.variable.name)], variable.location, getattr(node, "init", None), node if index == 0 else None
        return
    for child in _children(node):
        yield from _variables(child)


def _children(node: Any) -> Iterable[Any]:
    if isinstance(node, list):
        yield from node
    elif dataclasses.is_dataclass(node):
        for field in dataclasses.fields(node):
            if field.name != "meta":
                yield getattr(node, field.name)


def _dimensions(init: Any, module: types.ModuleType) -> tuple[Bound, ...] | None:
    """The bounds of an ARRAY declaration's outer dimensions, each with its value; None where one has none."""
    from blark import transform as tf

    spec = getattr(init, "spec", None)
    if not isinstance(spec, tf.ArraySpecification):
        return None
    dims: list[Bound] = []
    for subrange in spec.subranges:
        if not isinstance(subrange, tf.PartialSubrange):
            return None
        low, high = _value(subrange.start, module), _value(subrange.stop, module)
        if low is None or high is None:
            return None
        dims.append(Bound(str(subrange.start), str(subrange.stop), (low, high)))
    return tuple(dims)


def _value(node: Any, module: types.ModuleType) -> int | None:
    """The value of a constant bound: an integer, ``GVL.constant``, and ``+ - *`` of those."""
    from blark import transform as tf

    if isinstance(node, tf.Integer):
        try:
            return int(str(node.value).replace("_", ""), 0) if "#" not in str(node.value) else None
        except ValueError:
            return None
    if isinstance(node, tf.UnaryOperation) and str(node.op) == "-":
        inner = _value(node.expr, module)
        return None if inner is None else -inner
    if isinstance(node, tf.BinaryOperation) and str(node.op) in ("+", "-", "*"):
        left, right = _value(node.left, module), _value(node.right, module)
        if left is None or right is None:
            return None
        return {"+": left + right, "-": left - right, "*": left * right}[str(node.op)]
    if isinstance(node, tf.MultiElementVariable) and len(node.elements) == 1 and isinstance(node.elements[0], tf.FieldSelector):
        holder = _member(module, str(node.name.name))
        value = _member(holder, str(node.elements[0].field.name)) if holder is not None else None
        return value if type(value) is int else None
    return None


def _member(owner: Any, name: str) -> Any:
    """``owner``'s attribute ``name``, the case ST ignores ignored."""
    found = getattr(owner, name, None)
    if found is not None:
        return found
    key = name.lower()
    return next((getattr(owner, n) for n in dir(owner) if n.lower() == key), None)


def declared_in_python(cls: Any, exported: frozenset[Any]) -> Declared | None:
    """The ARRAY bounds a Python class writes with a constant of a global list (``VAR(bounds=(1,
    GVL_Param.cMax))``), read from the class's syntax tree: ST keeps the name where the list is in the
    export (``exported``: the GVL classes written with it). None when there is none or no source."""
    import sys

    module = sys.modules.get(getattr(cls, "__module__", "") or "")
    names = vars(module) if module is not None else {}
    bounds: dict[str, tuple[Bound, ...]] = {}
    for name, given in _bounds_given(cls):
        dims = _named_dimensions(given, names, exported)
        if dims is not None:
            bounds[name.lower()] = dims
    return Declared(bounds=bounds, from_st=False) if bounds else None


def _bounds_given(cls: Any) -> list[tuple[str, list[Any]]]:
    """(variable, the expressions of its ``bounds=``) of each variable of ``cls``'s own source."""
    import ast
    import inspect
    import textwrap

    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(cls)))
    except (OSError, TypeError, SyntaxError):
        return []
    body = tree.body[0].body if tree.body and isinstance(tree.body[0], ast.ClassDef) else []
    found = []
    for stmt in body:
        if isinstance(stmt, ast.AnnAssign) and isinstance(stmt.target, ast.Name) and isinstance(stmt.value, ast.Call):
            given = next((k.value for k in stmt.value.keywords if k.arg == "bounds"), None)
            if isinstance(given, ast.Tuple) and given.elts and not len(given.elts) % 2:
                found.append((stmt.target.id, list(given.elts)))
    return found


def _named_dimensions(given: list[Any], names: Mapping[str, Any], exported: frozenset[Any]) -> tuple[Bound, ...] | None:
    """The dimensions of ``bounds=`` pairs when every bound has an ST text and one of them is a name."""
    texts = [_bound_text(node, names, exported) for node in given]
    known = [t for t in texts if t is not None]
    if len(known) != len(texts) or all(text == str(value) for text, value in known):
        return None
    return tuple(Bound(known[i][0], known[i + 1][0], (known[i][1], known[i + 1][1])) for i in range(0, len(known), 2))


def _bound_text(node: Any, names: Mapping[str, Any], exported: frozenset[Any]) -> tuple[str, int] | None:
    """(the ST text, the value) of a bound: an integer, or a constant of a global list that is exported."""
    import ast

    from iecoop.metadata import field_record, kind_of

    if isinstance(node, ast.Constant) and type(node.value) is int:
        return str(node.value), node.value
    if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
        holder = names.get(node.value.id)
        if kind_of(type(holder)) == "gvl" and type(holder) in exported:
            try:
                record = field_record(type(holder), node.attr)
            except KeyError:
                return None
            value = getattr(holder, node.attr)
            if record.spec.constant and type(value) is int:
                return f"{type(holder).__name__}.{record.st_name}", value
    return None
