"""Parsing the files of a project: from the translation cache, on every core, or one by one.

blark's Earley parser runs in one Python thread; a project of many files is
parsed in a pool of processes, one per core, when more than one file is
missing from the cache and there is more than one core. Each worker hands
back the parse as data (``cache.tree_to_data``), checked against the text as
a cache entry is; results are taken in file order, so the units, and the
first error a bad file raises, are the same as parsed one by one.
"""

from __future__ import annotations

import concurrent.futures
import multiprocessing
import os
import pathlib
import typing
from collections.abc import Callable, Sequence
from typing import Any

from iecoop.st.read.cache import enabled, load_tree, raw_from_data, store_tree

__all__ = ["PARALLEL_MIN_CHARS", "Parser", "cores", "parse_files"]

#: Uncached ST (characters) below which a pool does not pay for its start (each worker loads blark's grammar).
PARALLEL_MIN_CHARS = 16_000

Flat = tuple[str, str, dict[int, tuple[str, int]]]
Raw = tuple[Any, tuple[Any, ...]]


class Parser(typing.NamedTuple):
    """How to parse one flat source: in this process (``raw``), in a worker (``as_data``, a module-level
    function, the parse as ``cache.tree_to_data`` data), and the name of the grammar a text needs."""

    raw: Callable[[str, str, dict[int, tuple[str, int]]], Raw]
    as_data: Callable[[str, str, dict[int, tuple[str, int]]], tuple[Any, list[Any]]]
    grammar: Callable[[str], str]


def cores() -> int:
    """The cores this process may run on."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def parse_files(flat: Sequence[Flat], cache: bool | None, parser: Parser) -> list[Raw | None]:
    """Per flat source, its raw parse (lark tree, comments); None where the caller parses it (no cache, one file)."""
    use = enabled(cache)
    raws: list[Raw | None] = [None] * len(flat)
    missing = []
    for index, (text, name, _) in enumerate(flat):
        if use:
            raws[index] = load_tree(pathlib.Path(name), text, parser.grammar(text))
        if raws[index] is None:
            missing.append(index)
    if len(missing) > 1 and cores() > 1 and sum(len(flat[i][0]) for i in missing) >= PARALLEL_MIN_CHARS:
        for index, raw in zip(missing, _in_pool([flat[i] for i in missing], parser)):
            raws[index] = raw
    elif use:
        for index in missing:
            raws[index] = parser.raw(*flat[index])
    if use:
        for index in missing:
            text, name, _ = flat[index]
            done = raws[index]
            if done is not None:
                store_tree(pathlib.Path(name), text, parser.grammar(text), *done)
    return raws


def _in_pool(flat: Sequence[Flat], parser: Parser) -> list[Raw]:
    """Parse ``flat`` in a pool of processes, the longest sources first; results in the order given."""
    # spawn, not fork: a process with a runtime's threads must not be forked.
    context = multiprocessing.get_context("spawn")
    order = sorted(range(len(flat)), key=lambda i: -len(flat[i][0]))
    with concurrent.futures.ProcessPoolExecutor(min(cores(), len(flat)), mp_context=context) as pool:
        futures = {i: pool.submit(parser.as_data, *flat[i]) for i in order}
        results = []
        for index, (text, _, _) in enumerate(flat):
            tree, comments = futures[index].result()  # a worker's StSyntaxError is raised here, in file order
            results.append(raw_from_data(tree, comments, text))
    return results
