"""``python -m mtcal`` — the same as the ``mtcal`` command."""

import sys

from mtcal.cli import main

if __name__ == "__main__":
    sys.exit(main())
