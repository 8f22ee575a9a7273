"""``python3 -m viscbridge.scan``: the scan's command line (:mod:`viscbridge.scan.cli`)."""
import sys

from .cli import main

sys.exit(main())
