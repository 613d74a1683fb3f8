"""Questions asked of blark trees and literals, shared by the phases (no state, no output)."""

from __future__ import annotations

import dataclasses
import json
import re
import struct
from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING, Any

import blark.transform as tf

from iecoop.st.language import APP_INFO_MEMBERS, TASK_INFO_MEMBERS

if TYPE_CHECKING:  # symbols imports this module
    from iecoop.st.read.table import Member

VISIBILITY = tf.AccessSpecifier.public | tf.AccessSpecifier.private | tf.AccessSpecifier.protected | tf.AccessSpecifier.internal


def structure_elements(value: Any) -> list[tuple[str | None, Any]] | None:
    """``(name, value)`` of each element of a structure initialiser, or None if ``value`` is not one.

    blark reads a one-element initialiser, ``(x := 1)``, as a parenthesised assignment, and
    inside an array initialiser may read ``(a := 1, b := 2, c := 3)`` as ``a := [1, b := 2], c := 3``.
    """
    if isinstance(value, tf.StructureInitialization):
        found: list[tuple[str | None, Any]] = []
        for element in value.elements:
            found += misread_elements(str(element.name) if element.name is not None else None, element.value)
        return found
    inner = value.expr if isinstance(value, tf.ParenthesizedExpression) else None
    if isinstance(inner, tf.BinaryOperation) and str(inner.op) == ":=" and isinstance(inner.left, tf.SimpleVariable):
        return [(str(inner.left.name), inner.right)]
    return None


def misread_elements(name: str | None, value: Any) -> list[tuple[str | None, Any]]:
    """``name := value`` of a structure initialiser, split again where blark read the next elements into ``value``
    (with four or more elements, as bare array initialisers nested in one another)."""
    items = list(_bare_items(value.elements)) if isinstance(value, tf.ArrayInitialization) and not value.brackets else []
    rest = items[1:]
    if len(items) > 1 and items[0].count is None and all(
        item.count is None and isinstance(item.element, tf.BinaryOperation) and str(item.element.op) == ":="
        and isinstance(item.element.left, tf.SimpleVariable) for item in rest
    ):
        return [(name, items[0].element)] + [(str(item.element.left.name), item.element.right) for item in rest]
    return [(name, value)]


def _bare_items(items: Sequence[Any]) -> Iterator[Any]:
    """The elements of a bare array initialiser, those of a bare one nested in it in its place."""
    for item in items:
        if item.count is None and isinstance(item.element, tf.ArrayInitialization) and not item.element.brackets:
            yield from _bare_items(item.element.elements)
        else:
            yield item


def exact_real(code: str) -> bool:
    """Whether ``code`` is a number literal that a REAL (32-bit) holds exactly: no TO_REAL needed."""
    try:
        number = float(code)
    except ValueError:
        return False
    return bool(struct.unpack("<f", struct.pack("<f", number))[0] == number)


VISIBILITY = tf.AccessSpecifier.public | tf.AccessSpecifier.private | tf.AccessSpecifier.protected | tf.AccessSpecifier.internal


def flag_keywords(flags: Any, kind: Any, names: Sequence[str]) -> list[str]:
    """``name=True`` for each of ``names`` set in blark's ``flags`` of enum ``kind`` (``CONSTANT RETAIN`` ...)."""
    if flags is None:
        return []
    return [f"{name}=True" for name in names if flags & getattr(kind, name)]


def accessor_access(node: Any) -> Any:
    """The access of one PROPERTY accessor: its own specifier, where it has one, in place of the property's.

    TwinCAT keeps an accessor's specifier at the head of the accessor's declaration, so the flat form
    reads ``PROPERTY PUBLIC Capacity : REAL PRIVATE`` (blark's ``access_override``); ABSTRACT and
    FINAL stay those of the property.
    """
    own = node.access_override
    if own is None:
        return node.access
    kept = node.access & ~VISIBILITY if node.access is not None else tf.AccessSpecifier(0)
    return kept | own


def is_zero(node: Any) -> bool:
    """Whether ``node`` is the literal 0 (``16#0``, ``UDINT#0`` too): the address of nothing."""
    return isinstance(node, tf.Integer) and int(str(node.value).replace("_", ""), node.base) == 0


def signature(members: Sequence[Member]) -> list[Member]:
    """A METHOD's / FUNCTION's parameters: inputs and in-outs in declaration order, then the outputs."""
    inputs = [m for m in members if m.section in ("VAR_INPUT", "VAR_IN_OUT")]
    return inputs + [m for m in members if m.section == "VAR_OUTPUT"]


def variables(node: Any) -> Iterator[Any]:
    """The variables (``x``, ``fb.Prop``) read by the expression ``node``."""
    kinds = (tf.SimpleVariable, tf.MultiElementVariable)
    for variable in walk(node, lambda item: isinstance(item, kinds)):
        if not isinstance(variable, kinds):
            continue
        yield variable
        if isinstance(variable, tf.MultiElementVariable):
            for element in variable.elements:
                if isinstance(element, tf.SubscriptList):
                    for subscript in element.subscripts:
                        yield from variables(subscript)


#: The fields of each blark node class that may hold nodes (``meta`` holds none), in declaration order.
_NODE_FIELDS: dict[type, tuple[str, ...]] = {}


def _node_fields(cls: type) -> tuple[str, ...] | None:
    """The fields of node class ``cls`` to walk, or None when ``cls`` is not a node class (a token, a number ...)."""
    found = _NODE_FIELDS.get(cls)
    if found is None:
        if not dataclasses.is_dataclass(cls):
            return None
        found = _NODE_FIELDS[cls] = tuple(field.name for field in dataclasses.fields(cls) if field.name != "meta")
    return found


def walk(node: Any, stop: Any = None) -> Iterator[Any]:
    """``node`` (or the items of a list) and every blark node below, depth first in field order; below a node
    for which ``stop(node)`` is true, nothing. One loop, no recursion: the translator asks this of every body."""
    stack = [node]
    while stack:
        item = stack.pop()
        kind = type(item)
        if kind is list or kind is tuple:
            stack.extend(reversed(item))
            continue
        names = _node_fields(kind)
        if names is None:
            continue
        yield item
        if stop is None or not stop(item):
            stack.extend([getattr(item, name) for name in reversed(names)])


def _is_adr(node: Any) -> bool:
    return isinstance(node, tf.FunctionCall) and str(node.name).lower() == "adr" and len(node.parameters or []) == 1


def by_reference_arguments(node: Any, in_out: set[str]) -> Iterator[str]:
    """The bare variables (lower case) that the calls in ``node`` get as an output (``=>``), or as an argument of
    a METHOD or FUNCTION whose name (in ``in_out``) has a VAR_IN_OUT: by name, so never fewer than need an address."""
    for call in walk(node):
        if not isinstance(call, tf.FunctionCall):
            continue
        callee = str(call.name).split(".")[-1].lower()
        if callee == "adr":
            yield from address_taken(call)  # ADR(x) of a local: x needs an address
        for param in call.parameters or []:
            value = getattr(param, "value", None)
            if isinstance(value, tf.SimpleVariable) and not value.dereferenced and (
                    isinstance(param, tf.OutputParameterAssignment) or callee in in_out):
                yield str(value.name).lower()


def address_taken(node: Any) -> Iterator[str]:
    """The bare variables (lower case) whose address ``ADR(x)`` takes in ``node`` (a call, or anything holding calls)."""
    for call in walk(node, _is_adr):
        if _is_adr(call):
            value = getattr(call.parameters[0], "value", None)
            if isinstance(value, tf.SimpleVariable) and not value.dereferenced:
                yield str(value.name).lower()


def has_call(node: Any) -> bool:
    """Whether the expression ``node`` calls a function, method or block (something that may have a side effect)."""
    return any(isinstance(item, (tf.FunctionCall, tf.ChainedFunctionCall)) for item in walk(node))


def assigned(node: Any) -> Iterator[Any]:
    """The variables the statements in ``node`` assign with ``:=`` (each target of each assignment)."""
    for statement in walk(node):
        if isinstance(statement, tf.AssignmentStatement):
            yield from statement.variables


def jumps_in_loop(node: Any) -> bool:
    """Whether a JMP in ``node`` sits inside a FOR, WHILE or REPEAT loop (it would leave the loop)."""
    loops = (tf.ForStatement, tf.WhileStatement, tf.RepeatStatement)
    return any(
        isinstance(jump, tf.JumpStatement) for loop in walk(node) if isinstance(loop, loops) for jump in walk(_below(loop))
    )


def _below(node: Any) -> list[Any]:
    names = _node_fields(type(node)) or ()
    return [getattr(node, name) for name in names]


def statements_of(body: Any) -> list[Any]:
    """The statements of a POU body (blark gives a lone statement of the grammar overlay as itself)."""
    if body is None:
        return []
    statements = getattr(body, "statements", None)
    return list(statements) if statements is not None else [body]


def lark_token_type() -> type:
    import lark

    return lark.Token


def python_string(text: str) -> str:
    """An ST string literal ('...' or "...") as a Python literal: ``$41`` in a STRING, ``$0041`` in a WSTRING."""
    digits = 4 if text[0] == '"' else 2  # IEC 61131-3: a WSTRING's character code is four hex digits
    body = text[1:-1]
    escapes = {"$$": "$", "$'": "'", '$"': '"', "$L": "\n", "$N": "\n", "$P": "\f", "$R": "\r", "$T": "\t"}
    out = []
    i = 0
    while i < len(body):
        if body[i] == "$" and i + 1 < len(body):
            pair = body[i:i + 2].upper() if body[i + 1].isalpha() else body[i:i + 2]
            if pair in escapes:
                out.append(escapes[pair])
                i += 2
                continue
            code = body[i + 1:i + 1 + digits]
            if len(code) == digits and all(c in "0123456789abcdefABCDEF" for c in code):
                out.append(chr(int(code, 16)))
                i += 1 + digits
                continue
        out.append(body[i])
        i += 1
    # A lone UTF-16 half ($D800) is a WSTRING character, but no UTF-8 file (the cache, linecache) can hold it raw.
    return re.sub("[\ud800-\udfff]", lambda half: f"\\u{ord(half.group()):04x}", json.dumps("".join(out), ensure_ascii=False))


def nodes_below(node: Any) -> Iterator[Any]:
    """``node`` and every blark node below it."""
    return walk(node)


def inline_enumerations(pou: Any, prefix: str = "") -> Iterator[tuple[Any, Any]]:
    """``eState : (Idle, Run);`` in the VAR of ``pou``: each initialisation and a ``TYPE <prefix>_<variable>``
    declaration made for it (``prefix``: the POU's name by default; new nodes, the tree is left as read)."""
    for block in getattr(pou, "declarations", None) or []:
        for item in getattr(block, "items", None) or []:
            init = getattr(item, "init", None)
            if not isinstance(init, tf.EnumeratedTypeInitialization) or not init.spec.values or init.indirection is not None:
                continue
            names = [str(v.variable.name) for v in getattr(item, "variables", [])]
            name = lark_token_type()("IDENTIFIER", f"{prefix or pou.name}_{names[0] if names else 'enum'}")
            spec = tf.EnumeratedSpecification(type_name=None, values=init.spec.values, meta=init.spec.meta)
            node = tf.EnumeratedTypeDeclaration(
                name=name, init=tf.EnumeratedTypeInitialization(indirection=None, spec=spec, value=init.value, meta=init.meta),
                meta=item.meta)
            yield init, tf.DataTypeDeclaration(declaration=node, access=None, meta=item.meta)


def valued_constants(owner: Any) -> Iterator[tuple[Any, Any, list[str]]]:
    """``(declaration, initialisation, names)`` of each VAR CONSTANT of ``owner`` with a type and a value."""
    for block in getattr(owner, "declarations", None) or []:
        if not (getattr(block, "attrs", None) and block.attrs & tf.VariableAttributes.constant):
            continue
        for item in block.items:
            init = getattr(item, "init", None)
            if isinstance(init, tf.TypeInitialization) and init.value is not None:
                yield item, init, [str(var.variable.name) for var in getattr(item, "variables", [])]


def location(item: Any) -> str:
    """``AT %IX0.0`` / ``AT %I*`` of a located declaration, or ""."""
    if isinstance(item, (tf.LocatedVariableDeclaration, tf.IncompleteLocatedVariableDeclaration)):
        return str(item.location)
    spec = getattr(item, "spec", None)
    if isinstance(spec, tf.GlobalVariableSpec) and spec.location is not None:
        return str(spec.location)
    located = [str(var.location) for var in getattr(item, "variables", []) if getattr(var, "location", None) is not None]
    return located[0] if located else ""


def located_section(item: Any, section: str) -> str:
    """iecoop has no process image: a located variable is an ordinary one. An input (``%I``) of a block's
    VAR is a VAR_INPUT, so a test or a simulation can write it as the I/O update would (fields only: a
    METHOD's or FUNCTION's inputs stay the ones it declares)."""
    return "VAR_INPUT" if section == "VAR" and "%I" in location(item).upper() else section


def drop_empty_arguments(tree: Any) -> Any:
    """``fb(Done => , BufferMode := , Execute := TRUE)``: the arguments written without a value are not passed, as
    TwinCAT and CODESYS read them (their input keeps its value, the output is not read); ``tree`` is changed in place."""
    for node in walk(tree):
        if isinstance(node, tf.FunctionCall) and any(getattr(p, "value", True) is None for p in node.parameters or []):
            node.parameters = [p for p in node.parameters if getattr(p, "value", True) is not None]
    return tree


def names_read(expression: Any) -> Iterator[str]:
    """The first names (lower case) of the variables a constant expression reads: ``GVL_Param.cMax + 1``
    reads ``gvl_param``."""
    for node in nodes_below(expression):
        if isinstance(node, (tf.SimpleVariable, tf.MultiElementVariable)):
            name = node.name.name if isinstance(node.name, tf.SimpleVariable) else node.name
            yield str(name).lower()


# --- the marks iecoop's ST writer leaves in plain text (``iecoop.st.dump``) ---------------------------------

def accessor_mark(unit: Any, node: Any) -> tuple[str, int] | None:
    """``("get" | "set", the comment's id)`` of a PROPERTY block marked by a ``// Get`` or ``// Set`` line before it.

    Besides ``Name.Get`` / ``Name.Set``, the plain-text form iecoop's ST writer uses for a property with both
    accessors: two blocks of the same name.
    """
    line = getattr(node.meta, "line", None) if node.meta else None
    for token in unit.comments:
        if line is not None and token.line == line - 1:
            marker = str(token).strip()[2:].strip().lower() if str(token).strip().startswith("//") else ""
            if marker in ("get", "set"):
                return marker, id(token)
    return None


def list_mark(unit: Any, node: Any) -> tuple[str, int] | None:
    """``(name, the comment's id)`` of a VAR_GLOBAL block marked by a ``// GVL <name>`` line above it (and its
    pragmas), as dump writes it."""
    line = getattr(node.meta, "line", None) if node.meta else None
    if line is None:
        return None
    # The mark is on the line right above the block or above the pragmas ({attribute ...}) heading it.
    expected = line - 1
    for token in sorted((t for t in unit.comments if t.line < line), key=lambda t: -t.line):
        text = str(token).strip()
        if token.line != expected:
            return None
        if text.startswith("{"):
            expected -= 1
            continue
        words = text[2:].split() if text.startswith("//") else []
        return (words[1], id(token)) if len(words) == 2 and words[0] == "GVL" and words[1].isidentifier() else None
    return None


def task_info_member(elements: Sequence[Any], store: bool) -> tuple[str, Any, bool] | str:
    """``_TaskInfo[index].Member``'s (member as TaskInfo spells it, the index expression, whether the index is
    GETCURTASKINDEXEX(), the running task's), or the refusal's message."""
    index = elements[0].subscripts if elements and isinstance(elements[0], tf.SubscriptList) else []
    if len(index) != 1:
        return "_TaskInfo takes one index, the task's (GETCURTASKINDEX)"
    call = index[0]
    running = isinstance(call, tf.FunctionCall) and str(call.name).upper() == "GETCURTASKINDEXEX" and not call.parameters
    field = elements[1].field if len(elements) == 2 and isinstance(elements[1], tf.FieldSelector) else None
    name = str(field.name) if isinstance(field, tf.SimpleVariable) else str(field)
    member = next((m for m in TASK_INFO_MEMBERS if m.lower() == name.lower()), None) if field is not None else None
    if member is None:
        return f"_TaskInfo[...].{name if field is not None else ''}: iecoop's TaskInfo has {', '.join(TASK_INFO_MEMBERS)}"
    if store:
        return f"assignment to _TaskInfo[...].{member} (the PLC's task information is read-only)"
    return member, call, running


def system_list_entry(node: tf.MultiElementVariable) -> tuple[str, list[Any]] | None:
    """``("_taskinfo" | "_appinfo", the elements after it)`` of ``_TaskInfo[i].X`` / ``_AppInfo.X``, bare or written
    with their list's name (``TwinCAT_SystemInfoVarList._AppInfo.ProjectName``); None for any other variable."""
    name, elements = str(node.name.name).lower(), list(node.elements)
    if name == "twincat_systeminfovarlist" and elements and isinstance(elements[0], tf.FieldSelector):
        name, elements = str(elements[0].field).lower(), elements[1:]
    return (name, elements) if name in ("_taskinfo", "_appinfo") else None


def app_info_member(elements: Sequence[Any], store: bool) -> str:
    """``_AppInfo.Member``'s member as AppInfo spells it; a refusal's message (it starts with ``_AppInfo``) for
    another member or a store."""
    field = elements[0].field if len(elements) == 1 and isinstance(elements[0], tf.FieldSelector) else None
    name = str(field.name) if isinstance(field, tf.SimpleVariable) else str(field) if field is not None else ""
    member = next((m for m in APP_INFO_MEMBERS if m.lower() == name.lower()), None)
    if member is None:
        return f"_AppInfo.{name}: iecoop's AppInfo has {', '.join(APP_INFO_MEMBERS)}"
    if store:
        return f"_AppInfo: assignment to {member} (the PLC's application information is read-only)"
    return member
