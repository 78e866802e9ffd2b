"""``python -m mudforce`` runs the command line."""

import sys

from mudforce.cli import main

status = main()
# CPython notes a KeyboardInterrupt that ends any code run from a string (``exec`` or ``eval`` of source, which the
# libraries mudforce calls use to build functions) even when a caller catches it, and under ``-m`` it then ends the
# process by SIGINT (status -2) in place of the status returned: a Ctrl-C handled by the command (one line, status
# 130) came out as -2 about once in 20 runs. Each evaluation of a string clears that note first, so one here, after
# the command has returned, makes the exit status the command's. (A console script is run as a file: not affected.)
exec("pass")
sys.exit(status)
