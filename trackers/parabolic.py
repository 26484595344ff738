"""``parabolic``: 3-point parabola interpolation of each row's peak."""

from __future__ import annotations

from ._peak import DETECTION_DOC, PeakTracker

__all__ = ["ParabolicTracker"]


class ParabolicTracker(PeakTracker):
    __doc__ = """3-point parabola fit: vertex of the parabola through each row's peak and its neighbours.

    The 3-point parabolic (quadratic) estimator compared by Fisher & Naidu
    (1996, "A comparison of algorithms for subpixel peak detection"): with
    ``a, b, c`` the values left of, at and right of the peak pixel ``j*``,
    the column is

    ``j* + 0.5 (a - c) / (a - 2 b + c)``.

    It needs no background level, and is biased towards the pixel centre on
    Gaussian profiles (most for narrow ones; see ``docs/estimators.png``).
""" + DETECTION_DOC + """
    Notes
    -----
    * ``j*`` is the leftmost maximum of the row; if several equal maxima are
      adjacent (a plateau: saturation, quantisation) the column is the
      plateau's centre. A peak on the first or last column is reported at
      that column.
    * ``score`` is the peak's contrast in noise units, as for ``threshold``.
    * The ``background`` frame is ignored.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((1, 40), np.uint8); img[0, :7] = [0, 10, 50, 90, 70, 10, 0]
    >>> float(ParabolicTracker().track(img).columns[0])
    3.1666666666666665
    """

    name = "parabolic"
    _estimator = "parabolic"
