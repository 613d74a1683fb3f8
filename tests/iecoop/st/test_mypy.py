"""The Python that ``st.to_python`` writes passes ``mypy --strict``: every ST source of these tests, in one run."""

from __future__ import annotations

import pathlib

import pytest

from iecoop import st
from tests.iecoop.st.test_load import CASES, OOP
from tests.iecoop.st.test_load_cases import CASES as MORE_CASES, TASK_INFO
from tests.iecoop.st.test_semantics import CASES as SEMANTIC_CASES
from tests.typing.test_typing import run_mypy

DATA = pathlib.Path(__file__).parent / "data"


@pytest.mark.slow  # seconds each: once, in the slow gate
def test_generated_python_passes_mypy_strict(tmp_path: pathlib.Path) -> None:
    sources: dict[str, str | pathlib.Path] = {"twincat": DATA / "twincat", "oop": OOP, "task_info": TASK_INFO}
    sources.update({path.stem: path for path in sorted((DATA / "course").glob("*.st"))})
    sources.update({f"case_{name.replace('-', '_')}": text for name, text, *_ in [*CASES, *SEMANTIC_CASES, *MORE_CASES]})
    files = []
    for name, source in sources.items():
        path = tmp_path / f"st_{name}.py"
        path.write_text(st.to_python(source))
        files.append(path)
    report, status = run_mypy(files)
    assert (report, status) == ("", 0)
