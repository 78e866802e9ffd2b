"""The subcommands of the ``mudforce`` command line, one module each."""
