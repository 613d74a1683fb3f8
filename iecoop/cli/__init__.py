"""The ``iecoop`` command: Structured Text in and out, run with a trace or behind an OPC UA server.

::

    iecoop st2py FILE_OR_FOLDER... [-o DIR]       ST to iecoop Python
    iecoop st run FILE_OR_FOLDER --cycles N       run a PROGRAM in virtual time, print its trace
    iecoop export MODULE --format twincat -o DIR  iecoop classes as TwinCAT / PLCopen / ST files
    iecoop serve FILE_OR_FOLDER                   a PROGRAM in real time behind an OPC UA server
    iecoop test PROJECT_OR_FOLDER [-k EXPR]       the project's TcUnit tests in virtual time

Exit status: 0 when all went well, 1 for a PLC fault at run time or a failed
check (``export --strict``, a server that cannot start), 2 for bad usage or
input that does not load.

- :mod:`iecoop.cli.app`: the subcommand table, the parser and :func:`main`.
- :mod:`iecoop.cli.base`: :class:`Command`, :class:`UsageError`, :class:`Names` (a catalogue
  of names a package plugs into ``export`` and ``serve``), the option types.
- :mod:`iecoop.cli.trace`: the trace table, the fault text and the progress line.
- :mod:`iecoop.cli.st`, :mod:`iecoop.cli.export`, :mod:`iecoop.cli.serve`, :mod:`iecoop.cli.test`: the subcommands.

The installed ``iecoop`` script is the showcase's (``patterns.showcase.main``),
which adds the tour of the patterns and plugs its catalogue in.
"""

from __future__ import annotations

from iecoop.cli.app import COMMANDS, commands, main
from iecoop.cli.base import Command, Names, Served, UsageError

__all__ = ["COMMANDS", "Command", "Names", "Served", "UsageError", "commands", "main"]
