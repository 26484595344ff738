"""The loop behind :func:`bench.evaluate.ranking.bootstrap_frames`'s AP intervals (numba).

Imported only when a bootstrap of AP runs, so that ``bench.evaluate.outcomes`` stays light.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def ap_resamples(weights, frame_of, tp, last, n_pos, out):  # pragma: no cover - compiled
    """All-point AP of each resample; ``out[b]`` for row ``b`` of ``weights``.

    Parameters
    ----------
    weights : (B, F) int64
        Times each frame is drawn in each resample.
    frame_of : (N,) int64
        The frame of each report, reports ranked best first.
    tp : (N,) bool
        Whether each ranked report is a hit.
    last : (N,) bool
        True at the last report of a run of tied scores (one threshold each).
    n_pos : (B,) int64
        Stripe rows in each resample.
    out : (B,) float64
        Written: the AP (NaN where a resample has no stripe row).
    """
    B = weights.shape[0]
    N = frame_of.shape[0]
    T = 0
    for i in range(N):
        if last[i]:
            T += 1
    prec = np.empty(T)
    rec = np.empty(T)
    for b in range(B):
        if n_pos[b] == 0:
            out[b] = np.nan
            continue
        ctp = 0.0
        cfp = 0.0
        t = 0
        for i in range(N):
            w = weights[b, frame_of[i]]
            if tp[i]:
                ctp += w
            else:
                cfp += w
            if last[i]:
                prec[t] = ctp / (ctp + cfp) if ctp + cfp > 0 else 0.0
                rec[t] = ctp / n_pos[b]
                t += 1
        env = 0.0
        for k in range(T - 1, -1, -1):  # the precision envelope max_{k' >= k} P(k')
            if prec[k] > env:
                env = prec[k]
            prec[k] = env
        ap = 0.0
        before = 0.0
        for k in range(T):
            ap += (rec[k] - before) * prec[k]
            before = rec[k]
        out[b] = ap
