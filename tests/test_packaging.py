"""The package as users install it: a built wheel, and the README's editable install under mypy.

The wheel test builds the wheel and the sdist with ``python -m build``,
installs the wheel into a fresh virtual environment (nothing of the source
tree on its path) and runs the ``iecoop`` command there: ``list``, then
``run NAME --cycles 3`` for every entry, the course chapters included. It is
marked ``slow`` (about 20 s): it runs in the normal pass of ``python -m tests``
and is left out of the fast-mode pass, whose subject is the checked writes.

The typing test writes a user's file in a temporary folder outside the
repository and runs ``mypy --strict`` on it with the ``iecoop.mypy`` plugin,
as a user does after ``pip install -e .``: iecoop must be found, and a wrong
block input reported.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import textwrap
import zipfile
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from importlib import metadata
from pathlib import Path

import pytest

from patterns.showcase import catalogue

ROOT = Path(__file__).resolve().parent.parent
#: Import packages the wheel may install, and nothing else at the top level.
TOP_LEVEL = {"iecoop", "iecoop_examples", "patterns"}
BUILD_TIMEOUT = 300
_NOT_SOURCE = (".git", ".venv*", "__pycache__", "*.egg-info", "build", "dist", "_build", ".*_cache", ".hypothesis", ".iecoop")
RUN_TIMEOUT = 120


def _clean_env() -> dict[str, str]:
    """The environment without anything that would put the source tree on the path."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    return env


def _run(command: list[str], cwd: Path, timeout: float = RUN_TIMEOUT) -> subprocess.CompletedProcess[str]:
    return subprocess.run(command, cwd=cwd, env=_clean_env(), capture_output=True, text=True, timeout=timeout)


@pytest.fixture(scope="module")
def dist(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    # From a copy of the tree, as a fresh clone has it: the build leaves no egg-info in the work tree.
    source = tmp_path_factory.mktemp("source") / "iecoop"
    shutil.copytree(ROOT, source, ignore=shutil.ignore_patterns(*_NOT_SOURCE))
    out = tmp_path_factory.mktemp("dist")
    built = _run([sys.executable, "-m", "build", "--outdir", str(out), str(source)], cwd=out, timeout=BUILD_TIMEOUT)
    assert built.returncode == 0, built.stdout[-3000:] + built.stderr[-3000:]
    yield out


@pytest.fixture(scope="module")
def venv(dist: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """A fresh virtual environment holding only the wheel (iecoop has no dependencies)."""
    home = tmp_path_factory.mktemp("venv")
    made = _run([sys.executable, "-m", "venv", "--without-pip", str(home)], cwd=home)
    assert made.returncode == 0, made.stderr
    wheel = next(dist.glob("*.whl"))
    python = home / "bin" / "python"
    installed = _run(
        [sys.executable, "-m", "pip", "--python", str(python), "install", "-q", "--no-deps", "--no-index", str(wheel)],
        cwd=home,
    )
    assert installed.returncode == 0, installed.stdout + installed.stderr
    yield home


@pytest.mark.slow
def test_build_gives_a_wheel_and_an_sdist_that_carry_the_typing_markers(dist: Path) -> None:
    (wheel,) = dist.glob("iecoop-*.whl")
    (sdist,) = dist.glob("iecoop-*.tar.gz")
    assert sdist.stat().st_size > 0
    names = zipfile.ZipFile(wheel).namelist()
    assert "iecoop/py.typed" in names and "patterns/py.typed" in names
    assert "iecoop/mypy.py" in names, "the mypy plugin ships in the package"
    assert any(n.startswith("iecoop_examples/") for n in names)
    tops = {n.split("/")[0] for n in names if not n.split("/")[0].endswith(".dist-info")}
    assert tops == TOP_LEVEL, f"unexpected top-level entries {tops - TOP_LEVEL}"


@pytest.mark.slow
def test_the_wheel_installs_no_generic_top_level_module(venv: Path) -> None:
    python = str(venv / "bin" / "python")
    probe = (
        "import importlib.util as u, iecoop, iecoop_examples, patterns;"
        "print(iecoop.__file__);"
        "print([m for m in ('examples', 'tests', 'benchmarks', 'docs') if u.find_spec(m) is not None])"
    )
    found = _run([python, "-c", probe], cwd=venv)
    assert found.returncode == 0, found.stderr
    where, generic = found.stdout.splitlines()
    assert Path(where).is_relative_to(venv), f"iecoop imported from {where}, not from the fresh environment"
    assert generic == "[]"


@pytest.mark.slow
def test_the_wheels_iecoop_command_runs_every_showcase_entry(venv: Path) -> None:
    command = str(venv / "bin" / "iecoop")
    listed = _run([command, "list"], cwd=venv)
    assert listed.returncode == 0, listed.stderr
    names = re.findall(r"^  (\S+)\s", listed.stdout, flags=re.MULTILINE)
    assert names == catalogue.names(), "the wheel lists other entries than the source tree"
    assert {"ch08", "ch15", "observer", "dip"} <= set(names) and len(names) >= 40

    def run(name: str) -> tuple[str, subprocess.CompletedProcess[str]]:
        return name, _run([command, "run", name, "--cycles", "3"], cwd=venv)

    with ThreadPoolExecutor(max_workers=2) as pool:
        results = list(pool.map(run, names))
    failures = {
        name: (done.stdout + done.stderr)[-400:]
        for name, done in results
        if done.returncode != 0 or not done.stdout.strip() or _broken(done.stdout + done.stderr)
    }
    assert failures == {}
    tour = _run([command], cwd=venv)
    assert tour.returncode == 0 and not _broken(tour.stdout + tour.stderr), tour.stdout[-2000:] + tour.stderr


def _broken(output: str) -> bool:
    return "cannot import" in output or "Traceback" in output or "ModuleNotFoundError" in output


USER_FILE = '''\
from iecoop import BOOL, INT, FunctionBlock, Interface, VAR_INPUT, VAR_OUTPUT, method


class IPump(Interface):
    @method
    def healthy(self) -> BOOL: ...


class Counter(FunctionBlock, IPump):
    enable: BOOL = VAR_INPUT(False)
    count: INT = VAR_OUTPUT(0)

    @method
    def healthy(self) -> BOOL:
        return self.count < 100

    def body(self) -> None:
        if self.enable:
            self.count += 1


counter = Counter()
counter(enable=True)
'''


def _mypy_on_user_file(folder: Path, source: str, *extra: str) -> subprocess.CompletedProcess[str]:
    (folder / "user.py").write_text(source)
    (folder / "mypy.ini").write_text('[mypy]\nstrict = True\nplugins = iecoop.mypy\n')
    command = [sys.executable, "-m", "mypy", "--no-incremental", "--config-file", "mypy.ini", *extra, "user.py"]
    return _run(command, cwd=folder)


def test_a_users_file_outside_the_repository_type_checks_after_the_editable_install(tmp_path: Path) -> None:
    # The README installs the package editable; mypy must find it from any folder.
    metadata.distribution("iecoop")  # raises PackageNotFoundError before 'pip install -e .'
    assert not tmp_path.resolve().is_relative_to(ROOT)
    passed = _mypy_on_user_file(tmp_path, USER_FILE)
    assert passed.returncode == 0, passed.stdout + passed.stderr
    assert "Success" in passed.stdout
    failed = _mypy_on_user_file(tmp_path, USER_FILE + 'counter(enable="yes")\ncounter(nonexistent=1)\n')
    assert failed.returncode == 1
    reported, line = failed.stdout, USER_FILE.count("\n") + 1
    assert f'user.py:{line}: error: Argument "enable" to "Counter" has incompatible type "str"; expected "bool"' in reported
    assert f'user.py:{line + 1}: error: Unexpected keyword argument "nonexistent" for "Counter"' in reported
    assert "Cannot find implementation or library stub" not in reported


@pytest.mark.slow
def test_a_users_file_type_checks_against_the_installed_wheel(venv: Path, tmp_path: Path) -> None:
    # mypy run for the fresh environment's interpreter finds iecoop there, through py.typed.
    python = str(venv / "bin" / "python")
    failed = _mypy_on_user_file(tmp_path, USER_FILE + "counter(enable=1.5)\n", "--python-executable", python)
    assert failed.returncode == 1
    line = USER_FILE.count("\n") + 1
    assert f'user.py:{line}: error: Argument "enable" to "Counter" has incompatible type "float"; expected "bool"' in failed.stdout
    assert failed.stdout.count("error:") == 1, failed.stdout


def test_importing_iecoop_imports_neither_mypy_nor_the_plugin() -> None:
    probe = textwrap.dedent(
        """
        import sys, iecoop, iecoop.testing, iecoop.runtime, iecoop.stdlib
        print(sorted(m for m in sys.modules if m == "mypy" or m.startswith(("mypy.", "iecoop.mypy"))))
        """
    )
    done = _run([sys.executable, "-c", probe], cwd=ROOT)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"
