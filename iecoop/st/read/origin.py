"""Where each object of a loaded module was read from, so an unchanged object is written back as it was.

``st.load`` records one :class:`Source` per POU, DUT, GVL and INTERFACE: the file, the exact text of
the object (for a TwinCAT file the whole ``.TcPOU`` / ``.TcDUT`` / ``.TcGVL`` / ``.TcIO`` bytes, with its
object Id and LineIds kept in them), and a fingerprint of what the loaded Python object declares. At
export the fingerprint is taken again: equal means nothing was changed in Python, and the recorded text
is written instead of what the writer would make of the object (comments, layout, pragmas, ``AT``
addresses, constants by name and the Ids all survive). Only data is kept: no parse tree, no reader state.
"""

from __future__ import annotations

import dataclasses
import hashlib
import pathlib
import re
import types
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from iecoop.gvl import GlobalVariables
from iecoop.metadata import iec_class

__all__ = ["Source", "fingerprint", "object_name", "project_name", "sources"]

#: the TwinCAT object kinds, by the XML element under ``<TcPlcObject>``
_TWINCAT_ELEMENT = re.compile(rb"<(POU|DUT|GVL|Itf)\s+Name=\"([^\"]+)\"\s+Id=\"([^\"]*)\"")
_LINE_IDS = re.compile(rb"<LineIds\s+Name=\"([^\"]+)\"")
#: blark's nodes that belong to the object before them in flat text (a METHOD after its FUNCTION_BLOCK)
_MEMBER_NODES = ("Method", "Property", "PropertyGet", "PropertySet", "Action")


@dataclasses.dataclass(frozen=True)
class Source:
    """What one loaded object was read from."""

    name: str
    #: ``"twincat"`` (``text`` is the whole file), ``"plcopen"`` (the whole PLCopen XML export, which
    #: holds every object) or ``"st"`` (``text`` is the object's lines)
    format: str
    #: the file read (``"<st>"`` for text passed to ``st.load``)
    file: str
    #: the first line of the object in ``file``
    line: int
    text: bytes
    #: the TwinCAT object Id (``{...}``), empty for ST text
    object_id: str = ""
    #: the names of the ``<LineIds>`` blocks of a TwinCAT file (the POU and each METHOD / accessor)
    line_ids: tuple[str, ...] = ()
    #: :func:`fingerprint` of the loaded object
    fingerprint: str = ""


def sources(units: Sequence[Any], namespace: Mapping[str, Any], text: str | None = None) -> dict[str, Source]:
    """Each loaded object's :class:`Source`, by ST name; ``units`` are the reader's parsed units, ``text`` the
    ST text ``st.load`` was given (None for files)."""
    found: dict[str, Source] = {}
    for unit in units:
        if _is_twincat(unit.filename):
            read = _twincat(unit.filename)
        elif _is_plcopen(unit.filename):
            read = _plcopen(unit)
        else:
            read = _st(unit, text)
        for source in read:
            if source.name in namespace and source.name not in found:
                found[source.name] = dataclasses.replace(source, fingerprint=fingerprint(namespace[source.name]))
    return found


def project_name(source: Any) -> str | None:
    """The name of the project ``source`` is (a ``.plcproj``'s, a folder's or a file's stem), None for text."""
    if isinstance(source, str) and ("\n" in source or ";" in source):
        return None
    path = pathlib.Path(source)
    if not path.exists():
        return None
    projects = sorted(path.glob("*.plcproj")) if path.is_dir() else []
    name = (projects[0] if len(projects) == 1 else path).stem
    return name if name.isidentifier() else None


def _is_twincat(filename: str) -> bool:
    return pathlib.Path(filename).suffix.lower() in (".tcpou", ".tcdut", ".tcgvl", ".tcio")


def _is_plcopen(filename: str) -> bool:
    return pathlib.Path(filename).suffix.lower() == ".xml" and pathlib.Path(filename).is_file()


def _plcopen(unit: Any) -> Iterable[Source]:
    """Each object of a PLCopen XML export: the file's lines are XML, so no object has ST lines of its own."""
    data = pathlib.Path(unit.filename).read_bytes()
    for item in getattr(unit.tree, "items", ()):
        name = object_name(item)
        if name is not None and type(item).__name__ not in _MEMBER_NODES:
            yield Source(name, "plcopen", unit.filename, getattr(getattr(item, "meta", None), "line", 1) or 1, data)


def _twincat(filename: str) -> Iterable[Source]:
    data = pathlib.Path(filename).read_bytes()
    match = _TWINCAT_ELEMENT.search(data)
    if match is None:
        return []
    line_ids = tuple(m.group(1).decode("utf-8", "replace") for m in _LINE_IDS.finditer(data))
    name = match.group(2).decode("utf-8", "replace")
    return [Source(name, "twincat", filename, 1, data, match.group(3).decode("utf-8", "replace"), line_ids)]


def _st(unit: Any, text: str | None) -> Iterable[Source]:
    """One source per named top-level object of flat ST text: its lines, with the comments before it."""
    if unit.filename == "<st>" or not pathlib.Path(unit.filename).is_file():
        if text is None:
            return []
    else:
        text = pathlib.Path(unit.filename).read_bytes().decode("utf-8-sig", "replace")
    lines = text.splitlines(keepends=True)
    spans: list[list[Any]] = []  # [name, first line, last line]
    previous_end = 0
    for item in getattr(unit.tree, "items", ()):
        meta = getattr(item, "meta", None)
        start, end = getattr(meta, "line", None), getattr(meta, "end_line", None)
        if not isinstance(start, int) or not isinstance(end, int):
            continue
        if type(item).__name__ in _MEMBER_NODES and spans:
            spans[-1][2] = max(spans[-1][2], end)  # a METHOD written inside its FUNCTION_BLOCK ends before the block
        else:
            spans.append([object_name(item), previous_end + 1, end])
        previous_end = max(previous_end, end)
    found = []
    for name, first, last in spans:
        if name is not None:
            body = "".join(lines[first - 1:last])
            found.append(Source(name, "st", unit.filename, first, body.encode("utf-8")))
    return found


def object_name(item: Any) -> str | None:
    """The ST name of a top-level object blark parsed (a global list of flat text: its ``// GVL`` mark's)."""
    name = getattr(item, "name", None)
    if name is None:
        declaration = getattr(item, "declaration", None)
        name = getattr(declaration, "name", None)
    if type(item).__name__ == "GlobalVariableDeclarations":
        # a global list of flat text is named by the ``// GVL name`` line above it, as dump writes it
        marks = [str(t).split()[2:] for t in getattr(getattr(item, "meta", None), "comments", None) or () if str(t).split()[:2] == ["//", "GVL"]]
        name = next((words[0] for words in marks if len(words) == 1 and words[0].isidentifier()), name)
    return str(name) if name is not None else None


def fingerprint(obj: Any) -> str:
    """A digest of what ``obj`` (a class, a PROGRAM or GVL instance, a FUNCTION) declares.

    A METHOD replaced, a variable or member added or removed, a body changed in Python: the digest changes.
    """
    digest = hashlib.sha256()
    target = type(obj) if isinstance(obj, GlobalVariables) or _is_instance(obj) else obj
    for part in _parts(target, set()):
        digest.update(part.encode("utf-8", "replace"))
        digest.update(b"\0")
    return digest.hexdigest()


def _is_instance(obj: Any) -> bool:
    return not isinstance(obj, (type, types.FunctionType, types.BuiltinFunctionType)) and iec_class(type(obj)) is not None


def _parts(obj: Any, seen: set[int]) -> Iterable[str]:
    if isinstance(obj, type):
        if id(obj) in seen:
            yield f"class {obj.__qualname__}"
            return
        seen.add(id(obj))
        yield f"class {obj.__qualname__} {[base.__qualname__ for base in obj.__bases__]}"
        for key in sorted(vars(obj)):
            if key in ("__dict__", "__weakref__", "__module__", "__doc__"):
                continue
            yield key
            yield from _value(vars(obj)[key], seen)
    else:
        yield from _value(obj, seen)


def _value(value: Any, seen: set[int]) -> Iterable[str]:
    function = getattr(value, "__func__", value)  # classmethod, staticmethod
    if isinstance(function, types.FunctionType):
        yield from _code(function.__code__)
        yield repr(function.__defaults__) if _stable(repr(function.__defaults__)) else type(function.__defaults__).__name__
        yield repr(function.__annotations__)
    elif isinstance(value, property):
        for accessor in (value.fget, value.fset):
            if isinstance(accessor, types.FunctionType):
                yield from _code(accessor.__code__)
    elif isinstance(value, type):
        yield from _parts(value, seen)
    else:
        text = repr(value)
        yield text if _stable(text) else type(value).__qualname__


def _code(code: types.CodeType) -> Iterable[str]:
    yield code.co_code.hex()
    yield repr(code.co_names)
    yield repr(code.co_varnames)
    for constant in code.co_consts:
        if isinstance(constant, types.CodeType):
            yield from _code(constant)
        else:
            yield repr(constant)


def _stable(text: str) -> bool:
    """A repr with no memory address in it (the same object gives the same text in every process)."""
    return " at 0x" not in text and " object at " not in text
