"""The typing contract, proven: user FB code type-checks, and misuse is reported where it is written.

``pass/`` holds function-block code ``mypy --strict`` must accept; ``fail/``
holds code whose mistakes are marked on their line with a trailing
``# E: <part of the mypy message>``. mypy runs in-process, once per folder,
with the project's configuration. It is part of the normal test run (a few
seconds), so a change that breaks what users see in their editor fails CI.

Imports are followed silently: errors inside iecoop belong to the project-wide
mypy gate, not to the users' code checked here.
"""

from __future__ import annotations

import os
import re
import runpy
from collections.abc import Iterator
from pathlib import Path

import pytest
from mypy import api

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent
PASS_FILES = sorted((HERE / "pass").glob("*.py"))
FAIL_FILES = sorted((HERE / "fail").glob("*.py"))

MYPY_OPTIONS = [
    f"--config-file={ROOT / 'pyproject.toml'}",
    "--strict",
    "--no-incremental",
    "--cache-dir=/dev/null",
    "--follow-imports=silent",
    "--show-absolute-path",
    "--no-error-summary",
    "--no-pretty",
    "--no-color-output",
]

_ERROR = re.compile(r"^(?P<path>.+?):(?P<line>\d+): error: (?P<message>.*?)(?:  \[(?P<code>[a-z0-9-]+)\])?$")
_EXPECTED = re.compile(r"#\s*E:\s*(?P<fragment>.+?)\s*$")

Location = tuple[str, int]


def run_mypy(files: list[Path]) -> tuple[str, int]:
    """mypy's report on ``files``, run from the project root so ``iecoop`` resolves to the source tree."""
    previous = Path.cwd()
    os.chdir(ROOT)
    try:
        stdout, stderr, status = api.run([*MYPY_OPTIONS, *map(str, files)])
    finally:
        os.chdir(previous)
    assert not stderr, stderr
    return stdout, status


def reported_errors(stdout: str) -> dict[Location, list[str]]:
    errors: dict[Location, list[str]] = {}
    for line in stdout.splitlines():
        match = _ERROR.match(line)
        if match:
            where = (str(Path(match["path"]).resolve()), int(match["line"]))
            errors.setdefault(where, []).append(match["message"])
    return errors


def expected_errors(files: list[Path]) -> dict[Location, list[str]]:
    """``# E: fragment`` comments (several on one line are written ``# E: a # E: b``)."""
    expected: dict[Location, list[str]] = {}
    for path in files:
        for number, text in enumerate(path.read_text().splitlines(), start=1):
            if "# E:" not in text:
                continue
            code, _, marks = text.partition("# E:")
            fragments = [f.strip() for f in ("# E:" + marks).split("# E:") if f.strip()]
            assert code.strip(), f"{path.name}:{number}: an expectation needs code on its line"
            expected[(str(path.resolve()), number)] = fragments
    return expected


@pytest.fixture(scope="module")
def pass_report() -> Iterator[tuple[str, int]]:
    yield run_mypy(PASS_FILES)


@pytest.fixture(scope="module")
def fail_report() -> Iterator[tuple[str, int]]:
    yield run_mypy(FAIL_FILES)


def test_both_folders_hold_cases() -> None:
    assert len(PASS_FILES) >= 2 and len(FAIL_FILES) >= 2
    assert all(expected_errors([path]) for path in FAIL_FILES), "every fail/ file marks at least one error"


def test_user_code_in_pass_type_checks_under_strict(pass_report: tuple[str, int]) -> None:
    stdout, status = pass_report
    assert reported_errors(stdout) == {}, stdout
    assert status == 0, stdout


def test_fail_reports_exactly_the_marked_lines_with_the_marked_messages(fail_report: tuple[str, int]) -> None:
    stdout, status = fail_report
    reported = reported_errors(stdout)
    expected = expected_errors(FAIL_FILES)
    assert status == 1, stdout

    def short(where: Location) -> str:
        return f"{Path(where[0]).name}:{where[1]}"

    unexpected = {short(w): m for w, m in reported.items() if w not in expected}
    missing = {short(w): f for w, f in expected.items() if w not in reported}
    assert unexpected == {}, "errors on lines without '# E:'"
    assert missing == {}, "marked lines mypy accepted"
    for where, fragments in expected.items():
        messages = reported[where]
        for fragment in fragments:
            assert any(fragment in message for message in messages), f"{short(where)}: {fragment!r} not in {messages}"
        for message in messages:
            assert any(fragment in message for fragment in fragments), f"{short(where)}: unmarked error {message!r}"


def test_the_marker_parser_reads_several_marks_on_one_line(tmp_path: Path) -> None:
    sample = tmp_path / "sample.py"
    sample.write_text("x = 1\ny: str = 2  # E: first part # E: second part\n# just a comment\n")
    assert expected_errors([sample]) == {(str(sample.resolve()), 2): ["first part", "second part"]}
    line = f"{sample}:2: error: Incompatible types in assignment  [assignment]"
    assert reported_errors(line) == {(str(sample.resolve()), 2): ["Incompatible types in assignment"]}


@pytest.mark.parametrize("path", PASS_FILES, ids=lambda p: p.name)
def test_the_code_mypy_accepts_also_runs(path: Path) -> None:
    namespace = runpy.run_path(str(path), run_name=f"typing_pass_{path.stem}")
    namespace["main"]()
