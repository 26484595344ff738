"""``blais_rioux``: zero crossing of Blais & Rioux's derivative filter."""

from __future__ import annotations

from ._peak import DETECTION_DOC, PeakTracker

__all__ = ["BlaisRiouxTracker"]


class BlaisRiouxTracker(PeakTracker):
    __doc__ = """Blais & Rioux: zero crossing of a 4th-order derivative filter next to each row's peak.

    Blais, F. and Rioux, M. (1986), "Real-time numerical peak detector",
    *Signal Processing* 11(2), 145-155; compared by Fisher & Naidu (1996).
    The row is filtered with

    ``g(i) = I(i-2) + I(i-1) - I(i+1) - I(i+2)``

    (a smoothed derivative: negative left of a peak, positive right of it;
    edge pixels repeated at the row's ends). With ``j*`` the row's peak, the
    crossing is looked for in ``[j*, j*+1]`` if ``I(j*+1) >= I(j*-1)``, else
    in ``[j*-1, j*]``; with ``g0 = g(i)`` and ``g1 = g(i+1)`` at the
    interval's ends the column is the linear interpolation of the zero
    crossing, ``i + g0 / (g0 - g1)``, clamped to the interval.
""" + DETECTION_DOC + """
    Notes
    -----
    * ``j*`` is the row's maximum; on a plateau of equal maxima (saturation)
      its middle pixel, and on a plateau of 5 pixels or more, where the
      filter sees only the flat top, the column is the plateau's centre.
    * The filter needs no background level. Being 5 pixels long it averages
      noise better than 3-point fits but is biased on narrow stripes
      (sigma below about 1 px; see ``docs/estimators.png``).
    * ``score`` is the peak's contrast in noise units, as for ``threshold``.
    * The ``background`` frame is ignored.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((1, 40), np.uint8); img[0, :7] = [0, 10, 60, 100, 60, 10, 0]
    >>> float(BlaisRiouxTracker().track(img).columns[0])
    3.0
    """

    name = "blais_rioux"
    _estimator = "blais_rioux"
