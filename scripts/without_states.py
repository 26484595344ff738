"""A copy of a real set whose references give no row states, as many labelled sets' do.

Every file of ``SRC`` is copied to ``DST`` (which must not exist); each ``NAME_ref.csv`` keeps its ``row,col``
columns and loses its ``state`` column, so ``stripebench real`` reads its rows by the fallback rule
(:func:`bench.evaluate.outcomes.fallback_states`: a row without a reference, 15 or more rows from every row with one,
has no stripe) and ``stripebench predict`` reads its frames so too (``bench.run.predict_frames.Photo.fallback_rows``). The
columns are copied as written, byte for byte:

    python scripts/without_states.py bench/data/real results/runs/real-without-states
    stripebench real results/runs/real-without-states --predict --out results/runs/real-ws
"""

from __future__ import annotations

import argparse
import shutil
import sys
from pathlib import Path


def strip_states(text: str, name: str = "reference") -> str:
    """``text``, a ``NAME_ref.csv``'s whose header is ``row,col,state``, without its ``state`` column (the header
    is checked by :func:`bench.store.realset.reference_gives_states` first).

    Examples
    --------
    >>> strip_states("row,col,state\\n0,3.5,stripe\\n1,,none\\n")
    'row,col\\n0,3.5\\n1,\\n'
    """
    out = []
    for k, line in enumerate(text.splitlines()):
        if not line:
            continue
        cells = line.split(",")
        if len(cells) != 3:
            raise ValueError(f"{name} line {k + 1}: expected 3 fields, got {line!r}")
        out.append(",".join(cells[:2]))
    return "\n".join(out) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("src", type=Path, help="a real set's folder (manifest.csv, NAME_ref.csv)")
    ap.add_argument("dst", type=Path, help="the copy's folder (must not exist)")
    args = ap.parse_args(argv)
    if not (args.src / "manifest.csv").is_file():
        print(f"without_states: {str(args.src)!r}: not a real set (no manifest.csv)", file=sys.stderr)
        return 2
    if args.dst.exists():
        print(f"without_states: {str(args.dst)!r}: exists; give a new folder", file=sys.stderr)
        return 2
    from bench.store.realset import reference_gives_states  # its DatasetError is a ValueError

    try:  # a file without states is copied as it is
        refs = {p.name: strip_states(p.read_text(encoding="utf-8"), p.name)
                for p in args.src.glob("*_ref.csv") if reference_gives_states(p)}
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        print(f"without_states: {exc}", file=sys.stderr)
        return 2
    shutil.copytree(args.src, args.dst)
    for name, text in refs.items():
        (args.dst / name).write_text(text, encoding="utf-8")
    print(f"without_states: {len(refs)} references' states taken out in {args.dst}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
