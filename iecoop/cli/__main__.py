"""``python -m iecoop.cli``: the ``iecoop`` command without the showcase."""

import sys

from iecoop.cli import main

sys.exit(main())
