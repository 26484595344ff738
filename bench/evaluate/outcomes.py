"""The benchmark's scoring rules, in one home: the paper's numbers, the hit rule and row outcomes.

The paper's numbers (Wang et al. 2008): :data:`WITHIN_MM` (its Fig. 10 band), :data:`GROSS_MM`,
:data:`PAPER_IMPROVEMENT` (its "30 % improvement in the precision") and :data:`N_SAMPLES`; the
hit rule :func:`hits` with :data:`HIT_PX`. Every caller imports them from here; a test
(``tests/test_layout.py``) fails if a tolerance is compared anywhere else.

Row outcomes: both halves of detection, scored on every row.

Every row of every frame is one of five outcomes (:data:`OUTCOMES`), decided by the
row's *state* (does it have a stripe?) and by what the tracker reported there:

============  =====================  ===============================================
outcome       state                  the tracker
============  =====================  ===============================================
``hit``       stripe                 reports a column within ``tol_px`` of the truth
``wrong``     stripe                 reports a column further off (a false lock is one)
``missed``    stripe                 reports nothing
``false``     no stripe              reports a column: a false 3-D point
``quiet``     no stripe              reports nothing
``unknown``   unknown                (a real reference that is not sure: not scored)
============  =====================  ===============================================

From the counts: ``precision = hit / (hit + wrong + false)`` (reports that are right),
``recall = hit / (hit + wrong + missed)`` (stripe rows found: the hit rate),
``f1`` their harmonic mean (``2 hit / (2 hit + wrong + false + wrong + missed)``: a wrong
row is a false positive and a miss at once) and the ``false_report_rate = false / (false +
quiet)`` (stripe-less rows that get a column). :mod:`bench.evaluate.ranking` ranks the
reports by the tracker's per-row ``score`` (AP, the threshold-free figure) and gives any of these an
interval over frames or photographs.

Row states: a render's truth is exact (a column where a lit visible stripe is, NaN
where none is). A real set's reference has an explicit third state, *unknown*
(ambiguous, or occluded and unsure); a reference with columns only is read with
:func:`fallback_states` (a NaN row at least ``gap_rows`` rows from any stripe row is
*no stripe*, any other NaN row *unknown*).

Pure functions: arrays in, numbers out.
"""

from __future__ import annotations

import numpy as np


__all__ = ["HIT_PX", "WITHIN_MM", "GROSS_MM", "PAPER_IMPROVEMENT", "N_SAMPLES", "hits", "within", "gross", "HIT", "WRONG", "MISSED", "FALSE", "QUIET", "UNKNOWN", "OUTCOMES", "STRIPE", "NO_STRIPE",
           "UNSURE", "STATES", "STATE_NAMES", "GAP_ROWS", "truth_states", "fallback_states", "fallback_of",
           "distant_states",
           "REFERENCE_HALF_WIDTH", "REFERENCE_MIN_CONTRAST", "reference_noise", "referenced_states", "window_centre",
           "referenced_columns", "row_outcomes",
           "outcome_counts", "detection_figures",
           "COUNT_KEYS", "FIGURE_KEYS"]

#: A row is a hit when the reported column is within this many px of the truth (the one hit rule).
HIT_PX = 3.0
#: The paper's Fig. 10 band: "most samples locate within the range from -5 to +5 millimeter" (mm).
WITHIN_MM = 5.0
#: A gross depth error: the tracker followed something else than the object's stripe (mm).
GROSS_MM = 50.0
#: "a 30 % improvement in the precision" (sec. 4.3): the paper's ratio ``1 - S_DP / S_noDP``.
PAPER_IMPROVEMENT = 0.30
#: The paper's "150 random surface samples" per experiment (the profiles' default ``n_samples``).
N_SAMPLES = 150


def hits(pred, truth, tol_px: float = HIT_PX) -> np.ndarray:
    """The one hit rule: ``|pred - truth| <= tol_px``, elementwise; a row with no
    detection or no truth (NaN on either side) is not a hit.

    Parameters
    ----------
    pred, truth : array_like, float, px
        Reported and true columns, broadcastable to one shape.
    tol_px : float
        Largest hit distance in px (default :data:`HIT_PX`).

    Returns
    -------
    numpy.ndarray of bool, the broadcast shape

    Examples
    --------
    >>> hits([10.0, 14.0, np.nan, 5.0], [11.0, 10.0, 7.0, np.nan]).tolist()
    [True, False, False, False]
    """
    with np.errstate(invalid="ignore"):
        return np.abs(np.asarray(pred, dtype=np.float64) - np.asarray(truth, dtype=np.float64)) <= tol_px


def within(errors_mm, within_mm: float = WITHIN_MM) -> np.ndarray:
    """The paper's band: ``|error| <= within_mm``, elementwise; no value (NaN) is never within.

    Examples
    --------
    >>> within([4.9, -5.0, 5.1, np.nan]).tolist()
    [True, True, False, False]
    """
    with np.errstate(invalid="ignore"):
        return np.abs(np.asarray(errors_mm, dtype=np.float64)) <= within_mm


def gross(errors_mm, gross_mm: float = GROSS_MM) -> np.ndarray:
    """A gross error: ``|error| > gross_mm``, elementwise (NaN is not one).

    Examples
    --------
    >>> gross([49.0, -51.0, np.nan]).tolist()
    [False, True, False]
    """
    with np.errstate(invalid="ignore"):
        return np.abs(np.asarray(errors_mm, dtype=np.float64)) > gross_mm


# outcome codes (int8): the index into OUTCOMES
HIT, WRONG, MISSED, FALSE, QUIET, UNKNOWN = range(6)
#: The outcome names, by code.
OUTCOMES = ("hit", "wrong", "missed", "false", "quiet", "unknown")
#: The count columns of a record: ``n_hit``, ``n_wrong``, ... (``n_unknown`` last).
COUNT_KEYS = tuple(f"n_{o}" for o in OUTCOMES)
#: The detection figures of :func:`detection_figures`.
FIGURE_KEYS = ("precision", "recall", "f1", "false_report_rate")

# row states (int8)
NO_STRIPE, STRIPE, UNSURE = 0, 1, -1
#: A state's name in a reference file -> its code.
STATES = {"stripe": STRIPE, "none": NO_STRIPE, "unknown": UNSURE}
#: A state's code -> its name.
STATE_NAMES = {v: k for k, v in STATES.items()}
#: The fallback's distance (rows) from any stripe row beyond which a NaN reference row has no stripe.
GAP_ROWS = 15


def truth_states(truth) -> np.ndarray:
    """The states of exact truth: :data:`STRIPE` where ``truth`` has a column, :data:`NO_STRIPE` where NaN.

    Examples
    --------
    >>> truth_states([3.0, np.nan]).tolist()
    [1, 0]
    """
    t = np.asarray(truth, dtype=np.float64)
    return np.where(np.isnan(t), NO_STRIPE, STRIPE).astype(np.int8)


def fallback_states(reference, gap_rows: int = GAP_ROWS) -> np.ndarray:
    """The states of a reference that has columns only (NaN where it has none).

    A row with a column is :data:`STRIPE`; a NaN row at least ``gap_rows`` rows from
    every stripe row (``|r - s| >= gap_rows``) is :data:`NO_STRIPE`; every other NaN row
    is :data:`UNSURE` (the stripe may fade there without the reference saying so). A
    reference with no column at all has no stripe anywhere.

    Parameters
    ----------
    reference : array_like, shape (H,) or (F, H)
        Reference columns (px), NaN where there is none; rows along the last axis.
    gap_rows : int
        The least distance, in rows, >= 1.

    Returns
    -------
    numpy.ndarray of int8, the shape of ``reference``

    Examples
    --------
    >>> ref = np.full(40, np.nan); ref[10:20] = 5.0
    >>> s = fallback_states(ref, gap_rows=15)
    >>> s[:10].tolist() == [-1] * 10, s[10:20].tolist() == [1] * 10, s[20:34].tolist() == [-1] * 14, s[34:].tolist()
    (True, True, True, [0, 0, 0, 0, 0, 0])
    """
    if isinstance(gap_rows, bool) or not isinstance(gap_rows, (int, np.integer)) or gap_rows < 1:
        raise ValueError(f"`gap_rows` must be an integer >= 1, got {gap_rows!r}")
    ref = np.asarray(reference, dtype=np.float64)
    if ref.ndim == 0:
        raise ValueError(f"`reference` must have at least one axis, got shape {ref.shape}")
    has = ~np.isnan(ref)
    H = ref.shape[-1]
    idx = np.arange(H)
    # distance to the nearest stripe row along the last axis: a forward and a backward sweep
    big = np.iinfo(np.int64).max // 4
    last = np.where(has, idx, -big)
    last = np.maximum.accumulate(last, axis=-1)
    nxt = np.where(has, idx, big)
    nxt = np.flip(np.minimum.accumulate(np.flip(nxt, axis=-1), axis=-1), axis=-1)
    dist = np.minimum(idx - last, nxt - idx)
    out = np.where(has, STRIPE, np.where(dist >= gap_rows, NO_STRIPE, UNSURE))
    return out.astype(np.int8)


def fallback_of(states, gap_rows: int = GAP_ROWS) -> np.ndarray:
    """``states`` as a reference without row states would give them: its :data:`STRIPE` rows kept, every other row
    read by :func:`fallback_states` around them (:data:`NO_STRIPE` at least ``gap_rows`` rows from every stripe row,
    else :data:`UNSURE`). A real set whose ``NAME_ref.csv`` files have no ``state`` column is scored so
    (:func:`bench.store.realset.read_reference_states`); a prediction for such a set reads its frames' rows the same
    way.

    Parameters
    ----------
    states : array_like of int, shape (H,) or (F, H)
        Row states (:data:`STATES`' values).
    gap_rows : int
        As :func:`fallback_states`'.

    Returns
    -------
    numpy.ndarray of int8, the shape of ``states``

    Examples
    --------
    A faint stretch left unscored (rows 20-39) between two stripe stretches, and an unscored row by the stripe:

    >>> s = np.r_[np.full(20, STRIPE), np.full(20, UNSURE), np.full(20, STRIPE)]; s[5] = UNSURE
    >>> f = fallback_of(s, gap_rows=5)
    >>> int(f[5]), f[20:24].tolist(), f[24:36].tolist() == [NO_STRIPE] * 12, f[36:40].tolist()
    (-1, [-1, -1, -1, -1], True, [-1, -1, -1, -1])
    """
    st = np.asarray(states)
    return fallback_states(np.where(st == STRIPE, 0.0, np.nan), gap_rows)


def distant_states(states, truth, gap_rows: int = GAP_ROWS) -> np.ndarray:
    """``states`` with every :data:`NO_STRIPE` row nearer than ``gap_rows`` rows to a row of ``truth``
    :data:`UNSURE`: the stripe-less rows a photograph's reference without explicit states scores
    (:func:`fallback_states`). On a render they leave out the few rows where the stripe jumps at an occlusion,
    which a photograph's reference leaves unscored.

    Parameters
    ----------
    states : array_like of int, shape (H,) or (F, H)
        Row states (:data:`STATES`' values).
    truth : array_like, the shape of ``states``, px
        The true columns, NaN where there is no stripe.
    gap_rows : int
        As :func:`fallback_states`'.

    Returns
    -------
    numpy.ndarray of int8, the shape of ``states``: :data:`UNSURE` in the near stripe-less rows, else ``states``

    Examples
    --------
    >>> t = np.where((np.arange(40) >= 10) & (np.arange(40) < 20), 5.0, np.nan)
    >>> s = distant_states(truth_states(t), t, gap_rows=15)
    >>> s[10:20].tolist() == [1] * 10, s[20:34].tolist() == [-1] * 14, s[34:].tolist(), s[:10].tolist() == [-1] * 10
    (True, True, [0, 0, 0, 0, 0, 0], True)
    """
    st = np.asarray(states)
    if np.shape(truth) != st.shape:
        raise ValueError(f"`states` and `truth` must have one shape, got {st.shape} and {np.shape(truth)}")
    near = (st == NO_STRIPE) & (fallback_states(truth, gap_rows) != NO_STRIPE)
    return np.where(near, UNSURE, st).astype(np.int8)


#: The real set's reference rule (docs/real.md, ``scripts/make_real_set.py``): a row gets a reference only
#: where the frame's maximum within this many px of the stripe ...
REFERENCE_HALF_WIDTH = 6
#: ... stands this many times :func:`reference_noise` above the window's median.
REFERENCE_MIN_CONTRAST = 6.0


def reference_noise(frame) -> float:
    """The robust noise of a frame as the real set's references measure it (DN).

    1.4826 x the median absolute deviation of every third pixel of every third row, at least 1:
    a robust spread of the whole frame (scene and sensor), the unit of :data:`REFERENCE_MIN_CONTRAST`.

    Parameters
    ----------
    frame : array_like, shape (H, W)
        The tracker's frame (DN).

    Examples
    --------
    >>> reference_noise(np.zeros((9, 9)))
    1.0
    """
    f = np.asarray(frame, dtype=np.float64)
    if f.ndim != 2:
        raise ValueError(f"`frame` must be 2-D (H, W), got shape {f.shape}")
    sample = f[::3, ::3].ravel()
    return max(1.4826 * float(np.median(np.abs(sample - np.median(sample)))), 1.0)


def referenced_states(frame, truth, *, half_width: int = REFERENCE_HALF_WIDTH,
                      min_contrast: float = REFERENCE_MIN_CONTRAST) -> np.ndarray:
    """The states of exact truth as the real set's references would give them.

    A reference exists only where the stripe is visible (docs/real.md): a row is :data:`STRIPE`
    where ``truth`` has a column and the frame's maximum within ``half_width`` px of it stands
    ``min_contrast`` x :func:`reference_noise` above the window's median; :data:`UNSURE` (not
    scored) where ``truth`` has a column the rule does not see (a window under 3 px is not seen);
    :data:`NO_STRIPE` where ``truth`` is NaN. Scoring a render with these states compares it with
    photographs row for row (``stripebench predict``); the render's own truth scores every lit row.

    Parameters
    ----------
    frame : array_like, shape (H, W)
        The tracker's frame (DN).
    truth : array_like, shape (H,), px
        The true columns, NaN where there is no stripe.
    half_width : int
        The window's half width (px), >= 1.
    min_contrast : float
        The least peak over the window's median, in :func:`reference_noise` units, > 0.

    Returns
    -------
    numpy.ndarray of int8, shape (H,)

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> img = rng.normal(50.0, 2.0, (4, 40))
    >>> img[0, 20] += 100.0; img[1, 20] += 5.0           # a bright and a faint stripe row
    >>> referenced_states(img, [20.0, 20.0, 20.0, np.nan]).tolist()
    [1, -1, -1, 0]
    """
    seen = np.zeros(np.shape(truth), bool)
    seen[[r for r, _, _ in _reference_windows(frame, truth, half_width, min_contrast)]] = True
    out = truth_states(truth)
    out[(out == STRIPE) & ~seen] = UNSURE
    return out


def _reference_windows(frame, truth, half_width: int, min_contrast: float) -> list:
    """``[(row, lo, window pixels), ...]``: the rows whose true column the real set's reference rule sees (the window
    of ``half_width`` px about it, at least 3 px, whose maximum stands ``min_contrast`` x :func:`reference_noise`
    over its median), each with its window's first column; the one pass :func:`referenced_states` and
    :func:`referenced_columns` read (arguments checked here)."""
    f = np.asarray(frame, dtype=np.float64)
    t = np.asarray(truth, dtype=np.float64)
    if f.ndim != 2 or t.shape != (f.shape[0],):
        raise ValueError(f"`frame` must be (H, W) and `truth` (H,), got {f.shape} and {t.shape}")
    if isinstance(half_width, bool) or not isinstance(half_width, (int, np.integer)) or half_width < 1:
        raise ValueError(f"`half_width` must be an integer >= 1, got {half_width!r}")
    if not (isinstance(min_contrast, (int, float, np.floating)) and min_contrast > 0):
        raise ValueError(f"`min_contrast` must be a number > 0, got {min_contrast!r}")
    W = f.shape[1]
    level = float(min_contrast) * reference_noise(f)
    seen = []
    for r in np.flatnonzero(np.isfinite(t)):
        c = int(round(float(t[r])))
        lo, hi = max(0, c - half_width), min(W, c + half_width + 1)
        if hi - lo < 3:
            continue
        win = f[r, lo:hi]
        if float(win.max()) - float(np.median(win)) >= level:
            seen.append((int(r), lo, win))
    return seen


def window_centre(win, level: float | None = None) -> float:
    """The real set's reference centre within one row's window (px from the window's first pixel; docs/real.md).

    ``win`` holds the frame's pixels within the reference window of the guide; its maximum's excess over the
    window's median is the *contrast*. The centre is the contrast-weighted centroid of the pixels at least half
    that contrast up within 3 px of the maximum, or, with ``level``, of the run of pixels at least ``level`` x the
    contrast up around the maximum (the middle of a wide saturated plateau). The caller has checked the contrast
    (:data:`REFERENCE_MIN_CONTRAST`); this rule's one home (``scripts/make_real_set.py``, :func:`referenced_columns`).

    Examples
    --------
    >>> window_centre(np.array([0.0, 0.0, 2.0, 4.0, 2.0, 0.0, 0.0]))
    3.0
    >>> window_centre(np.array([0.0, 9.0, 10.0, 10.0, 10.0, 9.0, 0.0]), level=0.95)  # the plateau's middle
    3.0
    """
    win = np.asarray(win, dtype=np.float64)
    base = float(np.median(win))
    j = int(np.argmax(win))
    peak = float(win[j]) - base
    if level is None:  # pixels above half the contrast within 3 px of the maximum
        a, b = max(0, j - 3), min(win.size, j + 4)
        w = win[a:b] - base
        w = np.where(w >= 0.5 * peak, w, 0.0)
    else:  # the run of pixels above `level` x the contrast around the maximum (a wide stripe)
        above = win - base >= level * peak
        a = j
        while a > 0 and above[a - 1]:
            a -= 1
        b = j + 1
        while b < win.size and above[b]:
            b += 1
        w = win[a:b] - base
    return a + float(np.sum(w * np.arange(w.size)) / np.sum(w))


def referenced_columns(frame, truth, *, half_width: int = REFERENCE_HALF_WIDTH,
                       min_contrast: float = REFERENCE_MIN_CONTRAST) -> np.ndarray:
    """Exact truth's columns as the real set's references would give them: in each row that
    :func:`referenced_states` calls :data:`STRIPE`, the reference centre (:func:`window_centre`) of the window of
    ``half_width`` px about the true column; NaN in every other row. A photograph's reference is an intensity
    centre, and a tracker is scored against it; scoring a render against these columns scores it as a photograph
    is, where the stripe's intensity centre and the laser sheet's true centre part (a clipped stripe on a slanted
    surface; docs/predict.md).

    Parameters
    ----------
    frame, truth, half_width, min_contrast
        As :func:`referenced_states`': the tracker's frame (H, W) in DN, the true columns (H,) in px.

    Returns
    -------
    numpy.ndarray, shape (H,), px

    Examples
    --------
    >>> img = np.zeros((3, 20)); img[:, 9:12] = [2.0, 4.0, 2.0]   # a stripe centred on column 10
    >>> img[2] = 0.0                                            # no stripe in the last row
    >>> referenced_columns(img, [10.0, 12.0, 10.0], min_contrast=3.0).tolist()   # the truth 2 px off in row 1
    [10.0, 10.0, nan]
    """
    out = np.full(np.shape(truth), np.nan)
    for r, lo, win in _reference_windows(frame, truth, half_width, min_contrast):
        out[r] = lo + window_centre(win)
    return out


def _states(truth, state) -> np.ndarray:
    if state is None:
        return truth_states(truth)
    s = np.asarray(state)
    if s.shape != np.shape(truth):
        raise ValueError(f"`state` must have the shape of `truth` {np.shape(truth)}, got {s.shape}")
    bad = ~np.isin(s, (NO_STRIPE, STRIPE, UNSURE))
    if bad.any():
        raise ValueError(f"`state` must hold {NO_STRIPE} (no stripe), {STRIPE} (stripe) or {UNSURE} (unknown), "
                         f"got {s[bad].flat[0]!r}")
    if np.any((s == STRIPE) & np.isnan(np.asarray(truth, dtype=np.float64))):
        raise ValueError("`state` says stripe where `truth` has no column")
    return s.astype(np.int8)


def row_outcomes(pred, truth, state=None, tol_px: float = HIT_PX) -> np.ndarray:
    """Each row's outcome code (:data:`HIT` ... :data:`UNKNOWN`).

    Parameters
    ----------
    pred : array_like, float, px
        Reported columns, NaN where the tracker reports nothing; any shape.
    truth : array_like, float, px
        True (or reference) columns, the shape of ``pred``; NaN where there is none.
    state : array_like of int, optional
        The rows' states (:data:`STRIPE`, :data:`NO_STRIPE`, :data:`UNSURE`); default
        :func:`truth_states` (exact truth: NaN means no stripe). A stripe row must have
        a column in ``truth``.
    tol_px : float
        The hit rule's distance (:func:`bench.evaluate.metrics.hits`).

    Returns
    -------
    numpy.ndarray of int8, the shape of ``pred``

    Examples
    --------
    >>> t = [10.0, 10.0, 10.0, np.nan, np.nan, np.nan]
    >>> p = [11.0, 20.0, np.nan, 4.0, np.nan, 3.0]
    >>> [OUTCOMES[c] for c in row_outcomes(p, t, [1, 1, 1, 0, 0, -1])]
    ['hit', 'wrong', 'missed', 'false', 'quiet', 'unknown']
    """
    p = np.asarray(pred, dtype=np.float64)
    t = np.asarray(truth, dtype=np.float64)
    if p.shape != t.shape:
        raise ValueError(f"`pred` {p.shape} and `truth` {t.shape} must have one shape")
    s = _states(t, state)
    reported = ~np.isnan(p)
    out = np.full(p.shape, UNKNOWN, dtype=np.int8)
    stripe = s == STRIPE
    none = s == NO_STRIPE
    hit = hits(p, t, tol_px)
    out[stripe & hit] = HIT
    out[stripe & reported & ~hit] = WRONG
    out[stripe & ~reported] = MISSED
    out[none & reported] = FALSE
    out[none & ~reported] = QUIET
    return out


def outcome_counts(codes, axis=None):
    """How many rows have each outcome: a dict ``n_hit, n_wrong, n_missed, n_false, n_quiet,
    n_unknown`` (ints), or with ``axis`` an int array with the outcomes along a new last axis.

    Examples
    --------
    >>> outcome_counts(np.array([0, 0, 3, 4], np.int8))["n_hit"]
    2
    >>> outcome_counts(np.array([[0, 3], [4, 4]], np.int8), axis=1).tolist()
    [[1, 0, 0, 1, 0, 0], [0, 0, 0, 0, 2, 0]]
    """
    c = np.asarray(codes)
    if axis is None:
        n = np.bincount(c.ravel().astype(np.intp), minlength=len(OUTCOMES))
        return {k: int(v) for k, v in zip(COUNT_KEYS, n)}
    return np.stack([np.count_nonzero(c == k, axis=axis) for k in range(len(OUTCOMES))], axis=-1)


def _div(a, b):
    return float(a / b) if b else float("nan")


def detection_figures(counts) -> dict[str, float]:
    """Precision, recall, F1 and the false-report rate of outcome counts (NaN where undefined).

    Parameters
    ----------
    counts : dict or array_like
        :func:`outcome_counts` (a dict with the ``n_*`` keys, or the 6 counts in
        :data:`OUTCOMES` order).

    Examples
    --------
    >>> f = detection_figures({"n_hit": 8, "n_wrong": 1, "n_missed": 1, "n_false": 2, "n_quiet": 8})
    >>> f["precision"], f["recall"], round(f["f1"], 4), f["false_report_rate"]
    (0.7272727272727273, 0.8, 0.7619, 0.2)
    """
    if isinstance(counts, dict):
        h, w, m, f, q = (int(counts.get(k, 0)) for k in COUNT_KEYS[:5])
    else:
        h, w, m, f, q = (int(v) for v in np.asarray(counts)[:5])
    return {"precision": _div(h, h + w + f), "recall": _div(h, h + w + m),
            "f1": _div(2 * h, 2 * h + 2 * w + f + m), "false_report_rate": _div(f, f + q)}
