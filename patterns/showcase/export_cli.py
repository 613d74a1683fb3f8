"""``iecoop export`` and ``iecoop show NAME --st``: a catalogue entry (or any module) as Structured Text.

``iecoop export NAME|MODULE --format twincat|plcopen|st -o DIR`` writes the
entry's classes as TwinCAT source files, one PLCopen XML file or plain ST
files. Statements with no ST form are written as ST comments that say so
(the command never stops half way); ``--strict`` makes them an error.

>>> text = st_text("observer")
>>> "FUNCTION_BLOCK TemperatureTransmitter IMPLEMENTS ISubject" in text
True
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence
from types import ModuleType
from typing import TextIO

from iecoop.st.export import StExportError, dump, export
from patterns.showcase.catalogue import find

__all__ = ["EXPORT_HELP", "add_export_arguments", "export_command", "export_run", "module_of", "st_text"]

#: The help line of ``iecoop export``.
EXPORT_HELP = "write a pattern, example or module as TwinCAT files, PLCopen XML or plain ST"


def module_of(name: str) -> ModuleType:
    """The module of a catalogue entry (``observer``), or a module by its dotted name."""
    try:
        return find(name).load()
    except KeyError:
        pass
    try:
        return importlib.import_module(name)
    except ImportError:
        raise KeyError(f"no catalogue entry or module named {name!r}") from None


def st_text(entry_name: str, *, strict: bool = False) -> str:
    """The generated ST of an entry (what ``iecoop show NAME --st`` prints)."""
    return dump(module_of(entry_name), lenient=not strict)


def add_export_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``iecoop export``."""
    parser.add_argument("name", help="catalogue entry (observer, srp, ch08...) or module (patterns.behavioral.state)")
    parser.add_argument("--format", choices=("twincat", "plcopen", "st"), default="twincat")
    parser.add_argument("-o", "--output", default=".", help="folder to write into (created if missing)")
    parser.add_argument("--strict", action="store_true", help="fail on a statement with no ST form")


def export_command(argv: Sequence[str], out: TextIO | None = None) -> int:
    """``iecoop export NAME|MODULE --format twincat|plcopen|st -o DIR``; the exit status."""
    parser = argparse.ArgumentParser(prog="iecoop export", description="Write a design as Structured Text files.")
    add_export_arguments(parser)
    return export_run(parser.parse_args(list(argv)), out if out is not None else sys.stdout, sys.stderr)


def export_run(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    """``iecoop export`` with its parsed arguments."""
    try:
        module = module_of(args.name)
        files = export(module, args.output, format=args.format, lenient=not args.strict)
    except KeyError as exc:
        print(f"iecoop export: {exc.args[0]}", file=err)
        return 2
    except StExportError as exc:
        print(f"iecoop export: {exc}", file=err)
        return 1
    for path in files:
        print(path, file=out)
    return 0
