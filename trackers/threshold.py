"""``threshold``: the brightest pixel of each row, if it stands out of its row."""

from __future__ import annotations

import numpy as np

from ._base import Track, Tracker
from ._params import Int, Real
from ._stripe import StripeSettings, answer

__all__ = ["ThresholdTracker", "DEFAULT_K_SIGMA", "DEFAULT_PROMINENCE", "DEFAULT_MIN_RUN", "DEFAULT_WIDTH_RATIO"]

# The detection defaults below were chosen together by ``stripebench tune threshold`` (stage 1; profile
# ``bench/config/profiles/tune_threshold.toml``: the hard synthetic frames of seeds 100-105, renders of
# spheres and planes at seed 1 and the shipped photographs; the objective: the mean over those groups of
# F1 over rows, a miss and a false report priced alike, among the settings that report on at most 10 % of
# the photographs' stripe-less rows; docs/detection.md).
#: Default noise multiple of the per-row detection.
DEFAULT_K_SIGMA = 4.0
#: Default least ratio of the peak's contrast to the runner-up's.
DEFAULT_PROMINENCE = 1.1
#: Default least number of vertically linked candidate rows.
DEFAULT_MIN_RUN = 12
#: Default widest half-contrast run of a stripe, in medians of the frame's (None: any).
DEFAULT_WIDTH_RATIO = 4.0


class ThresholdTracker(Tracker):
    """Per row, the column of the brightest pixel if it stands out of that row.

    The paper's "simple method such as threshold" (Wang et al. 2008, sec. 2):
    rows where no stripe is found report NaN. Each row is decided against its
    own statistics (:func:`trackers._detect.detect_rows`), never against the
    spread of the whole frame's values, so texture, daylight or a lamp
    elsewhere cannot hide a stripe that is the brightest thing in its row:
    with ``b`` the row's median, ``s`` the pixel noise (from the median
    difference of adjacent pixels over a fixed sample of the frame, which
    smooth texture does not inflate) and ``q`` the brightest pixel of the row
    outside the peak's exclusion zone (the run above half the peak's contrast,
    widened by its own length on each side), the row's peak ``m`` is reported
    iff ``m - b > k_sigma * s`` and ``m - b > prominence * (q - b)`` (``s``
    includes the quantisation's own noise, so a one-level excursion of a dark
    8-bit row is not a stripe), its half-contrast run is at most ``width_ratio``
    times the frame's median (a lamp or a window is wider than the stripe), and it lines up with at least ``min_run - 1`` other such rows (a
    stripe is a curve: :func:`trackers._detect.detect_rows`).
    Rows where no stripe stands out report nothing, as in the paper: "for
    those rows with the laser light undetectable, the depth of the
    corresponding point could not be computed".

    Parameters
    ----------
    threshold : float or None, default None
        An explicit threshold in image units: a row is reported iff its peak
        exceeds it (the per-row rule above is then not used).
    k_sigma : float, default :data:`DEFAULT_K_SIGMA`
        Noise multiple of the per-row rule (>= 0).
    prominence : float, default :data:`DEFAULT_PROMINENCE`
        Least ratio of the peak's contrast to the runner-up's (>= 0; 0 turns
        the test off).
    min_run : int, default :data:`DEFAULT_MIN_RUN`
        Least number of vertically linked rows that pass (>= 1; 1 turns the
        test off); not used with an explicit ``threshold``.
    width_ratio : float or None, default :data:`DEFAULT_WIDTH_RATIO`
        Widest half-contrast run of a stripe, in medians of the frame's rows
        that pass (>= 1; None: any); not used with an explicit ``threshold``.
    stripe_test : dict or None, default None
        The stripe question's settings (:class:`trackers.StripeTest`; ``{}``:
        its defaults): a row whose peak it says is not a stripe is not a
        candidate (before the chain). It reads the laser-off frame and the
        colour evidence where given. None: not asked (the rule above alone);
        not used with an explicit ``threshold``.

    Notes
    -----
    ``columns`` are whole pixels: the leftmost maximum, or the middle of a run
    of equal maxima (a clipped stripe). ``score`` is the peak's contrast over
    the row's background in noise units, ``(m - b) / s`` (``s`` floored at
    1e-3 of the frame's range). A constant frame reports nothing. The defaults
    were chosen by ``stripebench tune threshold`` (``bench/studies/tune_threshold.py``).

    Examples
    --------
    >>> img = np.zeros((2, 40), np.uint8); img[:, 3] = 200
    >>> ThresholdTracker().track(img).columns
    array([3., 3.])
    """

    name = "threshold"
    subpixel = False
    uses_colour = True

    def __init__(self, threshold=None, k_sigma=DEFAULT_K_SIGMA, prominence=DEFAULT_PROMINENCE,
                 min_run=DEFAULT_MIN_RUN, width_ratio=DEFAULT_WIDTH_RATIO, stripe_test=None):
        self.threshold = threshold
        self.k_sigma = k_sigma
        self.prominence = prominence
        self.min_run = min_run
        self.width_ratio = width_ratio
        self.stripe_test = stripe_test

    parameter_constraints = {"threshold": Real(optional=True), "k_sigma": Real(low=0, high=1e6),
                             "prominence": Real(low=0, high=1e6), "min_run": Int(low=1, high=100000),
                             "width_ratio": Real(low=1, high=1e6, optional=True), "stripe_test": StripeSettings()}

    def detect(self, image, *, raw=None, background=None, colour=None):
        """The per-row decision on a validated frame (:class:`trackers._detect.RowDetection`).

        ``raw``, ``background`` and ``colour`` feed the stripe question (``stripe_test``): the
        laser-on frame (default ``image``), the laser-off frame and the colour evidence, each or None.
        """
        from ._detect import detect_rows

        question = None
        if self.stripe_test is not None:
            def question(columns):
                return answer(self.stripe_test, image, columns, image=raw, background=background, colour=colour).yes
        return detect_rows(image, float(self.k_sigma), float(self.prominence), self.threshold,
                           min_run=int(self.min_run), width_ratio=self.width_ratio, ask=question)

    def find_stripe(self, image, background, colour=None):
        d = self.detect(image, background=background, colour=colour)
        columns = np.where(d.hit, d.mid.astype(np.float64), np.nan)
        score = np.where(d.hit, d.score, np.nan)
        return Track(columns, score)
