"""A child process the kill tests start, read and kill with SIGKILL."""

from __future__ import annotations

import signal
import subprocess
import threading
from pathlib import Path

TIMEOUT = 30.0


class ReportingChild:
    """Runs ``argv``; a thread collects the numbers it prints, one per line.

    A line ``ready [n ...]`` says the child has started (with what it
    restored, if anything); every other line is one number it reports.
    """

    def __init__(self, argv: list[str], lines_wanted: int, cwd: Path | None = None) -> None:
        self.process = subprocess.Popen(argv, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        self.restored: list[int] = []
        self.reported: list[int] = []
        self.ready = threading.Event()
        self.enough = threading.Event()
        self.lines_wanted = lines_wanted
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self) -> None:
        assert self.process.stdout is not None
        for raw in self.process.stdout:
            words = raw.split()
            if words and words[0] == b"ready":
                self.restored = [int(w) for w in words[1:]]
                self.ready.set()
            elif words:
                self.reported.append(int(words[0]))
            if len(self.reported) >= self.lines_wanted:
                self.enough.set()
        self.ready.set()
        self.enough.set()

    def kill(self, what: str) -> None:
        """SIGKILL, then drain what was printed before it; the child must not have ended on its own."""
        self.process.send_signal(signal.SIGKILL)
        self.process.wait(TIMEOUT)
        self.reader.join(TIMEOUT)
        assert self.process.stderr is not None and self.process.stdout is not None
        errors = self.process.stderr.read().decode(errors="replace")
        self.process.stderr.close()
        self.process.stdout.close()
        assert self.process.returncode == -signal.SIGKILL, f"{what} ended on its own:\n{errors}"
