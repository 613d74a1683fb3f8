"""Write Structured Text: iecoop classes to plain ST, TwinCAT source files or PLCopen XML.

``dump`` gives the flat text (each METHOD and PROPERTY accessor follows the
FUNCTION_BLOCK or INTERFACE it belongs to); ``export`` writes a folder.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from iecoop.st._emit_decl import Unit, flat_text, units
from iecoop.st._emit_model import StExportError, collect, with_dependencies

__all__ = ["StExportError", "dump", "export"]


def _units(classes_or_module: Any, lenient: bool) -> list[Unit]:
    found, _untranslated = units(with_dependencies(collect(classes_or_module)), lenient=lenient)
    return found


def dump(classes_or_module: Any, *, lenient: bool = False) -> str:
    """The flat ST text of a module's (or a list of) declared classes: types, GVLs, interfaces, POUs.

    A statement outside the translated subset raises StExportError naming the
    file and line; ``lenient=True`` writes it as an ST comment instead.
    """
    return "\n".join(flat_text(unit) for unit in _units(classes_or_module, lenient))


def export(classes_or_module: Any, folder: str | os.PathLike[str], *, format: str = "twincat", lenient: bool = False) -> list[Path]:
    """Write the classes to ``folder`` and return the files written, in order.

    ``format="twincat"``: one ``.TcPOU`` per POU (its METHODs and PROPERTYs
    inside), ``.TcDUT`` per data type, ``.TcGVL`` per GVL, ``.TcIO`` per
    interface, with ids derived from the names, so exporting again writes
    the same bytes. ``format="plcopen"``: one PLCopen XML file (TC6 2.01).
    ``format="st"``: the flat text of :func:`dump`, one ``.st`` file per object.
    """
    found = _units(classes_or_module, lenient)
    target = Path(folder)
    target.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    if format == "twincat":
        from iecoop.st._emit_files import twincat_file

        for unit in found:
            name, text = twincat_file(unit)
            written.append(_write(target / name, text))
    elif format == "st":
        for unit in found:
            written.append(_write(target / f"{unit.name}.st", flat_text(unit)))
    elif format == "plcopen":
        from iecoop.st._emit_files import plcopen_project

        name = _project_name(classes_or_module, found)
        written.append(_write(target / f"{name}.xml", plcopen_project(name, found)))
    else:
        raise ValueError(f"export format must be 'twincat', 'plcopen' or 'st', got {format!r}")
    return written


def _project_name(source: Any, found: list[Unit]) -> str:
    name = getattr(source, "__name__", None)
    if isinstance(name, str):
        return name.rsplit(".", 1)[-1]
    return found[0].name if found else "project"


def _write(path: Path, text: str) -> Path:
    # Bytes, not text mode: the files are the same on every platform (CRLF as TwinCAT writes them).
    path.write_bytes(text.encode("utf-8"))
    return path
