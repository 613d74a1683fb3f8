"""``iecoop export`` / ``iecoop show --st`` as functions (the dispatcher wires them)."""

from __future__ import annotations

import inspect
import io
from pathlib import Path

import pytest

from iecoop import BOOL, VAR_INPUT, FunctionBlock
from iecoop.cli import export
from iecoop.st.export import StExportError
from patterns.showcase.catalogue import NAMES
from patterns.showcase.cli import st_text


def export_command(argv: list[str], out: io.StringIO) -> int:
    """``iecoop export`` with the catalogue's names, as the installed command runs it."""
    return export.export_command(argv, out, names=NAMES)


class Refusing(FunctionBlock):
    """An FB whose body throws, which a PLC cannot: the strict export must refuse it."""

    go: BOOL = VAR_INPUT(False)

    def body(self) -> None:
        if self.go:
            raise ValueError("no PLC form")


def test_export_writes_twincat_files(tmp_path: Path) -> None:
    out = io.StringIO()
    assert export_command(["observer", "--format", "twincat", "-o", str(tmp_path)], out) == 0
    written = out.getvalue().split()
    assert str(tmp_path / "TemperatureTransmitter.TcPOU") in written
    assert (tmp_path / "IObserver.TcIO").read_text().count("<Method Name=") == 1


def test_export_by_module_name_as_plcopen(tmp_path: Path) -> None:
    assert export_command(["patterns.solid.srp", "--format", "plcopen", "-o", str(tmp_path)], io.StringIO()) == 0
    assert (tmp_path / "srp.xml").read_text().startswith('<?xml version="1.0" encoding="utf-8"?>\n<project')


def test_strict_export_fails_on_a_statement_with_no_st_form(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert export_command([__name__, "--strict", "-o", str(tmp_path)], io.StringIO()) == 1
    assert "raise has no Structured Text form (in Refusing.body)" in capsys.readouterr().err
    assert export_command(["observer", "--strict", "-o", str(tmp_path)], io.StringIO()) == 0


def test_unknown_name(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert export_command(["no_such_pattern", "-o", str(tmp_path)], io.StringIO()) == 2
    assert "no catalogue entry or module named 'no_such_pattern'" in capsys.readouterr().err


def test_st_text_is_the_dump() -> None:
    text = st_text("ch05")
    assert "FUNCTION_BLOCK" in text and "EXTENDS" in text


def test_export_and_show_st_are_commands_of_iecoop(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from patterns.showcase.cli import main

    assert main(["export", "observer", "--format", "twincat", "-o", str(tmp_path)]) == 0
    written = capsys.readouterr().out.split()
    assert written and all(Path(path).exists() for path in written)
    assert any(path.endswith(".TcPOU") for path in written)
    assert main(["show", "observer", "--st"]) == 0
    assert "FUNCTION_BLOCK TemperatureTransmitter IMPLEMENTS ISubject" in capsys.readouterr().out
    assert main(["export", "no-such-thing", "-o", str(tmp_path)]) == 2
    assert "no catalogue entry or module named 'no-such-thing'" in capsys.readouterr().err


def test_st_text_is_strict_unless_asked_to_be_lenient() -> None:
    with pytest.raises(StExportError, match=r"raise has no Structured Text form \(in Refusing\.body\)"):
        st_text(__name__)
    report: list[str] = []
    text = st_text(__name__, lenient=True, report=report)
    assert "FUNCTION_BLOCK Refusing" in text
    lines, first = inspect.getsourcelines(Refusing.body)
    line = first + next(n for n, text in enumerate(lines) if "raise" in text)
    assert f"(* not translated, raise (line {line}): raise ValueError(\"no PLC form\") *)" in text
    assert report == [f"{__file__}:{line}: raise"]


def test_show_st_is_strict_and_lists_nothing_for_a_catalogue_entry(capsys: pytest.CaptureFixture[str]) -> None:
    from patterns.showcase.cli import main

    assert main(["show", "observer", "--st"]) == 0
    captured = capsys.readouterr()
    assert "FUNCTION_BLOCK TemperatureTransmitter IMPLEMENTS ISubject" in captured.out
    assert "written as a comment" not in captured.err
    assert main(["show", "observer", "--st", "--lenient"]) == 0
    assert "FUNCTION_BLOCK TemperatureTransmitter" in capsys.readouterr().out
