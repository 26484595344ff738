"""``gauss3``: 3-point Gaussian (log-parabola) interpolation of each row's peak."""

from __future__ import annotations

from ._peak import DETECTION_DOC, PeakTracker

__all__ = ["Gauss3Tracker"]


class Gauss3Tracker(PeakTracker):
    __doc__ = """3-point Gaussian fit: vertex of the log-parabola through each row's peak and its neighbours.

    The classic 3-point Gaussian estimator (e.g. Fisher & Naidu 1996, "A
    comparison of algorithms for subpixel peak detection"; Naidu & Fisher,
    BMVC 1991): with ``a, b, c`` the background-subtracted values left of,
    at and right of the peak pixel ``j*``, the column is

    ``j* + 0.5 (ln a - ln c) / (ln a - 2 ln b + ln c)``,

    exact for a sampled Gaussian profile on a known background.
""" + DETECTION_DOC + """
    Notes
    -----
    * The background is the row's level ``b`` (its median, as in the
      detection, ``trackers._detect.row_statistics``); ``a`` and ``c`` are floored
      at ``1e-3 (I(j*) - b)`` before the logarithm (noise can take a tail
      pixel below the background), so the offset stays within +-0.5 px.
    * ``j*`` is the leftmost maximum of the row; if several equal maxima are
      adjacent (a plateau: saturation, quantisation) the column is the
      plateau's centre. A peak on the first or last column is reported at
      that column (one neighbour is missing).
    * ``score`` is the peak's contrast in noise units, as for ``threshold``.
    * The ``background`` frame is ignored.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.arange(40.0)
    >>> img = (10 + 100 * np.exp(-0.5 * (x - 4.3) ** 2))[None, :]
    >>> round(float(Gauss3Tracker(threshold=20).track(img).columns[0]), 6)
    4.3
    """

    name = "gauss3"
    _estimator = "gauss3"
