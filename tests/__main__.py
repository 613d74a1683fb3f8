"""The whole test suite in one command: ``python -m tests``.

Runs, and fails if any of them fails:

1. pytest over the tests, the package docstrings and the docs pages (every
   ``>>>`` example runs); a run that collects no test is a failure;
2. the tests of the core, runtime, libraries and patterns again in fast mode
   (``IECOOP_CHECKS=0``, the simulation setting that drops the per-write
   checks), so both code paths are tested;
3. ``mypy --strict`` on iecoop, patterns, iecoop_examples and tests;
4. the Sphinx docs build with warnings as errors.

Options (CI uses both)::

    python -m tests --slow                     # also the slow tests: build the wheel, install it, run it
    python -m tests --pythons 3.11,3.12,3.13   # also the whole pytest suite on each of these CPythons

For ``--pythons``, each interpreter is ``python3.X`` on the PATH, else the
newest ``$(pyenv root)/versions/3.X.*``; the suite runs in a virtual
environment ``.venv-py3X`` made from it with ``pip install -e .[dev]``. The
interpreter running this command counts as tested by the main passes. A
missing interpreter is reported as skipped, and fails the run when the
environment variable ``CI`` is ``true``. On those interpreters the tests run
in checked mode, the default (the docs pages once, on this interpreter); the fast-mode pass, mypy and the docs build
run once, on the interpreter running this command (fast mode changes which
code iecoop generates, not how Python runs it).
"""

from __future__ import annotations

import argparse
import concurrent.futures
import dataclasses
import os
import re
import shutil
import subprocess
import sys
import threading
import time
from collections.abc import Sequence
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: Where pytest looks in the main pass: the tests, every docstring and every docs page.
EVERYWHERE = ["--doctest-glob=*.md", "docs", "README.md", "tests", "iecoop", "patterns", "iecoop_examples"]
FAST_MODE = {"IECOOP_CHECKS": "0"}
#: What the fast-mode pass runs: the core, runtime, libraries and patterns, where the per-write checks
#: change the code iecoop generates. The ST bridge, the servers, the command line and the docs read and
#: write text and protocols the checks do not touch: the checked pass covers them.
FAST_MODE_PATHS = [
    "tests", "--ignore=tests/docs", "--ignore=tests/iecoop/st", "--ignore=tests/iecoop/cli", "--ignore=tests/iecoop/ads",
    "--ignore=tests/typing",
]
#: What the other interpreters run: every test but the documentation's own (its pages and built site are
#: checked once, by the main pass).
OTHER_PYTHONS_PATHS = ["tests", "--ignore=tests/docs"]
#: pytest's last line, ``3 failed, 1200 passed, 4 deselected in 81.20s`` (framed by '=' without -q).
_SUMMARY = re.compile(r"^=*\s*((?:\d+ [a-z]+(?:, )?)+) in [\d.]+s")


@dataclasses.dataclass
class Gate:
    title: str
    command: list[str]
    env: dict[str, str] = dataclasses.field(default_factory=dict)


@dataclasses.dataclass
class Outcome:
    title: str
    verdict: str  # "ok", "FAILED" or "skipped"
    seconds: float = 0.0
    counts: str = ""


_print_lock = threading.Lock()


def _run(gate: Gate, *, live: bool = True) -> Outcome:
    """Run one gate; ``live=False`` (gates running side by side) prints its output in one piece at the end."""
    header = f"\n=== {gate.title}: {' '.join(gate.command)}"
    if live:
        print(header, flush=True)
    started = time.monotonic()
    process = subprocess.Popen(
        gate.command, cwd=ROOT, env={**os.environ, **gate.env}, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
    )
    assert process.stdout is not None
    counts = ""
    kept: list[str] = []
    for line in process.stdout:  # pytest's last line gives the counts
        if live:
            print(line, end="", flush=True)
        else:
            kept.append(line)
        found = _SUMMARY.search(line)
        if found:
            counts = found.group(1)
    code = process.wait()
    seconds = time.monotonic() - started
    verdict = "ok" if code == 0 else "FAILED"
    footer = f"=== {gate.title}: {verdict if code == 0 else f'FAILED (exit {code})'} in {seconds:.1f} s"
    with _print_lock:
        if not live:
            print(header + "\n" + "".join(kept), end="", flush=True)
        print(footer, flush=True)
    return Outcome(gate.title, verdict, seconds, counts)


#: The pytest passes run two at a time: each is one process on one core, and the machine has two.
JOBS = 2


def run_side_by_side(gates: Sequence[Gate], jobs: int = JOBS) -> list[Outcome]:
    """Run ``gates`` ``jobs`` at a time (longest first is the caller's order); outcomes in the given order."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        return list(pool.map(lambda gate: _run(gate, live=jobs == 1), gates))


def pytest_gates(python: str, label: str = "", *, fast_mode: bool = True) -> list[Gate]:
    """The pytest passes for one interpreter (the slow tests are left to ``--slow``): the main one with
    the fast-mode pass, or another interpreter's."""
    pytest = [python, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-m", "not slow"]
    if label:
        return [Gate(f"pytest on {label}", [*pytest, *OTHER_PYTHONS_PATHS])]
    gates = [Gate("pytest", [*pytest, *EVERYWHERE])]
    if fast_mode:
        gates.append(Gate("pytest, fast mode", [*pytest, *FAST_MODE_PATHS], FAST_MODE))
    return gates


def _version_of(python: str) -> str | None:
    """``3.12`` for a working interpreter, None for a missing one or a pyenv shim with no version behind it."""
    try:
        done = subprocess.run(
            [python, "-c", "import sys; print('%d.%d' % sys.version_info[:2])"],
            capture_output=True, text=True, timeout=30,
        )
    except (OSError, subprocess.TimeoutExpired):
        return None
    return done.stdout.strip() if done.returncode == 0 else None


def find_python(version: str) -> str | None:
    """CPython ``version`` (``"3.12"``): ``python3.12`` on the PATH, else the newest pyenv ``3.12.*``."""
    candidates: list[str] = []
    on_path = shutil.which(f"python{version}")
    if on_path:
        candidates.append(on_path)
    pyenv = shutil.which("pyenv")
    if pyenv:
        root = subprocess.run([pyenv, "root"], capture_output=True, text=True).stdout.strip()
        installed = Path(root, "versions").glob(f"{version}.*/bin/python")
        candidates += [str(p) for p in sorted(installed, key=lambda p: _patch(p.parent.parent.name), reverse=True)]
    return next((python for python in candidates if _version_of(python) == version), None)


def _patch(name: str) -> tuple[int, ...]:
    return tuple(int(part) if part.isdigit() else -1 for part in name.split("."))


def prepare_venv(python: str, version: str) -> tuple[str | None, Outcome]:
    """``.venv-py3X`` from ``python``, with the package installed editable and its dev tools."""
    home = ROOT / f".venv-py{version.replace('.', '')}"
    venv_python = home / "bin" / "python"
    title = f"environment for {version}"
    if _version_of(str(venv_python)) != version:
        made = _run(Gate(title, [python, "-m", "venv", "--clear", str(home)]))
        if made.verdict != "ok":
            return None, made
    installed = _run(Gate(title, [str(venv_python), "-m", "pip", "install", "-q", "-e", ".[dev]"]))
    return (str(venv_python) if installed.verdict == "ok" else None), installed


def other_pythons(versions: Sequence[str], ci: bool, gates: list[Gate] | None = None) -> list[Outcome]:
    """Prepare each other interpreter's environment and add its pytest pass to ``gates``; the failures so far."""
    outcomes: list[Outcome] = []
    gates = [] if gates is None else gates
    here = "%d.%d" % sys.version_info[:2]
    for version in versions:
        if version == here:
            print(f"\n=== CPython {version}: the interpreter running the main passes", flush=True)
            continue
        python = find_python(version)
        if python is None:
            verdict = "FAILED" if ci else "skipped"
            print(f"\n=== CPython {version}: {verdict}, not found (python{version} on the PATH, or pyenv)", flush=True)
            outcomes.append(Outcome(f"CPython {version} not found", verdict))
            continue
        venv_python, prepared = prepare_venv(python, version)
        if venv_python is None:
            outcomes.append(prepared)
            continue
        gates += pytest_gates(venv_python, f"CPython {version}", fast_mode=False)
    return outcomes


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tests", description="Run every gate of the test suite.")
    parser.add_argument("--slow", action="store_true", help="also run the slow tests (wheel build and install), once")
    parser.add_argument(
        "--pythons", default="", metavar="3.11,3.12,...", help="also run the whole pytest suite on these CPython versions"
    )
    args = parser.parse_args(argv)
    versions = [v.strip() for v in args.pythons.split(",") if v.strip()]
    for version in versions:
        if not re.fullmatch(r"3\.\d+", version):
            parser.error(f"--pythons takes versions like 3.12, not {version!r}")
    os.environ.setdefault("PYTHONHASHSEED", "0")
    python = sys.executable
    started = time.monotonic()
    # mypy and the docs first, one after the other (the docs build writes its generated pages into docs/)
    outcomes = [
        _run(Gate("mypy", [python, "-m", "mypy", "--strict"])),
        # -E: a fresh environment, so pages the docs build generates and later removes leave nothing stale behind
        _run(Gate("docs", [python, "-m", "sphinx", "-E", "-W", "--keep-going", "-q", "-b", "html", "docs", "docs/_build/html"])),
    ]
    # then every pytest pass, each in its own process and temporary folders, two at a time, the longest first
    gates: list[Gate] = []
    if args.slow:
        gates.append(Gate("slow tests", [python, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-m", "slow", "tests"]))
    gates += pytest_gates(python)
    outcomes += other_pythons(versions, ci=os.environ.get("CI", "").lower() == "true", gates=gates)
    outcomes += run_side_by_side(gates)
    print("\nsummary:")
    for outcome in outcomes:
        counts = f"  ({outcome.counts})" if outcome.counts else ""
        print(f"  {outcome.verdict:<8} {outcome.seconds:6.1f} s  {outcome.title}{counts}")
    tally = {verdict: sum(o.verdict == verdict for o in outcomes) for verdict in ("ok", "FAILED", "skipped")}
    print(
        f"\ngates: {tally['ok']} passed, {tally['FAILED']} failed, {tally['skipped']} skipped"
        f" in {time.monotonic() - started:.0f} s"
    )
    return 0 if tally["FAILED"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
