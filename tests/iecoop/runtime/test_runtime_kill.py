"""``kill -9`` of a process running a Runtime, at random instants, then a restart on its store.

After each kill a new Runtime on the same store must restore the RETAIN image
of the last cycle that had completed (the child prints its number right
after ``run(cycles=1)`` returns) or of the one cycle under way; never an
older one, and never a torn mix of two cycles.
"""

from __future__ import annotations

import random
import sys
import time
import warnings
from pathlib import Path

import pytest

from ._child import TIMEOUT, ReportingChild
from ._runtime_cycler import build, values

CYCLER = Path(__file__).with_name("_runtime_cycler.py")
ROOT = Path(__file__).resolve().parents[3]


def restore(store: Path) -> set[int]:
    """What a fresh Runtime on ``store`` restores, before its first cycle."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a record torn by the kill is reported, then skipped
        runtime, cell = build(str(store))
        runtime.run(cycles=0)
        return values(cell)


@pytest.mark.slow  # seconds each: once, in the slow gate
def test_kill_a_cycling_runtime_at_random_instants(tmp_path: Path) -> None:
    store = tmp_path / "plc"
    last_completed = 0
    restarts_in_flight = 0
    for iteration in range(20):
        rng = random.Random(f"runtime-kill-{iteration}")
        child = ReportingChild([sys.executable, str(CYCLER), str(store)], rng.randint(1, 60), cwd=ROOT)
        try:
            assert child.ready.wait(TIMEOUT), "the runtime did not start"
            assert child.enough.wait(TIMEOUT), "the runtime stalled"
            time.sleep(rng.uniform(0.0, 0.003))
        finally:
            child.kill(f"kill {iteration}: the runtime")
        where = f"kill {iteration} (reported {child.reported[-3:]})"
        # The child restored what the previous kill left: the same image the parent saw.
        assert child.restored == [last_completed], f"{where}: the child restored {child.restored}"
        completed = child.reported[-1]
        assert completed >= last_completed + 1
        seen = restore(store)
        assert len(seen) == 1, f"{where}: a torn mix of cycles {sorted(seen)}"
        (cycle,) = seen
        assert completed <= cycle <= completed + 1, f"{where}: restored cycle {cycle}, last completed {completed}"
        restarts_in_flight += cycle != completed
        last_completed = cycle
    assert last_completed >= 20
    # Not asserted (timing decides), shown with -s: how often the kill landed after a cycle's write.
    print(f"20 kills; {restarts_in_flight} restored the cycle that was under way")
