"""``python -m patterns.showcase``: the ``iecoop`` command."""

import sys

from patterns.showcase.cli import main

sys.exit(main())
