"""``python -m iecoop.cli``: the ``iecoop`` command without the showcase."""

import sys

from iecoop.cli import main

if __name__ == "__main__":  # a walk over the package's modules imports this one too
    sys.exit(main())
