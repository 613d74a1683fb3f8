"""The ``iecoop`` command, driven through its entry point: in-process, as the installed script and with ``-m``."""

from __future__ import annotations

import importlib
import inspect
import io
import pkgutil
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

from iecoop import DINT, INT, VAR, VAR_OUTPUT, Program
from iecoop.cli import trace
import patterns.showcase.cli as showcase
from patterns.showcase.cli import TOUR_CATEGORIES, main, run_entry
from patterns.showcase import catalogue, cli
from patterns.showcase.catalogue import Column, Entry, Showcase, build, entries, find, read

SCRIPT = Path(sys.executable).with_name("iecoop")


class Faulty(Program):
    """Divides by zero in its third scan."""

    scan: INT = VAR(0)
    quotient: DINT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.scan += 1
        self.quotient = 100 // (3 - self.scan)


FAULTY = Entry("faulty", "behavioral", __name__, program="Faulty", columns=(Column("scan", "scan"), Column("quotient", "quotient")))


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def rows(out: str) -> list[list[str]]:
    """The table rows of a ``run`` output (lines starting with the time and the cycle), split on spaces."""
    return [line.split() for line in out.splitlines() if re.match(r"^\s*\d+\s+\d+\s", line)]


# -- list and show ---------------------------------------------------------------------------------


def test_list_names_every_entry_by_category(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, err = run(capsys, "list")
    assert status == 0 and err == ""
    for heading in ("Creational patterns", "Structural patterns", "Behavioral patterns", "SOLID principles"):
        assert heading in out
    listed = {line.split()[0] for line in out.splitlines() if line.startswith("  ")}
    assert listed == {entry.name for entry in entries()}
    assert re.search(r"^  state\s+State: the PackML unit state machine", out, re.M)


def test_show_prints_the_module_documentation(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "show", "Template_Method")
    assert status == 0
    assert out.startswith("template-method (patterns.behavioral.template_method)")
    assert "Template Method: axis homing" in out and "Intent" in out


def test_show_renders_the_docs_for_a_terminal_and_names_the_file(capsys: pytest.CaptureFixture[str]) -> None:
    import patterns.behavioral.state as state

    status, out, _ = run(capsys, "show", "state")
    assert status == 0
    assert f"Python: {Path(state.__file__).resolve()}" in out.splitlines()
    assert "``" not in out and ":class:" not in out and "ST::" not in out and "\n::\n" not in out
    assert "implementing\nI_PackMLState. It knows" in out  # a literal over a line break loses its quotes too
    # The ST of the IEC mapping is shown indented, as a block under its heading.
    mapping = out[out.index("IEC 61131-3 mapping"):]
    assert "\n\n    TYPE E_PackMLState : (CLEARING := 1" in mapping
    assert "\n        METHOD ChangeState     // VAR_INPUT target : E_PackMLState;" in mapping


def test_show_takes_its_sections_from_one_list(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    import patterns.showcase.cli as showcase

    sections = [*showcase.SHOW_SECTIONS, lambda entry, module: f"ST of {module.__name__}"]
    monkeypatch.setattr(showcase, "SHOW_SECTIONS", sections)
    status, out, _ = run(capsys, "show", "state")
    assert status == 0 and out.rstrip().endswith("ST of patterns.behavioral.state")


# -- run -------------------------------------------------------------------------------------------


def test_run_state_traces_the_packml_batch(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, err = run(capsys, "run", "state", "--cycles", "250")
    assert status == 0 and err == ""
    assert out.splitlines()[1:3] == [
        "  expected: refused (part of the scenario: Start is pressed again while the unit is already in EXECUTE)",
        "PackagingLine on PlcTask (10 ms), twincat profile, 250 cycles; rows where a traced value changed",
    ]
    table = rows(out)
    assert table[0] == ["0", "1", "RESETTING", "0", "1", "0", "0"]
    assert ["510", "52", "EXECUTE", "0", "4", "0", "0"] in table
    assert ["620", "63", "EXECUTE", "1", "4", "1", "0"] in table  # Start pressed again: refused
    assert ["820", "83", "SUSPENDING", "3", "5", "1", "0"] in table
    assert table[-1] == ["2490", "250", "STOPPED", "5", "14", "1", "1"]
    assert [row[2] for row in table].count("EXECUTE") == 7


def test_run_command_undoes_to_an_empty_history(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "run", "command")
    assert status == 0
    table = rows(out)
    assert table[1][:8] == ["10", "2", "FALSE", "60", "FALSE", "1", "EXECUTED", "P201"]
    assert table[2][:7] == ["50", "6", "TRUE", "25", "TRUE", "2", "EXECUTED"]
    assert " ".join(table[-1]) == "250 26 FALSE 0 FALSE 0 REFUSED undo: history empty"


def test_run_interpreter_counts_two_pump_starts(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "run", "interpreter", "--profile", "codesys")
    assert status == 0
    assert "twincat" not in out and "codesys profile, 100 cycles" in out
    assert [row[:2] + row[-2:] for row in rows(out)] == [
        ["0", "1", "-", "0"],
        ["600", "61", "ON", "1"],   # TT101 above 80
        ["700", "71", "-", "1"],    # PT102 too high
        ["800", "81", "ON", "2"],   # ... bypassed
        ["900", "91", "-", "2"],    # LS3: the tank is full
        ["990", "100", "-", "2"],
    ]


def test_run_every_k_prints_every_kth_cycle_and_the_last(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "run", "observer", "--cycles", "95", "--every", "30")
    assert status == 0 and "a row every 30 cycles" in out
    assert [row[1] for row in rows(out)] == ["1", "31", "61", "91", "95"]


def test_a_long_run_draws_a_progress_bar_only_on_a_terminal(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    status, out, err = run(capsys, "run", "strategy", "--cycles", "2100")
    assert status == 0 and err == ""
    assert [row[:5] for row in rows(out)] == [  # mode, strategy, T: the swap is bumpless
        ["0", "1", "PID", "PID", "20.0"], ["20000", "2001", "PWM", "PWM", "60.0"], ["20990", "2100", "PWM", "PWM", "60.0"],
    ]

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    assert main(["run", "strategy", "--cycles", "2000"]) == 0
    assert "\r[" in terminal.getvalue() and "100% 2000/2000 cycles" in terminal.getvalue()
    assert terminal.getvalue().endswith("\r")  # the bar is wiped at the end
    assert "PWM" not in terminal.getvalue()  # stdout is not the terminal: the rows are not mixed in


def test_on_a_terminal_the_rows_stream_above_a_progress_line(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    terminal = Terminal()
    monkeypatch.setattr(sys, "stdout", terminal)
    monkeypatch.setattr(trace, "FLUSH_EVERY", 0.0)  # draw at every cycle
    assert main(["run", "strategy", "--cycles", "2100"]) == 0
    text = terminal.getvalue()
    # Each row is written on a wiped line, after the progress of the cycles before it.
    before_pwm = text[: text.index("  20000   2001  PWM")]
    assert "2000/2100 cycles" in before_pwm and before_pwm.endswith("\r")
    assert "2001/2100" not in before_pwm
    assert [line.split()[:3] for line in text.replace("\r", "\n").splitlines() if re.match(r"^\s*\d+\s+\d+\s", line)] == [
        ["0", "1", "PID"], ["20000", "2001", "PWM"], ["20990", "2100", "PWM"],
    ]
    assert text.endswith("\r") and "100% 2100/2100 cycles" in text


def test_rows_are_handed_over_as_the_cycles_run() -> None:
    seen: list[tuple[int, int]] = []
    cycle_when_seen: list[int] = []

    def on_row(row: tuple[int, int, list[str]]) -> None:
        seen.append(row[:2])
        cycle_when_seen.append(progress[-1] if progress else 0)

    progress: list[int] = []
    trace = run_entry(find("strategy"), 2100, on_row=on_row, progress=progress.append)
    assert trace.rows == []  # streamed, not kept
    assert seen == [(0, 1), (20000, 2001), (20990, 2100)]
    assert cycle_when_seen == [0, 2000, 2099]  # each row arrives in its own cycle, not at the end


# -- errors ----------------------------------------------------------------------------------------


@pytest.mark.parametrize("command", ["run", "show"])
def test_an_unknown_name_suggests_close_ones_and_exits_2(capsys: pytest.CaptureFixture[str], command: str) -> None:
    status, out, err = run(capsys, command, "stat")
    assert status == 2 and out == ""
    assert "unknown name 'stat'" in err and "state" in err and "strategy" in err
    assert "iecoop list" in err


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["run", "state", "--cycles", "-1"], "must be at least 1"),
        (["run", "state", "--cycles", "ten"], "expected a whole number"),
        (["run", "state", "--every", "0"], "must be at least 1"),
        (["run", "state", "--profile", "s7"], "invalid choice: 's7'"),
        (["run"], "the following arguments are required: name"),
        (["start"], "invalid choice: 'start'"),
    ],
)
def test_bad_options_exit_2(capsys: pytest.CaptureFixture[str], argv: list[str], message: str) -> None:
    status, out, err = run(capsys, *argv)
    assert status == 2 and out == ""
    assert message in err and err.startswith("usage: iecoop")


def test_help_describes_the_commands(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "--help")
    assert status == 0
    for command in ("tour", "list", "show", "run"):
        assert command in out
    status, out, _ = run(capsys, "run", "--help")
    assert status == 0 and "--cycles N" in out and "{twincat,codesys}" in out


def test_a_plc_fault_is_reported_with_its_code_and_exits_1(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(catalogue, "ENTRIES", (*catalogue.ENTRIES, FAULTY))
    status, out, err = run(capsys, "run", "faulty", "--cycles", "10")
    assert status == 1
    assert rows(out) == [["0", "1", "1", "50"], ["10", "2", "2", "100"]]
    assert err.startswith("iecoop: faulty: PLC fault in cycle 3: RTSEXCPT_DIVIDEBYZERO (ZeroDivisionError")
    assert "cycle 2" not in err  # the runtime's own count from 0 is not shown beside the CLI's count from 1


class FirstScanFault(Program):
    """Divides by zero in its first scan."""

    quotient: DINT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.quotient = 100 // self.quotient


def test_a_fault_in_the_first_cycle_is_cycle_1(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    first = Entry("first", "behavioral", __name__, program="FirstScanFault", columns=(Column("q", "quotient"),))
    monkeypatch.setattr(catalogue, "ENTRIES", (*catalogue.ENTRIES, first))
    status, out, err = run(capsys, "run", "first")
    assert status == 1 and rows(out) == []
    assert err.startswith("iecoop: first: PLC fault in cycle 1: RTSEXCPT_DIVIDEBYZERO")
    assert "cycle 0" not in err


def test_the_tour_reports_a_fault_and_goes_on(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(catalogue, "ENTRIES", (FAULTY, *catalogue.ENTRIES))
    status, out, _ = run(capsys, "tour")
    assert status == 1
    assert "PLC fault in cycle 3: RTSEXCPT_DIVIDEBYZERO" in out
    assert out.index("RTSEXCPT_DIVIDEBYZERO") < out.index("\ndip -- Dependency inversion")


def test_the_tour_marks_the_deliberate_faults_as_expected(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "tour")
    assert status == 0
    factory = out[out.index("\nfactory-method -- "):out.index("\nprototype -- ")]
    assert factory.splitlines()[2] == (
        "  expected: UNKNOWN_TYPE (part of the scenario: row 5 of the I/O table names a BUTTERFLY valve, "
        "a type no factory builds)"
    )
    assert "UNKNOWN_TYPE  TRUE" in factory  # ... and the trace does show it
    for entry in entries():
        for what, why in entry.expected:
            assert f"  expected: {what} (part of the scenario: {why})" in out
    assert sum(len(entry.expected) for entry in entries()) >= 10


# -- the tour --------------------------------------------------------------------------------------


def test_the_tour_runs_every_pattern_quickly_and_readably(capsys: pytest.CaptureFixture[str]) -> None:
    started = time.process_time()  # CPU time: what the tour costs, whatever else the machine runs
    status, out, err = run(capsys)
    elapsed = time.process_time() - started
    assert status == 0 and err == ""
    toured = [entry for entry in entries() if entry.category in TOUR_CATEGORIES]
    assert len(toured) >= 28
    for entry in toured:
        assert f"\n{entry.name} -- " in out
    assert "RESETTING" in out and "EXECUTE" in out
    assert len(out.splitlines()) < 400
    assert elapsed < 15


# -- the catalogue ---------------------------------------------------------------------------------


def _modules(package: str) -> list[str]:
    root = importlib.import_module(package)
    return [
        m.name for m in pkgutil.walk_packages(root.__path__, prefix=f"{package}.")
        if not m.ispkg and not m.name.rsplit(".", 1)[-1].startswith(("_", "test"))
    ]


@pytest.mark.parametrize("package", ["patterns.creational", "patterns.structural", "patterns.behavioral",
                                     "patterns.solid", "iecoop_examples"])
def test_every_module_has_an_entry(package: str) -> None:
    covered = {entry.module for entry in entries()}
    assert set(_modules(package)) <= covered


def test_every_pattern_and_principle_has_a_hand_written_entry() -> None:
    hand = [entry for entry in entries() if entry.category in TOUR_CATEGORIES and not entry.generic]
    assert len(hand) == 28
    for entry in hand:
        assert 3 <= len(entry.columns) <= 6, entry.name


@pytest.mark.parametrize("name", [entry.name for entry in entries()])
def test_every_entry_runs_five_cycles(name: str, capsys: pytest.CaptureFixture[str]) -> None:
    entry = find(name)
    assert entry.runnable, entry.problem
    if entry.demo:
        entry.load().main()
        assert capsys.readouterr().out
        return
    trace = run_entry(entry, 5)
    assert trace.fault is None
    assert trace.cycles_run == 5 and trace.rows[0][:2] == (0, 1) and trace.rows[-1][:2] == (40, 5)


def test_names_ignore_case_and_underscores() -> None:
    assert find("Chain_Of_Responsibility").module == "patterns.behavioral.chain_of_responsibility"
    assert find("patterns.solid.srp").name == "srp"
    with pytest.raises(KeyError):
        find("singleton-pattern")


def test_a_module_without_an_entry_gets_a_generic_one(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "showcase_sample.py").write_text(
        '"""A sample: a counter."""\n'
        "from iecoop import BOOL, INT, REAL, TIME, Program, T, VAR, VAR_INPUT, VAR_OUTPUT\n"
        "from iecoop.stdlib import TON\n"
        "class Sample(Program):\n"
        "    enable: BOOL = VAR_INPUT(True)\n"
        "    timer: TON = VAR()\n"
        "    count: INT = VAR_OUTPUT(0)\n"
        "    elapsed: TIME = VAR_OUTPUT(0)\n"
        "    level: REAL = VAR(0.5)\n"
        "    def body(self) -> None:\n"
        "        self.timer(IN=self.enable, PT=T('1s'))\n"
        "        self.elapsed = self.timer.ET\n"
        "        self.count += 1\n"
    )
    (tmp_path / "showcase_empty.py").write_text('"""Nothing to run."""\n')
    monkeypatch.syspath_prepend(str(tmp_path))
    sample = catalogue._generic_entry("sample", "examples", "showcase_sample")
    empty = catalogue._generic_entry("empty", "examples", "showcase_empty")
    assert sample is not None and empty is not None
    assert [column.label for column in sample.columns] == ["count", "elapsed", "level", "timer.Q", "timer.ET"]
    assert sample.heading() == "A sample: a counter."
    assert not empty.runnable and "no Program" in empty.problem
    monkeypatch.setattr(catalogue, "ENTRIES", (*catalogue.ENTRIES, sample, empty))
    status, out, _ = run(capsys, "run", "sample", "--cycles", "3")
    assert status == 0 and rows(out) == [
        ["0", "1", "1", "0ms", "0.50", "FALSE", "0ms"],
        ["10", "2", "2", "10ms", "0.50", "FALSE", "10ms"],
        ["20", "3", "3", "20ms", "0.50", "FALSE", "20ms"],
    ]
    status, _, err = run(capsys, "run", "empty")
    assert status == 2 and "empty cannot run: no Program and no main() to run" in err


def test_build_puts_the_program_on_a_10_ms_task() -> None:
    scenario = build(find("visitor"))
    (task,) = scenario.runtime.tasks
    assert (task.name, task.interval, task.priority) == ("PlcTask", 10, 20)
    assert [type(p).__name__ for _, p in task.programs] == ["PlantMain"]


# -- through the installed script and python -m ----------------------------------------------------


def test_the_installed_script_runs_the_tour_from_anywhere(tmp_path: Path) -> None:
    done = subprocess.run([str(SCRIPT)], capture_output=True, text=True, cwd=tmp_path, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stderr == ""
    assert done.stdout.startswith("iecoop tour: ")
    for entry in entries():
        if entry.category in TOUR_CATEGORIES:
            assert f"\n{entry.name} -- " in done.stdout


def test_the_installed_script_lists_and_runs(tmp_path: Path) -> None:
    listed = subprocess.run([str(SCRIPT), "list"], capture_output=True, text=True, cwd=tmp_path, timeout=60)
    assert listed.returncode == 0
    assert {entry.name for entry in entries()} <= set(listed.stdout.split())
    ran = subprocess.run([str(SCRIPT), "run", "state", "--cycles", "60"], capture_output=True, text=True,
                         cwd=tmp_path, timeout=60)
    assert ran.returncode == 0 and ran.stderr == ""
    assert ["510", "52", "EXECUTE", "0", "4", "0", "0"] in rows(ran.stdout)


def test_python_m_patterns_showcase() -> None:
    done = subprocess.run([sys.executable, "-m", "patterns.showcase", "run", "sigleton"], capture_output=True,
                          text=True, timeout=60)
    assert done.returncode == 2 and done.stdout == ""
    assert "unknown name 'sigleton'. Did you mean: singleton?" in done.stderr
    done = subprocess.run([sys.executable, "-m", "patterns.showcase", "run", "dip", "--cycles", "0"],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 2 and "--cycles: must be at least 1, got 0" in done.stderr


@pytest.mark.parametrize(
    "argv",
    [["list"], ["run", "strategy", "--cycles", "1000000000", "--every", "1"], ["show", "state"], []],
    ids=["list", "long run", "show", "tour"],
)
def test_a_reader_that_stops_early_ends_the_command_quietly(argv: list[str]) -> None:
    with subprocess.Popen([str(SCRIPT), *argv], stdout=subprocess.PIPE, stderr=subprocess.PIPE) as process:
        assert process.stdout is not None and process.stderr is not None
        first = process.stdout.readline()
        process.stdout.close()  # what head -1 does
        # A billion cycles take hours: ending within the wait means they are not run for nobody.
        status = process.wait(timeout=120)
        err = process.stderr.read().decode()
    assert first and status == 0 and err == ""


def test_into_a_pipe_the_rows_come_before_the_run_ends() -> None:
    with subprocess.Popen([str(SCRIPT), "run", "state", "--cycles", "100000000", "--every", "1"],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) as process:
        assert process.stdout is not None
        lines = [process.stdout.readline() for _ in range(6)]
        process.kill()
    assert lines[3].split() == ["time", "ms", "cycle", "state", "packs", "transitions", "refused", "batches"]
    assert lines[4].split()[:3] == ["0", "1", "RESETTING"] and lines[5].split()[:2] == ["10", "2"]
    assert "\r" not in "".join(lines)  # no progress line in a pipe


def test_serve_is_one_of_the_commands(capsys: pytest.CaptureFixture[str]) -> None:
    assert "serve" in cli.COMMANDS
    assert main(["serve", "no-such-pattern"]) == 2
    assert "iecoop serve: unknown name 'no-such-pattern'" in capsys.readouterr().err
    assert main(["serve", "state", "--duration", "0ms"]) == 2
    assert "must be longer than 0 ms" in capsys.readouterr().err


# -- the declarations ------------------------------------------------------------------------------


@pytest.mark.parametrize("name", [e.name for e in entries() if e.category in TOUR_CATEGORIES])
def test_each_pattern_declares_its_showcase_next_to_its_main(name: str) -> None:
    entry = find(name)
    module = entry.load()
    declared = module.SHOWCASE
    assert isinstance(declared, Showcase)
    assert entry.columns == declared.columns and entry.script is declared.script
    assert (entry.cycles, entry.tour_cycles, entry.expected) == (declared.cycles, declared.tour_cycles, declared.expected)
    source = inspect.getsource(module)
    assert source.index("\nSHOWCASE = Showcase(") > source.index("\ndef main()"), "the declaration follows main()"


def test_a_declared_program_class_is_the_one_built() -> None:
    import iecoop_examples.ch09_pointers_and_references as ch09

    assert ch09.SHOWCASE.program is ch09.SrAverage and find("ch09").program is ch09.SrAverage
    assert [type(p).__name__ for p in build(find("ch09")).programs] == ["SrAverage"]


def test_a_column_reads_the_program_it_names() -> None:
    scenario = build(find("srp"))
    scenario.runtime.run(cycles=1)
    texts = [column for column in find("srp").columns if column.label == "texts: violating"]
    assert texts[0].of == 1 and read(scenario, texts[0]) == scenario.programs[1].drive.format_count
    with pytest.raises(AttributeError, match="no_such_variable"):
        read(scenario, Column("bad", lambda p: p.no_such_variable))


def test_the_solid_principles_keep_their_acronyms_order() -> None:
    assert [e.name for e in entries() if e.category == "solid"] == ["srp", "ocp", "lsp", "isp", "dip"]


def test_a_pattern_module_imports_the_declaration_but_not_the_command() -> None:
    code = "import sys, patterns.behavioral.state; print(sorted(m for m in sys.modules if m.startswith('patterns.showcase')))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "['patterns.showcase', 'patterns.showcase.entry']"


def test_a_module_that_does_not_import_is_listed_with_its_problem(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "showcase_broken.py").write_text("import no_such_module_anywhere\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    entry = catalogue._collect("broken", "examples", "showcase_broken")
    assert entry is not None and not entry.runnable
    assert entry.problem.startswith("cannot import: ModuleNotFoundError") and "no_such_module_anywhere" in entry.problem


def test_finding_one_entry_imports_only_its_module() -> None:
    code = (
        "import sys; from patterns.showcase.catalogue import find; entry = find('state'); "
        "print(entry.name, sorted(m for m in sys.modules if m.startswith('patterns.behavioral.')))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "state ['patterns.behavioral.state']"
