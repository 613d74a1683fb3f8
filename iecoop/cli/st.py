"""``iecoop st2py`` and ``iecoop st run``: Structured Text to Python, and ST run with a trace.

::

    iecoop st2py FILE_OR_FOLDER... [-o DIR]      the Python of each source (to DIR/<name>.py, or printed)
    iecoop st run FILE_OR_FOLDER --program MAIN --cycles N [--every K] [--profile codesys]

``st run`` loads the source, puts its PROGRAM on a 10 ms ``PlcTask`` of a
``Runtime(store=":memory:")`` in virtual time and prints the same trace table
as ``iecoop run``: the program's first elementary variables, by default only
the cycles where one of them changed. A source that does not translate exits
with status 2, a PLC fault during the run with status 1.

>>> import pathlib, tempfile
>>> folder = pathlib.Path(tempfile.mkdtemp())
>>> _ = (folder / "count.st").write_text('''
... PROGRAM MAIN
... VAR nCount : INT; bEven : BOOL; END_VAR
... nCount := nCount + 1;
... bEven := nCount MOD 2 = 0;
... END_PROGRAM
... ''')
>>> st_run([str(folder / "count.st"), "--cycles", "3"])
MAIN on PlcTask (10 ms), twincat profile, 3 cycles; rows where a traced value changed
time ms  cycle  nCount  bEven
      0      1       1  FALSE
     10      2       2  TRUE
     20      3       3  FALSE
0
>>> st2py([str(folder / "count.st"), "-o", str(folder / "out")])
wrote ... (MAIN)
0
"""

from __future__ import annotations

import argparse
import pathlib
import sys
from collections.abc import Sequence
from typing import TextIO

from iecoop import DefinitionError, Program, T, st
from iecoop.cli.base import UsageError
from iecoop.cli.trace import fault_text, run_cycles, table, variable_probes
from iecoop.runtime import Runtime, Task

__all__ = ["ST2PY_HELP", "ST_HELP", "add_st2py_arguments", "add_st_arguments", "load_program", "plc_task", "st2py", "st2py_command", "st_command", "st_run"]

#: The help lines of ``iecoop st2py`` and ``iecoop st``.
ST2PY_HELP = "translate Structured Text (.st, TwinCAT files, a folder, a .plcproj) to iecoop Python"
ST_HELP = "run Structured Text: 'iecoop st run FILE_OR_FOLDER --program MAIN --cycles N'"


def add_st2py_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``iecoop st2py``."""
    parser.add_argument("sources", nargs="+", metavar="FILE_OR_FOLDER", help=".st, TwinCAT files, a folder or a .plcproj")
    parser.add_argument("-o", "--output", metavar="DIR", help="write DIR/<name>.py for each source instead of printing")


def _st2py_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="iecoop st2py", description="Translate Structured Text to iecoop Python.")
    add_st2py_arguments(parser)
    return parser


def _add_run_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("source", metavar="FILE_OR_FOLDER")
    parser.add_argument("--program", default="MAIN", help="the PROGRAM to run (default MAIN)")
    parser.add_argument("--cycles", type=int, default=100, help="cycles to run (default 100)")
    parser.add_argument("--every", type=int, default=None, help="show every K-th cycle instead of the changes")
    parser.add_argument("--profile", default="twincat", choices=("twincat", "codesys"))


def add_st_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``iecoop st``: its one subcommand, ``run``."""
    commands = parser.add_subparsers(dest="st_command", metavar="COMMAND", required=True)
    _add_run_arguments(commands.add_parser("run", help="run a PROGRAM of the source and print its trace"))


def _run_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="iecoop st run", description="Run a Structured Text PROGRAM with a trace.")
    _add_run_arguments(parser)
    return parser


def st2py(argv: Sequence[str], out: TextIO | None = None, err: TextIO | None = None) -> int:
    """``iecoop st2py``: the Python module of each source; 2 when a source does not translate."""
    return st2py_command(_st2py_parser().parse_args(list(argv)), out or sys.stdout, err or sys.stderr)


def st2py_command(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    """``iecoop st2py`` with its parsed arguments."""
    for source in args.sources:
        try:
            text = st.to_python(source)
        except (DefinitionError, FileNotFoundError) as exc:
            err.write(f"iecoop st2py: {exc}\n")
            return 2
        if args.output is None:
            out.write(text)
            continue
        folder = pathlib.Path(args.output)
        folder.mkdir(parents=True, exist_ok=True)
        target = folder / f"{pathlib.Path(source).stem.replace('.', '_') or 'st'}.py"
        target.write_text(text)
        classes = [line.split()[1].split("(")[0] for line in text.splitlines() if line.startswith("class ")]
        out.write(f"wrote {target} ({', '.join(classes)})\n")
    return 0


def st_run(argv: Sequence[str], out: TextIO | None = None, err: TextIO | None = None) -> int:
    """``iecoop st run``: run a PROGRAM of the source and print its trace; 1 on a PLC fault, 2 on a bad source."""
    return st_command(_run_parser().parse_args(list(argv)), out or sys.stdout, err or sys.stderr)


def plc_task() -> Task:
    """The command's cyclic task: ``PlcTask``, 10 ms, priority 20."""
    return Task("PlcTask", interval=T("10ms"), priority=20)


def load_program(source: str, name: str, profile: str) -> Program:
    """The PROGRAM ``name`` of the ST ``source``, loaded under ``profile``; :class:`UsageError` if it cannot be."""
    try:
        module = st.load(source, profile=profile)
        program = getattr(module, name)
    except (DefinitionError, FileNotFoundError) as exc:
        raise UsageError(str(exc)) from None
    except AttributeError:
        raise UsageError(f"{source} declares no PROGRAM {name}") from None
    if not isinstance(program, Program):
        raise UsageError(f"{name} is not a PROGRAM")
    return program


def st_command(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    """``iecoop st run`` with its parsed arguments."""
    try:
        program = load_program(args.source, args.program, args.profile)
    except UsageError as exc:
        err.write(f"iecoop st run: {exc}\n")
        return 2
    runtime = Runtime(store=":memory:", profile=args.profile)
    runtime.add_task(plc_task(), program)
    trace = run_cycles(runtime, variable_probes(program), args.cycles, every=args.every)
    rows = f"a row every {args.every} cycles" if args.every else "rows where a traced value changed"
    header = f"{trace.where}, {args.profile} profile, {args.cycles} cycles; {rows}"
    out.write("\n".join([header, *table(trace)]) + "\n")
    if trace.fault is None:
        return 0
    err.write(f"iecoop st run: {fault_text(trace)}\n")
    return 1
