"""``python -m strainwave``: the same command line as the ``strainwave`` script."""
import sys

from strainwave.cli import main

if __name__ == "__main__":
    sys.exit(main())
