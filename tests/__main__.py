"""The whole test suite in one command: ``python -m tests``.

Runs, and fails if any of them fails:

1. pytest over the tests, the package docstrings and the docs pages (every
   ``>>>`` example runs); a run that collects no test is a failure;
2. the tests again in fast mode (``IECOOP_CHECKS=0``, the simulation
   setting that drops the per-write checks), so both code paths are tested;
3. ``mypy --strict`` on iecoop, patterns, iecoop_examples and tests;
4. the Sphinx docs build with warnings as errors.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _run(title: str, command: list[str], env: dict[str, str] | None = None) -> bool:
    print(f"\n=== {title}: {' '.join(command)}", flush=True)
    started = time.monotonic()
    result = subprocess.run(command, cwd=ROOT, env=None if env is None else {**os.environ, **env})
    seconds = time.monotonic() - started
    ok = result.returncode == 0
    verdict = "ok" if ok else f"FAILED (exit {result.returncode})"
    print(f"=== {title}: {verdict} in {seconds:.1f} s", flush=True)
    return ok


def main() -> int:
    python = sys.executable
    pytest = [python, "-m", "pytest", "-q", "-p", "no:cacheprovider"]
    gates: list[tuple[str, list[str], dict[str, str] | None]] = [
        ("pytest", [*pytest, "--doctest-glob=*.md", "docs", "README.md", "tests", "iecoop", "patterns", "iecoop_examples"], None),
        ("pytest, fast mode", [*pytest, "tests"], {"IECOOP_CHECKS": "0"}),
        ("mypy", [python, "-m", "mypy", "--strict"], None),
        ("docs", [python, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", "docs", "docs/_build/html"], None),
    ]
    os.environ.setdefault("PYTHONHASHSEED", "0")
    results = [_run(title, command, env) for title, command, env in gates]
    passed = sum(results)
    failed = len(results) - passed
    print(f"\ngates: {passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
