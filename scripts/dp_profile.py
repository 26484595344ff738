"""Where a DP tracker's time goes: its parts, one by one, on the perf frame set.

For ``dp4`` and ``dp8`` (default parameters) on the frames of one size of
``bench.studies.perf.frames.varied_frames(2, seed=0)`` (default 512x480, 18 frames): the whole
``track()``, the half costs, the solve, the labelling of the optimal nodes, the row summaries and
the reporting rule (the stages of :mod:`trackers.dp_stages`: ``half_costs``, ``distance_field``,
``optimal_nodes``, ``row_readings``, ``reporting_rule``, each a thin call of the tracker's own
kernel). Each part is timed alone on the arrays the tracker would give it, as the least of
``--repeats`` calls in the thread's CPU time; the table shows the median over the frames in ms.
The parts do not add up to ``track()`` exactly (validation, the ``Track`` and the Python between
them are not listed, and each part alone runs with warm caches).

Run with the project's Python: ``python scripts/dp_profile.py [--size 512x480] [--repeats 7]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import trackers
from bench.studies.perf.frames import varied_frames
from trackers import dp_stages as S

PARTS = ("track", "half costs", "solve", "labelling", "row summaries", "reporting rule")


def least_ms(fn, repeats: int) -> float:
    best = np.inf
    for _ in range(repeats):
        t0 = time.thread_time()
        fn()
        best = min(best, time.thread_time() - t0)
    return 1e3 * best


def profile(name: str, frames, repeats: int) -> dict[str, float]:
    t = trackers.make(name)
    hw = float(t.h_weight)
    out = {p: [] for p in PARTS}
    for img in frames:
        H, W = img.shape
        t.track(img)
        out["track"].append(least_ms(lambda: t.track(img), repeats))
        hc = np.empty((H, W))
        out["half costs"].append(least_ms(lambda: S.half_costs(img, t.eps, hc), repeats))
        hc, rowmin, centre, rightc = S.half_costs(img, t.eps, hc)
        D = np.empty((H, W))
        out["solve"].append(least_ms(lambda: S.distance_field(hc, rowmin, centre, t.connectivity, hw, right=rightc,
                                                              out=D), repeats))
        rows = np.empty(H * W, np.int64)
        cols = np.empty(H * W, np.int64)

        def label():  # a zeroed label array per call, as the tracker allocates it
            return S.optimal_nodes(D, hc, t.connectivity, hw, rows=rows, cols=cols)

        out["labelling"].append(least_ms(label, repeats))
        mark, rows_n, cols_n = label()
        readings = (np.empty(H), np.empty(H), np.empty(H), np.empty(H, np.int64))

        def summaries():
            S.row_readings(img, mark, rows_n, cols_n, t.side_inner, t.side_outer, t.row_rule, out=readings)

        out["row summaries"].append(least_ms(summaries, repeats))
        _, contrast, side_sd, span = readings
        out["reporting rule"].append(least_ms(lambda: S.reporting_rule(img, contrast, side_sd, span, t), repeats))
    return {p: float(np.median(v)) for p, v in out.items()}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", default="512x480", help="frame size WxH of the perf set (default 512x480)")
    parser.add_argument("--repeats", type=int, default=7, help="calls per part and frame, the least counts")
    args = parser.parse_args(argv)
    w, h = (int(x) for x in args.size.split("x"))
    frames = [img for _, img in varied_frames(2, seed=0) if img.shape == (h, w)]
    if not frames:
        parser.error(f"no frames of size {args.size} in the perf set")
    print(f"{len(frames)} frames of {args.size}, median over frames of the least of {args.repeats} calls, CPU ms")
    print(f"{'tracker':<8}" + "".join(f"{p:>16}" for p in PARTS))
    for name in ("dp4", "dp8"):
        res = profile(name, frames, args.repeats)
        print(f"{name:<8}" + "".join(f"{res[p]:>16.3f}" for p in PARTS))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
