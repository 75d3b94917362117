"""``python -m workcell``: the same as the ``workcell`` command."""

from workcell.cli.main import main

raise SystemExit(main())
