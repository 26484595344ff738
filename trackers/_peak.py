"""Base class of the trackers that refine each row's brightest pixel."""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from ._base import Track
from ._params import Int, Real
from ._subpixel import ESTIMATORS, refine
from .threshold import DEFAULT_K_SIGMA, DEFAULT_MIN_RUN, DEFAULT_PROMINENCE, DEFAULT_WIDTH_RATIO, ThresholdTracker

__all__ = ["PeakTracker", "WindowedPeakTracker", "DETECTION_DOC"]

#: The detection paragraph and ``Parameters`` section shared by the docstrings of the
#: :class:`PeakTracker` subclasses without parameters of their own (``gauss3``, ``parabolic``,
#: ``blais_rioux``): each docstring is its own text, then this, then its own ``Notes``.
DETECTION_DOC = """
    Detection is :class:`~trackers.threshold.ThresholdTracker`'s (same
    parameters, the same per-row rule); rows whose peak does not
    exceed it report NaN.

    Parameters
    ----------
    threshold, k_sigma, prominence, min_run, width_ratio, stripe_test
        As for :class:`~trackers.threshold.ThresholdTracker`.
"""


class PeakTracker(ThresholdTracker):
    """Detection as :class:`~trackers.threshold.ThresholdTracker` (same
    parameters, the same per-row rule), then a sub-pixel estimator from
    :mod:`trackers._subpixel` around each detected row's brightest pixel,
    with the row's own background level (its median).

    Subclasses set ``_estimator`` (a key of ``trackers._subpixel.ESTIMATORS``)
    and may override :meth:`_estimator_args` (``frac``, ``half_window``).
    ``score`` is the peak's contrast in noise units, as for ``threshold``.
    """

    subpixel = True
    _estimator: ClassVar[str] = ""

    def _estimator_args(self) -> tuple[float, int]:
        return 0.0, 0

    def find_stripe(self, image, background, colour=None):
        d = self.detect(image, background=background, colour=colour)
        H = image.shape[0]
        columns = np.empty(H)
        ok = np.empty(H, dtype=np.bool_)
        frac, half_window = self._estimator_args()
        refine(image, d.col, d.hit, d.bg, ESTIMATORS[self._estimator], 0, float(frac), int(half_window),
               columns, ok)
        score = np.where(d.hit, d.score, np.nan)
        return Track(columns, score)


class WindowedPeakTracker(PeakTracker):
    """A :class:`PeakTracker` whose estimator takes a level inside the peak (``frac``) and a window
    (``half_window``): the detection parameters, then those two, checked by :attr:`parameter_constraints`
    and passed to the estimator. The defaults are ``centroid``'s; ``com_bg`` has its own, and its own
    :meth:`find_stripe` (on the laser-on minus laser-off difference).
    """

    def __init__(self, threshold=None, k_sigma=DEFAULT_K_SIGMA, prominence=DEFAULT_PROMINENCE, frac=0.5,
                 half_window=7, min_run=DEFAULT_MIN_RUN, width_ratio=DEFAULT_WIDTH_RATIO, stripe_test=None):
        super().__init__(threshold=threshold, k_sigma=k_sigma, prominence=prominence, min_run=min_run,
                         width_ratio=width_ratio, stripe_test=stripe_test)
        self.frac = frac
        self.half_window = half_window

    parameter_constraints = {**PeakTracker.parameter_constraints, "frac": Real(low=0, high=1, high_open=True),
                             "half_window": Int(low=0)}

    def _estimator_args(self):
        return float(self.frac), int(self.half_window)
