"""The translation cache: blark's parse of each ST file, kept as data beside the sources.

Parsing is most of a cold load (blark's Earley parser, about half a second a
kilobyte); the translation after it is quick. So each source file's tree
(blark's dataclasses, as ``read.nodedata`` writes them) and comment tokens
are kept in ``__iecoop_cache__/<file>.json`` beside it (as ``__pycache__``
keeps bytecode), or in the user's cache folder when that one cannot be
written or is a link to somewhere else. An entry is used only when everything it was made from is the same:
the flat ST text (its SHA-256), the versions of iecoop, blark, lark and
Python, blark's grammar and transform files, and the grammar used.

An entry is never trusted. It holds plain JSON (no pickle, nothing that runs
on load: a node is one of blark's classes from a fixed table, given its
fields); it is signed with a key kept in the user's cache folder
(HMAC-SHA256), so an entry this user did not write (copied in, edited,
damaged) is ignored and rebuilt; and a token or string is kept as its place
in the source, its text read back from the ST itself, so the tree can only
say what the ST says. Opt out with ``st.load(..., cache=False)`` or the
environment variable ``IECOOP_ST_CACHE=0``.
"""

from __future__ import annotations

import functools
import hashlib
import hmac
import json
import os
import pathlib
import secrets
import sys
import tempfile
from typing import Any

from iecoop.st.read.nodedata import Lines, Unencodable, nodes_from_data, nodes_to_data

__all__ = ["CACHE_FOLDER", "Lines", "Parsed", "enabled", "entry_data", "load_entry", "store_entry"]

#: The folder beside the sources that holds their entries.
CACHE_FOLDER = "__iecoop_cache__"
#: Bumped when the entry's layout changes.
FORMAT = 3

#: blark's tree (``blark.transform.SourceCode``) and the comment tokens of one flat source.
Parsed = tuple[Any, tuple[Any, ...]]


def enabled(cache: bool | None) -> bool:
    """Whether to use the cache: ``cache`` if given, else not when ``IECOOP_ST_CACHE`` is ``0`` / ``false`` / ``no``."""
    if cache is not None:
        return cache
    return os.environ.get("IECOOP_ST_CACHE", "1").strip().lower() not in ("0", "false", "no", "off")


def user_cache_dir() -> pathlib.Path:
    """``$XDG_CACHE_HOME/iecoop`` (``~/.cache/iecoop``), ``%LOCALAPPDATA%\\iecoop\\cache`` on Windows."""
    if sys.platform == "win32" and os.environ.get("LOCALAPPDATA"):
        return pathlib.Path(os.environ["LOCALAPPDATA"]) / "iecoop" / "cache"
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return pathlib.Path(base) / "iecoop"


@functools.lru_cache(maxsize=1)
def versions() -> str:
    """What a parse depends on besides the text: iecoop, blark (its version and files), lark, Python and the entry format."""
    from importlib.metadata import PackageNotFoundError, version

    found = []
    for package in ("iecoop", "blark", "lark"):
        try:
            found.append(f"{package}={version(package)}")
        except PackageNotFoundError:
            found.append(f"{package}=?")
    return ";".join([*found, f"blark-files={blark_files()}", f"python={sys.version.split()[0]}", f"format={FORMAT}"])


def blark_files() -> str:
    """A digest of blark's grammar and transform as installed: a blark of the same version number that makes other
    trees (a checkout, a patched copy) has other entries."""
    import importlib.resources

    digest = hashlib.sha256()
    try:
        package = importlib.resources.files("blark")
        for name in ("iec.lark", "transform.py"):
            digest.update(package.joinpath(name).read_bytes())
    except (ModuleNotFoundError, OSError):
        return "?"
    return digest.hexdigest()[:16]


def _key_file() -> pathlib.Path:
    return user_cache_dir() / "signing.key"


def _signing_key() -> bytes | None:
    """This user's key for signing entries (made on first use, readable by the user alone); None if it cannot be had."""
    path = _key_file()
    try:
        data = path.read_bytes()
        if len(data) == 32:
            return data
    except OSError:
        pass
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        key = secrets.token_bytes(32)
        descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        with os.fdopen(descriptor, "wb") as handle:
            handle.write(key)
        return key
    except FileExistsError:  # another process made it first
        try:
            data = path.read_bytes()
        except OSError:
            return None
        return data if len(data) == 32 else None
    except OSError:
        return None


def _entry_paths(source: pathlib.Path) -> list[pathlib.Path]:
    """Where the entry of ``source`` may be: beside it, then in the user's cache folder."""
    digest = hashlib.sha256(str(source.resolve()).encode()).hexdigest()[:16]
    return [source.parent / CACHE_FOLDER / f"{source.name}.json", user_cache_dir() / "st" / f"{source.name}.{digest}.json"]


def _identity(text: str, grammar: str) -> str:
    return f"{versions()};grammar={grammar};sha256={hashlib.sha256(text.encode()).hexdigest()}"


def load_entry(source: pathlib.Path, text: str, grammar: str) -> Parsed | None:
    """blark's tree and comment tokens for the flat ``text`` of ``source`` from its entry; None if there is no valid one."""
    key = _signing_key()
    if key is None:
        return None
    identity = _identity(text, grammar)
    for path in _entry_paths(source):
        try:
            raw = path.read_bytes()
        except OSError:
            continue
        found = _verified(raw, key, identity, text, str(source))
        if found is not None:
            return found
    return None


def _verified(raw: bytes, key: bytes, identity: str, text: str, filename: str) -> Parsed | None:
    """The tree and comments of an entry whose signature, identity and data all check; None otherwise."""
    signature, _, body = raw.partition(b"\n")
    expected = hmac.new(key, body, hashlib.sha256).hexdigest().encode()
    if not hmac.compare_digest(signature, expected):
        return None
    try:
        entry = json.loads(body)
        if not isinstance(entry, dict) or entry.get("identity") != identity:
            return None
        return nodes_from_data(entry["nodes"], text, filename)
    except (ValueError, TypeError, KeyError, IndexError, AttributeError, RecursionError):
        return None


def entry_data(tree: Any, comments: tuple[Any, ...], text: str, filename: str) -> dict[str, Any] | None:
    """What an entry keeps of a parse (``read.nodedata``), or None when the tree holds what that form does not."""
    try:
        return nodes_to_data(tree, comments, text, filename)
    except Unencodable:
        return None


def store_entry(source: pathlib.Path, text: str, grammar: str, nodes: dict[str, Any]) -> None:
    """Keep the entry for ``source`` (``nodes``: its ``entry_data``): beside it if that folder can be written, else in
    the user's cache folder."""
    key = _signing_key()
    if key is None:
        return
    body = json.dumps({"identity": _identity(text, grammar), "nodes": nodes}, separators=(",", ":")).encode()
    data = hmac.new(key, body, hashlib.sha256).hexdigest().encode() + b"\n" + body
    for path in _entry_paths(source):
        if path.parent.is_symlink() and path.parent.parent == source.parent:
            continue  # a project's __iecoop_cache__ that links elsewhere: nothing is written outside the project
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            # Written whole then renamed: a reader sees the old entry or the new one, never half of one.
            descriptor, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
            try:
                with os.fdopen(descriptor, "wb") as handle:
                    handle.write(data)
                os.replace(temporary, path)
            except BaseException:
                os.unlink(temporary)
                raise
            return
        except OSError:
            continue
