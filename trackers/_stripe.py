"""The stripe question every tracker asks of the rows it would report: is this row's peak a laser stripe?

A tracker finds, per row, a column: the brightest pixel, a path's node, a ridge point, a network's
candidate. Whether a laser stripe is there is a question of its own, and every tracker answers it the
same way, here, from the frame (:func:`ask`, with the settings :class:`StripeTest`). A row's peak is
a stripe unless one of these says no (each test can be turned off):

*width*
    the peak's half-contrast run is at most ``width_ratio`` times the frame's stripe width, the
    ``width_quantile`` quantile of the runs of its strongest rows (the top ``strong_frac`` by
    contrast of the asked rows whose peaks lie in line as the *continuity* test counts them, or of
    all asked rows where none does or that test is off: in a dim frame the isolated peaks of noise
    are as strong as the stripe and one pixel wide). A window, a glow, a lamp or a lit wall is wider
    than the stripe the frame shows where it is brightest, and a low quantile keeps such a
    distractor among the strongest rows from widening the measure;
*ridge*
    both flanks fall: on each side, the mean of the pixels between one and two stripe widths (at
    least 2 and 4 px) from the peak lies below ``flank_level`` of the peak's contrast over its row (a
    side outside the frame is not read: a stripe on the frame's edge has one flank). A step edge (a
    lit door edge, a table edge, a bright plateau) keeps one flank high;
*colour* (where the frame has colour)
    somewhere in the peak's run (one pixel either side included) the light it adds over its row has
    the laser's colour: a share of at least ``colour_min`` (:func:`colour_evidence`). White and warm
    light, skin and print are not laser-coloured;
*laser-off* (where a laser-off frame is given)
    the peak's contrast in the laser-off frame is below ``off_ratio`` of its contrast in the
    laser-on frame: light that is there with the laser off is not the laser;
*level*
    the peak's contrast is at least ``level_min`` of the frame's stripe contrast, the median contrast of
    the same strongest rows the width is measured on: along its own path the laser is the brightest
    light, so a peak far dimmer than the stripe's strong rows (a poster, a lit wall in a dark room, the
    room beyond where the stripe ends) is not it. Not asked by default (None);
*continuity*
    at least ``continuity_min`` of the ``continuity_rows`` rows on either side hold a peak that
    passes the tests above and lies within ``continuity_px`` px per row of this one: a stripe is a
    curve, LED clusters and glints are isolated. A frame of at most ``continuity_min`` rows asks
    it of all its other rows.

The trackers read it through their ``stripe_test`` parameter (None, the default: the question is
not asked, and the tracker reports as it did without it; a dict of :class:`StripeTest`'s fields,
``{}`` for its defaults). How each tracker reads the answer is in docs/detection.md.

:func:`ask` is a thin wrapper over the numba kernels of :mod:`trackers._stripe_kernels` (the per-row
measurements and the curve test); this module imports no numba, so ``import trackers`` stays light.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import asdict, dataclass, fields

import numpy as np

from ._validation import check_colour

__all__ = ["StripeTest", "StripeAnswer", "StripeSettings", "ask", "colour_evidence", "check_colour", "REASONS",
           "as_test", "answer"]

#: The bits of :attr:`StripeAnswer.reasons`: which test said no.
REASONS = {"width": 1, "ridge": 2, "colour": 4, "off": 8, "continuity": 16, "level": 32}


@dataclass(frozen=True)
class StripeTest:
    """The stripe question's settings (one object; a test whose setting is None is not asked).

    Attributes
    ----------
    width_ratio : float or None, default 3.0
        Widest half-contrast run of a stripe's peak, in multiples of the frame's stripe width: a
        stripe's run varies with its brightness by less than that; a window or a glow is wider.
    strong_frac : float, default 0.5
        The frame's stripe width is measured on this fraction of its asked rows in line (the
        continuity test's neighbours, before the other tests) with the largest contrast, in (0, 1]:
        where the stripe is brightest it is least confused with noise.
    width_quantile : float, default 0.25
        Which quantile of those rows' runs is the frame's stripe width, in [0, 1] (the lower value
        of a tie): a distractor among the strongest rows is wider than the stripe, so a low quantile
        measures the stripe while it holds at least that share of them.
    flank_level : float or None, default 0.5
        Highest mean level of either flank (one to two stripe widths from the peak, at least 2 to 4 px),
        as a fraction of
        the peak's contrast over its row: a ridge's flanks have fallen there (to under 0.1 of a
        Gaussian's); a step edge keeps one at about 1.
    colour_min : float or None, default 0.5
        Least laser share (:func:`colour_evidence`) in the peak's run, in [0, 1]: the laser's own
        light scores about 0.85-1 (its crosstalk into the other channels is 0.04-0.15), skin about
        0.3-0.4, warm light about 0.2, white light 0.
    off_ratio : float or None, default 0.5
        Largest contrast of the peak in the laser-off frame, as a fraction of its contrast in the
        laser-on frame: the laser's own peak is gone with the laser off (a ratio near 0), ambient
        light stays (near 1).
    continuity_rows : int or None, default 8
        Rows looked at on each side for the curve test, >= 1.
    continuity_min : int, default 4
        Least number of those rows (both sides together) whose peak passes the other tests and lies
        in line: an LED dot or a glint spans a few rows, a stripe many (a frame of fewer rows asks
        for all of its other rows).
    continuity_px : float, default 3.0
        Largest column change per row between two peaks in line, px (> 0): a stripe tilted up to
        about 70 degrees from the vertical stays in line, as in the threshold family's chain.
    level_min : float or None, default None
        Least contrast of a stripe's peak, as a fraction of the frame's stripe contrast (the median
        contrast of the rows the stripe width is measured on), in [0, 1]. None: not asked.

    Examples
    --------
    >>> StripeTest().width_ratio, StripeTest(colour_min=None).colour_min
    (3.0, None)
    >>> StripeTest(width_ratio=0.5)
    Traceback (most recent call last):
    ...
    ValueError: `width_ratio` must be None or a number >= 1, got 0.5
    """

    width_ratio: float | None = 3.0
    strong_frac: float = 0.5
    width_quantile: float = 0.25
    flank_level: float | None = 0.5
    colour_min: float | None = 0.5
    off_ratio: float | None = 0.5
    continuity_rows: int | None = 8
    continuity_min: int = 4
    continuity_px: float = 3.0
    level_min: float | None = None

    def __post_init__(self):
        def real(name, lo, hi=None, optional=True, lo_open=False):
            v = getattr(self, name)
            if v is None and optional:
                return
            ok = isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v) and \
                (v > lo if lo_open else v >= lo) and (hi is None or v <= hi)
            if not ok:
                rng = f"{'>' if lo_open else '>='} {lo}" if hi is None else f"in [{lo}, {hi}]"
                raise ValueError(f"`{name}` must be {'None or ' if optional else ''}a number {rng}, got {v!r}")

        def integer(name, lo, optional):
            v = getattr(self, name)
            if v is None and optional:
                return
            if isinstance(v, bool) or not isinstance(v, numbers.Integral) or v < lo:
                raise ValueError(f"`{name}` must be {'None or ' if optional else ''}an integer >= {lo}, got {v!r}")

        real("width_ratio", 1)
        real("strong_frac", 0, 1, optional=False, lo_open=True)
        real("width_quantile", 0, 1, optional=False)
        real("flank_level", 0, 1)
        real("colour_min", 0, 1)
        real("off_ratio", 0)
        integer("continuity_rows", 1, True)
        integer("continuity_min", 1, False)
        real("continuity_px", 0, optional=False, lo_open=True)
        real("level_min", 0, 1)
        if self.continuity_rows is not None and self.continuity_min > 2 * self.continuity_rows:
            raise ValueError(f"`continuity_min` must be at most 2 * continuity_rows ({2 * self.continuity_rows}), "
                             f"got {self.continuity_min!r}")

    def as_dict(self) -> dict:
        """The settings as a plain dict (what a tracker's ``stripe_test`` parameter and a TOML table hold)."""
        return asdict(self)

    def label(self) -> str:
        """A short name of the settings that differ from the defaults (``"defaults"`` if none), for tables.

        Examples
        --------
        >>> StripeTest(colour_min=None, width_ratio=4.0).label()
        'width_ratio=4,colour_min=none'
        """
        base = StripeTest()
        parts = [f"{f.name}={'none' if getattr(self, f.name) is None else format(getattr(self, f.name), 'g')}"
                 for f in fields(self) if getattr(self, f.name) != getattr(base, f.name)]
        return ",".join(parts) or "defaults"


def as_test(value) -> StripeTest | None:
    """A tracker's ``stripe_test`` parameter as a :class:`StripeTest` (None stays None).

    Parameters
    ----------
    value : None, dict or StripeTest
        A dict holds some of :class:`StripeTest`'s fields (the others take their defaults).

    Raises
    ------
    ValueError
        Not one of those, an unknown field, or a bad value (one line naming ``stripe_test``).
    """
    if value is None or isinstance(value, StripeTest):
        return value
    if not isinstance(value, dict):
        raise ValueError(f"`stripe_test` must be None or a table of the stripe question's settings, got {value!r}")
    names = {f.name for f in fields(StripeTest)}
    unknown = sorted(set(value) - names)
    if unknown:
        raise ValueError(f"`stripe_test` has unknown setting(s) {unknown}; valid: {', '.join(sorted(names))}")
    try:
        return StripeTest(**value)
    except ValueError as exc:
        raise ValueError(f"`stripe_test`: {exc}") from None


class StripeSettings:
    """The constraint of a tracker's ``stripe_test`` parameter (:mod:`trackers._params`' protocol):
    None, or a dict (or :class:`StripeTest`) of the stripe question's settings."""

    def check(self, name: str, value) -> None:
        try:
            as_test(value)
        except ValueError as exc:
            msg = str(exc).replace("`stripe_test`", f"`{name}`")
            raise ValueError(msg) from None

    def invalid(self) -> list:
        """Values the constraint refuses (for the conformance suite)."""
        return [1.0, "defaults", {"width_ratio": 0.5}, {"no_such_setting": 1}, {"continuity_min": 0}]


@dataclass(frozen=True, eq=False)
class StripeAnswer:
    """The stripe question's answer for every row of a frame; arrays of shape (H,).

    Attributes
    ----------
    yes : bool
        The row's peak is a stripe (False where no column was asked about).
    asked : bool
        A column was asked about (finite).
    contrast : float64
        The peak's contrast over its row's median, in the frame's units.
    width_px : int64
        The peak's half-contrast run, px (0 where not asked).
    flank : float64
        The higher flank's mean level over the row's median, as a fraction of the contrast.
    colour : float64
        The highest laser share in the peak's run (NaN without colour).
    off : float64
        The peak's contrast in the laser-off frame over its contrast in the laser-on frame (NaN
        without a laser-off frame).
    reasons : int64
        The tests that said no (bits of :data:`REASONS`); 0 where ``yes``.
    stripe_width_px : float
        The frame's stripe width (a low quantile of the runs of its strongest rows in line), px; NaN if
        no row was asked.
    stripe_contrast : float
        The frame's stripe contrast (the median contrast of those rows), the frame's units; NaN if no
        row was asked.
    """

    yes: np.ndarray
    asked: np.ndarray
    contrast: np.ndarray
    width_px: np.ndarray
    flank: np.ndarray
    colour: np.ndarray
    off: np.ndarray
    reasons: np.ndarray
    stripe_width_px: float
    stripe_contrast: float = float("nan")

    def said_no(self, test: str) -> np.ndarray:
        """Rows where the test ``test`` (a key of :data:`REASONS`) said no, (H,) bool."""
        return (self.reasons & REASONS[test]) != 0


def colour_evidence(rgb, laser: str = "red") -> np.ndarray:
    """Per pixel, the share of the light it adds over its row that has the laser's colour.

    With ``D = rgb - m`` (each channel's row median ``m`` subtracted), ``L`` the laser's channel of ``D``
    and ``O`` the larger of the other two, the share is ``clip((L - max(O, 0)) / L, 0, 1)`` where
    ``L > 0`` and 0 elsewhere: the laser's light (crosstalk 0.04-0.15 into the other channels) scores
    0.85-1, white or grey light 0, skin or warm light 0.2-0.4. Where a stripe clips the laser's channel its
    core turns white (a low share) and its flanks stay coloured, which is why :func:`ask` takes the
    largest share over the peak's run and one pixel either side.

    Parameters
    ----------
    rgb : array_like, shape (H, W, 3)
        A colour photograph in any real units (DN), in the orientation of the frame the tracker gets.
    laser : {'red', 'green', 'blue'}

    Returns
    -------
    ndarray of float64, shape (H, W)
        In [0, 1]: what a tracker's ``colour`` argument takes.

    Examples
    --------
    >>> px = np.full((1, 9, 3), 40.0)  # a grey row: the laser, white light, skin
    >>> px[0, 1] = [200, 52, 50]; px[0, 4] = [200, 200, 200]; px[0, 7] = [200, 150, 130]
    >>> colour_evidence(px, "red").round(2).tolist()
    [[0.0, 0.92, 0.0, 0.0, 0.0, 0.0, 0.0, 0.31, 0.0]]
    """
    index = {"red": 0, "green": 1, "blue": 2}
    if laser not in index:
        raise ValueError(f"`laser` must be one of red, green, blue, got {laser!r}")
    img = np.asarray(rgb, np.float64)
    if img.ndim != 3 or img.shape[2] != 3:
        raise ValueError(f"`rgb` must have shape (H, W, 3), got {img.shape}")
    d = img - np.median(img, axis=1, keepdims=True)
    k = index[laser]
    big = d[..., k]
    other = np.maximum(np.max(np.delete(d, k, axis=2), axis=2), 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        share = np.where(big > 0, (big - other) / big, 0.0)
    return np.clip(share, 0.0, 1.0)


def ask(settings: StripeTest, frame: np.ndarray, columns, *, image=None, background=None,
        colour=None) -> StripeAnswer:
    """Ask, for every row with a column, whether its peak is a laser stripe (module docstring).

    Parameters
    ----------
    settings : StripeTest
    frame : ndarray, shape (H, W), uint8 or float64
        The frame the tracker sees (the image, or laser-on minus laser-off).
    columns : array_like, shape (H,)
        The column the tracker would report in each row (px), NaN where it reports nothing; the peak
        is the brightest pixel within one pixel of it.
    image : ndarray, shape (H, W), optional
        The laser-on frame, for the laser-off test (default ``frame``).
    background : ndarray, shape (H, W), optional
        The laser-off frame; None: the laser-off test is not asked.
    colour : ndarray, shape (H, W), optional
        :func:`colour_evidence` of the frame's colour photograph; None: the colour test is not asked.

    Returns
    -------
    StripeAnswer

    Examples
    --------
    >>> f = np.full((12, 40), 10.0); f[:, 20] = 100.0; f[:, 19] = f[:, 21] = 60.0  # a ridge, 3 px
    >>> f[:3, 5:] = 10.0 + 80.0 * np.exp(-np.arange(35) / 30.0)  # rows 0-2: a lit edge at column 5
    >>> cols = np.where(np.arange(12) < 3, 5.0, 20.0)
    >>> a = ask(StripeTest(continuity_rows=None), f, cols)
    >>> a.yes.tolist()
    [False, False, False, True, True, True, True, True, True, True, True, True]
    >>> bool(a.said_no("ridge")[0]), a.stripe_width_px
    (True, 3.0)
    """
    from ._stripe_kernels import _continuity, _flanks, _off_ratio, _row_evidence, _window_max

    s = settings
    f = np.asarray(frame)
    H, W = f.shape
    col = np.asarray(columns, np.float64)
    peak = np.empty(H, np.int64)
    lo = np.empty(H, np.int64)
    hi = np.empty(H, np.int64)
    contrast = np.empty(H)
    level = np.empty(H)
    _row_evidence(f, col, peak, contrast, lo, hi, level)
    asked = peak >= 0
    width = np.where(asked, hi - lo + 1, 0).astype(np.int64)
    positive = asked & (contrast > 0)
    reasons = np.where(asked & ~positive, REASONS["ridge"], 0).astype(np.int64)  # no peak at all: not a ridge
    ref = level_ref = float("nan")
    if positive.any():
        measured = positive
        if s.continuity_rows is not None:  # the stripe's rows: peaks in line (isolated noise peaks are 1 px wide)
            line = np.empty(H, np.bool_)
            _continuity(positive, np.where(positive, peak, 0).astype(np.float64), int(s.continuity_rows),
                        int(s.continuity_min), float(s.continuity_px), line)
            if line.any():
                measured = line
        c = contrast[measured]
        n = max(1, int(math.ceil(s.strong_frac * c.size)))
        strongest = c >= np.sort(c)[c.size - n]  # ties all in: the same rows whichever way the frame is turned
        ref = float(np.quantile(width[measured][strongest], s.width_quantile, method="lower"))
        level_ref = float(np.median(c[strongest]))
    flank = np.full(H, np.nan)
    if positive.any():
        _flanks(f, np.where(positive, peak, -1), contrast, level, ref, flank)
    if s.width_ratio is not None and positive.any():
        reasons |= np.where(positive & (width > s.width_ratio * ref), REASONS["width"], 0)
    if s.flank_level is not None and positive.any():
        reasons |= np.where(positive & ~(flank <= s.flank_level), REASONS["ridge"], 0)
    if s.level_min is not None and positive.any():
        reasons |= np.where(positive & (contrast < s.level_min * level_ref), REASONS["level"], 0)
    col_ev = np.full(H, np.nan)
    if colour is not None:
        _window_max(np.asarray(colour, np.float64), peak, lo, hi, col_ev)
        if s.colour_min is not None:
            reasons |= np.where(asked & ~(col_ev >= s.colour_min), REASONS["colour"], 0)
    off = np.full(H, np.nan)
    if background is not None:
        on = f if image is None else np.asarray(image)
        _off_ratio(on, np.asarray(background), peak, off)
        if s.off_ratio is not None:
            reasons |= np.where(asked & ~(off <= s.off_ratio), REASONS["off"], 0)
    local = asked & (reasons == 0)
    if s.continuity_rows is not None:
        line = np.empty(H, np.bool_)
        _continuity(local, np.where(asked, peak, 0).astype(np.float64), int(s.continuity_rows),
                    int(s.continuity_min), float(s.continuity_px), line)
        reasons |= np.where(local & ~line, REASONS["continuity"], 0)
    yes = asked & (reasons == 0)
    return StripeAnswer(yes, asked, contrast, width, flank, col_ev, off, reasons.astype(np.int64), ref, level_ref)


def answer(stripe_test, frame, columns, *, image=None, background=None, colour=None) -> StripeAnswer | None:
    """What a tracker's ``stripe_test`` parameter makes of its rows: None when it is None (the question
    is not asked), else :func:`ask` with its settings (same arguments)."""
    test = as_test(stripe_test)
    if test is None:
        return None
    return ask(test, frame, columns, image=image, background=background, colour=colour)
