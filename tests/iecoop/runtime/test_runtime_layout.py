"""The Runtime class stays within the house limit: its cohesive groups live in modules of iecoop.runtime."""

from __future__ import annotations

from pathlib import Path

from iecoop.runtime import runtime
from tests.iecoop.st.layout import oversized


def test_no_class_of_the_runtime_module_is_over_600_lines() -> None:
    assert oversized(Path(runtime.__file__), module_lines=1000, class_lines=600) == []
