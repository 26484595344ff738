"""Digest of every registered tracker's output on the perf varied frame set.

For every tracker (``trackers.available(unlisted=True)`` except ``external``,
which needs a program), its default parameters, every frame of
``bench.studies.perf.frames.varied_frames(2, seed=0)``: the bytes of
``columns`` and ``score`` (float64, (H,)), and for trackers with
``uses_background`` also with a laser-off frame (the element-wise minimum of
the frame and the next frame of the same shape). Prints the number of
entries and a SHA-256 over them; with an output path, also writes the
entries (pickle) for a row-by-row comparison. Two checkouts that print the
same digest give byte-identical tracks on these frames.

Run from a checkout with the project's Python:
``python scripts/tracker_digest.py [OUT.pkl]``.
"""

from __future__ import annotations

import argparse
import hashlib
import pickle

import numpy as np

import trackers
from bench.studies.perf.frames import varied_frames


def digest() -> dict:
    frames = varied_frames(2, seed=0)
    out = {}
    for name in (n for n in trackers.available(unlisted=True) if n != "external"):
        t = trackers.make(name)
        for i, (_, img) in enumerate(frames):
            tr = t.track(img)
            out[(name, i, "nobg")] = (tr.columns.tobytes(), tr.score.tobytes())
            bg = frames[(i + 1) % len(frames)][1]
            if bg.shape == img.shape and t.uses_background:
                tr = t.track(img, background=np.minimum(bg, img))
                out[(name, i, "bg")] = (tr.columns.tobytes(), tr.score.tobytes())
    return out


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out", nargs="?", help="also write the entries to this pickle file")
    args = p.parse_args(argv)
    out = digest()
    if args.out:
        with open(args.out, "wb") as fh:
            pickle.dump(out, fh)
    print(len(out), hashlib.sha256(pickle.dumps(sorted(out.items()))).hexdigest())


if __name__ == "__main__":
    main()
