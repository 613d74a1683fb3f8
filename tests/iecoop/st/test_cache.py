"""The translation cache: an entry per ST file, used only when it matches and checks, never trusted."""

from __future__ import annotations

import hashlib
import hmac
import json
import os
import pathlib
import shutil
import sys
from collections.abc import Iterator
from typing import Any

import pytest

from iecoop import st
from iecoop.st.read import cache, parallel, parse

PROJECT = pathlib.Path(__file__).parent / "data" / "sourcemaps"


@pytest.fixture
def project(tmp_path: pathlib.Path) -> pathlib.Path:
    folder = tmp_path / "plc"
    folder.mkdir()
    for name in ("FB_Calc.TcPOU", "MAIN.TcPOU"):
        shutil.copy(PROJECT / name, folder / name)
    return folder


@pytest.fixture(autouse=True)
def user_cache(tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch) -> pathlib.Path:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "user-cache"))
    monkeypatch.delenv("IECOOP_ST_CACHE", raising=False)
    cache.versions.cache_clear()
    return tmp_path / "user-cache" / "iecoop"


@pytest.fixture
def parsed(monkeypatch: pytest.MonkeyPatch) -> Iterator[list[str]]:
    """The names of the files blark parses (not read from the cache)."""
    names: list[str] = []
    real = parse.raw_tree

    def counting(text: str, name: str, line_map: dict[int, tuple[str, int]]) -> Any:
        names.append(pathlib.Path(name).name)
        return real(text, name, line_map)

    monkeypatch.setattr(parse, "raw_tree", counting)
    yield names


def _files(root: pathlib.Path) -> set[str]:
    return {str(p.relative_to(root)) for p in root.rglob("*") if p.is_file()}


def _divide(module: Any, divisor: int) -> int:
    calc = module.FB_Calc()
    calc(nDivisor=divisor)
    return int(calc.nResult)


def test_a_second_load_reads_the_cache_and_an_edit_reparses_only_that_file(project: pathlib.Path, parsed: list[str]) -> None:
    assert _divide(st.load(project), 5) == 20
    assert sorted(parsed) == ["FB_Calc.TcPOU", "MAIN.TcPOU"]
    assert _files(project / cache.CACHE_FOLDER) == {"FB_Calc.TcPOU.json", "MAIN.TcPOU.json"}
    parsed.clear()
    assert _divide(st.load(project), 5) == 20
    assert parsed == []
    calc = project / "FB_Calc.TcPOU"
    calc.write_text(calc.read_text().replace("nResult := Divide(100);", "nResult := Divide(200);"))
    assert _divide(st.load(project), 5) == 40
    assert parsed == ["FB_Calc.TcPOU"]


@pytest.mark.parametrize("package", ["iecoop", "blark", "lark"])
def test_a_version_change_invalidates(
    project: pathlib.Path, parsed: list[str], monkeypatch: pytest.MonkeyPatch, request: pytest.FixtureRequest, package: str
) -> None:
    import importlib.metadata

    st.load(project)
    parsed.clear()
    real = importlib.metadata.version
    monkeypatch.setattr(importlib.metadata, "version", lambda name: "9.9.9" if name == package else real(name))
    cache.versions.cache_clear()
    request.addfinalizer(cache.versions.cache_clear)
    assert f"{package}=9.9.9" in cache.versions()
    st.load(project)
    assert sorted(parsed) == ["FB_Calc.TcPOU", "MAIN.TcPOU"]
    parsed.clear()
    st.load(project)
    assert parsed == []


def test_a_different_blark_of_the_same_version_invalidates(
    project: pathlib.Path, parsed: list[str], monkeypatch: pytest.MonkeyPatch, request: pytest.FixtureRequest
) -> None:
    """blark's grammar or transform changed (a checkout, a patch) with its version number kept: the entries are not used."""
    import importlib.resources

    st.load(project)
    parsed.clear()
    real = importlib.resources.files("blark")

    class Patched:
        def joinpath(self, name: str) -> Any:
            path = real.joinpath(name)
            if name != "iec.lark":
                return path

            class Changed:
                def read_bytes(self) -> bytes:
                    return path.read_bytes() + b"\n// a patched grammar\n"

            return Changed()

    files = importlib.resources.files
    monkeypatch.setattr(importlib.resources, "files", lambda package: Patched() if package == "blark" else files(package))
    cache.versions.cache_clear()
    request.addfinalizer(cache.versions.cache_clear)
    st.load(project)
    assert sorted(parsed) == ["FB_Calc.TcPOU", "MAIN.TcPOU"]


@pytest.mark.parametrize("damage", [b"", b"not json at all", b"truncated"])
def test_a_damaged_entry_is_ignored_and_rebuilt(project: pathlib.Path, parsed: list[str], damage: bytes) -> None:
    st.load(project)
    entry = project / cache.CACHE_FOLDER / "FB_Calc.TcPOU.json"
    good = entry.read_bytes()
    entry.write_bytes(good[: len(good) // 2] if damage == b"truncated" else damage)
    parsed.clear()
    assert _divide(st.load(project), 5) == 20
    assert parsed == ["FB_Calc.TcPOU"]
    assert entry.read_bytes() == good  # rebuilt: the same entry as before


def _resign(entry: pathlib.Path, user_cache: pathlib.Path, change: Any) -> None:
    """Rewrite the entry's JSON with ``change`` and sign it with the user's own key (the strongest tamper)."""
    _, _, body = entry.read_bytes().partition(b"\n")
    data = json.loads(body)
    change(data)
    body = json.dumps(data, separators=(",", ":")).encode()
    key = (user_cache / "signing.key").read_bytes()
    entry.write_bytes(hmac.new(key, body, hashlib.sha256).hexdigest().encode() + b"\n" + body)


def _forms(node: Any, tag: int) -> Iterator[list[Any]]:
    """The items of an entry's tree data with the form ``tag`` (``read.nodedata``: 1 a token, 10 and up a node)."""
    if isinstance(node, list) and node and isinstance(node[0], int):
        if node[0] == tag or (tag >= 10 and node[0] >= 10):
            yield node
        for child in node[1:]:
            yield from _forms(child, tag)


def _first_string_field(data: dict[str, Any]) -> None:
    """Point the first string-holding field at a place past the end of the text."""
    token = next(_forms(data["nodes"]["tree"], 1))
    token[3] = 10**9


def _class_named(name: str) -> Any:
    def change(data: dict[str, Any]) -> None:
        data["nodes"]["classes"][0][0] = name

    return change


def _field_named(name: str) -> Any:
    def change(data: dict[str, Any]) -> None:
        data["nodes"]["classes"][0].append(name)
        for node in _forms(data["nodes"]["tree"], 10):
            if node[0] == 10:
                node.append(None)

    return change


def _enumeration_named(name: str) -> Any:
    def change(data: dict[str, Any]) -> None:
        next(_forms(data["nodes"]["tree"], 1))[:] = [3, name, "system"]

    return change


def _token_typed(name: str) -> Any:
    def change(data: dict[str, Any]) -> None:
        next(_forms(data["nodes"]["tree"], 1))[1] = name

    return change


TAMPERING = {
    "a place outside the text": _first_string_field, "a class not blark's": _class_named("Popen"),
    "a dotted class": _class_named("os.system"), "a field __class__": _field_named("__class__"),
    "a field __dict__": _field_named("__dict__"), "an enumeration not blark's": _enumeration_named("RegexFlag"),
    "a token type that is no name": _token_typed("x') or __import__('os"),
}


def test_a_tampered_entry_is_not_used(project: pathlib.Path, parsed: list[str], user_cache: pathlib.Path) -> None:
    """An entry edited without the user's key is refused; a signed one still cannot hold text the ST does not,
    nor a class, field or enumeration other than blark's own."""
    st.load(project)
    entry = project / cache.CACHE_FOLDER / "FB_Calc.TcPOU.json"
    good = entry.read_bytes()
    signature, _, body = good.partition(b"\n")
    # Edited without the key (even to the same JSON data): the signature no longer matches.
    entry.write_bytes(signature + b"\n" + body + b" ")
    parsed.clear()
    assert _divide(st.load(project), 5) == 20 and parsed == ["FB_Calc.TcPOU"]
    # Signed again with the user's own key and unchanged, it is used: what follows is refused for its change.
    _resign(entry, user_cache, lambda data: None)
    parsed.clear()
    assert _divide(st.load(project), 5) == 20 and parsed == []
    # Signed with the user's own key: a token or string is a place in the ST file, so it holds no text of its
    # own, and a node is one of blark's classes from a table, given only that class's fields.
    for what, change in TAMPERING.items():
        entry.write_bytes(good)
        _resign(entry, user_cache, change)
        parsed.clear()
        assert _divide(st.load(project), 5) == 20 and parsed == ["FB_Calc.TcPOU"], what
        assert entry.read_bytes() == good, what  # rebuilt
    assert b"nValue" not in good  # the entry holds places, not the ST's text


def test_an_entry_from_elsewhere_is_not_used(project: pathlib.Path, parsed: list[str], user_cache: pathlib.Path) -> None:
    """An entry copied in from another user (another key) is ignored: a project cannot bring its own cache."""
    st.load(project)
    (user_cache / "signing.key").write_bytes(b"k" * 32)
    parsed.clear()
    st.load(project)
    assert sorted(parsed) == ["FB_Calc.TcPOU", "MAIN.TcPOU"]


def test_the_cache_writes_only_in_its_folders(project: pathlib.Path, user_cache: pathlib.Path, tmp_path: pathlib.Path) -> None:
    before = _files(tmp_path)
    st.load(project)
    written = _files(tmp_path) - before
    assert written == {
        "plc/__iecoop_cache__/FB_Calc.TcPOU.json", "plc/__iecoop_cache__/MAIN.TcPOU.json", "user-cache/iecoop/signing.key",
    }
    assert (user_cache / "signing.key").stat().st_mode & 0o077 == 0  # the key is the user's alone


@pytest.mark.skipif(sys.platform == "win32", reason="symbolic links need privileges on Windows")
def test_a_cache_folder_that_is_a_link_out_is_not_written_through(
    project: pathlib.Path, parsed: list[str], user_cache: pathlib.Path, tmp_path: pathlib.Path,
) -> None:
    """A project may come with __iecoop_cache__ as a link to a folder elsewhere: nothing is written there."""
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    os.symlink(elsewhere, project / cache.CACHE_FOLDER)
    st.load(project)
    assert list(elsewhere.iterdir()) == []
    assert sorted(p.name.split(".")[0] for p in (user_cache / "st").iterdir()) == ["FB_Calc", "MAIN"]
    parsed.clear()
    st.load(project)
    assert parsed == []


def test_an_unwritable_source_folder_uses_the_user_cache(project: pathlib.Path, parsed: list[str], user_cache: pathlib.Path) -> None:
    (project / cache.CACHE_FOLDER).write_text("a file where the folder would be")
    st.load(project)
    assert sorted(p.name.split(".")[0] for p in (user_cache / "st").iterdir()) == ["FB_Calc", "MAIN"]
    parsed.clear()
    st.load(project)
    assert parsed == []


@pytest.mark.parametrize("how", ["argument", "environment", "environment false"])
def test_opt_out(project: pathlib.Path, parsed: list[str], monkeypatch: pytest.MonkeyPatch, tmp_path: pathlib.Path, how: str) -> None:
    """Without the cache nothing is read from it and nothing written: every file is parsed, no entry made."""
    def load() -> Any:
        if how == "argument":
            return st.load(project, cache=False)
        monkeypatch.setenv("IECOOP_ST_CACHE", "0" if how == "environment" else "false")
        try:
            return st.load(project)
        finally:
            monkeypatch.delenv("IECOOP_ST_CACHE")

    before = _files(tmp_path)
    assert _divide(load(), 5) == 20
    assert _files(tmp_path) == before  # no entry, not even the signing key
    st.load(project)  # with the cache: entries made
    entries = {name: (project / cache.CACHE_FOLDER / name).read_bytes() for name in _files(project / cache.CACHE_FOLDER)}
    calc = project / "FB_Calc.TcPOU"
    calc.write_text(calc.read_text().replace("nResult := Divide(100);", "nResult := Divide(200);"))
    parsed.clear()
    parse._tree.cache_clear()  # the parses this process keeps in memory (of the first load) aside
    assert _divide(load(), 5) == 40
    assert sorted(parsed) == ["FB_Calc.TcPOU", "MAIN.TcPOU"]  # parsed, the unchanged file too: no entry read
    assert {name: (project / cache.CACHE_FOLDER / name).read_bytes() for name in entries} == entries  # none written


def test_parsing_in_a_pool_gives_the_same_module(project: pathlib.Path, monkeypatch: pytest.MonkeyPatch, parsed: list[str]) -> None:
    serial = st.to_python(project, cache=False)
    monkeypatch.setattr(parallel, "PARALLEL_MIN_CHARS", 0)
    monkeypatch.setattr(parallel, "WORKER_START_CHARS", 0)
    monkeypatch.setattr(parallel, "cores", lambda: 2)
    pooled: list[int] = []
    real = parallel._in_pool

    def counted(flat: Any, parser: Any) -> Any:
        pooled.append(len(flat))
        return real(flat, parser)

    monkeypatch.setattr(parallel, "_in_pool", counted)
    parsed.clear()
    assert st.to_python(project, cache=True) == serial
    assert pooled == [2]
    assert len(parsed) == 1  # this process parsed the longer file, a worker the other
    assert _files(project / cache.CACHE_FOLDER) == {"FB_Calc.TcPOU.json", "MAIN.TcPOU.json"}  # both kept
    parsed.clear()
    assert st.to_python(project, cache=True) == serial and parsed == [] and pooled == [2]


def test_files_are_shared_out_longest_first_to_the_process_free_first() -> None:
    start = parallel.WORKER_START_CHARS
    # this process: 10000; the worker starts late, then takes 5000 and 3000; the last goes to whichever is free
    sizes = [start + 8000, 5000, 3000, 1000]
    assert parallel.shares(sizes, 2) == [[0, 3], [1, 2]]
    assert parallel.shares(sizes, 1) == [[0, 1, 2, 3]]
    assert parallel.shares([100, 200], 2) == [[1, 0], []]  # too little for a worker to be worth its start


def test_a_small_project_starts_no_pool(project: pathlib.Path, monkeypatch: pytest.MonkeyPatch, parsed: list[str]) -> None:
    monkeypatch.setattr(parallel, "cores", lambda: 2)
    monkeypatch.setattr(parallel, "_in_pool", lambda flat, parser: pytest.fail("a pool for a small project"))
    assert sum(len(text) for text, _, _ in parse._flat_sources(project)) < parallel.PARALLEL_MIN_CHARS
    st.load(project)
    assert sorted(parsed) == ["FB_Calc.TcPOU", "MAIN.TcPOU"]


def test_a_syntax_error_in_a_pool_names_the_first_bad_file(project: pathlib.Path, monkeypatch: pytest.MonkeyPatch) -> None:
    for name in ("FB_Calc.TcPOU", "MAIN.TcPOU"):
        path = project / name
        path.write_text(path.read_text().replace(":=", ":= :=", 1))
    monkeypatch.setattr(parallel, "PARALLEL_MIN_CHARS", 0)
    monkeypatch.setattr(parallel, "WORKER_START_CHARS", 0)
    monkeypatch.setattr(parallel, "cores", lambda: 2)
    with pytest.raises(st.StSyntaxError, match=r"FB_Calc\.TcPOU:\d+: Structured Text syntax error"):
        st.load(project, cache=False)


def _same(a: Any, b: Any, where: str = "tree") -> None:
    """``a`` and ``b`` are the same tree: the same classes, fields, token types, texts and places."""
    import dataclasses

    import lark

    assert type(a) is type(b), where
    if isinstance(a, lark.Token):
        fields = ("type", "value", "start_pos", "end_pos", "line", "column", "end_line", "end_column")
        assert [getattr(a, f) for f in fields] == [getattr(b, f) for f in fields], where
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b), where
        for index, (x, y) in enumerate(zip(a, b)):
            _same(x, y, f"{where}[{index}]")
    elif dataclasses.is_dataclass(a):
        assert vars(a).keys() == vars(b).keys(), where
        for name in vars(a):
            _same(getattr(a, name), getattr(b, name), f"{where}.{name}")
    else:
        assert a == b, where


@pytest.mark.parametrize("name", ["sourcemaps/FB_Calc.TcPOU", "coverage/FB_Sort.TcPOU", "twincat/GVLs/GVL_Tank.TcGVL", "course/ch04_properties.st"])
def test_an_entry_holds_blarks_tree_as_parsed(name: str) -> None:
    """What an entry keeps reads back as the very tree blark's transform makes, comments shared as blark shares them."""
    from iecoop.st.read import nodedata

    [(text, filename, line_map)] = list(parse._flat_sources(PROJECT.parent / name))
    tree, comments = parse.parse_one(text, filename, line_map)
    data = json.loads(json.dumps(nodedata.nodes_to_data(tree, comments, text, filename)))
    again, again_comments = nodedata.nodes_from_data(data, text, filename)
    _same(again, tree)
    _same(again_comments, comments)
    in_tree = {id(token) for item in parse_tree_nodes(again) for token in getattr(getattr(item, "meta", None), "comments", None) or []}
    assert {id(token) for token in again_comments} <= in_tree  # blark's meta holds the same comment tokens
    assert bool(comments) is ("FB_Calc" not in name)
    assert again.raw_source is text and str(again.filename) == filename


def parse_tree_nodes(tree: Any) -> Iterator[Any]:
    from iecoop.st.read.trees import walk

    return walk(tree)


def test_a_tree_the_entry_cannot_hold_is_parsed_each_time(project: pathlib.Path, parsed: list[str]) -> None:
    """A string of blark's that is no text of the file has no place to be kept as: no entry, the file parsed again."""
    from iecoop.st.read import nodedata

    [(text, filename, line_map)] = list(parse._flat_sources(project / "FB_Calc.TcPOU"))
    tree, comments = parse.parse_one(text, filename, line_map)
    tree.items[0].name = "NotInTheText"
    with pytest.raises(nodedata.Unencodable, match="not in the text"):
        nodedata.nodes_to_data(tree, comments, text, filename)
    assert cache.entry_data(tree, comments, text, filename) is None

    real = parse.parse_one

    def renamed(text: str, name: str, line_map: dict[int, tuple[str, int]]) -> Any:
        done = real(text, name, line_map)
        if name.endswith("FB_Calc.TcPOU"):
            done[0].raw_source = "a text of blark's own"  # not the file's text: no place to keep it as
        return done

    import unittest.mock

    with unittest.mock.patch.object(parse, "parse_one", renamed):
        st.load(project)
        assert _files(project / cache.CACHE_FOLDER) == {"MAIN.TcPOU.json"}
        parsed.clear()
        assert _divide(st.load(project), 5) == 20
    assert parsed == ["FB_Calc.TcPOU"]


def test_a_load_leaves_the_cycle_collector_as_it_found_it() -> None:
    """The collector is paused while loading (see st.load) and resumed after, when the load fails too."""
    import gc

    seen: list[bool] = []
    plc = st.load("FUNCTION_BLOCK FB_A\nVAR_INPUT x : INT; END_VAR\nEND_FUNCTION_BLOCK\n", externals={})
    assert gc.isenabled() and plc.FB_A is not None
    real = parse.parse_sources

    def watching(source: Any, **kwargs: Any) -> Any:
        seen.append(gc.isenabled())
        return real(source, **kwargs)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr("iecoop.st.parse_sources", watching)
        with pytest.raises(st.StSyntaxError):
            st.load("FUNCTION_BLOCK FB_B\nVAR x : INT END_VAR\nEND_FUNCTION_BLOCK\n")
        assert gc.isenabled() and seen == [False]
        gc.disable()
        try:
            st.load("FUNCTION_BLOCK FB_C\nEND_FUNCTION_BLOCK\n")
            assert not gc.isenabled()  # paused by the caller: left paused
        finally:
            gc.enable()


def test_the_grammar_is_built_before_the_workers_start(project: pathlib.Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A forked worker starts with blark's parser built (about 0.3 s each worker would spend building its own)."""
    import concurrent.futures

    import blark.parse

    serial = st.to_python(project, cache=False)
    monkeypatch.setattr(parallel, "PARALLEL_MIN_CHARS", 0)
    monkeypatch.setattr(parallel, "WORKER_START_CHARS", 0)
    monkeypatch.setattr(parallel, "cores", lambda: 2)
    monkeypatch.setattr(blark.parse, "_PARSER", None)
    parse._tree.cache_clear()  # the parses this process keeps in memory aside
    built_at_start: list[bool] = []
    real = concurrent.futures.ProcessPoolExecutor

    def pool(*args: Any, **kwargs: Any) -> Any:
        built_at_start.append(blark.parse._PARSER is not None)
        return real(*args, **kwargs)

    monkeypatch.setattr(concurrent.futures, "ProcessPoolExecutor", pool)
    assert st.to_python(project, cache=True) == serial
    assert built_at_start == [True]
