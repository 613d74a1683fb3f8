"""The blark front end: ST text, ``.st`` files, TwinCAT files, folders and ``.plcproj`` to blark trees.

Every source becomes *flat* Structured Text first: the form TwinCAT exports
and blark parses, where a METHOD or PROPERTY follows the FUNCTION_BLOCK or
INTERFACE it belongs to. A TwinCAT file is split by blark into its parts
(declaration, implementation, each method, each property accessor); they are
joined back here in that order, and a property accessor is renamed
``Name.Get`` / ``Name.Set`` (the plain-text form of a property with both
accessors). A map from each flat line to its file and line keeps error
messages pointing at the real source.
"""

from __future__ import annotations

import contextlib
import contextvars
import dataclasses
import functools
import os
import pathlib
import re
import stat
from collections.abc import Iterator
from typing import Any

from iecoop.st.read.errors import StSyntaxError, StUnsupportedError
from iecoop.st.read.grammar import build_grammars, grammar_of, needs_overlay, overlay_parser

__all__ = ["StSyntaxError", "StUnsupportedError", "Unit", "leaving_out", "parse_sources"]

#: The TwinCAT file kinds blark reads (POUs, data types, global and I/O lists).
TWINCAT_SUFFIXES = (".tcpou", ".tcdut", ".tcgvl", ".tcio")
ST_SUFFIXES = (".st",)

#: What one source may hold. Each limit is checked on the parse tree before Python is generated:
#: the generated module mirrors the ST's nesting, and CPython allows 20 nested blocks (loops,
#: ``try``) in one function and 100 levels of indentation; the translator and the parser recurse
#: once per nested expression and per chained operator.
MAX_STATEMENT_NESTING = 20
MAX_EXPRESSION_NESTING = 16
MAX_EXPRESSION_OPERATORS = 200
#: A safety net for nesting the two limits above do not count (subscripts in initial values, ...).
MAX_PARSE_DEPTH = 320
#: Bytes in one file; real TwinCAT POUs are well below a megabyte.
MAX_FILE_BYTES = 16 * 1024 * 1024

#: Encodings an ST file is read with, in order (a UTF-8 byte order mark decides at once):
#: TwinCAT and CODESYS write UTF-8, older projects the Windows code page 1252.
ST_ENCODINGS = ("utf-8", "cp1252")

#: The TwinCAT XML elements whose ``Name`` attribute becomes ST code (POU, method, action, ...).
_NAMED_ELEMENTS = frozenset({"POU", "DUT", "GVL", "Itf", "Method", "Property", "Action", "Transition", "Get", "Set"})
_ST_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")

_PROPERTY_NAME = re.compile(
    r"^(\s*PROPERTY\s+(?:(?:PUBLIC|PRIVATE|PROTECTED|INTERNAL|ABSTRACT|FINAL)\s+)*)([A-Za-z_]\w*)", re.IGNORECASE | re.MULTILINE
)


@dataclasses.dataclass
class Unit:
    """One parsed flat source: the blark tree and where its lines came from."""

    tree: Any  # blark.transform.SourceCode
    filename: str
    #: flat line number -> (file, line) for sources joined from TwinCAT parts
    line_map: dict[int, tuple[str, int]] = dataclasses.field(default_factory=dict)
    #: every comment and pragma token of the source, in order (each has ``.line``)
    comments: tuple[Any, ...] = ()

    def where(self, line: int | None) -> str:
        """``file:line`` of a flat line."""
        if line is None:
            return self.filename
        file, real = self.line_map.get(line, (self.filename, line))
        return f"{file}:{real}"


def is_st_identifier(name: str) -> bool:
    """``name`` is an ST identifier: an ASCII letter or ``_`` first, then letters, digits and ``_``."""
    return _ST_IDENTIFIER.match(name) is not None


def parse_sources(source: str | os.PathLike[str], *, cache: bool | None = None) -> list[Unit]:
    """Parse ``source`` (ST text, a file, a folder or a ``.plcproj``) into flat units.

    A file's parse is kept in the translation cache (``read.cache``) unless
    ``cache`` is False (None: as ``IECOOP_ST_CACHE`` says); files not in it
    are parsed on every core when there are several.
    """
    if isinstance(source, str) and ("\n" in source or ";" in source or not _looks_like_path(source)):
        return [_parse_text(source, "<st>", {})]
    path = pathlib.Path(source)
    if not path.exists():
        raise FileNotFoundError(f"ST source {str(path)!r} does not exist")
    from iecoop.st.read.parallel import Parser, parse_files
    from iecoop.st.read.trees import drop_empty_arguments  # on the tree as the cache gives it back too

    flat = list(_flat_sources(path))
    parsed = parse_files(flat, cache, Parser(parse_one, parse_as_data, grammar_of, build_grammars))
    units = [
        _parse_text(text, name, line_map) if done is None else Unit(drop_empty_arguments(done[0]), name, line_map, done[1])
        for (text, name, line_map), done in zip(flat, parsed)
    ]
    _check_gvl_names(units)
    return units


def _looks_like_path(text: str) -> bool:
    if not text.strip():
        return False  # Path("") is the current folder: an empty text is empty Structured Text
    return pathlib.Path(text).suffix.lower() in (*ST_SUFFIXES, *TWINCAT_SUFFIXES, ".plcproj", ".xml") or pathlib.Path(text).is_dir()


#: The folders whose files a folder or ``.plcproj`` read inside ``leaving_out`` does not read.
_LEFT_OUT: contextvars.ContextVar[tuple[pathlib.Path, ...]] = contextvars.ContextVar("iecoop_st_left_out", default=())


@contextlib.contextmanager
def leaving_out(*folders: str | os.PathLike[str]) -> Iterator[None]:
    """Inside the block, a folder or ``.plcproj`` is read without the files below ``folders``.

    ``iecoop test --tcunit iecoop`` reads a project this way without the copy of TcUnit's source it carries.
    """
    token = _LEFT_OUT.set(_LEFT_OUT.get() + tuple(pathlib.Path(folder).resolve() for folder in folders))
    try:
        yield
    finally:
        _LEFT_OUT.reset(token)


def _left_out(path: pathlib.Path) -> bool:
    folders = _LEFT_OUT.get()
    return bool(folders) and any(path.resolve().is_relative_to(folder) for folder in folders)


def _flat_sources(path: pathlib.Path) -> Iterator[tuple[str, str, dict[int, tuple[str, int]]]]:
    if path.is_dir():
        folder = path.resolve()
        for child in sorted(path.rglob("*")):
            if child.is_file() and child.suffix.lower() in (*ST_SUFFIXES, *TWINCAT_SUFFIXES) and not _left_out(child):
                if not child.resolve().is_relative_to(folder):  # as a .plcproj's Include: nothing read from outside
                    raise StSyntaxError(f"{child}: a link to {str(child.resolve())!r}, outside the folder {str(folder)!r}; "
                                        "a folder reads only files below it")
                yield from _flat_sources(child)
        return
    suffix = path.suffix.lower()
    if suffix in ST_SUFFIXES:
        yield _read_text(path), str(path), {}
    elif suffix in TWINCAT_SUFFIXES:
        yield _flatten_twincat(path)
    elif suffix == ".xml":
        from iecoop.st.read.plcopen import flatten_plcopen  # a PLCopen XML export (CODESYS's text form)
        yield flatten_plcopen(path, read_xml(path))
    elif suffix == ".plcproj":
        for included in _plcproj_files(path):
            if not _left_out(included):
                yield from _flat_sources(included)
    else:
        raise StUnsupportedError(f"{path}: unsupported file kind {path.suffix!r} (use .st, .TcPOU, .TcDUT, .TcGVL, .TcIO, "
                                 ".plcproj, PLCopen .xml or a folder)")


def _read_bytes(path: pathlib.Path) -> bytes:
    if not stat.S_ISREG(path.stat().st_mode):  # a pipe or a device would be read for ever
        raise StUnsupportedError(f"{path}: not a regular file (a pipe, device or socket is not read as a source)")
    with path.open("rb") as file:
        data = file.read(MAX_FILE_BYTES + 1)  # not the size stat gave: a file may grow while it is read
    if len(data) > MAX_FILE_BYTES:
        raise StUnsupportedError(f"{path}: {max(len(data), path.stat().st_size)} bytes is more than the {MAX_FILE_BYTES} bytes one file may hold")
    return data


def _read_text(path: pathlib.Path) -> str:
    """An ST file's text: UTF-8, UTF-16 or UTF-32 with a byte order mark, else strict UTF-8, else Windows-1252."""
    data = _read_bytes(path)
    if data.startswith(b"\xef\xbb\xbf"):
        encodings: tuple[str, ...] = ("utf-8-sig",)
    elif data.startswith((b"\xff\xfe\x00\x00", b"\x00\x00\xfe\xff")):
        encodings = ("utf-32",)
    elif data.startswith((b"\xff\xfe", b"\xfe\xff")):  # as Windows' editors save "Unicode"
        encodings = ("utf-16",)
    else:
        encodings = ST_ENCODINGS
    for encoding in encodings:
        try:
            return data.decode(encoding)
        except UnicodeDecodeError as exc:
            failure = exc
    line = data[: failure.start].count(b"\n") + 1
    raise StSyntaxError(
        f"{path}:{line}: cannot decode byte {data[failure.start]:#04x} as {' or '.join(encodings)} "
        "(ST files are UTF-8 or Windows-1252, or UTF-16 or UTF-32 after a byte order mark)"
    ) from None


def read_xml(path: pathlib.Path) -> Any:
    """The root element of a TwinCAT XML file, parsed without DTDs, entities or network access."""
    import lxml.etree  # type: ignore[import-untyped]  # installed with blark; ships no type information

    data = _read_bytes(path)
    # No DTD is loaded and no entity resolved, so an entity bomb or an external entity stays inert;
    # any DOCTYPE at all is refused, as TwinCAT and MSBuild files never carry one.
    parser = lxml.etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False)
    try:
        root = lxml.etree.fromstring(data, parser)
    except lxml.etree.XMLSyntaxError as exc:
        line = exc.lineno if isinstance(exc.lineno, int) and exc.lineno > 0 else 1
        raise StSyntaxError(f"{path}:{line}: not well-formed XML: {str(exc.msg).splitlines()[0]}") from None
    except ValueError as exc:  # lxml refuses some inputs before parsing (a str with an encoding declaration, ...)
        raise StSyntaxError(f"{path}:1: not well-formed XML: {exc}") from None
    if root is None:
        raise StSyntaxError(f"{path}:1: not well-formed XML: no root element")
    if root.getroottree().docinfo.doctype:
        at = data.find(b"<!DOCTYPE")
        line = data[:at].count(b"\n") + 1 if at >= 0 else 1
        raise StSyntaxError(f"{path}:{line}: a DOCTYPE is not allowed (DTDs and entities are not read)")
    return root


def _check_xml_names(path: pathlib.Path, root: Any) -> None:
    """Every POU, method, action, property and accessor name in the XML is an ST identifier (it becomes code)."""
    for element in root.iter():
        if not isinstance(element.tag, str):
            continue  # comments and processing instructions
        name = element.get("Name")
        if name is not None and element.tag.rsplit("}", 1)[-1] in _NAMED_ELEMENTS and not is_st_identifier(name):
            raise StSyntaxError(
                f"{path}:{element.sourceline}: <{element.tag.rsplit('}', 1)[-1]} Name={name!r}> is not an ST identifier "
                "(an ASCII letter or _ first, then letters, digits and _)"
            )


#: The owners of an <Implementation>, as the refusal of a graphical body names them.
_BODY_OWNERS = {"POU": "", "Method": "METHOD", "Action": "ACTION", "Get": "PROPERTY", "Set": "PROPERTY", "Transition": "TRANSITION"}
#: An <NWL> network list's DefaultViewMode -> the language TwinCAT edits it in.
_NETWORK_MODES = {"fbd": "FBD", "ld": "LD", "il": "IL"}


def _check_bodies(path: pathlib.Path, root: Any) -> None:
    """Every body is ST: blark skips a body in FBD, LD, IL, SFC or CFC, which would then run as an empty one."""
    for implementation in root.iter("{*}Implementation"):
        for body in implementation:
            if not isinstance(body.tag, str) or body.tag.rsplit("}", 1)[-1] == "ST":
                continue
            tag = body.tag.rsplit("}", 1)[-1]
            mode = next((v.text or "" for v in body.iter("{*}v") if v.get("n") == "DefaultViewMode"), "")
            language = _NETWORK_MODES.get(mode.strip('"').lower(), "a network (FBD, LD or IL)") if tag == "NWL" else tag
            raise StUnsupportedError(f"{path}:{body.sourceline}: {_body_owner(implementation.getparent())}: its body is written in "
                                     f"{language}, not Structured Text: iecoop reads ST only (write the body in ST)")


def _body_owner(element: Any) -> str:
    """``PROGRAM P_Pump``, ``METHOD FB_X.Step``, ``PROPERTY FB_X.Speed``: the POU part a body belongs to."""
    names = []
    kind = ""
    while element is not None and isinstance(element.tag, str):
        tag = element.tag.rsplit("}", 1)[-1]
        if tag in _BODY_OWNERS and element.get("Name") and tag not in ("Get", "Set"):
            names.append(element.get("Name"))
            kind = kind or _BODY_OWNERS[tag]
        elif tag in ("Get", "Set"):
            kind = "PROPERTY"
        if tag == "POU":
            declaration = element.find("{*}Declaration")
            words = re.findall(r"\b(PROGRAM|FUNCTION_BLOCK|FUNCTION)\b", declaration.text or "") if declaration is not None else []
            kind = kind or (words[0] if words else "POU")
        element = element.getparent()
    return f"{kind} {'.'.join(reversed(names))}"


def _plcproj_files(path: pathlib.Path) -> list[pathlib.Path]:
    """The TwinCAT files a ``.plcproj`` compiles: each must exist and lie below the project's folder."""
    root = read_xml(path)
    folder = path.parent.resolve()
    files = []
    for element in root.iter():
        if not isinstance(element.tag, str) or element.tag.rsplit("}", 1)[-1] != "Compile":
            continue
        include = element.get("Include", "").strip()  # as MSBuild reads an item: spaces around it are not part of the name
        where = f"{path}:{element.sourceline}"
        relative = include.replace("\\", "/")
        if pathlib.PureWindowsPath(include).is_absolute() or pathlib.PureWindowsPath(include).drive or relative.startswith("/"):
            raise StSyntaxError(f"{where}: Compile Include={include!r} is an absolute path; a project reads only files below its folder")
        candidate = path.parent / relative
        if candidate.suffix.lower() not in TWINCAT_SUFFIXES:
            continue  # tasks, visualisations, ...: not Structured Text
        if not candidate.resolve().is_relative_to(folder):
            raise StSyntaxError(f"{where}: Compile Include={include!r} is outside the project folder {str(folder)!r}")
        if not candidate.is_file():
            raise StSyntaxError(f"{where}: Compile Include={include!r}: the file {str(candidate)!r} does not exist")
        files.append(candidate)
    return files


@dataclasses.dataclass(frozen=True)
class LibraryReference:
    """A library a ``.plcproj`` references: ``<PlaceholderReference>`` or ``<LibraryReference>``.

    ``name`` is its title (``Tc2_Standard``), ``namespace`` what qualified names use (``<Namespace>``,
    else the title), ``version`` and ``company`` as the reference resolves it (``*``: the newest).
    """

    name: str
    namespace: str
    version: str
    company: str
    where: str


#: ``Tc2_MC2, 3.3.52.0 (Beckhoff Automation GmbH)``: title, version, company
_RESOLUTION = re.compile(r"\s*([^,()]+?)\s*(?:,\s*([^()]*?)\s*)?(?:\(([^()]*)\))?\s*\Z")
#: a library's title: words, as vendors name them ("Base Interfaces", "Tc2_Standard"); never a path
_LIBRARY_TITLE = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_ .\-]*\Z")


def library_references(source: str | os.PathLike[str]) -> list[LibraryReference]:
    """The libraries a ``.plcproj`` (or the one ``.plcproj`` directly in a folder) references; [] for other sources."""
    path = _project_file(source)
    if path is None:
        return []
    return [
        _library_reference(path, element)
        for element in read_xml(path).iter()
        if isinstance(element.tag, str) and element.tag.rsplit("}", 1)[-1] in ("PlaceholderReference", "LibraryReference")
    ]


def _project_file(source: str | os.PathLike[str]) -> pathlib.Path | None:
    """The ``.plcproj`` a source names (itself, or the only one in a folder), or None."""
    if isinstance(source, str) and ("\n" in source or ";" in source or not _looks_like_path(source)):
        return None
    path = pathlib.Path(source)
    if path.is_dir():
        projects = sorted(path.glob("*.plcproj"))
        if len(projects) != 1:
            return None
        path = projects[0]
    return path if path.suffix.lower() == ".plcproj" and path.is_file() else None


def _library_reference(path: pathlib.Path, element: Any) -> LibraryReference:
    """One ``PlaceholderReference`` / ``LibraryReference`` element: title, namespace, version, company."""
    children = {child.tag.rsplit("}", 1)[-1]: (child.text or "").strip() for child in element if isinstance(child.tag, str)}
    # A placeholder names the library it resolves to in <DefaultResolution>; a plain reference in Include.
    resolution = children.get("DefaultResolution") or element.get("Include", "")
    match = _RESOLUTION.match(resolution)
    where = f"{path}:{element.sourceline}"
    if match is None or not _LIBRARY_TITLE.match(match.group(1).strip()):
        raise StSyntaxError(f"{where}: library reference {resolution!r} names no library (Title, version (company))")
    name = match.group(1).strip()
    namespace = children.get("Namespace") or element.get("Include", "").split(",")[0].strip() or name
    if not is_st_identifier(namespace):
        raise StSyntaxError(f"{where}: library {name}: namespace {namespace!r} is not an ST identifier")
    return LibraryReference(name, namespace, (match.group(2) or "*").strip(), (match.group(3) or "").strip(), where)


def _check_gvl_names(units: list[Unit]) -> None:
    """A GVL named after its file has an ASCII ST name, and no POU or type has that name too."""
    import blark.transform as tf

    declared: dict[str, str] = {}
    for unit in units:
        for item in getattr(unit.tree, "items", ()):
            inner = item.declaration if isinstance(item, tf.DataTypeDeclaration) else item
            if isinstance(inner, tf.GlobalVariableDeclarations) or getattr(inner, "name", None) is None:
                continue
            declared.setdefault(str(inner.name).lower(), f"{type(inner).__name__} {inner.name} ({unit.where(_line(inner))})")
    for unit in units:
        for item in getattr(unit.tree, "items", ()):
            if not isinstance(item, tf.GlobalVariableDeclarations) or item.name is None:
                continue
            stem = str(item.name)  # blark names the list after the file
            for name in dict.fromkeys((stem, stem.split(".")[0])):
                if name.isidentifier() and not is_st_identifier(name):
                    raise StSyntaxError(
                        f"{unit.where(_line(item))}: the GVL takes its name {name!r} from the file name, which is not an ST "
                        "identifier (an ASCII letter or _ first, then letters, digits and _)"
                    )
            clash = declared.get(stem.lower()) if is_st_identifier(stem) else None
            if clash is not None:
                raise StSyntaxError(f"{unit.where(_line(item))}: the GVL {stem} (named after its file) has the name of {clash}")


def _line(node: Any) -> int | None:
    meta = getattr(node, "meta", None)
    line = getattr(meta, "line", None)
    return line if isinstance(line, int) else None


def _flatten_twincat(path: pathlib.Path) -> tuple[str, str, dict[int, tuple[str, int]]]:
    from blark.input import BlarkCompositeSourceItem

    lines: list[str] = []
    line_map: dict[int, tuple[str, int]] = {}

    def add(code: str, inner: dict[int, int]) -> None:
        for offset, text in enumerate(code.split("\n"), start=1):
            lines.append(text)
            line_map[len(lines)] = (str(path), inner.get(offset, max(inner.values(), default=0)))

    def walk(item: Any) -> None:
        if isinstance(item, BlarkCompositeSourceItem):
            parts = list(item.parts)
            index = 0
            while index < len(parts):
                part = parts[index]
                if isinstance(part, BlarkCompositeSourceItem):
                    walk(part)
                    index += 1
                    continue
                code, inner = part.get_code_and_line_map(include_end=False)
                accessor = part.identifier.split("/")[0].rsplit(".", 1)[-1].lower()
                if part.type.name == "action":  # a TwinCAT <Action> holds only its code: the flat form names it
                    first = min(inner.values(), default=0)
                    add(f"ACTION {part.identifier.split('/')[0].rsplit('.', 1)[-1]}:", {1: first})
                    add(code, inner)
                    add("END_ACTION", {1: max(inner.values(), default=first)})
                    index += 1
                    continue
                if part.type.name in ("property_get", "property_set"):
                    code = _PROPERTY_NAME.sub(lambda m: f"{m.group(1)}{m.group(2)}.{accessor.capitalize()}", code, count=1)
                add(code, inner)
                end = part.implicit_end
                nxt = parts[index + 1] if index + 1 < len(parts) else None
                if (
                    nxt is not None
                    and not isinstance(nxt, BlarkCompositeSourceItem)
                    and nxt.identifier.endswith("/implementation")
                    and nxt.identifier.split("/")[0] == part.identifier.split("/")[0]
                ):
                    impl, impl_map = nxt.get_code_and_line_map(include_end=False)
                    if impl.strip():
                        add(impl, impl_map)
                    index += 1
                if end:
                    add(end, {1: max(inner.values(), default=0)})
                index += 1
        else:
            code, inner = item.get_code_and_line_map(include_end=True)
            add(code, inner)

    from blark.solution import TcSource

    root = read_xml(path)
    _check_xml_names(path, root)
    _check_bodies(path, root)
    try:
        items = TcSource.from_xml(root, filename=path).to_blark()
    except Exception as exc:  # blark's reader has no error type of its own; any failure means a file it cannot read
        raise StSyntaxError(f"{path}: not a TwinCAT file blark can read: {type(exc).__name__}: {exc}") from None
    for item in items:
        walk(item)
    return "\n".join(lines) + "\n", str(path), line_map


def _parse_text(text: str, filename: str, line_map: dict[int, tuple[str, int]]) -> Unit:
    from iecoop.st.read.trees import drop_empty_arguments

    tree, comments = _tree(text, filename, tuple(sorted(line_map.items())))
    return Unit(drop_empty_arguments(tree), filename, line_map, comments)


@functools.lru_cache(maxsize=128)
def _tree(text: str, filename: str, line_map_items: tuple[tuple[int, tuple[str, int]], ...]) -> Any:
    """blark's tree and comment tokens for ``text``; cached, because blark's Earley parser takes a while and a test loads one source often."""
    return parse_one(text, filename, dict(line_map_items))


def parse_one(text: str, filename: str, line_map: dict[int, tuple[str, int]]) -> tuple[Any, tuple[Any, ...]]:
    """blark's tree (its dataclasses) and comment tokens for the flat ``text``, or StSyntaxError naming the file and line."""
    import blark.transform as tf
    import lark

    tree, comments = raw_tree(text, filename, line_map)  # the limits are checked on lark's tree
    try:
        return tf.transform(source_code=text, tree=tree, comments=list(comments), filename=pathlib.Path(filename)), comments
    except (lark.LarkError, ValueError, TypeError) as exc:  # a tree blark cannot build
        raise StSyntaxError(f"{filename}: blark could not build the tree: {exc}") from None
    except RecursionError:  # only beyond the limits _check_limits holds, e.g. when called from a deep stack
        raise StUnsupportedError(f"{filename}: the source nests too deeply for the parser") from None


def parse_as_data(text: str, filename: str, line_map: dict[int, tuple[str, int]]) -> dict[str, Any] | None:
    """``parse_one`` as a cache entry's data (``read.cache.entry_data``): what a worker process hands back."""
    from iecoop.st.read.cache import entry_data

    return entry_data(*parse_one(text, filename, line_map), text, filename)


def raw_tree(text: str, filename: str, line_map: dict[int, tuple[str, int]]) -> tuple[Any, tuple[Any, ...]]:
    """blark's parse of ``text``: the lark tree and the comment tokens, or StSyntaxError naming the file and line."""
    import blark
    import lark

    from iecoop.st.read.dialect import rewrite

    parser = overlay_parser() if needs_overlay(text) else None
    try:
        result = blark.parse_source_code(text, fn=filename, parser=parser)
    except (IndexError, ValueError, KeyError) as scanned:  # blark's comment scanner on unbalanced (* *) and { }
        raise StSyntaxError(
            f"{filename}: Structured Text syntax error: unbalanced comment or pragma ({type(scanned).__name__}: {scanned})"
        ) from None
    if isinstance(result.exception, RecursionError):
        raise StUnsupportedError(f"{filename}: the source nests too deeply for the parser") from None
    if result.exception is not None:
        exc = result.exception
        line = getattr(exc, "line", None)
        unit = Unit(None, filename, line_map)
        detail = _syntax_detail(exc, text)
        if not (isinstance(line, int) and line > 0):  # the parser ran out of text: the error is at its end
            line = max(text.rstrip().count("\n") + 1, 1)
            detail = "the source ends before its last declaration or statement does"
        where = unit.where(line)
        raise StSyntaxError(f"{where}: Structured Text syntax error: {detail}") from None
    _check_limits(result.tree, Unit(None, filename, line_map))
    if parser is not None:
        try:
            rewrite(result.tree)  # the dialect's forms into blark's own shapes, before the tree is cached
        except (lark.LarkError, ValueError, TypeError) as exc:
            raise StSyntaxError(f"{filename}: blark could not build the tree: {exc}") from None
    return result.tree, tuple(result.comments)


#: Grammar rules (blark's ``iec.lark``) that nest one statement list in another.
_NESTING_STATEMENTS = {
    "if_statement": "IF", "case_statement": "CASE", "for_statement": "FOR", "while_statement": "WHILE",
    "repeat_statement": "REPEAT", "try_statement": "__TRY",
}
#: Grammar rules of binary operators: ``operand (OPERATOR operand)*``, one nested Python expression per operator.
_OPERATOR_RULES = frozenset({
    "expression", "assignment_expression", "or_else_expression", "and_then_expression", "xor_expression",
    "and_expression", "comparison_expression", "equality_expression", "add_expression", "expression_term",
})


def _check_limits(tree: Any, unit: Unit) -> None:
    """Refuse a source nested deeper than the ``MAX_*`` limits, walking blark's raw tree without recursion."""
    import lark

    # node, line, statements, expressions and operators around it, parse depth
    stack: list[tuple[Any, int | None, int, int, int, int]] = [(tree, None, 0, 0, 0, 1)]
    while stack:
        node, line, statements, expressions, operators, depth = stack.pop()
        line = node.meta.line if not node.meta.empty else line
        rule = str(node.data)
        if rule in _NESTING_STATEMENTS:
            statements += 1
            if statements > MAX_STATEMENT_NESTING:
                raise StUnsupportedError(
                    f"{unit.where(line)}: {_NESTING_STATEMENTS[rule]} nested {statements} deep: statements (IF, CASE, "
                    f"FOR, WHILE, REPEAT, __TRY) nest at most {MAX_STATEMENT_NESTING} deep (MAX_STATEMENT_NESTING)"
                )
        elif rule == "expression":
            expressions += 1
            if expressions - 1 > MAX_EXPRESSION_NESTING:
                raise StUnsupportedError(
                    f"{unit.where(line)}: an expression nested {expressions - 1} deep: parentheses, call arguments and "
                    f"subscripts nest at most {MAX_EXPRESSION_NESTING} deep in one expression (MAX_EXPRESSION_NESTING)"
                )
        if rule in _OPERATOR_RULES:
            operators += sum(isinstance(child, lark.Token) for child in node.children)
            if operators > MAX_EXPRESSION_OPERATORS:
                raise StUnsupportedError(
                    f"{unit.where(line)}: more than {MAX_EXPRESSION_OPERATORS} operators chained or nested in one "
                    "expression (MAX_EXPRESSION_OPERATORS); split it with intermediate variables"
                )
        if depth > MAX_PARSE_DEPTH:
            raise StUnsupportedError(
                f"{unit.where(line)}: the source nests more than {MAX_PARSE_DEPTH} levels deep in its parse tree "
                "(MAX_PARSE_DEPTH)"
            )
        stack.extend(
            (child, line, statements, expressions, operators, depth + 1)
            for child in node.children if isinstance(child, lark.Tree)
        )


def _syntax_detail(exc: Exception, text: str) -> str:
    token = getattr(exc, "token", None)
    line = getattr(exc, "line", None)
    source_line = ""
    if isinstance(line, int) and 0 < line <= len(text.splitlines()):
        source_line = text.splitlines()[line - 1].strip()
    if token is not None:
        return f"unexpected {str(token)!r} in {source_line!r}"
    return f"cannot parse {source_line!r}" if source_line else type(exc).__name__
