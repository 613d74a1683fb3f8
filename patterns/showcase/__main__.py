"""``python -m patterns.showcase``: the ``iecoop`` command."""

import sys

from patterns.showcase import main

sys.exit(main())
