"""The test suite; ``python -m tests`` runs every gate."""

import pytest

from iecoop import _config

#: For a test of a per-write check that fast mode (``IECOOP_CHECKS=0``) drops on purpose.
checked_only = pytest.mark.skipif(
    not _config.CHECKS, reason="checked mode only: fast mode (IECOOP_CHECKS=0) drops the per-write checks"
)
