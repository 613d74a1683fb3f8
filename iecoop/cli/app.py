"""The ``iecoop`` command: the subcommand table, the parser and :func:`main`.

A package with commands of its own (the showcase's tour of the patterns)
composes its table with :func:`commands` and runs :func:`main` with it::

    COMMANDS = {"tour": Command(...), **commands(names=CATALOGUE)}
    main(argv, table=COMMANDS, default="tour")
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Mapping

from iecoop.cli import export, serve, st, test
from iecoop.cli.base import Command, Names

__all__ = ["COMMANDS", "DESCRIPTION", "commands", "main", "parser"]

#: What ``iecoop --help`` says of the command without a plugged-in catalogue.
DESCRIPTION = (
    "Structured Text to Python and back, ST programs run with a trace or behind an OPC UA server, "
    "TcUnit tests run in virtual time."
)


def commands(names: Names | None = None) -> dict[str, Command]:
    """The subcommands of iecoop itself; ``export`` and ``serve`` also take the names of ``names``."""
    return {
        "serve": serve.command(names),
        "st2py": Command(st.ST2PY_HELP, st.add_st2py_arguments, st.st2py_command),
        "st": Command(st.ST_HELP, st.add_st_arguments, st.st_command),
        "export": export.command(names),
        "test": test.command(),
    }


#: The subcommands, in the order ``--help`` lists them.
COMMANDS: Mapping[str, Command] = commands()


def parser(table: Mapping[str, Command] = COMMANDS, description: str = DESCRIPTION) -> argparse.ArgumentParser:
    """The argument parser of ``iecoop`` with the subcommands of ``table``."""
    built = argparse.ArgumentParser(prog="iecoop", description=description)
    subparsers = built.add_subparsers(dest="command", metavar="COMMAND")
    for name, command in table.items():
        command.arguments(subparsers.add_parser(name, help=command.help))
    return built


def _quiet_stdout() -> None:
    """Point stdout at the null device, so that the interpreter's last flush at exit cannot fail again.

    This is the handling the Python documentation gives for SIGPIPE / BrokenPipeError (``signal`` module).
    """
    try:
        descriptor = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # not a real file (a test's capture): nothing to redirect
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, descriptor)


def main(
    argv: list[str] | None = None,
    *,
    table: Mapping[str, Command] = COMMANDS,
    default: str | None = None,
    description: str = DESCRIPTION,
) -> int:
    """Entry point of the ``iecoop`` command; returns the exit status.

    ``default`` is the subcommand run when none is given; without one the
    usage is printed and the status is 2.
    """
    out, err = sys.stdout, sys.stderr
    built = parser(table, description)
    try:
        args = built.parse_args(argv)
    except SystemExit as exc:  # --help, or a bad option (argparse has printed why)
        return exc.code if isinstance(exc.code, int) else 0
    name = args.command or default
    if name is None:
        built.print_usage(err)
        err.write("iecoop: a COMMAND is needed ('iecoop --help' lists them)\n")
        return 2
    try:
        status = table[name].run(args, out, err)
        out.flush()  # inside the try: a reader that went away shows up here at the latest
        return status
    except KeyboardInterrupt:
        err.write("\niecoop: interrupted\n")
        return 130
    except BrokenPipeError:  # the reader stopped early (iecoop list | head -1): that is not an error
        _quiet_stdout()
        return 0
