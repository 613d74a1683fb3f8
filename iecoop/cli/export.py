"""``iecoop export``: a Python module of iecoop classes written as TwinCAT files, PLCopen XML or plain ST.

``iecoop export MODULE --format twincat|plcopen|st -o DIR`` writes the
module's classes (a dotted module name, or the names a plugged-in catalogue
knows) as TwinCAT source files, one PLCopen XML file or plain ST files.
Statements with no ST form are written as ST comments that say so (the
command never stops half way); ``--strict`` makes them an error.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence
from types import ModuleType
from typing import TextIO

from iecoop.cli.base import Command, Names
from iecoop.st.export import StExportError, export

__all__ = ["EXPORT_HELP", "add_export_arguments", "command", "export_command", "module_of"]

#: The help line of ``iecoop export``.
EXPORT_HELP = "write a pattern, example or module as TwinCAT files, PLCopen XML or plain ST"


def module_of(name: str, names: Names | None = None) -> ModuleType:
    """The module a catalogue of ``names`` calls ``name``, or the module of that dotted name; KeyError if none."""
    found = names.module(name) if names is not None else None
    if found is not None:
        return found
    try:
        return importlib.import_module(name)
    except ImportError:
        what = f"{names.what} or module" if names is not None else "module"
        raise KeyError(f"no {what} named {name!r}") from None


def add_export_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``iecoop export``."""
    parser.add_argument("name", help="catalogue entry (observer, srp, ch08...) or module (patterns.behavioral.state)")
    parser.add_argument("--format", choices=("twincat", "plcopen", "st"), default="twincat")
    parser.add_argument("-o", "--output", default=".", help="folder to write into (created if missing)")
    parser.add_argument("--strict", action="store_true", help="fail on a statement with no ST form")


def command(names: Names | None = None) -> Command:
    """The ``iecoop export`` subcommand, taking the names of ``names`` besides dotted module names."""

    def run(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
        try:
            module = module_of(args.name, names)
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

    return Command(EXPORT_HELP, add_export_arguments, run)


def export_command(argv: Sequence[str], out: TextIO | None = None, names: Names | None = None) -> int:
    """``iecoop export MODULE --format twincat|plcopen|st -o DIR``; the exit status."""
    parser = argparse.ArgumentParser(prog="iecoop export", description="Write a design as Structured Text files.")
    add_export_arguments(parser)
    return command(names).run(parser.parse_args(list(argv)), out if out is not None else sys.stdout, sys.stderr)
