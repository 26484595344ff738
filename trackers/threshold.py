"""``threshold``: the brightest pixel of each row, if bright enough."""

from __future__ import annotations

import numpy as np

from ._base import Track, Tracker
from ._params import check_optional_real, check_real
from ._stats import default_threshold, noise_floor, robust_level, row_peaks

__all__ = ["ThresholdTracker"]


class ThresholdTracker(Tracker):
    """Per row, the column of the brightest pixel if it exceeds a threshold.

    The paper's "simple method such as threshold" (Wang et al. 2008, sec. 2):
    rows whose maximum does not exceed the threshold report no stripe.

    Parameters
    ----------
    threshold : float or None, default None
        Threshold in image units. ``None`` derives it from the frame:
        ``b + max(k_sigma * s, rel * (m - b))`` where ``b`` and ``s`` are the
        robust background level and noise (median and 1.4826 x MAD of a fixed
        sample of the frame, see ``trackers._stats.robust_level``) and ``m``
        the frame maximum. The first term rejects noise, the second ambient
        structure much dimmer than the brightest stripe.
    k_sigma : float, default 5.0
        Noise multiple of the derived threshold.
    rel : float, default 0.25
        Fraction of the frame's dynamic range of the derived threshold.

    Notes
    -----
    ``columns`` are whole pixels (the leftmost maximum on ties); ``score`` is
    the peak's contrast over the background in noise units, ``(peak - b) / s``
    (``s`` floored at 1e-3 of the dynamic range). A row is reported only if its
    peak is strictly above the threshold, so a blank frame reports nothing.

    Examples
    --------
    >>> img = np.zeros((2, 5), np.uint8); img[:, 3] = 200
    >>> ThresholdTracker().track(img).columns
    array([3., 3.])
    """

    name = "threshold"
    subpixel = False

    def __init__(self, threshold=None, k_sigma=5.0, rel=0.25):
        self.threshold = threshold
        self.k_sigma = k_sigma
        self.rel = rel

    def _validate_params(self):
        check_optional_real("threshold", self.threshold)
        check_real("k_sigma", self.k_sigma, low=0)
        check_real("rel", self.rel, low=0, high=1)

    def _level(self, image):
        bg, sigma, vmax = robust_level(image)
        if self.threshold is None:
            thr = default_threshold(bg, sigma, vmax, self.k_sigma, self.rel)
        else:
            thr = float(self.threshold)
        return bg, noise_floor(sigma, bg, vmax), thr

    def _track(self, image, background):
        bg, noise, thr = self._level(image)
        cols, peaks = row_peaks(image)
        hit = peaks > thr
        columns = np.where(hit, cols.astype(np.float64), np.nan)
        score = np.where(hit, (peaks - bg) / noise, np.nan)
        return Track(columns, score)
