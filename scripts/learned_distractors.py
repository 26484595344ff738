"""F1 and false-report rate of ``learned`` weights on the distractor hard frames (docs/learned.md's rule, part 2).

``python scripts/learned_distractors.py [WEIGHTS ...]`` scores each weights file (``shipped``: the committed one) on
the hard frames of every kind of :data:`bench.studies.hard_frames.DISTRACTORS`, seeds 100-105, with and without
the laser-off frame, the colour evidence passed where a frame has colour; prints one line per weights file.
"""

from __future__ import annotations

import argparse

import numpy as np


def score(weights: str) -> dict:
    """``{True: counts, False: counts}`` (with and without the laser-off frame) of one weights file."""
    import trackers
    from bench.evaluate.outcomes import outcome_counts, row_outcomes, truth_states
    from bench.run.camera_view import colour_of
    from bench.studies.hard_frames import DISTRACTORS, hard_frame

    t = trackers.make("learned") if weights == "shipped" else trackers.make("learned", weights=weights)
    total = {True: np.zeros(6, int), False: np.zeros(6, int)}
    for kind in DISTRACTORS:
        for seed in range(100, 106):
            f = hard_frame(kind, seed)
            colour = colour_of(f.rgb, f.laser) if f.rgb is not None else None
            for with_off in (True, False):
                cols = t.track(f.laser_channel, background=f.laser_channel_off if with_off else None,
                               colour=colour).columns
                total[with_off] += outcome_counts(row_outcomes(cols, f.truth, truth_states(f.truth)), axis=0)
    return total


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("weights", nargs="*", default=["shipped"], help="weights files (default: the shipped one)")
    args = p.parse_args(argv)
    from bench.evaluate.outcomes import detection_figures

    for w in args.weights:
        tot = score(w)
        a, b, both = (detection_figures(tot[True]), detection_figures(tot[False]),
                      detection_figures(tot[True] + tot[False]))
        print(f"{w}: with the laser-off frame F1 {a['f1']:.4f} / false-report rate {a['false_report_rate']:.4f}; "
              f"without F1 {b['f1']:.4f} / {b['false_report_rate']:.4f}; pooled F1 {both['f1']:.4f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
