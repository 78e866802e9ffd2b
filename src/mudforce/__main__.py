"""``python -m mudforce`` runs the command line."""

import sys

from mudforce.cli import main

sys.exit(main())
