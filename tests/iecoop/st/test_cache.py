"""The translation cache: an entry per ST file, used only when it matches and checks, never trusted."""

from __future__ import annotations

import hashlib
import hmac
import json
import pathlib
import shutil
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


def _tokens(node: Any) -> Iterator[list[Any]]:
    if isinstance(node, list) and isinstance(node[1], int):
        yield node
    elif isinstance(node, list):
        for child in node[2]:
            yield from _tokens(child)


def test_a_tampered_entry_is_not_used(project: pathlib.Path, parsed: list[str], user_cache: pathlib.Path) -> None:
    """An entry edited without the user's key is refused; a signed one still cannot hold text the ST does not."""
    st.load(project)
    entry = project / cache.CACHE_FOLDER / "FB_Calc.TcPOU.json"
    signature, _, body = entry.read_bytes().partition(b"\n")
    # Edited without the key (even to the same JSON data): the signature no longer matches.
    entry.write_bytes(signature + b"\n" + body + b" ")
    parsed.clear()
    assert _divide(st.load(project), 5) == 20 and parsed == ["FB_Calc.TcPOU"]

    # Signed with the user's own key: a token is a place in the ST file, so it holds no text of its own;
    # one that points past the text, or a name that is no grammar name, refuses the entry.
    def outside(data: dict[str, Any]) -> None:
        token = next(_tokens(data["tree"]))
        token[2] = 10**9

    def named(data: dict[str, Any]) -> None:
        data["tree"][0] = "__import__('os').system('x')"

    for change in (outside, named):
        _resign(entry, user_cache, change)
        parsed.clear()
        module = st.load(project)
        assert _divide(module, 5) == 20 and parsed == ["FB_Calc.TcPOU"]
    assert b"nValue" not in entry.read_bytes()  # the entry holds places, not the ST's text


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


def test_an_unwritable_source_folder_uses_the_user_cache(project: pathlib.Path, parsed: list[str], user_cache: pathlib.Path) -> None:
    (project / cache.CACHE_FOLDER).write_text("a file where the folder would be")
    st.load(project)
    assert sorted(p.name.split(".")[0] for p in (user_cache / "st").iterdir()) == ["FB_Calc", "MAIN"]
    parsed.clear()
    st.load(project)
    assert parsed == []


@pytest.mark.parametrize("how", ["argument", "environment"])
def test_opt_out(project: pathlib.Path, parsed: list[str], monkeypatch: pytest.MonkeyPatch, how: str) -> None:
    if how == "environment":
        monkeypatch.setenv("IECOOP_ST_CACHE", "0")
        st.load(project)
    else:
        st.load(project, cache=False)
    assert not (project / cache.CACHE_FOLDER).exists()


def test_parsing_in_a_pool_gives_the_same_module(project: pathlib.Path, monkeypatch: pytest.MonkeyPatch) -> None:
    serial = st.to_python(project, cache=False)
    monkeypatch.setattr(parallel, "PARALLEL_MIN_CHARS", 0)
    monkeypatch.setattr(parallel, "cores", lambda: 2)
    pooled: list[int] = []
    real = parallel._in_pool

    def counted(flat: Any, parser: Any) -> Any:
        pooled.append(len(flat))
        return real(flat, parser)

    monkeypatch.setattr(parallel, "_in_pool", counted)
    assert st.to_python(project, cache=True) == serial
    assert pooled == [2]


def test_a_syntax_error_in_a_pool_names_the_first_bad_file(project: pathlib.Path, monkeypatch: pytest.MonkeyPatch) -> None:
    for name in ("FB_Calc.TcPOU", "MAIN.TcPOU"):
        path = project / name
        path.write_text(path.read_text().replace(":=", ":= :=", 1))
    monkeypatch.setattr(parallel, "PARALLEL_MIN_CHARS", 0)
    monkeypatch.setattr(parallel, "cores", lambda: 2)
    with pytest.raises(st.StSyntaxError, match=r"FB_Calc\.TcPOU:\d+: Structured Text syntax error"):
        st.load(project, cache=False)
