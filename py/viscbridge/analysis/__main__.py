"""``python3 -m viscbridge.analysis``: the analyses' command line (:mod:`viscbridge.analysis.cli`)."""
import sys

from .cli import main

if __name__ == '__main__':  # importing this module runs nothing
    sys.exit(main())
