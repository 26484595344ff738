"""``centroid``: gray-gravity centre of the stripe in each row."""

from __future__ import annotations

from ._peak import WindowedPeakTracker

__all__ = ["CentroidTracker"]


class CentroidTracker(WindowedPeakTracker):
    """Gray-gravity centre: intensity-weighted mean column around each row's peak.

    Detection is :class:`~trackers.threshold.ThresholdTracker`'s (same
    parameters, the same per-row rule). In a detected row with peak value
    ``p`` at column ``j*`` (the middle pixel of the run of equal maxima when
    the peak is flat, e.g. saturated) and row background ``b`` (the row's
    median), the window
    is the run of
    contiguous pixels around ``j*`` brighter than ``level = b + frac * (p - b)``,
    at most ``half_window`` pixels on each side; the column is
    ``sum(w_j * j) / sum(w_j)`` with weights ``w_j = I_j - level`` (continuous
    in the sub-pixel phase, so no jump when a pixel enters the window).

    Parameters
    ----------
    threshold, k_sigma, prominence, min_run, width_ratio, stripe_test
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
    _estimator = "centroid"
