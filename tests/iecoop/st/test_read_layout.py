"""The read wing stays a compiler one can work in: small rooms, and no handler too branchy to follow."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from iecoop.st.read import translate
from tests.iecoop.st.layout import complexity, functions, oversized

WING = Path(translate.__file__).parent
ROOMS = sorted(WING.glob("*.py"))

#: radon's grade C at most: a function past 20 paths is split into named steps.
MOST_PATHS = 20


@pytest.mark.parametrize("room", ROOMS, ids=lambda p: p.name)
def test_no_room_over_600_lines_and_no_class_over_600(room: Path) -> None:
    assert oversized(room, module_lines=600, class_lines=600) == []


@pytest.mark.parametrize("room", ROOMS, ids=lambda p: p.name)
def test_no_function_has_more_than_20_paths(room: Path) -> None:
    branchy = [f"{name} ({score})" for name, score in functions(room) if score > MOST_PATHS]
    assert branchy == [], f"{room.name}: split into named steps: {', '.join(branchy)}"


def test_the_measure_counts_each_branch_as_radon_does() -> None:
    source = '''
def f(a, b):
    if a and b or not a:          # if +1, two boolean operators +2
        return [x for x in a if x]  # its for +1, its if +1
    while b:                      # +1
        try:
            b -= 1
        except ValueError:        # +1
            pass
    return 0 if a else 1          # +1
'''
    function = ast.parse(source).body[0]
    assert isinstance(function, ast.FunctionDef)
    assert complexity(function) == 9  # 1 + the 8 above: radon cc's grade B (9)
