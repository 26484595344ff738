"""``python -m bench.cli.gate_spread``: the older name of ``stripebench spread`` (:mod:`bench.studies.gate_spread`)."""

from __future__ import annotations

import sys

if __name__ == "__main__":
    from bench.studies.gate_spread import main

    sys.exit(main())
