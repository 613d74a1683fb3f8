"""The catalogue is complete: all 23 patterns and the 5 SOLID principles exist, documented, runnable and tested.

Like a "no unhandled rule" meta-test: adding a pattern without its sections,
its runnable example or its test module fails here, as does a VAR section
kind that no test and no documentation page mentions.
"""

from __future__ import annotations

import doctest
import importlib
import inspect
import re
from pathlib import Path

import pytest

from iecoop.declarations import SECTIONS
from iecoop.uml import module_diagram

ROOT = Path(__file__).resolve().parents[2]

PATTERNS = {
    "creational": ["factory_method", "abstract_factory", "builder", "prototype", "singleton"],
    "structural": ["adapter", "bridge", "composite", "decorator", "facade", "flyweight", "proxy"],
    "behavioral": [
        "chain_of_responsibility", "command", "iterator", "mediator", "memento", "observer", "state", "strategy",
        "template_method", "visitor", "interpreter",
    ],
}
PATTERN_SECTIONS = ["Intent", "The PLC problem", "Roles", "IEC 61131-3 mapping", "When not to use it on a PLC", "References"]
SOLID = ["srp", "ocp", "lsp", "isp", "dip"]
SOLID_SECTIONS = ["Principle", "The course example", "Violating design", "Compliant design", "References"]

ALL = [(category, name) for category, names in PATTERNS.items() for name in names] + [("solid", n) for n in SOLID]


def _headings(doc: str) -> list[str]:
    """RST section titles: a line followed by a line of dashes as long."""
    lines = doc.splitlines()
    return [a.strip() for a, b in zip(lines, lines[1:]) if b.strip() and set(b.strip()) == {"-"} and len(b.strip()) >= len(a.strip())]


def test_there_are_23_patterns_and_5_principles_and_nothing_unlisted() -> None:
    assert sum(len(v) for v in PATTERNS.values()) == 23
    for category in [*PATTERNS, "solid"]:
        on_disk = {p.stem for p in (ROOT / "patterns" / category).glob("*.py") if p.stem != "__init__"}
        listed = set(PATTERNS.get(category, SOLID))
        assert on_disk == listed, f"patterns/{category}: unlisted {on_disk - listed}, missing {listed - on_disk}"


@pytest.mark.parametrize(("category", "name"), ALL, ids=[n for _, n in ALL])
def test_each_module_has_its_sections_a_runnable_main_a_test_module_and_a_diagram(category: str, name: str) -> None:
    module = importlib.import_module(f"patterns.{category}.{name}")
    doc = module.__doc__ or ""
    wanted = SOLID_SECTIONS if category == "solid" else PATTERN_SECTIONS
    headings = _headings(doc)
    missing = [s for s in wanted if s not in headings]
    assert not missing, f"{module.__name__}: docstring sections missing: {missing} (has {headings})"
    main = getattr(module, "main", None)
    assert callable(main) and inspect.signature(main).parameters == {}, f"{module.__name__} needs main()"
    examples = doctest.DocTestParser().get_examples(inspect.getdoc(main) or "")
    assert any("main()" in e.source for e in examples), f"{module.__name__}.main's docstring must run main()"
    assert (ROOT / "tests" / "patterns" / f"test_{name}.py").is_file(), f"no tests/patterns/test_{name}.py"
    diagram = module_diagram(module)
    assert len(diagram.classes) >= 2 and diagram.relations, f"{module.__name__}: the class diagram is empty"
    assert re.search(r"class \w+\(Program\)|\(Program\)", inspect.getsource(module)), f"{module.__name__}: no Program"


def test_every_var_section_kind_is_tested_and_documented() -> None:
    tests = "\n".join(p.read_text(encoding="utf-8") for p in (ROOT / "tests").rglob("*.py"))
    docs = "\n".join(p.read_text(encoding="utf-8") for p in (ROOT / "docs").rglob("*.md"))
    docs += (ROOT / "iecoop" / "declarations.py").read_text(encoding="utf-8")
    for section in SECTIONS:
        # VAR_GLOBAL is written as the variables of a GlobalVariables class
        declared = r"\(GlobalVariables\)" if section == "VAR_GLOBAL" else rf"\b{section}\("
        assert re.search(declared, tests), f"no test declares a {section} variable"
        assert section in docs, f"no documentation page mentions {section}"
