"""What every subcommand shares: :class:`Command`, :class:`UsageError`, :class:`Names` and the option types."""

from __future__ import annotations

import argparse
import dataclasses
import functools
from collections.abc import Callable
from types import ModuleType
from typing import TextIO

from iecoop.runtime import Runtime

__all__ = ["Command", "Names", "Run", "Served", "UsageError", "positive", "usage_errors"]


class UsageError(Exception):
    """Bad usage or input that does not load: the command prints ``iecoop COMMAND: message`` and exits 2."""


#: A subcommand's function: its parsed arguments, stdout and stderr in; the exit status out.
Run = Callable[[argparse.Namespace, TextIO, TextIO], int]


def usage_errors(prog: str) -> Callable[[Run], Run]:
    """Decorate a subcommand's function: a :class:`UsageError` is written as ``prog: message`` and exits 2."""

    def decorate(run: Run) -> Run:
        @functools.wraps(run)
        def guarded(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
            try:
                return run(args, out, err)
            except UsageError as exc:
                err.write(f"{prog}: {exc}\n")
                return 2

        return guarded

    return decorate


@dataclasses.dataclass(frozen=True)
class Command:
    """One subcommand: its help line, the function adding its arguments, and the function running it."""

    help: str
    arguments: Callable[[argparse.ArgumentParser], None]
    run: Run


@dataclasses.dataclass
class Served:
    """A scenario ready to serve: the runtime with its tasks, and what runs before each cycle.

    ``title`` is the line ``iecoop serve`` prints first; ``script`` is called
    with the number (from 1) of the cycle about to run.
    """

    name: str
    title: str
    runtime: Runtime
    script: Callable[[int], None] | None = None
    #: The PROGRAMs of an ST source served (their located variables go to Modbus), by name.
    programs: tuple[str, ...] = ()


@dataclasses.dataclass(frozen=True)
class Names:
    """Names that ``iecoop export`` and ``iecoop serve`` accept besides files and modules: a catalogue.

    ``module(name)`` is the module to export, ``scenario(name, profile)``
    the scenario to serve, each None for a name the catalogue does not
    have (they raise :class:`UsageError` for one it has but cannot use);
    ``unknown(name, command)`` is the message for a name nothing knows;
    ``what`` names the kind of name in messages ("catalogue entry").
    """

    what: str
    module: Callable[[str], ModuleType | None]
    scenario: Callable[[str, str], Served | None]
    unknown: Callable[[str, str], str]


def positive(text: str) -> int:
    """An argparse type: a whole number of at least 1 (cycles, every K-th)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value
