"""Process-wide switches read once at import.

``IECOOP_CHECKS=0`` selects fast mode: the per-write checks (value kinds,
writing outputs or locals from outside) are not installed on the classes built
after import, so a variable write is a plain C-level store. Method and property
access rules hold in both modes.
"""

from __future__ import annotations

import os

CHECKS: bool = os.environ.get("IECOOP_CHECKS", "1").strip().lower() not in ("0", "false", "no", "off")
