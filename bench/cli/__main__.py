"""``python -m bench.cli``: the same as the ``stripebench`` command."""

from bench.cli import main

raise SystemExit(main())
