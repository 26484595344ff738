"""``python -m bench.cli.translucency_profile``: the fast translucent path against the reference (:mod:`bench.studies.translucency_profile`)."""

from __future__ import annotations

import sys

__all__ = ["main"]


def main(argv=None) -> int:
    """Run the study (:data:`bench.cli.studies.TRANSLUCENCY_PROFILE`) with the options in ``argv``; the exit status."""
    from bench.cli.common import standalone
    from bench.cli.studies import TRANSLUCENCY_PROFILE

    return standalone(TRANSLUCENCY_PROFILE, "python -m bench.cli.translucency_profile", argv)


if __name__ == "__main__":
    sys.exit(main())
