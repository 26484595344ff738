"""``centroid``: gray-gravity centre of the stripe in each row."""

from __future__ import annotations

import numpy as np
from numba import njit

from ._base import Track
from ._params import check_int, check_real
from ._stats import row_peaks
from .threshold import ThresholdTracker

__all__ = ["CentroidTracker"]


@njit(cache=True, nogil=True)
def _centroids(image, peak_cols, peak_vals, hit, background, frac, half_window, out):
    H, W = image.shape
    for r in range(H):
        if not hit[r]:
            out[r] = np.nan
            continue
        p = peak_cols[r]
        level = background + frac * (peak_vals[r] - background)
        lo = p
        while lo - 1 >= 0 and lo - 1 >= p - half_window and image[r, lo - 1] > level:
            lo -= 1
        hi = p
        while hi + 1 < W and hi + 1 <= p + half_window and image[r, hi + 1] > level:
            hi += 1
        sw = 0.0
        swx = 0.0
        for j in range(lo, hi + 1):
            w = image[r, j] - level
            sw += w
            swx += w * j
        out[r] = swx / sw


class CentroidTracker(ThresholdTracker):
    """Gray-gravity centre: intensity-weighted mean column around each row's peak.

    Detection is :class:`~trackers.threshold.ThresholdTracker`'s (same
    parameters, same default threshold). In a detected row with peak value
    ``p`` at column ``j*`` and frame background ``b``, the window is the run of
    contiguous pixels around ``j*`` brighter than ``level = b + frac * (p - b)``,
    at most ``half_window`` pixels on each side; the column is
    ``sum(w_j * j) / sum(w_j)`` with weights ``w_j = I_j - level`` (continuous
    in the sub-pixel phase, so no jump when a pixel enters the window).

    Parameters
    ----------
    threshold, k_sigma, rel
        As for :class:`~trackers.threshold.ThresholdTracker`.
    frac : float, default 0.5
        Level inside the peak, as a fraction of the peak's contrast
        (0.5 = pixels above half maximum).
    half_window : int, default 7
        Most pixels taken on each side of the peak.

    Notes
    -----
    ``score`` is the peak contrast in noise units, as for ``threshold``.
    """

    name = "centroid"
    subpixel = True

    def __init__(self, threshold=None, k_sigma=5.0, rel=0.25, frac=0.5, half_window=7):
        super().__init__(threshold=threshold, k_sigma=k_sigma, rel=rel)
        self.frac = frac
        self.half_window = half_window

    def _validate_params(self):
        super()._validate_params()
        check_real("frac", self.frac, low=0, high=1)
        if self.frac >= 1:
            raise ValueError(f"`frac` must be < 1, got {self.frac!r}")
        check_int("half_window", self.half_window, low=0)

    def _track(self, image, background):
        bg, noise, thr = self._level(image)
        cols, peaks = row_peaks(image)
        hit = peaks > thr
        columns = np.empty(image.shape[0])
        _centroids(image, cols, peaks, hit, bg, float(self.frac), int(self.half_window), columns)
        score = np.where(hit, (peaks - bg) / noise, np.nan)
        return Track(columns, score)
