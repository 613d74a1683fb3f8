"""Every Python block of the docs that a reader would paste into a file runs, as it stands.

The ``>>>`` examples run as doctests; the blocks without prompts are whole
files (a test module, a script). Each is written to a file of its own and run:
a block with ``test_`` functions by pytest (every one of them must pass) and
checked by ``mypy --strict``, any other block by Python.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent.parent
#: The hand-written pages (the generated pattern pages show module source, which the tests run anyway).
PAGES = sorted(
    path for path in [*ROOT.glob("docs/**/*.md"), ROOT / "README.md"]
    if "_build" not in path.parts and not path.name.startswith("_")
)
_FENCE = re.compile(r"^```(python|py)\n(.*?)^```\s*$", re.M | re.S)


def blocks() -> list[tuple[str, str]]:
    found = []
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for number, match in enumerate(_FENCE.finditer(text), 1):
            code = match.group(2)
            if not code.lstrip().startswith(">>>"):
                line = text.count("\n", 0, match.start()) + 2
                found.append((f"{page.relative_to(ROOT)}:{line}", code))
    return found


BLOCKS = blocks()


def test_the_docs_have_paste_ready_blocks() -> None:
    assert any(where.startswith("docs/testing.md") for where, _ in BLOCKS)


@pytest.mark.parametrize(("where", "code"), BLOCKS, ids=[where for where, _ in BLOCKS])
def test_the_block_runs_as_pasted(where: str, code: str, tmp_path: Path) -> None:
    tests = re.findall(r"^def (test_\w+)\(", code, re.M)
    path = tmp_path / ("test_pasted.py" if tests else "pasted.py")
    path.write_text(code, encoding="utf-8")
    if not tests:
        done = subprocess.run([sys.executable, str(path)], capture_output=True, text=True, cwd=tmp_path, timeout=120)
        assert done.returncode == 0, f"{where}:\n{done.stderr}"
        return
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", str(path)],
        capture_output=True, text=True, cwd=tmp_path, timeout=300,
    )
    assert done.returncode == 0, f"{where}:\n{done.stdout}\n{done.stderr}"
    assert f"{len(tests)} passed" in done.stdout, done.stdout
    typed = subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-error-summary", str(path)],
        capture_output=True, text=True, cwd=ROOT, timeout=300,
    )
    assert typed.returncode == 0, f"{where}: mypy --strict\n{typed.stdout}"
