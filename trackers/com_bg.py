"""``com_bg``: the open scanners' pipeline: laser-on minus laser-off, threshold,
window, centre of mass."""

from __future__ import annotations

import numpy as np

from ._base import Track
from ._params import check_int
from ._stats import robust_level, row_peaks
from ._subpixel import ESTIMATORS, refine
from .threshold import ThresholdTracker

__all__ = ["ComBgTracker"]


class ComBgTracker(ThresholdTracker):
    """Centre of mass of the background-subtracted, thresholded row around its maximum.

    What open laser scanners do (Horus / BQ Ciclop,
    ``horus/engine/algorithms/laser_segmentation.py``; FabScanPi,
    ``FSImageProcessor.py``):

    1. the difference ``D = image - background`` of a laser-on and a
       laser-off frame of the same scene removes the ambient light;
    2. ``D`` is thresholded to zero below a threshold ``T``;
    3. in each row, only the pixels within ``half_window`` columns of the
       row's maximum of ``D`` are kept;
    4. the column is their centre of mass, ``sum(D_j * j) / sum(D_j)`` over
       the kept pixels with ``D_j > T``.

    A row is reported iff its maximum of ``D`` exceeds ``T``. Unlike the
    scanners' fixed thresholds (Horus: user-set; FabScan: fixed), ``T`` is
    derived from ``D`` as in :class:`~trackers.threshold.ThresholdTracker`:
    ``T = b + max(k_sigma * s, rel * (m - b))`` with ``b``, ``s`` the robust
    level and noise of ``D`` (median and 1.4826 x MAD of a fixed sample) and
    ``m`` its maximum; ``threshold`` overrides it (in units of ``D``).

    Fallback without ``background``: ``D = image - b_I``, with ``b_I`` the
    robust background level of the frame itself (a flat laser-off frame).
    Ambient structure is then not removed: it can pass the threshold (and be
    reported) where no laser-off frame would have cancelled it.

    Parameters
    ----------
    threshold : float or None, default None
        ``T`` in image units of ``D``; ``None`` derives it as above.
    k_sigma : float, default 5.0
    rel : float, default 0.25
        As for :class:`~trackers.threshold.ThresholdTracker`, applied to ``D``.
    half_window : int, default 5
        Half width of the window around each row's maximum, in pixels
        (FabScan uses 3; 5 keeps the bias of a sigma = 3 px stripe below
        0.05 px, see ``docs/estimators.png``).

    Notes
    -----
    ``score`` is the peak contrast of ``D`` in noise units, ``(max_D - b) / s``
    (``s`` floored at 1e-3 of the dynamic range of ``D``). The window is
    centred on the leftmost maximum, or on the middle of a run of equal
    maxima (saturation). Weights are the values of ``D`` themselves, as in
    the scanners, so a pixel crossing ``T`` moves the centre by a small jump.

    Examples
    --------
    >>> import numpy as np
    >>> on = np.full((1, 9), 20.0); on[0, 3:6] = [70, 120, 90]
    >>> off = np.full((1, 9), 20.0)
    >>> float(ComBgTracker().track(on, background=off).columns[0])
    4.090909090909091
    """

    name = "com_bg"
    subpixel = True
    uses_background = True

    def __init__(self, threshold=None, k_sigma=5.0, rel=0.25, half_window=5):
        super().__init__(threshold=threshold, k_sigma=k_sigma, rel=rel)
        self.half_window = half_window

    def _validate_params(self):
        super()._validate_params()
        check_int("half_window", self.half_window, low=0)

    def _track(self, image, background):
        if background is None:
            diff = np.subtract(image, robust_level(image)[0], dtype=np.float64)
        else:
            diff = np.subtract(image, background, dtype=np.float64)
        bg, noise, thr = self._level(diff)
        cols, peaks = row_peaks(diff)
        hit = peaks > thr
        H = image.shape[0]
        columns = np.empty(H)
        ok = np.empty(H, dtype=np.bool_)
        refine(diff, cols, hit, np.full(H, thr), ESTIMATORS["com"], 0, 0.0, int(self.half_window), columns, ok)
        score = np.where(hit, (peaks - bg) / noise, np.nan)
        return Track(columns, score)
