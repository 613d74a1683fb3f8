"""The docs extension's generated pieces: the patterns table and the check that every link of the site lands."""

from __future__ import annotations

import importlib
import re
import sys
from pathlib import Path
from types import ModuleType

import pytest

from patterns.showcase.catalogue import entries
from tests.iecoop.test_uml import label_boxes, overlapping

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


def test_dead_links_reads_only_the_pages_of_this_build(pages: ModuleType, tmp_path: Path) -> None:
    import os

    (tmp_path / "old.html").write_text('<a href="renamed-away.html">stale</a>')
    os.utime(tmp_path / "old.html", (1_000_000, 1_000_000))
    (tmp_path / "new.html").write_text('<a href="old.html">fine</a> <a href="gone.html">dead</a>')
    assert pages.dead_links(tmp_path, since=2_000_000) == [("new.html", "gone.html")]
    assert sorted(pages.dead_links(tmp_path)) == [("new.html", "gone.html"), ("old.html", "renamed-away.html")]


# -- the class diagrams of the pattern pages -------------------------------------------------------

@pytest.fixture(scope="module")
def generated(pages: ModuleType, tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("site")
    pages.generate(root)
    return root


def test_every_pattern_page_shows_a_legible_participants_diagram_and_links_the_full_one(
    pages: ModuleType, generated: Path
) -> None:
    pattern_pages = [p for p in generated.glob("patterns/*/*.rst") if p.name != "index.rst"]
    assert len(pattern_pages) == 28
    for page in pattern_pages:
        text = page.read_text(encoding="utf-8")
        roles, full = page.with_name(f"{page.stem}-roles.svg"), page.with_name(f"{page.stem}.svg")
        assert f".. figure:: {roles.name}" in text and f":download:`The full class diagram <{full.name}>`" in text
        svg = roles.read_text(encoding="utf-8")
        assert pages.text_px_on_page(svg) >= 11, page.stem
        boxes = re.findall(r"<rect [^>]*class=\" stroke-B1\"", svg) or re.findall(r"<rect [^>]*stroke=", svg)
        assert 3 <= len(boxes) <= 10, page.stem
        assert overlapping(label_boxes(svg)) == [], page.stem
        assert len(full.read_text(encoding="utf-8")) > len(svg)  # the full one has every member


def test_the_roles_come_from_the_docstring(pages: ModuleType) -> None:
    import patterns.behavioral.state as state
    import patterns.solid.dip as dip
    from iecoop.uml import module_diagram

    roles = pages.pattern_roles(state, module_diagram(state).names())
    assert list(roles.items())[:3] == [
        ("IPackMLState", "State"), ("PackMLStateBase", "State"), ("AbortableState", "State"),
    ]
    assert roles["PackMLMachine"] == "Context" and roles["PackagingLine"] == "Client" and len(roles) == 10
    fewer = pages.pattern_roles(state, module_diagram(state).names(), 5)
    assert list(fewer.values()) == ["State", "Concrete states", "Context", "State and command numbers", "Client"]
    principle = pages.pattern_roles(dip, module_diagram(dip).names())
    assert principle["ConveyorControllerFixed"] == "violating design" and principle["ILamp"] == "compliant design"


def test_text_px_on_page_shrinks_wide_pictures_only(pages: ModuleType) -> None:
    narrow = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 368 100"><text font-size="12">a</text></svg>'
    wide = narrow.replace("368", "1472")
    assert pages.text_px_on_page(narrow) == 12 and pages.text_px_on_page(wide) == 6


def test_every_course_chapter_has_a_page_with_the_st_written_from_its_code(generated: Path) -> None:
    from iecoop.st import dump

    chapters = sorted(p for p in generated.glob("examples/ch*.rst"))
    assert len(chapters) == 15
    index = (generated / "examples" / "index.rst").read_text(encoding="utf-8")
    for page in chapters:
        text = page.read_text(encoding="utf-8")
        assert f"<{page.stem}>`" in index and f"   {page.stem}\n" in index, page.stem
        assert text.count(".. code-block:: iecst") >= 1 and "iecoop.st.export.dump" in text, page.stem
    # The text shown is the writer's own output for the module, not a copy kept by hand.
    import iecoop_examples.ch12_fluent_interface as chapter

    shown = (generated / "examples" / "ch12_fluent_interface.rst").read_text(encoding="utf-8")
    assert "\n".join(f"   {line}" if line else "" for line in dump(chapter, lenient=True).splitlines()) in shown
    package = (generated / "examples" / "ch11_abstract_fb_vs_interface.rst").read_text(encoding="utf-8")
    assert package.count(".. code-block:: iecst") == 3  # one per solution of the chapter package
