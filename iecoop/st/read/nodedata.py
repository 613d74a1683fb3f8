"""blark's transformed tree (its dataclasses) as plain data, for the translation cache.

A warm load reads each file's tree from its cache entry; keeping blark's
dataclasses, not the lark parse tree they are made from, spares the load
blark's transform and the limit checks, which ran when the entry was made.

The data says only what the ST says. It is lists of numbers, names and
places: a node is a class of ``blark.transform`` (looked up in a table of
that module's dataclasses, never imported by name) with its fields; a token
or a string is a place in the flat ST text, its characters read back from the
text; an enumeration value is a member of one of blark's enumerations. Making
a node sets its fields and runs nothing (no ``__init__``, no descriptor).
A tree that holds anything else is not encoded (``Unencodable``): its file
then has no entry and is parsed on each load.

Forms (a JSON list's first item says which):

======================  =====================================================
``[0, item...]``        a list
``[1, type, start, end]``  a lark Token: its terminal name and its place
``[2, index]``          the comment token of that index (``comments``)
``[3, enum, member]``   a member (a name) or a combination (an int) of a flag
``[4, item...]``        a tuple
``[5]`` ``[6]`` ``[7]``  the flat text, the file's path, the file's stem
``[8, start, end]``     a string that is that slice of the flat text
``[9, rule, place, child...]``  a lark Tree blark left (place ``[start, end]`` or None)
``[10 + k, value...]``  a node of class ``k`` of the entry's class list
======================  =====================================================
"""

from __future__ import annotations

import bisect
import dataclasses
import enum
import functools
import pathlib
import re
from typing import Any

__all__ = ["Lines", "Unencodable", "nodes_from_data", "nodes_to_data"]

_LIST, _TOKEN, _COMMENT, _ENUM, _TUPLE, _TEXT, _PATH, _STEM, _SLICE, _TREE, _NODE = range(11)
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


class Lines:
    """Line and column (from 1, as lark counts them) of a character offset in a text."""

    def __init__(self, text: str) -> None:
        self.text = text
        self.starts = [0, *(match.end() for match in re.finditer("\n", text))]

    def at(self, offset: int) -> tuple[int, int]:
        line = bisect.bisect_right(self.starts, offset)
        return line, offset - self.starts[line - 1] + 1


class Unencodable(ValueError):
    """The tree holds something the data form does not keep (its file then has no cache entry)."""


@functools.cache
def _classes() -> dict[str, type]:
    """blark's node classes (the dataclasses ``blark.transform`` defines), by name."""
    import blark.transform as tf

    return {
        name: value for name, value in vars(tf).items()
        if isinstance(value, type) and dataclasses.is_dataclass(value) and value.__module__ == tf.__name__
    }


@functools.cache
def _enums() -> dict[str, type[enum.Enum]]:
    import blark.transform as tf

    return {
        name: value for name, value in vars(tf).items()
        if isinstance(value, type) and issubclass(value, enum.Enum) and value.__module__ == tf.__name__
    }


@functools.cache
def _flag_bits(kind: type[enum.Enum]) -> int:
    """Every bit of a flag enumeration (0 for another enumeration: no combination is one of its values)."""
    return functools.reduce(lambda bits, member: bits | member.value, kind, 0) if issubclass(kind, enum.IntFlag) else 0


@functools.cache
def _fields(cls: type) -> frozenset[str]:
    # ``meta`` is set on every node blark's transform makes, a field or not
    return frozenset({field.name for field in dataclasses.fields(cls)} | {"meta"})


class _Encoder:
    def __init__(self, text: str, filename: str, comments: tuple[Any, ...]) -> None:
        import lark

        self.text, self.path, self.stem = text, pathlib.Path(filename), pathlib.Path(filename).stem
        self.token, self.tree = lark.Token, lark.Tree
        self.comment_index = {id(token): index for index, token in enumerate(comments)}
        self.class_index: dict[type, tuple[int, list[str]]] = {}
        self.classes: list[list[str]] = []  # per class: its name, then its fields in the order kept

    def token_data(self, token: Any) -> list[Any]:
        start, end = token.start_pos, token.end_pos
        if not (isinstance(start, int) and isinstance(end, int) and self.text[start:end] == str(token)):
            raise Unencodable(f"a {token.type} token that is not its place in the text")
        return [_TOKEN, token.type, start, end]

    def encode(self, value: Any) -> Any:
        if value is None or type(value) in (bool, int):
            return value
        if isinstance(value, self.token):
            index = self.comment_index.get(id(value))
            return [_COMMENT, index] if index is not None else self.token_data(value)
        if type(value) is str:
            return self.string(value)
        if type(value) is list:
            return [_LIST, *(self.encode(item) for item in value)]
        if type(value) is tuple:
            return [_TUPLE, *(self.encode(item) for item in value)]
        if isinstance(value, enum.Enum):
            return self.enum_data(value)
        if isinstance(value, pathlib.PurePath) and value == self.path:
            return [_PATH]
        if isinstance(value, self.tree):
            meta = value.meta
            place = None if meta.empty else [meta.start_pos, meta.end_pos]
            return [_TREE, str(value.data), place, *(self.encode(child) for child in value.children)]
        cls = type(value)
        if _classes().get(cls.__name__) is not cls:
            raise Unencodable(f"a {cls.__name__} in the tree")
        return self.node(value)

    def string(self, value: str) -> list[Any]:
        if value == self.text:
            return [_TEXT]
        if value == self.stem:
            return [_STEM]
        at = self.text.find(value)
        if at < 0:
            raise Unencodable("a string that is not in the text")
        return [_SLICE, at, at + len(value)]

    def enum_data(self, value: enum.Enum) -> list[Any]:
        kind = type(value)
        if _enums().get(kind.__name__) is not kind:
            raise Unencodable(f"a {kind.__name__} in the tree")
        if value.name is not None and value.name in kind.__members__:
            return [_ENUM, kind.__name__, value.name]
        if isinstance(value, enum.IntFlag):
            return [_ENUM, kind.__name__, int(value)]
        raise Unencodable(f"a {kind.__name__} value without a name")

    def node(self, value: Any) -> list[Any]:
        cls: type = type(value)
        known = self.class_index.get(cls)
        if known is None:
            known = self.class_index[cls] = (len(self.classes), sorted(_fields(cls)))
            self.classes.append([cls.__name__, *known[1]])
        index, names = known
        state = vars(value)
        if not state.keys() <= _fields(cls):
            raise Unencodable(f"a {cls.__name__} with attributes of its own")
        return [_NODE + index, *(self.encode(state[name]) if name in state else _Missing for name in names)]


#: A field the node does not have (blark sets ``meta`` on most nodes, not all).
_Missing: list[Any] = [_LIST, "missing"]


def nodes_to_data(tree: Any, comments: tuple[Any, ...], text: str, filename: str) -> dict[str, Any]:
    """blark's tree and comment tokens of the flat ``text`` of ``filename`` as JSON data; Unencodable if it cannot be."""
    encoder = _Encoder(text, filename, comments)
    try:
        encoded_comments = [encoder.token_data(token) for token in comments]
        encoded = encoder.encode(tree)
    except RecursionError:
        raise Unencodable("a tree nested too deeply") from None
    return {"classes": encoder.classes, "comments": encoded_comments, "tree": encoded}


class _Decoder:
    def __init__(self, data: dict[str, Any], text: str, filename: str) -> None:
        import lark


        self.lines, self.text = Lines(text), text
        self.path, self.stem = pathlib.Path(filename), pathlib.Path(filename).stem
        self.token, self.tree = lark.Token, lark.Tree
        self.classes: list[tuple[type, list[str]]] = []
        known = _classes()
        for entry in data["classes"]:
            name, *names = entry
            cls = known.get(name) if isinstance(name, str) else None
            if cls is None or not all(isinstance(n, str) for n in names) or not set(names) <= _fields(cls):
                raise ValueError("not a node class")
            self.classes.append((cls, names))
        self.comments = [self.token_of(item) for item in data["comments"]]

    def place(self, start: Any, end: Any) -> tuple[int, int]:
        if not (type(start) is int and type(end) is int and 0 <= start <= end <= len(self.text)):
            raise ValueError("not a place in the text")
        return start, end

    def token_of(self, item: Any) -> Any:
        kind, name, start, end = item
        if kind != _TOKEN or not (isinstance(name, str) and _NAME.match(name)):
            raise ValueError("not a token")
        start, end = self.place(start, end)
        return self.token(name, self.text[start:end], start, *self.lines.at(start), *self.lines.at(end), end)

    def decode(self, item: Any) -> Any:
        if type(item) is not list:
            if item is None or type(item) in (bool, int):
                return item
            raise ValueError("not a value")
        tag = item[0]
        if tag >= _NODE:
            cls, names = self.classes[tag - _NODE]
            if len(item) != len(names) + 1:
                raise ValueError("not a node")
            node = object.__new__(cls)
            state = node.__dict__
            for name, value in zip(names, item[1:]):
                if value != _Missing:
                    state[name] = self.decode(value)
            return node
        if tag == _TOKEN:
            return self.token_of(item)
        if tag == _LIST:
            return [self.decode(value) for value in item[1:]]
        if tag == _COMMENT:
            return self.comments[item[1]]
        return self.decode_other(tag, item)

    def decode_other(self, tag: int, item: list[Any]) -> Any:
        if tag == _TUPLE:
            return tuple(self.decode(value) for value in item[1:])
        if tag == _SLICE:
            start, end = self.place(item[1], item[2])
            return self.text[start:end]
        if tag in (_TEXT, _PATH, _STEM):
            return {_TEXT: self.text, _PATH: self.path, _STEM: self.stem}[tag]
        if tag == _ENUM:
            return self.enum_of(item[1], item[2])
        if tag == _TREE:
            return self.tree_of(item)
        raise ValueError("not a form")

    def enum_of(self, name: Any, value: Any) -> Any:
        kind = _enums().get(name) if isinstance(name, str) else None
        if kind is None:
            raise ValueError("not an enumeration")
        if isinstance(value, str):
            return kind.__members__[value]
        if type(value) is not int or value < 0 or value & ~_flag_bits(kind):
            raise ValueError("not a flag value")
        return kind(value)

    def tree_of(self, item: list[Any]) -> Any:
        _, rule, place, *children = item
        if not (isinstance(rule, str) and _NAME.match(rule)):
            raise ValueError("not a rule")
        tree = self.tree(self.token("RULE", rule), [self.decode(child) for child in children])
        if place is not None:
            begin, end = self.place(*place)
            meta = tree.meta
            meta.line, meta.column = self.lines.at(begin)
            meta.end_line, meta.end_column = self.lines.at(end)
            meta.start_pos, meta.end_pos, meta.empty = begin, end, False
        return tree


def nodes_from_data(data: Any, text: str, filename: str) -> tuple[Any, tuple[Any, ...]]:
    """blark's tree and comment tokens of ``nodes_to_data``; ValueError (or TypeError, KeyError, IndexError) if the
    data is not such a tree of ``text``."""
    if not isinstance(data, dict):
        raise ValueError("not a tree")
    decoder = _Decoder(data, text, filename)
    return decoder.decode(data["tree"]), tuple(decoder.comments)
