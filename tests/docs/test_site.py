"""The docs extension's generated pieces: the patterns table and the check that every link of the site lands."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path
from types import ModuleType

import pytest

from patterns.showcase.catalogue import entries

ROOT = Path(__file__).resolve().parent.parent.parent


@pytest.fixture(scope="module")
def pages() -> ModuleType:
    pytest.importorskip("sphinx")
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    try:
        return importlib.import_module("iecoop_pages")
    finally:
        sys.path.remove(str(ROOT / "docs" / "_ext"))


def test_the_patterns_table_has_a_row_per_pattern_and_principle(pages: ModuleType) -> None:
    lines: list[str] = pages.patterns_table()
    rows = [line for line in lines if line.startswith("   * - :doc:")]
    assert len(rows) == 28
    assert lines[lines.index("   * - :doc:`State <behavioral/state>`") + 1:][:3] == [
        "     - Behavioral",
        "     - the PackML unit state machine, one function block per state.",
        f"     - {next(e.use_when for e in entries() if e.name == 'state')}",
    ]
    assert "   * - :doc:`Dependency inversion (DIP) <solid/dip>`" in lines
    assert "see its page" not in "\n".join(lines)  # every pattern and principle says when to use it


def test_every_pattern_and_principle_says_when_to_use_it() -> None:
    toured = [e for e in entries() if e.category != "examples"]
    assert len(toured) == 28
    for entry in toured:
        assert 30 <= len(entry.use_when) <= 120, entry.name


def test_dead_links_finds_missing_files_and_anchors(pages: ModuleType, tmp_path: Path) -> None:
    (tmp_path / "sub").mkdir()
    (tmp_path / "index.html").write_text(
        '<a href="sub/page.html#here">ok</a> <a href="sub/page.html#gone">anchor</a> '
        '<a href="missing.html">file</a> <a href="https://example.org/x.html">other site</a> '
        '<a href="#top">self</a> <link href="style.css?v=1"><p id="top"></p>'
    )
    (tmp_path / "sub" / "page.html").write_text('<div id="here"></div><a href="../index.html#top">back</a>')
    (tmp_path / "style.css").write_text("")
    assert pages.dead_links(tmp_path) == [("index.html", "sub/page.html#gone"), ("index.html", "missing.html")]
