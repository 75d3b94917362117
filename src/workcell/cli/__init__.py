"""The ``workcell`` command line; see :mod:`workcell.cli.main`."""
