"""Base class of the trackers that refine each row's brightest pixel."""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from ._base import Track
from ._subpixel import ESTIMATORS, refine
from .threshold import ThresholdTracker

__all__ = ["PeakTracker"]


class PeakTracker(ThresholdTracker):
    """Detection as :class:`~trackers.threshold.ThresholdTracker` (same
    parameters, the same per-row rule), then a sub-pixel estimator from
    :mod:`trackers._subpixel` around each detected row's brightest pixel,
    with the row's own background level (its median).

    Subclasses set ``_estimator`` (a key of ``trackers._subpixel.ESTIMATORS``)
    and may override :meth:`_estimator_args` (``frac``, ``half_window``).
    ``score`` is the peak's contrast in noise units, as for ``threshold``.
    """

    _estimator: ClassVar[str] = ""

    def _estimator_args(self) -> tuple[float, int]:
        return 0.0, 0

    def find_stripe(self, image, background):
        d = self.detect(image)
        H = image.shape[0]
        columns = np.empty(H)
        ok = np.empty(H, dtype=np.bool_)
        frac, half_window = self._estimator_args()
        refine(image, d.col, d.hit, d.bg, ESTIMATORS[self._estimator], 0, float(frac), int(half_window),
               columns, ok)
        score = np.where(d.hit, d.score, np.nan)
        return Track(columns, score)
