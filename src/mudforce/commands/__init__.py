"""The subcommands of the ``mudforce`` command line, one module each."""

__all__: list[str] = []  # the subcommands are modules (listed in mudforce.cli.COMMANDS); no names here
