"""``dp8_subpixel``: the paper's DP path, refined to sub-pixel precision where the stripe is seen."""

from __future__ import annotations

import numpy as np

from ._base import Track
from ._params import Choice, Int, Real
from ._stats import robust_level
from ._subpixel import ESTIMATORS, refine
from .dp import DEFAULT_H_WEIGHT, DEFAULT_REPORT, DPTracker

__all__ = ["DPSubpixelTracker", "DP8SubpixelTracker"]

_CHOICES = ("gauss3", "parabolic", "blais_rioux", "centroid")


class DPSubpixelTracker(DPTracker):
    """DP for robustness, a sub-pixel peak estimator for precision; use
    :class:`DP8SubpixelTracker`.

    1. The DP tracker (:class:`~trackers.dp.DPTracker`, same parameters and
       rules) finds the global minimum-cost path, which rows it reports and
       which rows *support* it (contrast ``z > k_sigma`` noise units against
       the pixels beside the path). Its column in a row (the DP tracker's
       row rule: the brightest node where an optimal path enters or leaves
       the row) is robust but whole-pixel.
    2. In every supporting row the peak is looked for within ``search``
       columns of that column (rounded); if that peak is a local maximum
       (not on the window's edge next to a brighter pixel outside), the
       ``estimator`` refines it exactly as the corresponding tracker does
       (``gauss3``, ``parabolic``, ``blais_rioux`` or ``centroid``; the
       background level is the frame's robust level, median of a sample).
    3. Every other reported row (bridged: the path crosses a dim stretch or a
       cut) keeps the DP column.

    ``score`` is the DP contrast ``z`` in refined rows and ``min(z, k_sigma)``
    in the others, so ``score > k_sigma`` exactly in the rows refined to
    sub-pixel precision.

    Parameters
    ----------
    eps, k_sigma, min_support, max_gap, min_run, side_inner, side_outer, h_weight, use_background, row_rule, max_walk
        As for :class:`~trackers.dp.DPTracker`.
    estimator : {'gauss3', 'parabolic', 'blais_rioux', 'centroid'}, default 'blais_rioux'
        The sub-pixel estimator (see ``docs/estimators.png``).
    search : int, default 2
        Half width, in columns, of the window around the DP column where the
        peak is looked for.
    frac : float, default 0.5
        ``centroid`` only: level as a fraction of the peak's contrast.
    half_window : int, default 7
        ``centroid`` only: most pixels taken on each side of the peak.

    Notes
    -----
    With a laser-off frame (and ``use_background``) every step, the
    refinement included, works on ``image - background`` (see
    :meth:`~trackers.dp.DPTracker.seen_frame`); its robust level is then
    close to 0.
    """

    def __init__(self, eps=1.0, k_sigma=DEFAULT_REPORT["k_sigma"], min_support=0.05, max_gap=DEFAULT_REPORT["max_gap"],
                 side_inner=4, side_outer=12, estimator="blais_rioux", search=2, frac=0.5, half_window=7,
                 h_weight=DEFAULT_H_WEIGHT, use_background=True, row_rule="crossing", max_walk=None,
                 min_run=DEFAULT_REPORT["min_run"], stripe_test=None):
        super().__init__(eps=eps, k_sigma=k_sigma, min_support=min_support, max_gap=max_gap,
                         side_inner=side_inner, side_outer=side_outer, h_weight=h_weight,
                         use_background=use_background, row_rule=row_rule, max_walk=max_walk, min_run=min_run,
                         stripe_test=stripe_test)
        self.estimator = estimator
        self.search = search
        self.frac = frac
        self.half_window = half_window

    parameter_constraints = {**DPTracker.parameter_constraints, "estimator": Choice(frozenset(_CHOICES)),
                             "search": Int(low=0), "frac": Real(low=0, high=1, high_open=True),
                             "half_window": Int(low=0)}

    def find_stripe(self, image, background, colour=None):
        raw = image
        image = self.seen_frame(image, background)
        H = image.shape[0]
        rows = self._path_rows(image, raw, background, colour)
        if rows is None:
            return Track.empty(H)
        mean_col, z, support, report = rows
        bg = robust_level(image)[0]
        centre = np.floor(np.nan_to_num(mean_col) + 0.5).astype(np.int64)  # NaN only in rows not reported
        refined = np.empty(H)
        ok = np.empty(H, dtype=np.bool_)
        refine(image, centre, support & report, np.full(H, bg), ESTIMATORS[self.estimator], int(self.search),
               float(self.frac), int(self.half_window), refined, ok)
        columns = np.where(report, np.where(ok, refined, mean_col), np.nan)
        score = np.where(report, np.where(ok, z, np.minimum(z, self.k_sigma)), np.nan)
        return Track(columns, score)


class DP8SubpixelTracker(DPSubpixelTracker):
    __doc__ = ("``dp8_subpixel``: the 8-connected DP path refined by a sub-pixel estimator.\n\n"
               + DPSubpixelTracker.__doc__.split("\n", 2)[2])
    name = "dp8_subpixel"
    subpixel = True
    connectivity = 8
