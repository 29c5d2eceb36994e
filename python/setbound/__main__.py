"""``python -m setbound``: the command line (see :mod:`setbound.cli`)."""
import sys

from .cli import main

sys.exit(main())
