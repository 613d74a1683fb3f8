"""The pytest plugin: registered through the ``pytest11`` entry point when iecoop is installed.

Fixtures:

- ``plc``: a fresh :class:`~iecoop.testing.VirtualPlc` (virtual time, no store
  on disk) for each test. Mark a test ``@pytest.mark.iecoop_profile("codesys")``
  to run it under the CODESYS profile.
- ``plc_runtime``: the same PLC's :class:`~iecoop.runtime.Runtime`.
"""

from __future__ import annotations

import pytest

from iecoop.profiles import get_profile
from iecoop.runtime import Runtime
from iecoop.testing import VirtualPlc

__all__ = ["plc", "plc_runtime", "pytest_configure"]


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers", "iecoop_profile(name): run the test's plc fixture under a vendor profile (twincat, codesys)"
    )


@pytest.fixture
def plc(request: pytest.FixtureRequest) -> VirtualPlc:
    """A fresh virtual PLC for this test: ``plc.add(Main())``, ``plc.run_cycles(n)``, ``plc.run_until(...)``."""
    marker = request.node.get_closest_marker("iecoop_profile")
    profile = "twincat"
    if marker is not None:
        if len(marker.args) != 1 or not isinstance(marker.args[0], str):
            raise pytest.UsageError("iecoop_profile takes one profile name, e.g. iecoop_profile('codesys')")
        profile = marker.args[0]
        get_profile(profile)  # an unknown name fails here, naming the known ones
    return VirtualPlc(profile=profile)


@pytest.fixture
def plc_runtime(plc: VirtualPlc) -> Runtime:
    """The :class:`~iecoop.runtime.Runtime` of this test's ``plc``."""
    return plc.runtime
