"""Which rows a real set's references leave out, measured on its labels alone (no tracker runs).

For each photograph the transplant can take (``stripebench predict``'s stripe estimate, ``auto``), the estimate's
visible rows are split by whether the reference gives the row a column, and each row's height (the peak over the
reference window's median, :class:`bench.evaluate.stripe.Extents`) is compared with the median height of the
visible rows: a row under ``dim_share`` of it (:class:`bench.evaluate.predict_settings.PredictSettings`) is *dim*;
its peak is *clipped* where :func:`bench.evaluate.rowstates.clipped_peaks` says so. Printed per rig (the manifest's ``rig``) and for
all: the rows the references score and the share of them dim, the rows they leave out and the share dim, and the
share of dim rows left out, once counting every dim row and once only those whose peak is not clipped (the
``--rows clear`` convention of ``stripebench predictcheck``). A second table does the same for the estimate's rows
between its first and last visible one that it does not call visible but guides (a height, under 6 of the frame's
noise units), each dim or not by the same median (:func:`bench.evaluate.rowstates.dim_rows` with ``guided``); a third
for its rows whose peak is clipped and which the reference rule does not see in the photograph. The yardstick of
``dim_share`` and of reading a clipped core in a glow as a stripe row (docs/predict.md):

    python scripts/reference_rows.py bench/data/real
"""

from __future__ import annotations

import argparse
import sys
from collections import defaultdict
from pathlib import Path

import numpy as np


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset", type=Path, help="a real set's folder (manifest.csv, NAME_ref.csv)")
    args = ap.parse_args(argv)

    from bench.evaluate import conditions as cond
    from bench.evaluate import rowstates as rs
    from bench.evaluate import stripe as sp
    from bench.evaluate import transplant as tp
    from bench.evaluate.outcomes import STRIPE, referenced_states
    from bench.run import predict_frames as pf
    from bench.store.realset import load_dataset, read_reference_states

    root = args.dataset

    rig_of = {im.name: im.rig for im in load_dataset(root)}
    counts = defaultdict(lambda: np.zeros(6, int))  # scored, scored dim, scored dim unclipped, left out, ...
    faint = defaultdict(lambda: np.zeros(4, int))  # invisible guided rows: scored, scored dim, left out, left out dim
    core = defaultdict(lambda: np.zeros(2, int))  # clipped peaks the rule does not see in place: scored, left out
    for p in pf.collect_photos(root):
        c = cond.measure(p.frame, p.background)
        if sp.out_of_range(c):
            print(f"{p.name}: out of range, left out", file=sys.stderr)
            continue
        ext, original, _ = pf.photo_extents(p, measured=c)
        cols, _, _ = read_reference_states(root / f"{p.name}_ref.csv", p.frame.shape)
        dim = rs.dim_rows(ext)
        dim_unclipped = rs.unclear_rows(ext, original)
        scored, vis = np.isfinite(cols), ext.visible
        row = [np.sum(vis & s & d) for s in (scored, ~scored) for d in (np.ones_like(vis), dim, dim_unclipped)]
        truth = tp.in_place_truth(ext)  # the guided rows of the visible span
        guided = np.isfinite(truth) & ~vis
        gdim = guided & rs.dim_rows(ext, guided=True)
        unseen = rs.clipped_peaks(original, ext) & np.isfinite(truth) & (referenced_states(p.frame, truth) != STRIPE)
        for key in (rig_of.get(p.name, "?"), "all"):
            counts[key] += row
            core[key] += [np.sum(unseen & scored), np.sum(unseen & ~scored)]
            faint[key] += [np.sum(guided & scored), np.sum(gdim & scored), np.sum(guided & ~scored),
                           np.sum(gdim & ~scored)]

    def share(a, b) -> str:
        return f"{a / b:.1%}" if b else "-"

    print(f"{'rig':<40}{'scored':>8}{'dim':>7}{'unclip':>8}{'left out':>10}{'dim':>7}{'unclip':>8}"
          f"{'dim left out':>14}{'unclip':>8}")
    for key, (n_s, d_s, u_s, n_o, d_o, u_o) in counts.items():
        print(f"{key:<40}{n_s:>8}{share(d_s, n_s):>7}{share(u_s, n_s):>8}{n_o:>10}{share(d_o, n_o):>7}"
              f"{share(u_o, n_o):>8}{share(d_o, d_s + d_o):>14}{share(u_o, u_s + u_o):>8}")
    print("\nthe estimate's rows it guides but does not call visible (within its visible span):")
    print(f"{'rig':<40}{'scored':>8}{'dim':>7}{'left out':>10}{'dim':>7}")
    for key, (n_s, d_s, n_o, d_o) in faint.items():
        print(f"{key:<40}{n_s:>8}{share(d_s, n_s):>7}{n_o:>10}{share(d_o, n_o):>7}")
    print("\nthe estimate's rows whose peak is clipped and which the reference rule does not see in place:")
    print(f"{'rig':<40}{'scored':>8}{'left out':>10}")
    for key, (n_s, n_o) in core.items():
        print(f"{key:<40}{n_s:>8}{n_o:>10}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
