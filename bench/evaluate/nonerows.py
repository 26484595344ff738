"""The check every ``none`` row of a real set's reference must pass: no sign of the stripe in the row.

A row marked ``none`` says "surely no laser stripe here": a tracker's report there is scored as a false one.
A row someone left unlabelled is often a stripe too faint, too far or too odd to trace (a continuation on a
far wall, a reflection in a glossy table), and scoring it as stripe-less turns a right report into a false
one. :func:`doubtful_rows` therefore looks for three signs of the stripe in each ``none`` row, on the
tracker's frame and, where the photograph has colour, on the laser colour's excess:

``continuation``
    a faint ridge near the stripe's own path carried on from the nearest stripe rows (a mean over a few
    rows, so that a stripe too faint to see in one row shows);
``reflection``
    a ridge anywhere in the row as narrow as the stripe and a fair share of its height;
``laser_colour``
    on a colour photograph, a ridge of the laser's colour as narrow as the stripe.

A *ridge* is a pixel standing over the row's running median (a step edge and a wide glow do not: the median
follows them) whose half-height run is at most a few stripe widths wide. Where a laser-off frame of the
same view exists the signs are looked for in the laser-on minus laser-off difference. The rows it flags are written
``unknown`` by ``scripts/make_real_set.py refs``; the check overlay (``docs/real/NAME_ref.png``) is the look.
The settings are :class:`NoneRowCheck`.

Pure functions: arrays in, masks out.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bench.evaluate.outcomes import NO_STRIPE, STRIPE

__all__ = ["NoneRowCheck", "REASONS", "stripe_profile", "ridge_rows", "path_guess", "doubtful_rows"]

#: The signs :func:`doubtful_rows` looks for, in the order it reports them.
REASONS = ("continuation", "reflection", "laser_colour")


@dataclass(frozen=True)
class NoneRowCheck:
    """The settings of :func:`doubtful_rows`.

    Attributes
    ----------
    background_px : int
        Width of the running median each row's ridges stand over (px, odd); at least 6 stripe widths are used.
    width_factor : float
        A ridge is at most this many times the stripe's median width at half height (a glow, a window or a lit
        wall is wider; a narrow highlight as narrow as the stripe is what a reflection looks like).
    k_noise : float
        A ridge stands at least this many noise units up (the noise: the spread of the frame's ridge contrast).
    reflection_share : float
        A reflection stands at least this share of the stripe's median height (fainter texture is not one).
    colour_share : float
        A laser-coloured ridge stands at least this share of the stripe's median height in the colour excess.
    faint_k : float
        A continuation stands this many noise units of the mean up in the mean of the ``none`` rows among
        ``faint_rows`` rows (it may be far fainter than the stripe: there is no share of the stripe's height for it).
    faint_rows : int
        Rows averaged for the continuation (odd).
    reach_px : float
        Half width of the search about the carried-on path at the nearest stripe row (px) ...
    reach_per_row : float
        ... widened by this much per row of distance from it (the path's slope is uncertain) ...
    max_reach_px : float
        ... up to this (px).
    fit_rows : int
        Stripe rows the path is carried on from (a line fitted through the nearest ones).
    """

    background_px: int = 31
    width_factor: float = 3.0
    k_noise: float = 6.0
    reflection_share: float = 0.2
    colour_share: float = 0.15
    faint_k: float = 5.0
    faint_rows: int = 9
    reach_px: float = 6.0
    reach_per_row: float = 0.1
    max_reach_px: float = 40.0
    fit_rows: int = 10

    def __post_init__(self):
        for name in ("width_factor", "k_noise", "reflection_share", "colour_share", "faint_k", "reach_px",
                     "max_reach_px"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and np.isfinite(v) and v > 0):
                raise ValueError(f"NoneRowCheck.{name} must be a finite number > 0, got {v!r}")
        for name in ("background_px", "faint_rows"):
            v = getattr(self, name)
            if not (isinstance(v, int) and v >= 1 and v % 2 == 1):
                raise ValueError(f"NoneRowCheck.{name} must be an odd integer >= 1, got {v!r}")
        if not (isinstance(self.fit_rows, int) and self.fit_rows >= 2):
            raise ValueError(f"NoneRowCheck.fit_rows must be an integer >= 2, got {self.fit_rows!r}")
        if not (isinstance(self.reach_per_row, (int, float)) and self.reach_per_row >= 0):
            raise ValueError(f"NoneRowCheck.reach_per_row must be a number >= 0, got {self.reach_per_row!r}")


def _contrast(frame, background_px: int) -> tuple[np.ndarray, float]:
    """Each pixel over its row's running median, and the robust spread of that contrast (at least 0.5)."""
    from scipy.ndimage import median_filter

    f = np.asarray(frame, dtype=np.float64)
    d = f - median_filter(f, size=(1, background_px), mode="nearest")
    s = d[::2, ::2].ravel()
    noise = 1.4826 * float(np.median(np.abs(s - np.median(s))))
    return d, max(noise, 0.5)


def _half_run(row, c: int) -> tuple[int, int]:
    """The run of pixels at least half ``row[c]`` about ``c``: (first, last), inclusive."""
    half = 0.5 * row[c]
    a = c
    while a > 0 and row[a - 1] >= half:
        a -= 1
    b = c
    while b < row.size - 1 and row[b + 1] >= half:
        b += 1
    return a, b


def stripe_profile(frame, cols, *, background_px: int = 31) -> tuple[float, float]:
    """The stripe's median height over the running median and its median width at half height.

    Parameters
    ----------
    frame : array_like, shape (H, W)
        DN.
    cols : array_like, shape (H,)
        The reference columns (px), NaN where there is none.

    Returns
    -------
    height : float
        DN (NaN where there is no stripe row).
    width_px : float
        px, at least 1 (NaN where there is no stripe row).

    Examples
    --------
    >>> img = np.zeros((4, 60)); img[:, 29:32] = [5.0, 10.0, 5.0]
    >>> stripe_profile(img, [30.0, 30.0, 30.0, np.nan])
    (10.0, 3.0)
    """
    d, _ = _contrast(frame, background_px)
    heights, widths = [], []
    W = d.shape[1]
    for r in np.flatnonzero(np.isfinite(np.asarray(cols, dtype=np.float64))):
        c0 = int(round(float(cols[r])))
        lo, hi = max(0, c0 - 2), min(W, c0 + 3)
        if hi <= lo:
            continue
        c = lo + int(np.argmax(d[r, lo:hi]))
        if d[r, c] <= 0:
            continue
        a, b = _half_run(d[r], c)
        heights.append(float(d[r, c]))
        widths.append(float(b - a + 1))
    if not heights:
        return float("nan"), float("nan")
    return float(np.median(heights)), max(float(np.median(widths)), 1.0)


def ridge_rows(contrast, min_height: float, max_width_px: float, *, rows=None, centre=None, reach=None) -> np.ndarray:
    """Which rows hold a ridge: a local maximum of ``contrast`` at least ``min_height`` up whose half-height run
    is at most ``max_width_px`` wide and ends inside the row on both sides.

    Parameters
    ----------
    contrast : ndarray, shape (H, W)
        The frame over its rows' running median (DN).
    min_height : float
    max_width_px : float
    rows : ndarray of bool, shape (H,), optional
        Only these rows are looked at (the others are False).
    centre, reach : ndarray, shape (H,), optional
        Only ridges within ``reach`` px of ``centre`` count (NaN centre: the row is not looked at).

    Returns
    -------
    ndarray of bool, shape (H,)

    Examples
    --------
    >>> d = np.zeros((3, 20)); d[0, 5] = 8.0; d[1, 3:15] = 8.0; d[2, 10] = 2.0
    >>> ridge_rows(d, 4.0, 3.0).tolist()          # a ridge; a plateau too wide; one too low
    [True, False, False]
    """
    d = np.asarray(contrast, dtype=np.float64)
    H, W = d.shape
    out = np.zeros(H, dtype=bool)
    look = np.ones(H, dtype=bool) if rows is None else np.asarray(rows, dtype=bool)
    left = np.concatenate([np.full((H, 1), -np.inf), d[:, :-1]], axis=1)
    right = np.concatenate([d[:, 1:], np.full((H, 1), -np.inf)], axis=1)
    cand = (d >= min_height) & (d >= left) & (d >= right)
    if centre is not None:
        x = np.arange(W)[None, :]
        ctr = np.asarray(centre, dtype=np.float64)[:, None]
        with np.errstate(invalid="ignore"):
            cand &= np.abs(x - ctr) <= np.asarray(reach, dtype=np.float64)[:, None]
    for r in np.flatnonzero(look & cand.any(axis=1)):
        for c in np.flatnonzero(cand[r]):
            a, b = _half_run(d[r], int(c))
            if a > 0 and b < W - 1 and b - a + 1 <= max_width_px:
                out[r] = True
                break
    return out


def path_guess(cols, settings: NoneRowCheck = NoneRowCheck()) -> tuple[np.ndarray, np.ndarray]:
    """The stripe's path carried into the rows without a column, and how far about it to look.

    Between two stripe rows the path is the line joining them; beyond the last one on a side, a line fitted
    through the ``fit_rows`` nearest stripe rows. The reach grows with the distance to the nearest stripe row.

    Returns
    -------
    centre : ndarray, shape (H,)
        px; NaN everywhere when there is no stripe row.
    reach : ndarray, shape (H,)
        px.

    Examples
    --------
    >>> c, r = path_guess([np.nan, 10.0, 11.0, np.nan, 13.0, np.nan], NoneRowCheck(fit_rows=2))
    >>> c.tolist(), r.tolist()
    ([9.0, 10.0, 11.0, 12.0, 13.0, 14.0], [6.1, 6.0, 6.0, 6.1, 6.0, 6.1])
    """
    c = np.asarray(cols, dtype=np.float64)
    H = c.size
    s = settings
    rows = np.flatnonzero(np.isfinite(c))
    centre = np.full(H, np.nan)
    reach = np.full(H, s.reach_px)
    if rows.size == 0:
        return centre, reach
    r_all = np.arange(H)
    centre[rows] = c[rows]
    inside = (r_all > rows[0]) & (r_all < rows[-1]) & ~np.isfinite(c)
    centre[inside] = np.interp(r_all[inside], rows, c[rows])

    def fit(sel):
        if sel.size == 1:
            return 0.0, float(c[sel[0]])
        k, b = np.polyfit(sel.astype(float), c[sel], 1)
        return float(k), float(b)

    for side, sel in (("above", rows[:s.fit_rows]), ("below", rows[-s.fit_rows:])):
        k, b = fit(sel)
        out = r_all < rows[0] if side == "above" else r_all > rows[-1]
        centre[out] = k * r_all[out] + b
    dist = np.abs(r_all[:, None] - rows[None, :]).min(axis=1)
    reach = np.minimum(s.reach_px + s.reach_per_row * dist, s.max_reach_px)
    return centre, reach


def doubtful_rows(frame, cols, states, *, colour=None, background=None, colour_background=None,
                  settings: NoneRowCheck = NoneRowCheck()) -> dict:
    """The ``none`` rows that show a sign of the stripe, per sign (module docstring).

    Parameters
    ----------
    frame : array_like, shape (H, W)
        The tracker's frame the references were found on (DN).
    cols : array_like, shape (H,)
        The reference columns (px), NaN where there is none.
    states : array_like of int, shape (H,)
        The rows' states (:data:`bench.evaluate.outcomes.STATES`); only ``none`` rows are looked at.
    colour : array_like, shape (H, W), optional
        The laser colour's excess of a colour photograph in the frame's orientation
        (:func:`bench.evaluate.pixels.select_channel` with ``'excess'``); None on a grey photograph.
    background, colour_background : array_like, shape (H, W), optional
        The laser-off frame of the same view, as ``frame`` and ``colour`` are read: where given, the signs are looked
        for in the laser-on minus laser-off difference (light that is there without the laser is not the laser's).
    settings : NoneRowCheck

    Returns
    -------
    dict
        reason (:data:`REASONS`) -> ndarray of bool (H,): the ``none`` rows flagged for it (all False for
        ``laser_colour`` without ``colour``). A photograph with no stripe row is judged by noise alone.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> img = rng.normal(20.0, 1.0, (60, 80)); img[:30, 40] += 40.0            # the stripe in rows 0-29
    >>> cols = np.r_[np.full(30, 40.0), np.full(30, np.nan)]
    >>> states = np.r_[np.full(30, 1), np.full(30, 0)]
    >>> int(doubtful_rows(img, cols, states)["continuation"].sum())          # rows 30-59 are clean
    0
    >>> img[30:, 41] += 3.0                                                   # a faint continuation
    >>> int(doubtful_rows(img, cols, states)["continuation"].sum()) > 20
    True
    """
    s = settings
    f = np.asarray(frame, dtype=np.float64)
    c = np.asarray(cols, dtype=np.float64)
    st = np.asarray(states)
    if f.ndim != 2 or c.shape != (f.shape[0],) or st.shape != c.shape:
        raise ValueError(f"`frame` must be (H, W), `cols` and `states` (H,), got {f.shape}, {c.shape}, {st.shape}")
    for name, a in (("colour", colour), ("background", background), ("colour_background", colour_background)):
        if a is not None and np.shape(a) != f.shape:
            raise ValueError(f"`{name}` must have the frame's shape {f.shape}, got {np.shape(a)}")
    if background is not None:
        f = f - np.asarray(background, dtype=np.float64)
    if colour is not None and colour_background is not None:
        colour = np.asarray(colour, dtype=np.float64) - np.asarray(colour_background, dtype=np.float64)
    none = st == NO_STRIPE
    H = f.shape[0]
    out = {k: np.zeros(H, dtype=bool) for k in REASONS}
    if not none.any():
        return out
    stripe = np.where(st == STRIPE, c, np.nan)
    height, width = stripe_profile(f, stripe, background_px=s.background_px)
    has_stripe = np.isfinite(height)
    width = width if has_stripe else 3.0
    bg = max(s.background_px, int(6 * width) | 1)
    d, noise = _contrast(f, bg)
    max_w = s.width_factor * width
    refl = s.k_noise * noise if not has_stripe else max(s.k_noise * noise, s.reflection_share * height)
    out["reflection"] = ridge_rows(d, refl, max_w, rows=none)
    if has_stripe:
        from scipy.ndimage import uniform_filter1d

        centre, reach = path_guess(stripe, s)
        # the mean over the `none` rows of each window (a stripe row beside one must not leak into it), in units of
        # its own noise (fewer rows near a stripe row: a noisier mean)
        n = uniform_filter1d(none.astype(np.float64), size=s.faint_rows, mode="constant") * s.faint_rows
        total = uniform_filter1d(np.where(none[:, None], d, 0.0), size=s.faint_rows, axis=0, mode="constant")
        z = total * s.faint_rows / np.sqrt(np.maximum(n, 1.0))[:, None] / noise
        out["continuation"] = ridge_rows(z, s.faint_k, max_w, rows=none, centre=centre, reach=reach)
    if colour is not None:
        e = np.asarray(colour, dtype=np.float64)
        de, noise_e = _contrast(e, bg)
        h_e, _ = stripe_profile(e, stripe, background_px=bg)
        level = s.k_noise * noise_e if not np.isfinite(h_e) else max(s.k_noise * noise_e, s.colour_share * h_e)
        out["laser_colour"] = ridge_rows(de, level, max_w, rows=none)
    return out
