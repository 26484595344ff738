"""``python -m bench.cli.gate_spread``: the older name of ``stripebench spread`` (:mod:`bench.studies.gate_spread`)."""

from __future__ import annotations

import sys

__all__ = ["main"]


def main(argv=None) -> int:
    """``stripebench spread`` with the same options (:data:`bench.cli.studies.SPREAD`); the exit status."""
    from bench.cli.common import standalone
    from bench.cli.studies import SPREAD

    return standalone(SPREAD, "stripebench spread", argv)


if __name__ == "__main__":
    sys.exit(main())
