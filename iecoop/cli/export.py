"""``iecoop export``: a Python module of iecoop classes written as TwinCAT files, PLCopen XML or plain ST.

``iecoop export MODULE --format twincat|plcopen|st -o DIR`` writes the
module's classes (a ``.py`` file, a dotted module name, or a name a
plugged-in catalogue knows) as TwinCAT source files, one PLCopen XML file or plain ST files.
``MODULE`` may also be an ST project: a ``.plcproj``, a folder or an ST / TwinCAT file, loaded with
``st.load``; its objects unchanged since loading are written back as they were read. A statement with
no ST form is an error naming its file and line; ``--lenient`` writes it as an ST comment instead and
lists every such comment on stderr.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import os
import pathlib
import sys
from collections.abc import Sequence
from types import ModuleType
from typing import TextIO

from iecoop.cli.base import Command, Names, UsageError, usage_errors
from iecoop.exceptions import DefinitionError
from iecoop.st.export import StExportError, export

__all__ = ["EXPORT_HELP", "add_export_arguments", "command", "export_command", "module_of"]

#: The help line of ``iecoop export``.
EXPORT_HELP = "write a pattern, example or module as TwinCAT files, PLCopen XML or plain ST"


#: the file kinds ``iecoop export`` loads as Structured Text
ST_PATHS = (".st", ".tcpou", ".tcdut", ".tcgvl", ".tcio", ".plcproj")


def _from_file(path: pathlib.Path) -> ModuleType:
    if not path.exists():
        raise UsageError(f"{path}: does not exist")
    if path.is_dir() or path.suffix.lower() in ST_PATHS:
        from iecoop import st

        return st.load(path)
    if path.is_dir():
        raise UsageError(f"{path}: is a folder; give a .py file or a module's dotted name")
    if path.suffix != ".py":
        raise UsageError(f"{path}: not a Python file (.py) nor a module's dotted name")
    name = f"iecoop_export_{path.stem}"
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None  # a .py file always has a source loader
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # the classes' annotations resolve through it, as for an import
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[name]
        raise
    return module


def _path_like(name: str) -> bool:
    return name.endswith(".py") or "/" in name or os.sep in name or pathlib.Path(name).exists()


def _missing(exc: ImportError, name: str) -> bool:
    """True when ``exc`` says that ``name`` itself (or its package) is not there, not one of its imports."""
    return isinstance(exc, ModuleNotFoundError) and exc.name is not None and (name + ".").startswith(exc.name + ".")


def module_of(name: str, names: Names | None = None) -> ModuleType:
    """The module a catalogue of ``names`` calls ``name``, a ``.py`` file, or the module of that dotted name.

    KeyError for a name nothing has; :class:`UsageError` for a module that
    does not import (naming its file and line where Python gives them).
    """
    try:
        found = names.module(name) if names is not None else None
        if found is not None:
            return found
        if _path_like(name):
            return _from_file(pathlib.Path(name))
        return importlib.import_module(name)
    except ImportError as exc:
        if not _missing(exc, name):
            raise UsageError(f"{name}: cannot import it: {type(exc).__name__}: {exc}") from None
        what = f"{names.what} or module" if names is not None else "module"
        raise KeyError(f"no {what} named {name!r}") from None
    except SyntaxError as exc:
        raise UsageError(f"{exc.filename or name}, line {exc.lineno}: {exc.msg}") from None
    except (UsageError, KeyError):
        raise
    except Exception as exc:  # the module's own code failed: a DefinitionError names its class and member
        raise UsageError(f"{name}: cannot import it: {type(exc).__name__}: {exc}") from None


def add_export_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``iecoop export``."""
    parser.add_argument("name", help="a .py file, a module (patterns.behavioral.state) or a catalogue entry (observer, srp, ch08...)")
    parser.add_argument("--format", choices=("twincat", "plcopen", "st"), default="twincat")
    parser.add_argument("-o", "--output", default=".", help="folder to write into (created if missing)")
    parser.add_argument("--lenient", action="store_true", help="write a statement with no ST form as an ST comment (listed on stderr)")
    parser.add_argument("--strict", action="store_true", help="fail on a statement with no ST form (the default)")


def command(names: Names | None = None) -> Command:
    """The ``iecoop export`` subcommand, taking the names of ``names`` besides dotted module names."""

    @usage_errors("iecoop export")
    def run(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
        output = pathlib.Path(args.output)
        if output.exists() and not output.is_dir():
            raise UsageError(f"cannot write into {output}: it is a file, not a folder")
        try:
            module = module_of(args.name, names)
            comments: list[str] = []
            files = export(module, output, format=args.format, lenient=args.lenient and not args.strict, report=comments)
        except KeyError as exc:
            raise UsageError(exc.args[0]) from None
        except (StExportError, DefinitionError) as exc:
            print(f"iecoop export: {exc}", file=err)
            return 1
        except OSError as exc:
            raise UsageError(f"cannot write into {output}: {exc.strerror or exc} ({exc.filename})") from None
        if not files:
            raise UsageError(f"{args.name}: no iecoop class to export")
        for path in files:
            print(path, file=out)
        for comment in comments:  # nothing is left out without a line saying so
            print(f"iecoop export: written as a comment: {comment}", file=err)
        return 0

    return Command(EXPORT_HELP, add_export_arguments, run)


def export_command(argv: Sequence[str], out: TextIO | None = None, names: Names | None = None) -> int:
    """``iecoop export MODULE --format twincat|plcopen|st -o DIR``; the exit status."""
    parser = argparse.ArgumentParser(prog="iecoop export", description="Write a design as Structured Text files.")
    add_export_arguments(parser)
    return command(names).run(parser.parse_args(list(argv)), out if out is not None else sys.stdout, sys.stderr)
