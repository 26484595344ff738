"""``python -m bench.cli.field_sheet``: the field profile's conditions at a glance (:mod:`bench.studies.field_sheet`)."""

from __future__ import annotations

import sys

__all__ = ["main"]


def main(argv=None) -> int:
    """Run the study (:data:`bench.cli.studies.FIELD_SHEET`) with the options in ``argv``; the exit status."""
    from bench.cli.common import standalone
    from bench.cli.studies import FIELD_SHEET

    return standalone(FIELD_SHEET, "python -m bench.cli.field_sheet", argv)


if __name__ == "__main__":
    sys.exit(main())
