"""The failure paths of the ``iecoop`` command: exit status 2 and one line naming the file, never a traceback.

Exit status: 0 ok, 1 a PLC fault at run time or a failed check, 2 bad usage or
input that does not load. Through ``main([...])`` with captured output, and
through the installed script.
"""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from iecoop import st
from iecoop.cli import main as iecoop_main
from patterns.showcase import main as showcase_main

SCRIPT = Path(sys.executable).with_name("iecoop")
COUNT = "PROGRAM MAIN\nVAR nCount : INT; END_VAR\nnCount := nCount + 1;\nEND_PROGRAM\n"


def run(capsys: pytest.CaptureFixture[str], *argv: str, main: Callable[[list[str]], int] = iecoop_main) -> tuple[int, str, str]:
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def one_line(err: str) -> str:
    """The error, asserted to be one line without a traceback."""
    assert "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 1, err
    return lines[0]


@pytest.fixture
def count(tmp_path: Path) -> Path:
    source = tmp_path / "count.st"
    source.write_text(COUNT)
    return source


@pytest.fixture
def broken_translation(monkeypatch: pytest.MonkeyPatch) -> None:
    """The translator hands back Python that does not compile (what an untranslated construct can give)."""

    def translate(units: Any, **options: Any) -> tuple[str, list[tuple[str, str]], list[tuple[str, int] | None]]:
        return "class MAIN(Program):\n    class: INT = VAR()\n", [("program", "MAIN")], []

    monkeypatch.setattr(st, "_translator", lambda: translate)


# -- 1, 2: a source whose translation does not compile ------------------------------------------------


def test_st_run_of_a_translation_that_does_not_compile_exits_2(
    capsys: pytest.CaptureFixture[str], count: Path, broken_translation: None
) -> None:
    status, out, err = run(capsys, "st", "run", str(count))
    line = one_line(err)
    assert (status, out) == (2, "")
    assert line.startswith(f"iecoop st run: {count}: ") and "cannot run" in line and "line 2" in line


def test_st2py_of_a_translation_that_does_not_compile_exits_2_and_prints_no_python(
    capsys: pytest.CaptureFixture[str], count: Path, broken_translation: None, tmp_path: Path
) -> None:
    status, out, err = run(capsys, "st2py", str(count))
    line = one_line(err)
    assert (status, out) == (2, "")
    assert line.startswith(f"iecoop st2py: {count}: ") and "does not compile" in line and "line 2" in line
    status, out, err = run(capsys, "st2py", str(count), "-o", str(tmp_path / "out"))
    assert status == 2 and not (tmp_path / "out" / "count.py").exists()


@pytest.mark.parametrize("empty", ["file", "folder"])
def test_st2py_of_a_source_that_declares_nothing_exits_2(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, empty: str
) -> None:
    source = tmp_path / ("empty.st" if empty == "file" else "empty")
    source.write_text("") if empty == "file" else source.mkdir()
    status, out, err = run(capsys, "st2py", str(source))
    assert (status, out) == (2, "")
    assert one_line(err) == f"iecoop st2py: {source}: no POU, type or GVL in it"


# -- 3: counts and durations ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["st", "run", "{src}", "--cycles", "-1"], "argument --cycles: must be at least 1, got -1"),
        (["st", "run", "{src}", "--cycles", "0"], "argument --cycles: must be at least 1, got 0"),
        (["st", "run", "{src}", "--every", "0"], "argument --every: must be at least 1, got 0"),
        (["st", "run", "{src}", "--every", "-3"], "argument --every: must be at least 1, got -3"),
        (["st", "run", "{src}", "--cycles", "1.5"], "argument --cycles: expected a whole number, got '1.5'"),
        (["serve", "{src}", "--duration", "0ms"], "argument --duration: must be longer than 0 ms"),
        (["serve", "{src}", "--duration=-5s"], "argument --duration: bad TIME literal '-5s'"),
    ],
)
def test_every_count_and_duration_must_be_positive(
    capsys: pytest.CaptureFixture[str], count: Path, argv: list[str], message: str
) -> None:
    status, out, err = run(capsys, *[arg.replace("{src}", str(count)) for arg in argv])
    assert (status, out) == (2, "")
    assert err.startswith("usage: iecoop") and message in err


def test_without_the_showcase_a_command_is_needed(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, err = run(capsys)
    assert (status, out) == (2, "")
    assert err.startswith("usage: iecoop") and "iecoop: a COMMAND is needed" in err


# -- 4: outputs of one run ------------------------------------------------------------------------------


def test_st2py_refuses_two_sources_with_one_output_name(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    first, second = tmp_path / "a" / "main.st", tmp_path / "b" / "main.st"
    for source in (first, second):
        source.parent.mkdir()
        source.write_text(COUNT)
    output = tmp_path / "out"
    status, out, err = run(capsys, "st2py", str(first), str(second), "-o", str(output))
    line = one_line(err)
    assert (status, out) == (2, "")
    assert str(first) in line and str(second) in line and str(output / "main.py") in line
    assert not output.exists() or list(output.iterdir()) == []  # nothing half written


def test_st2py_does_not_write_outside_the_output_folder(capsys: pytest.CaptureFixture[str], count: Path, tmp_path: Path) -> None:
    output, elsewhere = tmp_path / "out", tmp_path / "elsewhere.py"
    output.mkdir()
    elsewhere.write_text("kept\n")
    (output / "count.py").symlink_to(elsewhere)
    status, out, err = run(capsys, "st2py", str(count), "-o", str(output))
    line = one_line(err)
    assert (status, out) == (2, "")
    assert str(output / "count.py") in line and "outside" in line
    assert elsewhere.read_text() == "kept\n"


def test_st2py_into_a_file_instead_of_a_folder_exits_2(capsys: pytest.CaptureFixture[str], count: Path, tmp_path: Path) -> None:
    (tmp_path / "taken").write_text("")
    status, _, err = run(capsys, "st2py", str(count), "-o", str(tmp_path / "taken"))
    assert status == 2 and str(tmp_path / "taken") in one_line(err) and "not a folder" in err


# -- 5: export into a file, and bad inputs of every subcommand ------------------------------------------


def test_export_into_an_existing_file_exits_2(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    taken = tmp_path / "taken"
    taken.write_text("")
    status, out, err = run(capsys, "export", "observer", "-o", str(taken), main=showcase_main)
    assert (status, out) == (2, "")
    assert one_line(err) == f"iecoop export: cannot write into {taken}: it is a file, not a folder"


def _inputs(tmp_path: Path) -> dict[str, Path]:
    """Sources that do not load, by what is wrong with them."""
    folder = tmp_path / "folder"
    folder.mkdir()
    (tmp_path / "empty.st").write_text("")
    (tmp_path / "empty.py").write_text("")
    (tmp_path / "notes.txt").write_text("PROGRAM MAIN\nEND_PROGRAM\n")
    (tmp_path / "broken.py").write_bytes(b"from iecoop import FunctionBlock\nclass A(FunctionBlock:\n")
    return {
        "missing": tmp_path / "missing.st",
        "missing-py": tmp_path / "missing.py",
        "folder": folder,
        "empty": tmp_path / "empty.st",
        "empty-py": tmp_path / "empty.py",
        "suffix": tmp_path / "notes.txt",
        "broken-py": tmp_path / "broken.py",
    }


@pytest.mark.parametrize(
    ("command", "source", "message"),
    [
        ("st2py", "missing", "does not exist"),
        ("st2py", "empty", "no POU, type or GVL in it"),
        ("st2py", "folder", "no POU, type or GVL in it"),
        ("st2py", "suffix", "unsupported file kind '.txt'"),
        ("st run", "missing", "does not exist"),
        ("st run", "empty", "declares no PROGRAM MAIN"),
        ("st run", "folder", "declares no PROGRAM MAIN"),
        ("st run", "suffix", "unsupported file kind '.txt'"),
        ("serve", "missing", "does not exist"),
        ("serve", "empty", "declares no PROGRAM MAIN"),
        ("serve", "suffix", "unsupported file kind '.txt'"),
        ("export", "missing-py", "does not exist"),
        ("export", "folder", "no iecoop class to export"),  # a folder is an ST project: this one declares nothing
        ("export", "empty-py", "no iecoop class to export"),
        ("export", "suffix", "not a Python file"),
        ("export", "broken-py", "line 2"),
    ],
)
@pytest.mark.parametrize("main", [iecoop_main, showcase_main], ids=["iecoop.cli", "showcase"])
def test_a_source_that_does_not_load_gives_one_line_naming_it_and_exits_2(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, command: str, source: str, message: str,
    main: Callable[[list[str]], int],
) -> None:
    path = _inputs(tmp_path)[source]
    output = ["-o", str(tmp_path / "out")] if command == "export" else []
    status, out, err = run(capsys, *command.split(), str(path), *output, main=main)
    line = one_line(err)
    assert (status, out) == (2, "")
    assert line.startswith(f"iecoop {command}: ") and str(path) in line and message in line


@pytest.mark.parametrize(
    "error",
    [
        UnicodeDecodeError("utf-8", b"caf\xe9", 3, 4, "invalid continuation byte"),
        PermissionError(13, "Permission denied", "{path}"),
        IsADirectoryError(21, "Is a directory", "{path}"),
    ],
    ids=["cp1252", "unreadable", "directory"],
)
@pytest.mark.parametrize("command", ["st2py", "st run", "serve"])
def test_a_source_that_cannot_be_read_gives_one_line_naming_it(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch, count: Path, error: Exception, command: str
) -> None:
    if isinstance(error, OSError):
        error.filename = str(count)

    def fail(*args: object, **kwargs: object) -> object:
        raise error

    monkeypatch.setattr(st, "parse_sources", fail)
    status, out, err = run(capsys, *command.split(), str(count))
    line = one_line(err)
    assert (status, out) == (2, "")
    assert line.startswith(f"iecoop {command}: {count}: ")


def test_an_undecodable_file_in_a_folder_is_named(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    (tmp_path / "a.st").write_text(COUNT)
    (tmp_path / "b.st").write_bytes(b"PROGRAM P\nVAR s : STRING := '\x81\x8d'; END_VAR\nEND_PROGRAM\n")
    status, out, err = run(capsys, "st2py", str(tmp_path))
    if status == 0:  # the reader decodes Windows code pages
        assert "class P(Program)" in out
        return
    assert status == 2 and str(tmp_path / "b.st") in one_line(err) and "UTF-8" in err


# -- through the installed script -----------------------------------------------------------------------


def script(*argv: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(SCRIPT), *argv], capture_output=True, text=True, cwd=cwd, timeout=120,
                          env={**os.environ, "PYTHONWARNINGS": ""})


@pytest.mark.slow  # seconds each: once, in the slow gate
def test_the_installed_script_exits_2_without_a_traceback(tmp_path: Path) -> None:
    (tmp_path / "count.st").write_text(COUNT)
    (tmp_path / "keyword.st").write_text("PROGRAM MAIN\nVAR class : INT; END_VAR\nclass := 1;\nEND_PROGRAM\n")
    (tmp_path / "cp1252.st").write_bytes(b"PROGRAM MAIN\nVAR s : STRING := 'caf\xe9'; n : INT; END_VAR\nn := n + 1;\nEND_PROGRAM\n")
    (tmp_path / "taken").write_text("")
    for argv in (
        ["st", "run", "count.st", "--cycles", "-1"],
        ["st", "run", "count.st", "--every", "0"],
        ["export", "observer", "-o", "taken"],
        ["st", "run", "missing.st"],
        ["st2py", "notes.txt"],
    ):
        done = script(*argv, cwd=tmp_path)
        assert (done.returncode, done.stdout) == (2, ""), (argv, done.stderr)
        assert "Traceback" not in done.stderr and done.stderr.strip(), argv
    for argv in (["st", "run", "keyword.st"], ["st2py", "keyword.st"], ["st", "run", "cp1252.st"]):
        done = script(*argv, cwd=tmp_path)
        assert "Traceback" not in done.stderr, (argv, done.stderr)
        if done.returncode != 0:  # a translation that does not compile, or a file the reader does not decode
            assert done.returncode == 2 and argv[-1] in one_line(done.stderr), (argv, done.stderr)
        elif argv[0] == "st2py":
            compile(done.stdout, argv[-1], "exec")  # what st2py prints is Python
    done = script("st", "run", "count.st", "--cycles", "3", cwd=tmp_path)
    assert (done.returncode, done.stderr) == (0, "") and "nCount" in done.stdout
