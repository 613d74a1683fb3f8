"""Structured Text both ways: ``load`` and ``to_python`` read it, ``dump`` and ``export`` write it.

``st.load(source)`` reads ST text, an ``.st`` file, a TwinCAT file
(``.TcPOU``, ``.TcDUT``, ``.TcGVL``, ``.TcIO``), a folder of them or a
``.plcproj``, and returns a module whose attributes are the ST names:
FUNCTION_BLOCK, STRUCT, UNION, INTERFACE and enumeration names are classes,
PROGRAM and GVL names are their single instances, FUNCTIONs are callables.
``st.to_python(source)`` returns the Python module ``load`` runs: readable
iecoop code, one class per POU, that passes ``mypy --strict``.

The parser is blark (https://github.com/klauer/blark, GPL-2.0), installed by
the ``st`` extra (``pip install "iecoop[st]"``); ``import iecoop`` does not
need it, and ``load`` / ``to_python`` without it raise an ImportError that
names the extra.

>>> from iecoop import st
>>> plc = st.load('''
... FUNCTION_BLOCK FB_Counter
... VAR_INPUT bUp : BOOL; END_VAR
... VAR_OUTPUT nCount : INT; END_VAR
... IF bUp THEN nCount := nCount + 1; END_IF
... END_FUNCTION_BLOCK
... ''')
>>> counter = plc.FB_Counter()
>>> counter(bUp=True); counter(bUp=True); counter.nCount
2
"""

from __future__ import annotations

import contextlib
import contextvars
import gc
import linecache
import os
import pathlib
import re
import sys
import types
from collections.abc import Callable, Iterator, Mapping, Sequence
from typing import Any, TypeVar

from iecoop._codegen import script_number
from iecoop.exceptions import DefinitionError
from iecoop.st.read import origin
from iecoop.st.read.names import python_name
from iecoop.st.read.parse import StSyntaxError, StUnsupportedError, library_references, parse_sources
from iecoop.st.read.sourcemap import compile_mapped, register_text
from iecoop.st.export import StExportError, dump, export

__all__ = [
    "StExportError", "StModule", "StSyntaxError", "StUnsupportedError", "dump", "export", "external", "load", "to_python",
]

_F = TypeVar("_F", bound=Callable[..., Any])


_Translation = tuple[str, list[tuple[str, str]], list[tuple[str, int] | None]]


def _translator() -> Callable[..., _Translation]:
    """``read.translate.translate_mapped``, or an ImportError naming the extra when blark is not installed."""
    try:
        from iecoop.st.read.translate import translate_mapped as translate
    except ModuleNotFoundError as exc:
        missing = (exc.name or "").partition(".")[0]
        if missing not in ("blark", "lark", "lxml"):
            raise
        raise ImportError(
            f"iecoop.st needs the blark parser ({missing} is not installed): pip install \"iecoop[st]\""
        ) from None
    return translate


@contextlib.contextmanager
def _collector_paused() -> Iterator[None]:
    """Python's cycle collector paused while loading: a load makes many objects and few cycles, and the
    collector's passes over every object alive took a third of a warm load of 60 files."""
    if not gc.isenabled():  # paused by an outer load (a library's), or by the program
        yield
        return
    gc.disable()
    try:
        yield
    finally:
        gc.enable()


def external(name: str) -> Callable[[_F], _F]:
    """Mark a FUNCTION declared without a body (or ``{external}``): ``load(..., externals={name: callable})`` binds it."""

    def mark(function: _F) -> _F:
        setattr(function, "__iecoop_external__", name)
        return function

    return mark


class StModule(types.ModuleType):
    """The result of ``load``: ST names as attributes (case-insensitive, as ST names are).

    A name Python cannot spell is reached by its ST name through ``getattr``:
    ``getattr(plc, "in")`` is the FUNCTION_BLOCK ``in`` (``plc.in_``).
    """

    __python__: str
    __all__: list[str]
    __qualified_only__: list[str]
    #: what each object was read from (see ``iecoop.st.read.origin``), by ST name
    __st_sources__: dict[str, Any]
    #: the name of the project read (its ``.plcproj``, folder or file), which export names its project file after
    __st_project__: str | None
    #: the libraries the project read references (its ``.plcproj``), which export references again
    __st_references__: list[Any]

    def __getattr__(self, name: str) -> Any:
        lowered = name.lower()
        for key, value in self.__dict__.items():
            if key.lower() == lowered and not key.startswith("__"):
                return value
        # An ST name the naming rule changed (in -> in_, _x -> st_x_): the key is made from it.
        for key, value in self.__dict__.items():
            for spelled in (key[:-1], key[2:-1]):
                if spelled.lower() == lowered and key in (python_name(spelled), python_name(spelled, attribute=True)):
                    return value
        raise AttributeError(f"the loaded Structured Text declares no {name!r}")


def _source_name(source: str | os.PathLike[str]) -> str:
    if not isinstance(source, str) or (source.strip() and "\n" not in source and pathlib.Path(source).exists()):
        return pathlib.Path(source).name
    return "st"


def to_python(
    source: str | os.PathLike[str],
    *,
    libraries: Mapping[str, str | os.PathLike[str] | types.ModuleType] | None = None,
    library_path: Sequence[str | os.PathLike[str]] | None = None,
    cache: bool | None = None,
) -> str:
    """The readable Python module for ``source``: iecoop code, ST names kept, comments carried over.

    ``libraries`` and ``library_path`` bind the libraries the source uses, as for ``load``; the module
    imports what it uses from them.

    >>> from iecoop import st
    >>> print(st.to_python("TYPE E_Mode : (IDLE, RUN := 5) INT; END_TYPE"))
    \"\"\"Generated by iecoop.st from Structured Text; edit freely, it is plain iecoop code.\"\"\"
    <BLANKLINE>
    from __future__ import annotations
    <BLANKLINE>
    from iecoop import INT, IecEnum
    <BLANKLINE>
    <BLANKLINE>
    class E_Mode(IecEnum, base=INT):
        \"\"\"TYPE E_Mode (enumeration).\"\"\"
        IDLE = 0
        RUN = 5
    <BLANKLINE>
    """
    with _collector_paused():
        text, *_ = _translated(source, [], _bound_libraries(source, libraries, library_path, None, cache), cache)
    return text


def _translated(
    source: str | os.PathLike[str], externals: list[str], libraries: Sequence[Any] = (), cache: bool | None = None
) -> tuple[str, list[tuple[str, str]], list[tuple[str, int] | None], set[str], list[Any]]:
    """The Python module text, top-level names, ST line of each Python line, qualified-only names and parsed
    units for ``source``; nesting beyond the parser's limits is refused."""
    translate = _translator()
    units = parse_sources(source, cache=cache)
    qualified: set[str] = set()
    try:
        text, names, origins = translate(units, externals=externals, libraries=libraries, qualified_only=qualified)
        return text, names, origins, qualified, units
    except RecursionError:  # only beyond the limits read.parse checks, e.g. when called from a deep stack
        raise StUnsupportedError(f"{_source_name(source)}: the source nests too deeply to translate") from None


#: the libraries being loaded (resolved paths), innermost last: a reference back to one is a cycle
_loading: contextvars.ContextVar[tuple[pathlib.Path, ...]] = contextvars.ContextVar("iecoop_st_loading", default=())
#: the libraries one top-level ``load`` has loaded, by resolved path (a library two others use is loaded once)
_loaded: contextvars.ContextVar[dict[pathlib.Path, StModule] | None] = contextvars.ContextVar("iecoop_st_loaded", default=None)


def _bound_libraries(
    source: str | os.PathLike[str],
    libraries: Mapping[str, str | os.PathLike[str] | types.ModuleType] | None,
    library_path: Sequence[str | os.PathLike[str]] | None,
    profile: str | None,
    cache: bool | None = None,
) -> list[Any]:
    """The libraries ``source`` uses (its ``.plcproj`` references and ``libraries=``), ST ones loaded."""
    _translator()  # the ImportError naming the extra, before the reader is imported
    from iecoop.st.read.libraries import resolve
    from iecoop.st.read.parse import library_references

    def load_library(path: pathlib.Path) -> types.ModuleType:
        key = _library_key(path)
        chain = _loading.get()
        if key in chain:
            names = " -> ".join(p.name for p in (*chain[chain.index(key):], key))
            raise DefinitionError(f"{path}: libraries reference each other in a cycle: {names}")
        loaded = _loaded.get()
        if loaded is not None and key in loaded:
            return loaded[key]
        token = _loading.set((*chain, key))
        try:
            module = load(path, profile=profile, library_path=library_path, cache=cache)
        finally:
            _loading.reset(token)
        if loaded is not None:
            loaded[key] = module
        return module

    references = library_references(source)
    if not references and not libraries:
        return []
    top = _loaded.get() is None
    token = _loaded.set({}) if top else None
    outer = _loading.set((_library_key(pathlib.Path(source)),)) if top and not isinstance(source, str) or (
        isinstance(source, str) and top and "\n" not in source and pathlib.Path(source).exists()) else None
    try:
        return resolve(references, libraries, library_path, load_library)
    finally:
        if outer is not None:
            _loading.reset(outer)
        if token is not None:
            _loaded.reset(token)


def _library_key(path: pathlib.Path) -> pathlib.Path:
    """A library's identity: its ``.plcproj`` (the one in its folder, if the folder has one), resolved."""
    projects = sorted(path.glob("*.plcproj")) if path.is_dir() else []
    return (projects[0] if len(projects) == 1 else path).resolve()


def _generated_failure(source: str | os.PathLike[str], exc: BaseException) -> StUnsupportedError:
    """The error for generated Python that CPython refuses: it names the ST source, never a raw internal error."""
    where = _source_name(source)
    line = getattr(exc, "lineno", None)
    at = f" (line {line} of the generated Python)" if isinstance(line, int) else ""
    message = getattr(exc, "msg", None) or str(exc) or type(exc).__name__
    return StUnsupportedError(f"{where}: the Python generated for it cannot run{at}: {type(exc).__name__}: {message}")


def _class_failure(
    source: str | os.PathLike[str], text: str, filename: str, exc: Exception, st_files: Mapping[str, str]
) -> DefinitionError:
    """The error for a generated class that cannot be made, at the ST file and line of its declaration.

    The class builder checks what ST compilers check (an interface method left unimplemented, ...); its
    DefinitionError gets the place of the POU or type it is about. Any other error means Python the
    translator should not have written: an StUnsupportedError at the same place, never a raw internal error.
    """
    line = None
    mapped: tuple[str, int] | None = None
    trace = exc.__traceback__
    while trace is not None:
        code_file = trace.tb_frame.f_code.co_filename
        if code_file == filename:
            line, mapped = trace.tb_lineno, None
        elif code_file in st_files:  # compiled under the ST file's name and lines (source maps)
            mapped = (st_files[code_file], trace.tb_lineno)
        trace = trace.tb_next
    if mapped is not None:
        where = f"{mapped[0]}:{mapped[1]}"
        if isinstance(exc, DefinitionError):
            return exc if re.match(r"\S+:\d+: ", str(exc)) else type(exc)(f"{where}: {exc}")
        return StUnsupportedError(f"{where}: the Python generated for this declaration cannot run: {type(exc).__name__}: {exc}")
    name = None
    lines = text.splitlines()
    for at in range(min(line or 0, len(lines)) - 1, -1, -1):
        head = re.match(r"(?:class|def) (\w+)", lines[at])
        if head:
            name = head.group(1)
            break
    where, what = _declared_at(source, name)
    if isinstance(exc, DefinitionError):
        return exc if re.match(r"\S+:\d+: ", str(exc)) else type(exc)(f"{where}: {exc}")
    return StUnsupportedError(
        f"{where}: the Python generated for {what} cannot run: {type(exc).__name__}: {exc}"
    )


#: The ST keyword of each top-level declaration blark reads, by its node class.
_KEYWORDS = {
    "FunctionBlock": "FUNCTION_BLOCK", "Program": "PROGRAM", "Function": "FUNCTION", "Interface": "INTERFACE",
    "GlobalVariableDeclarations": "VAR_GLOBAL",
}


def _declared_at(source: str | os.PathLike[str], name: str | None) -> tuple[str, str]:
    """``file:line`` and kind of the top-level ST declaration a generated class or function ``name`` comes from."""
    import blark.transform as tf

    units = parse_sources(source)  # parsed before: the parser's cache answers
    for unit in units:
        for item in getattr(unit.tree, "items", ()):
            inner = item.declaration if isinstance(item, tf.DataTypeDeclaration) else item
            st_name = str(getattr(inner, "name", "") or "")
            if name is not None and st_name and name in (st_name, python_name(st_name)):
                line = getattr(getattr(item, "meta", None), "line", None)
                return unit.where(line if isinstance(line, int) else 1), f"{_KEYWORDS.get(type(inner).__name__, 'TYPE')} {st_name}"
    first = units[0] if units else None
    return (first.where(1) if first is not None else f"{_source_name(source)}:1"), "the source"


def load(
    source: str | os.PathLike[str],
    *,
    profile: str | None = None,
    externals: Mapping[str, Callable[..., Any]] | None = None,
    package: str | None = None,
    libraries: Mapping[str, str | os.PathLike[str] | types.ModuleType] | None = None,
    library_path: Sequence[str | os.PathLike[str]] | None = None,
    cache: bool | None = None,
) -> StModule:
    """Load Structured Text as live iecoop classes and instances (see the module docstring).

    ``profile`` ("twincat" or "codesys") is active while the PROGRAM and GVL
    instances are created; ``externals`` binds FUNCTIONs declared without a
    body (or marked ``{external}``) to Python callables. ``package`` is the
    Python package the loaded POUs belong to, the namespace INTERNAL is
    checked against (a TwinCAT PLC project or library is one namespace): by
    default the text is a namespace of its own, so only its own code reaches
    its INTERNAL members; with ``package="plant"`` code in ``plant`` does too.

    Libraries: the names a library declares resolve plain (``TON``) and qualified by its namespace
    (``Tc2_Standard.TON``). A ``.plcproj``'s ``<PlaceholderReference>`` / ``<LibraryReference>`` items
    are bound, each found in this order: ``libraries`` (title or namespace -> a folder or ``.plcproj``
    of ST, loaded as a library with its own references, or a module of iecoop classes whose
    ``__all__`` lists its ST names), the folders of ``library_path``, those of the environment
    variable ``IECOOP_LIBRARY_PATH`` (``os.pathsep``-separated; a library is ``<Name>/``,
    ``<Name>.plcproj`` or ``<Name>/<Name>.plcproj`` there), then the libraries iecoop ships
    (``iecoop.libraries.KNOWN``). Every entry of ``libraries`` is bound too, under its key as
    namespace, so plain ST text can use one. A reference found nowhere, or libraries that reference
    each other in a cycle, is a DefinitionError.

    Each file's parse is cached in ``__iecoop_cache__`` beside it (or the
    user's cache folder), keyed by its text and the iecoop, blark, lark and
    Python versions; ``cache=False`` (or the environment variable
    ``IECOOP_ST_CACHE=0``) parses afresh and writes nothing.
    """
    with _collector_paused():
        return _load(source, profile, dict(externals or {}), package, libraries, library_path, cache)


def _load(
    source: str | os.PathLike[str],
    profile: str | None,
    externals: dict[str, Callable[..., Any]],
    package: str | None,
    libraries: Mapping[str, str | os.PathLike[str] | types.ModuleType] | None,
    library_path: Sequence[str | os.PathLike[str]] | None,
    cache: bool | None,
) -> StModule:
    """``load``'s steps: the libraries, the translation, the module compiled and run, externals bound, PROGRAMs made."""
    from iecoop.profiles import use_profile

    used = _bound_libraries(source, libraries, library_path, profile, cache)
    text, names, origins, qualified, units = _translated(source, list(externals), used, cache)
    number = script_number()
    if package is not None and not all(part.isidentifier() for part in package.split(".")):
        raise ValueError(f"st.load: package must be a dotted Python name, got {package!r}")
    generated = _Generated(source, text, origins, number)
    module = _new_module(f"{package}.iecoop_st_{number}" if package else f"iecoop_st_{number}", generated, names, qualified)
    # before the PROGRAMs and GVLs are made: their blocks' instance paths start with it (<project>.MAIN.fbLog)
    module.__st_project__ = origin.project_name(source)
    try:
        with use_profile(profile) if profile is not None else contextlib.nullcontext():
            _run(module, generated)
            unbound = _bind_externals(module.__dict__, externals)
            _make_programs(module.__dict__, names, source)
        if unbound:
            raise StUnsupportedError(
                f"{_declared_at(source, unbound[0])[0]}: FUNCTION {unbound[0]} has no body and no Python callable: "
                f"pass externals={{{unbound[0]!r}: ...}}"
            )
    except BaseException:
        del sys.modules[module.__name__]
        raise
    # what each object was read from: export writes an object unchanged in Python back as it was read
    module.__st_sources__ = origin.sources(units, module.__dict__, source if isinstance(source, str) and _source_name(source) == "st" else None)
    module.__st_references__ = library_references(source)
    return module


class _Generated:
    """The generated module of one ``load``: its text, compiled under the ST files' names and lines (source maps)."""

    def __init__(self, source: str | os.PathLike[str], text: str, origins: list[tuple[str, int] | None], number: int) -> None:
        self.source, self.text, self.origins = source, text, origins
        self.filename = f"<iecoop.st {_source_name(source)} #{number}>"
        #: a unit's file name -> the name it is shown under (ST given as text: ``<st text #N>``)
        self.rename: dict[str, str] = {}
        if isinstance(source, str) and any(origin is not None and origin[0] == "<st>" for origin in origins):
            self.rename["<st>"] = f"<st text #{number}>"
            register_text(self.rename["<st>"], source)
        linecache.cache[self.filename] = (len(text), None, text.splitlines(True), self.filename)
        try:
            self.codes = compile_mapped(text, origins, self.filename, self.rename)
        except (SyntaxError, RecursionError, MemoryError, ValueError) as exc:  # the limits read.parse checks keep this rare
            raise _generated_failure(source, exc) from exc

    def st_files(self) -> dict[str, str]:
        """The name each ST file's code runs under -> the ST file."""
        return {self.rename.get(origin[0], origin[0]): origin[0] for origin in self.origins if origin is not None}


def _new_module(name: str, generated: _Generated, names: list[tuple[str, str]], qualified: set[str]) -> StModule:
    """The empty module ``load`` fills, in ``sys.modules`` so that annotations resolve through it, as for an import."""
    module = StModule(name, f"Loaded from Structured Text ({_source_name(generated.source)}).")
    module.__file__ = generated.filename
    module.__python__ = generated.text
    # what a project that uses this one as a library binds: its ST names, and those needing the namespace
    module.__all__ = [name for _kind, name in names]
    module.__qualified_only__ = sorted(qualified)
    sys.modules[name] = module
    return module


def _run(module: StModule, generated: _Generated) -> None:
    """Run the generated module's code in order (the classes are built); a failure names the ST file and line."""
    try:
        for code in generated.codes:
            exec(code, module.__dict__)  # noqa: S102 - the module iecoop generated, run in order
    except (RecursionError, MemoryError) as exc:
        raise _generated_failure(generated.source, exc) from exc
    except Exception as exc:  # noqa: BLE001 - a class the builder refuses, or Python the translator should not have written
        raise _class_failure(generated.source, generated.text, generated.filename, exc, generated.st_files()) from exc


def _bind_externals(namespace: dict[str, Any], externals: Mapping[str, Callable[..., Any]]) -> list[str]:
    """Put each callable of ``externals`` in place of the FUNCTION without a body it names; the names left unbound."""
    lowered = {k.lower(): v for k, v in externals.items()}
    unbound = []
    for key, value in list(namespace.items()):
        marker = getattr(value, "__iecoop_external__", None)
        if marker is not None:
            bound = lowered.get(marker.lower())
            if bound is None:
                unbound.append(marker)
            else:
                namespace[key] = bound
    return unbound


def _make_programs(namespace: dict[str, Any], names: list[tuple[str, str]], source: str | os.PathLike[str]) -> None:
    """Each PROGRAM's single instance, where the module has not made it itself."""
    for kind, name in names:
        if kind == "program" and isinstance(namespace[name], type):
            try:
                namespace[name] = namespace[name]()
            except (DefinitionError, TypeError, ValueError, AttributeError, MemoryError, RecursionError) as exc:  # FB_init ...
                where, _ = _declared_at(source, name)
                error = type(exc) if isinstance(exc, DefinitionError) else StUnsupportedError
                why = str(exc) or ("the machine has no memory for its variables" if isinstance(exc, MemoryError) else "")
                raise error(f"{where}: PROGRAM {name} cannot be made: {type(exc).__name__}: {why}") from exc
