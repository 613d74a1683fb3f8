"""Write Structured Text: iecoop classes to plain ST, TwinCAT source files or PLCopen XML.

``dump`` gives the flat text (each METHOD and PROPERTY accessor follows the
FUNCTION_BLOCK or INTERFACE it belongs to); ``export`` writes a folder.
"""

from __future__ import annotations

import dataclasses
import os
import sys
import types
from collections.abc import Collection
from pathlib import Path
from typing import Any

from iecoop.libraries import Library
from iecoop.st.read.origin import Source, fingerprint
from iecoop.st.write.recorded import Declared, declared_in_python, recorded
from iecoop.st.write.references import plcproj, used_libraries
from iecoop.st.write import StExportError, Unit, collect, flat_text, ident, plcopen_project, twincat_file, units, with_dependencies

__all__ = ["StExportError", "dump", "export"]


def _units(classes_or_module: Any, lenient: bool, kept: Collection[str] = (), report: list[str] | None = None) -> list[Unit]:
    """The writer's units of the classes, but those of ``kept`` (written as they were read); what was
    written as a comment is added to ``report``."""
    metas = [
        meta for meta in with_dependencies(collect(classes_or_module))
        if meta.name.lower() not in kept and not _other_loaded_project(meta.cls, classes_or_module)
    ]
    # A loaded object that goes through the writer keeps what its source declared beyond its class.
    found_in_source = _declared(metas)
    exported = frozenset(meta.cls for meta in metas if meta.kind == "gvl")
    metas = [
        dataclasses.replace(meta, declared=found_in_source.get(meta.name.lower()) or (
            declared_in_python(meta.cls, exported) if meta.kind in ("fb", "program", "struct", "union", "gvl") else None))
        for meta in metas
    ]
    found, untranslated = units(metas, lenient=lenient, functions={k: v for k, v in _loaded_functions(classes_or_module).items() if k.lower() not in kept})
    if report is not None:
        report.extend(untranslated)
    return [unit for unit in found if unit.name.lower() not in kept]


def _declared(metas: list[Any]) -> dict[str, Declared]:
    """What the ST source of each class ``st.load`` made (of the module exported or picked one by one) declared
    beyond the class, by lower-case ST name."""
    found: dict[str, Declared] = {}
    by_module: dict[str, list[str]] = {}
    for meta in metas:
        module = sys.modules.get(getattr(meta.cls, "__module__", "") or "")
        recorded_names = {name.lower(): name for name in getattr(module, "__st_sources__", None) or {}}
        if module is not None and meta.name.lower() in recorded_names:
            by_module.setdefault(module.__name__, []).append(recorded_names[meta.name.lower()])
    for module_name, names in by_module.items():
        found.update(recorded(sys.modules[module_name], names))
    return found


def _other_loaded_project(cls: Any, source: Any) -> bool:
    """``cls`` comes from another project ``st.load`` read: an ST library the exported project references."""
    if not (isinstance(source, types.ModuleType) and hasattr(source, "__st_sources__")):
        return False  # classes picked one by one are written, wherever they come from
    module = sys.modules.get(getattr(cls, "__module__", "") or "")
    return module is not None and module is not source and hasattr(module, "__st_sources__")


def _loaded_functions(source: Any) -> dict[str, Any]:
    """The FUNCTIONs of a module ``st.load`` made (its ST names that are Python functions), by ST name."""
    if not isinstance(source, types.ModuleType) or not hasattr(source, "__st_sources__"):
        return {}
    return {name: value for name in getattr(source, "__all__", ()) if isinstance(value := getattr(source, name, None), types.FunctionType)}


def _unchanged(source: Any, format: str) -> dict[str, Source]:
    """The objects of a module loaded by ``st.load`` that are as they were read, in the format they were read
    in, by lower-case ST name: export writes their recorded text (comments, layout, Ids and all)."""
    recorded: dict[str, Source] = getattr(source, "__st_sources__", None) or {} if isinstance(source, types.ModuleType) else {}
    return {
        name.lower(): origin
        for name, origin in recorded.items()
        # A PLCopen export is one file holding every object: the writer writes it whole, never in pieces.
        if origin.format == format != "plcopen" and fingerprint(getattr(source, name, None)) == origin.fingerprint
    }


def dump(classes_or_module: Any, *, lenient: bool = False, report: list[str] | None = None) -> str:
    """The flat ST text of a module's (or a list of) declared classes: types, GVLs, interfaces, POUs.

    A statement outside the translated subset raises StExportError naming the
    file and line; ``lenient=True`` writes it as an ST comment instead, and
    adds a line naming it to ``report`` when one is given.
    """
    return "\n".join(flat_text(unit) for unit in _units(classes_or_module, lenient, report=report))


def export(classes_or_module: Any, folder: str | os.PathLike[str], *, format: str = "twincat", lenient: bool = False, report: list[str] | None = None) -> list[Path]:
    """Write the classes to ``folder`` and return the files written, in order.

    ``format="twincat"``: one ``.TcPOU`` per POU (its METHODs and PROPERTYs
    inside), ``.TcDUT`` per data type, ``.TcGVL`` per GVL, ``.TcIO`` per
    interface, with ids derived from the names, so exporting again writes
    the same bytes. ``format="plcopen"``: one PLCopen XML file (TC6 2.01).
    ``format="st"``: the flat text of :func:`dump`, one ``.st`` file per object.
    A TwinCAT export whose classes use a library iecoop ships (``iecoop.libraries``, beyond the
    standard blocks every project has) also writes a ``.plcproj`` that compiles the files and
    references each library (``<PlaceholderReference>``); the library's own classes are never written.

    Files are written only directly in ``folder``, never through a symbolic link,
    and only once every one of them is made. A name that is not an ST identifier
    (letter or underscore, then ASCII letters, digits and underscores), a class
    named like an ST keyword, and two names of one scope that differ only in case
    raise StExportError; a variable, METHOD, PROPERTY or enumeration value named
    like a keyword is written with a trailing underscore (``TO`` -> ``TO_``).

    A module made by ``st.load``: each object unchanged in Python since loading is written back as it was
    read (its TwinCAT file byte for byte, or its ST text) when ``format`` is the one it was read in; a
    changed or added object goes through the writer. With ``lenient=True`` each statement written as a
    comment is appended to ``report``.
    """
    if format not in ("twincat", "st", "plcopen"):
        raise ValueError(f"export format must be 'twincat', 'plcopen' or 'st', got {format!r}")
    kept = _unchanged(classes_or_module, format)
    found = _units(classes_or_module, lenient, kept, report)
    project = _project_folder(classes_or_module) if format == "twincat" else None
    files: list[tuple[str, str | bytes]] = [(_kept_name(origin, project), origin.text) for origin in kept.values()]
    if format == "twincat":
        files += _twincat_files(classes_or_module, found, len(kept), project, [name for name, _ in files])
    elif format == "st":
        files += [(f"{unit.name}.st", flat_text(unit)) for unit in found]
    else:
        name = _project_name(classes_or_module, found)
        files = [(f"{name}.xml", plcopen_project(name, found))]
    # Every file is made before the first is written: a refused name leaves the folder as it was.
    target = Path(folder)
    target.mkdir(parents=True, exist_ok=True)
    # Only a loaded project's own layout has folders in its names (POUs/MAIN.TcPOU), never a name ST gave.
    layout = {_kept_name(origin, project) for origin in _recorded(classes_or_module).values()} | {
        _relative(path, project) for path in _task_files(project)}
    return [_write(target, file_name, text, nested=file_name in layout) for file_name, text in files]


def _twincat_files(source: Any, found: list[Unit], kept: int, project: Path | None, kept_names: list[str]) -> list[tuple[str, str | bytes]]:
    """The TwinCAT files of the units written, then the project file and the task files of a loaded project.

    A changed object goes where it was read from (``POUs/``, ``DUTs/`` ...), a new one beside the project file;
    a project of which nothing changed gets its ``.plcproj`` as read."""
    origins = {name.lower(): origin for name, origin in _recorded(source).items()}
    files: list[tuple[str, str | bytes]] = []
    for unit in found:
        file_name, text = twincat_file(unit)
        origin = origins.get(unit.name.lower())
        files.append((_kept_name(origin, project) if origin is not None and origin.format == "twincat" else file_name, text))
    libraries = _referenced(source, used_libraries(unit.meta for unit in found if unit.meta is not None))
    if not (libraries or kept):
        return files
    # a project file, so loading the folder binds the libraries again
    name = _project_name(source, found)
    tasks = [(_relative(path, project), path.read_bytes()) for path in _task_files(project)]
    original = project / f"{name}.plcproj" if project is not None else None
    if original is not None and not found and kept == len(origins) and original.is_file():
        files.append((original.name, original.read_bytes()))  # nothing changed: the project file as read
    else:
        compiled = [file_name.replace("/", "\\") for file_name in [*kept_names, *(n for n, _ in files)]]
        files.append((f"{name}.plcproj", plcproj(name, compiled, libraries, [n.replace("/", "\\") for n, _ in tasks])))
    return files + tasks


def _referenced(source: Any, libraries: list[Library]) -> list[Library]:
    """The libraries the project read references (a loaded module's ``.plcproj``), then those ``libraries`` add."""
    kept = [
        Library(reference.name, "", reference.company, reference.version, "", reference.namespace)
        for reference in getattr(source, "__st_references__", ()) if isinstance(source, types.ModuleType)
    ]
    return kept + [library for library in libraries if library.name.lower() not in {k.name.lower() for k in kept}]


def _recorded(source: Any) -> dict[str, Source]:
    return dict(getattr(source, "__st_sources__", None) or {}) if isinstance(source, types.ModuleType) else {}


def _project_folder(source: Any) -> Path | None:
    """The folder of the TwinCAT project (its ``.plcproj``) a module was loaded from, None for another module."""
    project = getattr(source, "__st_project__", None) if isinstance(source, types.ModuleType) else None
    origins = [o for o in _recorded(source).values() if o.format == "twincat"]
    if not isinstance(project, str) or not origins:
        return None
    path = Path(origins[0].file).resolve()
    return next((parent for parent in list(path.parents)[:4] if (parent / f"{project}.plcproj").is_file()), None)


def _task_files(project: Path | None) -> list[Path]:
    """The task files (``.TcTTO``) of a TwinCAT project, written as read: the exported project runs on the same
    cycle time and priority (``iecoop st run`` and ``iecoop serve`` read them)."""
    if project is None:
        return []
    return sorted(p for p in project.rglob("*.TcTTO") if p.is_file() and not p.is_symlink() and "__iecoop_cache__" not in p.parts)


def _relative(path: Path, project: Path | None) -> str:
    """``path`` inside the project folder as a relative name (``POUs/MAIN.TcPOU``), or its file name."""
    resolved = path.resolve()
    if project is not None and resolved.is_relative_to(project):
        return resolved.relative_to(project).as_posix()
    return path.name


def _kept_name(origin: Source, project: Path | None = None) -> str:
    """The file an object written as it was read goes to: its TwinCAT file where it was in the project
    (``POUs/MAIN.TcPOU``), or ``NAME.st``."""
    return _relative(Path(origin.file), project) if origin.format == "twincat" else f"{origin.name}.st"


def _project_name(source: Any, found: list[Unit]) -> str:
    name = getattr(source, "__st_project__", None) or getattr(source, "__name__", None)
    if isinstance(name, str):
        project = name.rsplit(".", 1)[-1]
        ident(project, "the PLCopen project (the module's name)")  # it names the file
        return project
    return found[0].name if found else "project"


def _write(folder: Path, name: str, text: str | bytes, *, nested: bool = False) -> Path:
    """Write ``folder/name``, which must be a file right in ``folder`` (the names were checked before, this
    holds whatever the name), or with ``nested`` (a loaded project's own layout) in a folder of plain names
    under it: no path leaves the folder, and no symbolic link in it is written through."""
    base = folder.resolve()
    parts = name.split("/") if nested else [name]  # a loaded project's own layout (POUs/MAIN.TcPOU): plain names
    if any(not part or part in (".", "..") or os.sep in part or (os.altsep and os.altsep in part) for part in parts):
        raise StExportError(f"export: the file name {name!r} is outside the folder {str(folder)!r}; nothing is written outside it")
    parent = base
    for part in parts[:-1]:
        parent = parent / part
        if parent.is_symlink():
            raise StExportError(f"export: {str(parent)!r} is a symbolic link; export does not write through links: remove it")
        parent.mkdir(exist_ok=True)
    path = parent / parts[-1]
    if not path.parent.resolve().is_relative_to(base):
        raise StExportError(f"export: the file name {name!r} is outside the folder {str(folder)!r}; nothing is written outside it")
    if path.is_symlink():
        raise StExportError(
            f"export: {str(path)!r} is a symbolic link (to {os.readlink(path)!r}); export does not write through links: remove it"
        )
    # O_NOFOLLOW: a link made between the check and the write is refused by the system too.
    flags = os.O_WRONLY | os.O_CREAT | os.O_TRUNC | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_BINARY", 0)
    try:
        descriptor = os.open(path, flags, 0o666)
    except OSError as exc:
        if path.is_symlink():
            raise StExportError(f"export: {str(path)!r} is a symbolic link; export does not write through links: remove it") from None
        raise StExportError(f"export: cannot write {str(path)!r} ({exc.strerror})") from None
    # Bytes, not text mode: the files are the same on every platform (CRLF as TwinCAT writes them).
    with os.fdopen(descriptor, "wb") as file:
        file.write(text if isinstance(text, bytes) else text.encode("utf-8"))
    return folder / name
