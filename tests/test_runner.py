"""``python -m tests``: how it finds the other CPythons and what a missing one does."""

from __future__ import annotations

import re
import sys
import tomllib
from pathlib import Path

import pytest

from tests import __main__ as runner

HERE = "%d.%d" % sys.version_info[:2]


def test_the_running_interpreters_version_is_found_and_reported() -> None:
    found = runner.find_python(HERE)
    assert found is not None
    assert runner._version_of(found) == HERE


def test_a_missing_interpreter_or_a_pyenv_shim_without_a_version_is_not_taken(tmp_path: Path) -> None:
    assert runner.find_python("3.99") is None
    shim = tmp_path / "python3.99"
    shim.write_text("#!/bin/sh\necho 'pyenv: python3.99: command not found' >&2\nexit 127\n")
    shim.chmod(0o755)
    assert runner._version_of(str(shim)) is None
    assert runner._version_of(str(tmp_path / "nothing")) is None


@pytest.mark.parametrize(("ci", "verdict"), [(True, "FAILED"), (False, "skipped")])
def test_a_missing_interpreter_fails_under_ci_and_is_a_visible_skip_otherwise(
    ci: bool, verdict: str, capsys: pytest.CaptureFixture[str]
) -> None:
    outcomes = runner.other_pythons(["3.99"], ci=ci)
    assert [(o.title, o.verdict) for o in outcomes] == [("CPython 3.99 not found", verdict)]
    assert f"CPython 3.99: {verdict}, not found" in capsys.readouterr().out


def test_the_running_interpreter_is_not_run_twice(capsys: pytest.CaptureFixture[str]) -> None:
    assert runner.other_pythons([HERE], ci=True) == []
    assert "the interpreter running the main passes" in capsys.readouterr().out


def test_versions_are_checked_and_pyenv_patch_releases_sort_numerically() -> None:
    with pytest.raises(SystemExit):
        runner.main(["--pythons", "3.x"])
    assert sorted(["3.12.10", "3.12.9", "3.12.1"], key=runner._patch) == ["3.12.1", "3.12.9", "3.12.10"]


def test_pytests_last_line_gives_the_counts() -> None:
    line = "=========== 3 failed, 1200 passed, 4 deselected in 81.20s (0:01:21) ==========="
    found = runner._SUMMARY.search(line)
    assert found is not None and found.group(1) == "3 failed, 1200 passed, 4 deselected"
    found = runner._SUMMARY.search("1200 passed, 2 skipped in 3.10s\n")
    assert found is not None and found.group(1) == "1200 passed, 2 skipped"
    assert runner._SUMMARY.search("tests/test_x.py::test_in 3 passed") is None


def test_the_classifiers_name_exactly_the_pythons_ci_runs_the_suite_on() -> None:
    root = Path(runner.ROOT)
    project = tomllib.loads((root / "pyproject.toml").read_text())["project"]
    prefix = "Programming Language :: Python :: "
    versions = (c.removeprefix(prefix) for c in project["classifiers"])
    claimed = sorted((v for v in versions if re.fullmatch(r"3\.\d+", v)), key=runner._patch)
    found = re.search(r"-m tests .*--pythons ([\d.,]+)", (root / ".ci" / "run").read_text())
    assert found is not None, ".ci/run runs the suite on several Pythons"
    tested = sorted(found.group(1).split(","), key=runner._patch)
    assert claimed == tested == ["3.11", "3.12", "3.13"]
    assert project["requires-python"] == f">={tested[0]}"


def test_main_runs_the_gates_in_order_and_ci_fails_on_a_missing_python(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    ran: list[str] = []

    def fake_run(gate: runner.Gate, *, live: bool = True) -> runner.Outcome:
        ran.append(gate.title)
        return runner.Outcome(gate.title, "ok", 0.1, "3 passed" if "pytest" in gate.title else "")

    monkeypatch.setattr(runner, "_run", fake_run)
    monkeypatch.setattr(runner, "find_python", lambda version: "/opt/python" if version == "3.98" else None)
    monkeypatch.setattr(runner, "prepare_venv", lambda python, version: ("/venv/bin/python", runner.Outcome("env", "ok")))
    argv = ["--slow", "--pythons", f"{HERE},3.98,3.99"]
    monkeypatch.setenv("CI", "true")
    assert runner.main(argv) == 1
    # mypy and the docs first, then the pytest passes side by side (in any order)
    assert ran[:2] == ["mypy", "docs"]
    assert sorted(ran[2:]) == ["pytest", "pytest on CPython 3.98", "pytest, fast mode", "slow tests"]
    out = capsys.readouterr().out
    assert re.search(r"FAILED +0\.0 s  CPython 3\.99 not found", out) and "gates: 6 passed, 1 failed, 0 skipped" in out
    monkeypatch.setenv("CI", "")
    assert runner.main(argv) == 0
    assert "gates: 6 passed, 0 failed, 1 skipped" in capsys.readouterr().out
