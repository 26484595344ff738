"""``com_bg``: the open scanners' pipeline: laser-on minus laser-off, threshold,
window, centre of mass."""

from __future__ import annotations

import numpy as np

from ._base import Track
from ._peak import WindowedPeakTracker
from ._subpixel import ESTIMATORS, refine
from .threshold import DEFAULT_K_SIGMA, DEFAULT_WIDTH_RATIO, DEFAULT_MIN_RUN, DEFAULT_PROMINENCE

__all__ = ["ComBgTracker", "DEFAULT_FRAC"]

#: Default threshold-to-zero level as a fraction of each row's peak contrast
#: (chosen by ``stripebench tune threshold``).
DEFAULT_FRAC = 0.25


class ComBgTracker(WindowedPeakTracker):
    """Centre of mass of the background-subtracted, thresholded row around its maximum.

    What open laser scanners do (Horus / BQ Ciclop,
    ``horus/engine/algorithms/laser_segmentation.py``; FabScanPi,
    ``FSImageProcessor.py``):

    1. the difference ``D = image - background`` of a laser-on and a
       laser-off frame of the same scene removes the ambient light;
    2. ``D`` is thresholded to zero below a level ``T``;
    3. in each row, only the pixels within ``half_window`` columns of the
       row's maximum of ``D`` are kept;
    4. the column is their centre of mass, ``sum(D_j * j) / sum(D_j)`` over
       the kept pixels with ``D_j > T``.

    Unlike the scanners' fixed thresholds (Horus: user-set; FabScan: fixed),
    both the detection and ``T`` are per row: a row of ``D`` is reported by
    :class:`~trackers.threshold.ThresholdTracker`'s per-row rule (same
    ``k_sigma``, ``prominence``), and its level is
    ``T_r = b_r + frac * (m_r - b_r)`` with ``b_r`` the median and ``m_r``
    the maximum of that row of ``D``, so the dim half of a stripe in a bright
    frame keeps its own level. An explicit ``threshold`` (units of ``D``)
    replaces both: rows whose maximum exceeds it are reported, with
    ``T = threshold``.

    Fallback without ``background``: ``D = image - b_I`` with ``b_I`` each
    row's median (a flat laser-off frame); the detection is the same as on the
    image. Ambient structure is not removed: it can win a row (and be
    reported) where no laser-off frame would have cancelled it.

    Parameters
    ----------
    threshold : float or None, default None
        Explicit threshold in units of ``D``; ``None``: the per-row rule.
    k_sigma, prominence, min_run, width_ratio, stripe_test
        As for :class:`~trackers.threshold.ThresholdTracker`, applied to ``D`` (the stripe
        question's laser-off test compares the image with the laser-off frame).
    frac : float, default :data:`DEFAULT_FRAC`
        Threshold-to-zero level as a fraction of each row's peak contrast, in [0, 1).
    half_window : int, default 5
        Half width of the window around each row's maximum, in pixels
        (FabScan uses 3; 5 keeps the bias of a sigma = 3 px stripe below
        0.05 px, see ``docs/estimators.png``).

    Notes
    -----
    ``score`` is the peak contrast of ``D`` in noise units, as for
    ``threshold``. The window is centred on the leftmost maximum, or on the
    middle of a run of equal maxima (saturation). Weights are the values of
    ``D`` themselves, as in the scanners, so a pixel crossing ``T`` moves
    the centre by a small jump.

    Examples
    --------
    >>> import numpy as np
    >>> on = np.full((1, 9), 20.0); on[0, 3:6] = [70, 120, 90]
    >>> off = np.full((1, 9), 20.0)
    >>> float(ComBgTracker().track(on, background=off).columns[0])
    4.090909090909091
    """

    name = "com_bg"
    uses_background = True
    _estimator = "com"

    def __init__(self, threshold=None, k_sigma=DEFAULT_K_SIGMA, prominence=DEFAULT_PROMINENCE, frac=DEFAULT_FRAC,
                 half_window=5, min_run=DEFAULT_MIN_RUN, width_ratio=DEFAULT_WIDTH_RATIO, stripe_test=None):
        super().__init__(threshold=threshold, k_sigma=k_sigma, prominence=prominence, frac=frac,
                         half_window=half_window, min_run=min_run, width_ratio=width_ratio, stripe_test=stripe_test)

    def find_stripe(self, image, background, colour=None):
        if background is None:  # a flat laser-off frame: each row's own level
            d = self.detect(image, colour=colour)
            diff = np.subtract(image, d.bg[:, None], dtype=np.float64)
            base = np.zeros(image.shape[0])
        else:
            diff = np.subtract(image, background, dtype=np.float64)
            d = self.detect(diff, raw=image, background=background, colour=colour)
            base = d.bg
        H = image.shape[0]
        columns = np.empty(H)
        ok = np.empty(H, dtype=np.bool_)
        if self.threshold is None:
            level, frac = base, float(self.frac)
        else:
            level, frac = np.full(H, float(self.threshold)), 0.0
        refine(diff, d.col, d.hit, level, ESTIMATORS[self._estimator], 0, frac, int(self.half_window), columns, ok)
        score = np.where(d.hit, d.score, np.nan)
        return Track(columns, score)
