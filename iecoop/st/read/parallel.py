"""Parsing the files of a project: from the translation cache, on every core, or one by one.

blark's Earley parser runs in one Python thread; a project of many files is
parsed on every core when more than one file is missing from the cache and
there is more than one core: by this process and a pool of one worker per
further core, the files shared out by their length. Each worker hands
back the parse as the data a cache entry holds (``read.nodedata``), read back
as an entry is; results are taken in file order, so the units, and the
first error a bad file raises, are the same as parsed one by one.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import multiprocessing
import multiprocessing.context
import os
import pathlib
import sys
import typing
from collections.abc import Callable, Sequence
from typing import Any

from iecoop.st.read.cache import Parsed, enabled, entry_data, load_entry, store_entry
from iecoop.st.read.nodedata import nodes_from_data

__all__ = ["PARALLEL_MIN_CHARS", "Parser", "WORKER_START_CHARS", "cores", "parse_files", "shares"]

#: Uncached ST (characters) below which a pool does not pay for its start (each worker loads blark's grammar).
PARALLEL_MIN_CHARS = 16_000
#: What a worker's start costs, as the characters of ST this process parses meanwhile (about a second).
WORKER_START_CHARS = 2_000

LineMap = dict[int, tuple[str, int]]
Flat = tuple[str, str, LineMap]


class Parser(typing.NamedTuple):
    """How to parse one flat source: in this process (``parse``: blark's tree and comments), in a worker
    (``as_data``, a module-level function: the tree as ``cache.entry_data``, None when it has no such
    form), the name of the grammar a text needs, and how to build the grammars some texts need
    (``prepare``: before the workers start, so a forked worker starts with them built)."""

    parse: Callable[[str, str, LineMap], Parsed]
    as_data: Callable[[str, str, LineMap], dict[str, Any] | None]
    grammar: Callable[[str], str]
    prepare: Callable[[Sequence[str]], None] = lambda texts: None


def cores() -> int:
    """The cores this process may run on."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def parse_files(flat: Sequence[Flat], cache: bool | None, parser: Parser) -> list[Parsed | None]:
    """Per flat source, blark's tree and comments; None where the caller parses it (no cache, one file)."""
    use = enabled(cache)
    parsed: list[Parsed | None] = [None] * len(flat)
    missing = []
    for index, (text, name, _) in enumerate(flat):
        if use:
            parsed[index] = load_entry(pathlib.Path(name), text, parser.grammar(text))
        if parsed[index] is None:
            missing.append(index)
    if len(missing) > 1 and cores() > 1 and sum(len(flat[i][0]) for i in missing) >= PARALLEL_MIN_CHARS:
        for index, (done, data) in zip(missing, _in_pool([flat[i] for i in missing], parser)):
            text, name, _ = flat[index]
            parsed[index] = done if done is not None or data is None else nodes_from_data(data, text, name)
            if use and data is not None:
                store_entry(pathlib.Path(name), text, parser.grammar(text), data)
    for index in missing:
        if use and parsed[index] is None:  # without the cache, the caller parses (and keeps the parse in memory)
            text, name, line_map = flat[index]
            done = parsed[index] = parser.parse(text, name, line_map)
            data = entry_data(*done, text, name)
            if data is not None:
                store_entry(pathlib.Path(name), text, parser.grammar(text), data)
    return parsed


def shares(sizes: Sequence[int], processes: int) -> list[list[int]]:
    """Which sources (indices into ``sizes``) each process parses: this one first, then one worker per further core.

    The longest first, each to the process that will be free first by its characters so far; a worker
    starts ``WORKER_START_CHARS`` late (its interpreter, iecoop and blark's grammar).
    """
    load = [0] + [WORKER_START_CHARS] * (processes - 1)
    given: list[list[int]] = [[] for _ in range(processes)]
    for index in sorted(range(len(sizes)), key=lambda i: -sizes[i]):
        process = load.index(min(load))
        given[process].append(index)
        load[process] += sizes[index]
    return given


def _context() -> multiprocessing.context.BaseContext:
    """fork where it is safe (Linux, and this process runs one thread: never a process with a runtime's threads),
    so a worker starts with iecoop and blark imported; spawn elsewhere."""
    if sys.platform == "linux":
        try:
            threads = len(os.listdir("/proc/self/task"))  # every thread, those of C libraries too
        except OSError:
            threads = 0
        if threads == 1:
            return multiprocessing.get_context("fork")
    return multiprocessing.get_context("spawn")


#: The result for one source parsed by ``_in_pool``: the tree when parsed here, the entry's data (None when the
#: tree has no such form; a worker hands back only the data).
Result = tuple[Parsed | None, dict[str, Any] | None]


def _in_pool(flat: Sequence[Flat], parser: Parser) -> list[Result]:
    """Parse ``flat`` in this process and a pool of workers, shared out by ``shares``; results in the order given,
    and of the sources that fail, the first one's error is raised."""
    here, *away = shares([len(text) for text, _, _ in flat], cores())
    away = [share for share in away if share]
    done: dict[int, Result] = {}
    failed: dict[int, Exception] = {}
    with contextlib.ExitStack() as stack:
        futures = {}
        if away:
            parser.prepare([text for text, _, _ in flat])  # a forked worker inherits the grammars built here
            pool = stack.enter_context(concurrent.futures.ProcessPoolExecutor(len(away), mp_context=_context()))
            sent = sorted((index for share in away for index in share), key=lambda i: -len(flat[i][0]))  # longest first
            futures = {index: pool.submit(parser.as_data, *flat[index]) for index in sent}
        for index in here:
            text, name, line_map = flat[index]
            try:
                tree = parser.parse(text, name, line_map)
            except Exception as exc:  # noqa: BLE001 - raised below, in file order
                failed[index] = exc
                continue
            done[index] = (tree, entry_data(*tree, text, name))
        results: list[Result] = []
        for index in range(len(flat)):
            if index in failed:
                raise failed[index]
            results.append(done[index] if index in done else (None, futures[index].result()))  # a worker's error too
    return results
