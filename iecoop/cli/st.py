"""``iecoop st2py`` and ``iecoop st run``: Structured Text to Python, and ST run with a trace.

::

    iecoop st2py FILE_OR_FOLDER... [-o DIR]      the Python of each source (to DIR/<name>.py, or printed)
    iecoop st run FILE_OR_FOLDER [--program MAIN] --cycles N [--every K] [--profile codesys]

``st run`` loads the source, puts the programs its ``.TcTTO`` tasks call on
those tasks (else MAIN on a 10 ms ``PlcTask``) of a ``Runtime(store=":memory:")``
in virtual time and prints the same trace table as ``iecoop run``: the first
program's first elementary variables, by default only the cycles where one of
them changed. A source that does not translate exits
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
import ast
import functools
import pathlib
import sys
from collections.abc import Callable, Sequence
from typing import TextIO, TypeVar

from iecoop import DefinitionError, Program, T, st
from iecoop.cli.base import UsageError, positive, usage_errors
from iecoop.cli.st_scenario import ProjectTask, parse_set, project_tasks, writes_before
from iecoop.cli.trace import (
    add_trace_arguments, check_trace_options, fault_text, run_cycles, run_streamed, variable_probes, write_trace,
)
from iecoop.runtime import Runtime, Task

__all__ = [
    "ST2PY_HELP", "ST_HELP", "add_st2py_arguments", "add_st_arguments", "load_program", "load_tasks", "plc_task", "st2py",
    "st2py_command", "st_command", "st_run", "translated",
]

#: The help lines of ``iecoop st2py`` and ``iecoop st``.
ST2PY_HELP = "translate Structured Text (.st, TwinCAT files, a folder, a .plcproj) to iecoop Python"
ST_HELP = "run Structured Text: 'iecoop st run FILE_OR_FOLDER --program MAIN --cycles N'"

_T = TypeVar("_T")


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
    parser.add_argument("--program", default=None,
                        help="the PROGRAM to run (default: those the project's tasks call, else MAIN)")
    parser.add_argument("--cycles", type=positive, default=100, metavar="N", help="cycles to run (default 100)")
    parser.add_argument("--every", type=positive, default=None, metavar="K",
                        help="show every K-th cycle instead of the changes")
    parser.add_argument("--profile", default="twincat", choices=("twincat", "codesys"))
    parser.add_argument("--duration", metavar="T", help="run for a PLC time (2s, 500ms) instead of --cycles")
    parser.add_argument("--set", action="append", default=[], metavar="PATH=VALUE@TIME",
                        help="write a value at a PLC time, e.g. MAIN.bStart=TRUE@100ms (repeatable)")
    parser.add_argument("--watchdog", type=_watchdog, default=DEFAULT_WATCHDOG, metavar="T",
                        help="stop a cycle that runs longer than T of the machine's time, a PLC fault "
                             f"RTSEXCPT_WATCHDOG (default {DEFAULT_WATCHDOG}; 0: none)")
    add_trace_arguments(parser)


#: The watchdog of ``iecoop st run``'s task: a cycle that never ends (WHILE TRUE) is a PLC fault, not a hung command.
DEFAULT_WATCHDOG = "10s"


def _watchdog(text: str) -> str:
    """An argparse type: a TIME (``2s``, ``T#500ms``) or 0."""
    try:
        T(text if text.strip() != "0" else "0ms")
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"expected a TIME such as 10s or 500ms, or 0 for none: {exc}") from None
    return text


def add_st_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``iecoop st``: its one subcommand, ``run``."""
    commands = parser.add_subparsers(dest="st_command", metavar="COMMAND", required=True)
    _add_run_arguments(commands.add_parser("run", help="run a PROGRAM of the source and print its trace"))


def _run_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="iecoop st run", description="Run a Structured Text PROGRAM with a trace.")
    _add_run_arguments(parser)
    return parser


def _undecodable(path: pathlib.Path) -> pathlib.Path:
    """The first file at ``path`` (a file, or a folder's ST and TwinCAT files) that is not UTF-8 text."""
    for candidate in sorted(path.rglob("*")) if path.is_dir() else [path]:
        try:
            candidate.read_text(encoding="utf-8-sig")
        except (UnicodeDecodeError, OSError):
            return candidate
    return path


def translated(source: str, step: Callable[[pathlib.Path], _T]) -> _T:
    """``step`` (``st.load``, ``st.to_python``) of the ST file or folder ``source``.

    Every way the input can fail to load is a :class:`UsageError` of one line
    that names the file: a missing or unreadable file, an unknown suffix, text
    that is not UTF-8, a DefinitionError of the reader, XML that is not well
    formed, a translation that does not compile.
    """
    path = pathlib.Path(source)  # a path, never ST text: "notes.txt" is a file of an unknown kind
    try:
        return step(path)
    except DefinitionError as exc:
        raise UsageError(str(exc) if source in str(exc) else f"{source}: {exc}") from None
    except UnicodeDecodeError as exc:
        bad = _undecodable(path)
        raise UsageError(f"{bad}: not UTF-8 text ({exc.reason} at byte {exc.start}); save it as UTF-8") from None
    except FileNotFoundError as exc:
        raise UsageError(f"{exc.filename}: does not exist" if exc.filename else str(exc)) from None
    except OSError as exc:
        raise UsageError(f"{exc.filename or source}: cannot read it: {exc.strerror or exc}") from None
    except SyntaxError as exc:  # the translation's compile() (XML parsers' errors are SyntaxErrors too)
        if (exc.filename or "").startswith("<iecoop.st"):
            raise UsageError(_not_compiling(source, exc)) from None
        raise UsageError(f"{source}: not well-formed: {exc}") from None
    except Exception as exc:  # a construct the reader trips on: one line to report, not a traceback
        raise UsageError(f"{source}: cannot be translated ({type(exc).__name__}: {exc})") from None


def _not_compiling(source: str, exc: SyntaxError) -> str:
    text = (exc.text or "").strip()
    return f"{source}: its Python translation does not compile: line {exc.lineno}: {exc.msg}" + (
        f": {text}" if text else "")


def _python(source: str) -> str:
    """The Python of ``source``, checked to compile and to declare something."""
    text = translated(source, st.to_python)
    try:
        tree = ast.parse(text, f"<iecoop.st {source}>")
    except SyntaxError as exc:
        raise UsageError(_not_compiling(source, exc)) from None
    if not any(isinstance(node, _DECLARATIONS) for node in tree.body):
        raise UsageError(f"{source}: no POU, type or GVL in it")
    return text


#: What the translation of a POU, type or GVL makes at the top of the module.
_DECLARATIONS = (ast.ClassDef, ast.FunctionDef, ast.Assign, ast.AnnAssign)


def _target(folder: pathlib.Path, source: str) -> pathlib.Path:
    name = pathlib.Path(source).resolve().stem.replace(".", "_") or "st"
    target = folder / f"{name}.py"
    if not target.resolve().is_relative_to(folder.resolve()):
        raise UsageError(f"{target} leads outside {folder} (a link): not written")
    return target


def st2py(argv: Sequence[str], out: TextIO | None = None, err: TextIO | None = None) -> int:
    """``iecoop st2py``: the Python module of each source; 2 when a source does not translate."""
    return st2py_command(_st2py_parser().parse_args(list(argv)), out or sys.stdout, err or sys.stderr)


@usage_errors("iecoop st2py")
def st2py_command(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    """``iecoop st2py`` with its parsed arguments: every source is translated before anything is written."""
    texts = [(source, _python(source)) for source in args.sources]
    if args.output is None:
        for _, text in texts:
            out.write(text)
        return 0
    folder = pathlib.Path(args.output)
    if folder.exists() and not folder.is_dir():
        raise UsageError(f"-o {folder}: it is a file, not a folder")
    targets: dict[pathlib.Path, str] = {}
    for source, _ in texts:
        target = _target(folder, source)
        if target in targets:
            raise UsageError(f"{targets[target]} and {source} would both be written to {target}: "
                             "translate them into different folders")
        targets[target] = source
    try:
        folder.mkdir(parents=True, exist_ok=True)
        for target, (_, text) in zip(targets, texts):
            target.write_text(text, encoding="utf-8")
            classes = [line.split()[1].split("(")[0] for line in text.splitlines() if line.startswith("class ")]
            out.write(f"wrote {target} ({', '.join(classes)})\n")
    except OSError as exc:
        raise UsageError(f"cannot write {exc.filename or folder}: {exc.strerror or exc}") from None
    return 0


def st_run(argv: Sequence[str], out: TextIO | None = None, err: TextIO | None = None) -> int:
    """``iecoop st run``: run a PROGRAM of the source and print its trace; 1 on a PLC fault, 2 on a bad source."""
    return st_command(_run_parser().parse_args(list(argv)), out or sys.stdout, err or sys.stderr)


def plc_task() -> Task:
    """The command's cyclic task: ``PlcTask``, 10 ms, priority 20."""
    return Task("PlcTask", interval=T("10ms"), priority=20)


def load_tasks(source: str, name: str | None, profile: str) -> list[tuple[Task, list[tuple[str, Program]]]]:
    """The tasks to run the ST ``source`` on, loaded under ``profile``, each with its PROGRAMs by name.

    ``name`` (``--program``) runs that PROGRAM alone, on the task that calls it (else the first). Without it, the
    programs the project's ``.TcTTO`` task files call, on those tasks, as TwinCAT runs them; a project
    without task calls runs MAIN, or its one PROGRAM. :class:`UsageError` when there is no such choice.
    """
    module = translated(source, lambda path: st.load(path, profile=profile))
    declared = {key: value for key, value in vars(module).items() if isinstance(value, Program)}
    tasks = project_tasks(source)
    if name is not None:
        own = next((entry.task for entry in tasks if name.casefold() in (call.casefold() for call in entry.calls)), None)
        return [(own or (tasks[0].task if tasks else plc_task()), [_program(module, source, name)])]
    called = [entry for entry in tasks if entry.calls]
    if called:
        return [(entry.task, [_called(declared, entry, call) for call in entry.calls]) for entry in called]
    task = tasks[0].task if tasks else plc_task()
    if "MAIN" in declared or len(declared) != 1:
        return [(task, [_program(module, source, "MAIN", sorted(declared))])]
    return [(task, list(declared.items()))]


def load_program(source: str, name: str, profile: str) -> Program:
    """The PROGRAM ``name`` of the ST ``source``, loaded under ``profile``; :class:`UsageError` if it cannot be."""
    return load_tasks(source, name, profile)[0][1][0][1]


def _program(module: object, source: str, name: str, others: Sequence[str] = ()) -> tuple[str, Program]:
    program = getattr(module, name, None)
    if program is None:
        choice = f"; its PROGRAMs: {', '.join(others)} (choose one with --program)" if others else ""
        raise UsageError(f"{source} declares no PROGRAM {name}{choice}")
    if not isinstance(program, Program):
        raise UsageError(f"{name} is not a PROGRAM")
    return name, program


def _called(declared: dict[str, Program], entry: ProjectTask, call: str) -> tuple[str, Program]:
    """The PROGRAM a task file calls: by its name as declared, case aside as ST names are."""
    found = next(((key, value) for key, value in declared.items() if key.casefold() == call.casefold()), None)
    if found is None:
        raise UsageError(f"{entry.file}: task {entry.task.name} calls {call}, which the project declares no PROGRAM of")
    return found


@usage_errors("iecoop st run")
def st_command(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    """``iecoop st run`` with its parsed arguments."""
    check_trace_options(args)
    tasks = load_tasks(args.source, args.program, args.profile)
    writes = [parse_set(text) for text in args.set]
    runtime = Runtime(store=":memory:", profile=args.profile)
    watchdog = int(T(args.watchdog if args.watchdog.strip() != "0" else "0ms")) or None
    for task, programs in tasks:
        task.watchdog = watchdog
        runtime.add_task(task, *(program for _, program in programs))
    first_task, ((_, program), *_) = tasks[0]
    cycles = args.cycles
    if args.duration is not None:
        cycles = max(1, -(-int(T(args.duration)) // int(first_task.interval)))
    rows = "a row every cycle" if args.every == 1 else f"a row every {args.every} cycles" if args.every else "rows where a traced value changed"
    probes = variable_probes(program)
    trace = run_streamed(
        functools.partial(run_cycles, runtime, probes, cycles, every=args.every, paths=args.trace or (),
                          before_cycle=writes_before(runtime, writes)),
        cycles, out, err, lambda started: f"{started.where}, {args.profile} profile, {cycles} cycles; {rows}", "iecoop st run",
    )
    if trace is None:
        return 130
    write_trace(trace.source, args, out)
    if trace.fault is None:
        return 0
    err.write(f"iecoop st run: {fault_text(trace)}\n")
    return 1
