"""The pages a newcomer reads and pastes from: copy buttons, ST shown as ST, code that fits, legible diagrams.

The checks of the built site read the HTML the docs gate of ``python -m tests`` writes to
``docs/_build/html``; when that build is missing or older than the sources, the site is built
once into a temporary folder (a minute or two).
"""

from __future__ import annotations

import html
import importlib
import re
import runpy
import subprocess
import sys
import tomllib
from pathlib import Path
from typing import Any

import pytest

from tests.docs.test_code_blocks import PAGES

ROOT = Path(__file__).resolve().parent.parent.parent
DOCS = ROOT / "docs"
#: The width of furo's text column, in CSS pixels, and the smallest text a diagram may show in it.
COLUMN_PX = 740
MIN_TEXT_PX = 10.0
#: The longest code line that fits the column at furo's code font size.
MAX_LINE = 100

_FENCE = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```\s*$", re.M | re.S)


def _extension() -> Any:
    """The docs extension ``docs/_ext/iecoop_pages.py``, imported as Sphinx imports it."""
    pytest.importorskip("sphinx")
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        return importlib.import_module("iecoop_pages")
    finally:
        sys.path.remove(str(DOCS / "_ext"))


@pytest.fixture(scope="module")
def conf() -> dict[str, Any]:
    saved = list(sys.path)  # conf.py puts the repository and docs/_ext on the path, as Sphinx needs
    try:
        return runpy.run_path(str(DOCS / "conf.py"))
    finally:
        sys.path[:] = saved


def copied(text: str, conf: dict[str, Any]) -> str:
    """What the copy button of a block copies: sphinx-copybutton's ``formatCopyText``, in Python."""
    prompt = re.compile(f"^({conf['copybutton_prompt_text']})(.*)")
    lines = text.split("\n")
    if not any(prompt.match(line) for line in lines):
        return text
    # Prompt lines lose their prompt, empty lines stay, every other line (the output) is left out.
    kept = []
    for line in lines:
        found = prompt.match(line)
        if found or not line.strip():
            kept.append(found.group(2) if found else line)
    return "\n".join(kept)


# -- copy buttons -----------------------------------------------------------------------------------


def test_the_copy_button_strips_prompts_and_leaves_output_out(conf: dict[str, Any]) -> None:
    assert "sphinx_copybutton" in conf["extensions"]
    assert conf["copybutton_prompt_is_regexp"] is True and conf["copybutton_only_copy_prompt_lines"] is True
    session = ">>> from iecoop import INT\n>>> def f(n: INT) -> INT:\n...     return n + 1\n...\n>>> f(1)\n2\n"
    assert copied(session, conf) == "from iecoop import INT\ndef f(n: INT) -> INT:\n    return n + 1\nf(1)\n"
    dev = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["optional-dependencies"]
    assert any(requirement.startswith("sphinx-copybutton") for requirement in dev["dev"])


def _sessions() -> list[tuple[str, str]]:
    found = []
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for match in _FENCE.finditer(text):
            if match.group(1) in ("python", "py", "pycon") and match.group(2).lstrip().startswith(">>>"):
                line = text.count("\n", 0, match.start()) + 2
                found.append((f"{page.relative_to(ROOT)}:{line}", match.group(2)))
    return found


@pytest.mark.parametrize(("where", "session"), _sessions(), ids=[where for where, _ in _sessions()])
def test_each_example_as_copied_is_a_python_file(where: str, session: str, conf: dict[str, Any]) -> None:
    """The text the copy button gives for a ``>>>`` session compiles: it can be pasted into a file as it is."""
    try:
        compile(copied(session, conf), where, "exec")
    except SyntaxError as error:
        pytest.fail(f"{where}: the copied example is no Python file: {error}")


# -- ST shown as ST ---------------------------------------------------------------------------------


def _st_beside_python(page: Path) -> list[tuple[str, list[str]]]:
    """Each ``iecst`` block of the page with the Python blocks just before and after it."""
    fences = list(_FENCE.finditer(page.read_text(encoding="utf-8")))
    return [
        (fence.group(2), [f.group(2) for f in fences[max(i - 1, 0):i + 2] if f.group(1) == "python"])
        for i, fence in enumerate(fences)
        if fence.group(1) == "iecst"
    ]


def _plain(session: str) -> str:
    """A ``>>>`` session without its prompts and ``<BLANKLINE>`` markers."""
    lines = (re.sub(r"^(>>> |\.\.\. ?)", "", line) for line in session.splitlines())
    return "\n".join(lines).replace("<BLANKLINE>", "")


@pytest.mark.parametrize(("page", "at_least"), [("st.md", 2), ("st-export.md", 1)])
def test_the_st_pages_show_the_st_they_load_as_st_blocks(page: str, at_least: int) -> None:
    pairs = [(st_text, near) for st_text, near in _st_beside_python(DOCS / page) if near]
    assert len(pairs) >= at_least, f"docs/{page} shows no ST block beside its examples"
    for st_text, near in pairs:
        # The ST block is the text a session beside it loads (its string) or prints (its output), as it stands.
        assert any(st_text.strip() in _plain(session) for session in near), f"docs/{page}: differs:\n{st_text}"


# -- the names the written ST uses ----------------------------------------------------------------


def test_a_pattern_page_says_which_names_its_st_uses() -> None:
    import patterns.behavioral.state as state
    import patterns.creational.singleton as singleton

    pages = _extension()
    section = "\n".join(pages._st_section(state))
    assert "``IPackMLState`` (not ``I_PackMLState``)" in section and "--format st -o DIR" in section
    # The note comes before the text, which is the writer's own.
    assert section.index("(not ``I_PackMLState``)") < section.index("INTERFACE IPackMLState")
    assert ("PackMLState", "E_PackMLState") in pages.st_names(state)
    assert all(python != st for python, st in pages.st_names(singleton))


# -- the built site ---------------------------------------------------------------------------------


def _sources() -> list[Path]:
    found = [p for p in DOCS.rglob("*") if p.is_file() and "_build" not in p.parts and p.suffix in (".md", ".py", ".css")]
    return [*found, *(ROOT / "iecoop" / "uml").glob("*.py")]


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    pytest.importorskip("sphinx")
    built = DOCS / "_build" / "html"
    pages = list(built.glob("*.html"))
    if pages and max(p.stat().st_mtime for p in pages) >= max(p.stat().st_mtime for p in _sources()):
        return built
    out = tmp_path_factory.mktemp("html")
    done = subprocess.run(
        [sys.executable, "-m", "sphinx", "-q", "-b", "html", str(DOCS), str(out)],
        capture_output=True, text=True, cwd=ROOT, timeout=1800,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return out


def _pages(site: Path) -> list[Path]:
    return [p for p in site.rglob("*.html") if not {"_modules", "_sources", "_static"} & set(p.relative_to(site).parts)]


def test_every_page_with_examples_has_the_copy_button(site: Path) -> None:
    with_code = [p for p in _pages(site) if '<div class="highlight' in p.read_text(encoding="utf-8")]
    assert len(with_code) >= 20
    for page in with_code:
        text = page.read_text(encoding="utf-8")
        assert re.search(r'<script src="[./]*_static/copybutton\.js', text), page.relative_to(site)
    script = (site / "_static" / "copybutton.js").read_text(encoding="utf-8")
    assert "formatCopyText(text, '>>> |\\\\.\\\\.\\\\. ', true, true" in script


def _wraps(css: str) -> bool:
    rule = re.search(r"\.highlight pre[^{]*\{([^}]*)\}", css)
    return rule is not None and "pre-wrap" in rule.group(1)


def test_no_code_line_runs_past_the_text_column(site: Path) -> None:
    """A line longer than the column wraps in its block (the site's stylesheet), or there is none."""
    long_lines: list[str] = []
    for page in _pages(site):
        text = page.read_text(encoding="utf-8")
        wrapped = any(
            _wraps((page.parent / href.split("?")[0]).read_text(encoding="utf-8"))
            for href in re.findall(r'<link rel="stylesheet"[^>]*href="([^"]*iecoop\.css[^"]*)"', text)
        )
        for pre in re.findall(r"<pre[^>]*>(.*?)</pre>", text, re.S):
            lines = html.unescape(re.sub(r"<[^>]+>", "", pre)).splitlines()
            long_lines += [f"{page.relative_to(site)}: {line}" for line in lines if len(line) > MAX_LINE and not wrapped]
    assert long_lines == []


def _text_px(svg: str) -> float:
    width = float(re.search(r'viewBox="[-\d.]+ [-\d.]+ ([\d.]+)', svg).group(1))  # type: ignore[union-attr]
    sizes = [float(size) for size in re.findall(r'font-size(?::|=")\s*([\d.]+)', svg)]
    return min(sizes) * min(1.0, COLUMN_PX / width)


def test_the_state_diagrams_are_legible_in_the_column(tmp_path: Path) -> None:
    import patterns.behavioral.state as state

    _extension()._state_section(state, tmp_path, "state", set())
    drawn = {path.name: _text_px(path.read_text(encoding="utf-8")) for path in tmp_path.glob("*.svg")}
    assert len(drawn) == 2 and min(drawn.values()) >= MIN_TEXT_PX, drawn


def test_every_diagram_shown_on_a_page_is_legible_in_the_column(site: Path) -> None:
    shown = {
        (page.parent / src).resolve()
        for page in _pages(site)
        for src in re.findall(r'<img [^>]*src="([^"]+\.svg)"', page.read_text(encoding="utf-8"))
    }
    assert len(shown) >= 30  # the participants of 28 patterns and principles, the state model twice
    small = {path.name: round(_text_px(path.read_text(encoding="utf-8")), 1) for path in shown}
    assert {name: px for name, px in small.items() if px < MIN_TEXT_PX} == {}
