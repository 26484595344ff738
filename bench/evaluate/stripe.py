"""A photograph's stripe, found without truth: its guide, each row's extent and centre.

The first step of a transplant (:mod:`bench.evaluate.transplant`). The *working frame* is the tracker's frame, less
its laser-off frame where given, smoothed ``[1, 2, 1] / 4`` along the row (as
:func:`bench.evaluate.conditions.measure` smooths it). Its *guide* is found one of two ways (:data:`ESTIMATES`):

- ``path``: the most continuous bright path through the frame, a dynamic programme over rows whose pixel score is
  the height over the row's median capped at ``path_cap_k`` noise units (a rival brighter than the stripe in a few
  rows does not pull it off), paying ``path_jump`` to move more than 1 px between rows, ties broken by brightness
  (:func:`tie_break`);
- ``argmax``: each row's pixel standing highest over the reference window around it (:func:`window_lift`), a clipped
  one first (:func:`argmax_pick`);

``auto`` (the default) takes ``argmax`` for a thin stripe (at most ``auto_width_px``) or a frame whose path score
caps on many pixels (a noiseless JPEG), else ``path``. Path rows standing ``visible_k`` noise units over the row's
median, with ``support_min`` such rows within ``support_rows``, are *strong*; a row's guide is the median column of
the strong rows within ``guide_rows``. A colour photograph's guide is arbitrated between its laser colour and its
frame (:mod:`bench.evaluate.colourguide`).

Each guided row's stripe (:func:`stripe_extents`) is the maximum within the reference window of the guide,
*visible* where it stands ``visible_k`` noise units over the window's median (the real set's reference rule,
docs/real.md, with the guide read from the frame). Its *extent* is the run of columns around the peak over that
level by ``edge_k`` noise units (on across a dip to a second hump of ``dip_share`` of the peak's height), widened by
``pad_px`` and at most ``max_half_px`` each side; its *centre* is the centroid of the excess over half the peak's
height within ``centre_half_px`` of the peak. Every tuned value is a field of
:class:`bench.evaluate.predict_settings.PredictSettings`. Pure functions: arrays in, arrays out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bench.evaluate import conditions as cond
from bench.evaluate.predict_settings import DEFAULT, PredictSettings

__all__ = ["ESTIMATES", "Extents", "stripe_extents", "estimate_guide", "clipped_pixels", "clipped_at", "channel_noise",
           "argmax_pick", "window_lift", "working_frame", "tie_break", "capped_share", "out_of_range", "span_extents",
           "SHRINKS", "shrink_for", "LEFT_OUT", "why_left_out"]

#: The ways :func:`stripe_extents` finds the stripe's guide (module docstring; the first is the default).
ESTIMATES = ("auto", "path", "argmax")
#: The shrink factors a photograph may be predicted at (``predict --downscale``, :func:`shrink_for`): each N x N
#: block of pixels averaged into one.
SHRINKS = (1, 2, 4, 8)
#: Why a photograph has no prediction at its own size, by :func:`out_of_range`'s code (and ``visible``: its moved
#: stripe seen in too few rows): the one wording of the reason, used by every view (:func:`why_left_out`).
LEFT_OUT = {"width_px": "its stripe is {width:.1f} px wide, wider than the reference window's {window:g} px",
            "visible": "its moved stripe is seen in fewer than {min_rows} rows"}


@dataclass(frozen=True)
class Extents:
    """The stripe of one frame (:func:`stripe_extents`); arrays of shape (H,).

    ``peak``: in a guided row the maximum within ``guide_half_px`` px of its guide, else the row's
    argmax (px); ``visible``: the stripe stands out in that row; ``lo``, ``hi``: the extent's first
    and last column (inclusive; meaningful where visible); ``centre``: the stripe's centre (px, NaN
    in a row without a guide); ``noise_dn``: the frame's sensor noise (DN); ``height``: the peak over
    the window's median (DN, NaN in a row without a guide; None when not measured)."""

    peak: np.ndarray
    visible: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    centre: np.ndarray
    noise_dn: float
    height: np.ndarray | None = None


def stripe_extents(frame, background=None, *, estimate: str = "auto", measured=None, guide=None,
                   settings: PredictSettings = DEFAULT) -> Extents:
    """The stripe of a frame: visible rows, their extents and centres (module docstring).

    Parameters
    ----------
    frame : array_like, shape (H, W)
        What the tracker sees (DN), stripe running top to bottom.
    background : array_like, shape (H, W), optional
        Its laser-off frame (DN).
    estimate : {'auto', 'path', 'argmax'}
        How the guide is found (:data:`ESTIMATES`): ``path``, the DP path (module docstring);
        ``argmax``, each row's pixel standing highest over the median of the reference window around it
        (:func:`window_lift`; of its clipped pixels standing out, the highest, where it has one:
        :func:`argmax_pick`), kept where it stands ``visible_k`` noise units up within ``jump_px`` px of the median
        of such rows within ``guide_rows`` rows and has ``support_min`` such rows within ``support_rows``; or
        ``auto`` (the default), ``argmax`` for a stripe at most ``auto_width_px`` wide or a frame with at least
        ``auto_capped`` of its pixels at the path's cap, else ``path``.
    measured : bench.evaluate.conditions.Conditions, optional
        The frame's conditions (``conditions.measure(frame, background)``, with or without its colour
        photograph: only ``width_px`` and ``noise_dn`` are read), when the caller has them; measured otherwise.
    guide : array_like, shape (H,), optional
        The stripe's columns (px, NaN where a row has none) to follow instead of estimating them
        (``estimate`` is then not used): the colour guide (``bench.run.predict_frames.colour_guide``), or a
        render's truth. Each row's peak is still sought within ``guide_half_px`` of it, as around an estimated guide.
    settings : PredictSettings
        The tuned values (:mod:`bench.evaluate.predict_settings`).

    Returns
    -------
    Extents

    Examples
    --------
    Two stripes, the left one brighter: the estimate takes the left one, a guide the right one.

    >>> img = np.full((40, 60), 10.0)
    >>> img[:, 15] += 120.0
    >>> img[:, 45] += 60.0
    >>> float(np.nanmedian(stripe_extents(img).centre))
    15.0
    >>> float(np.nanmedian(stripe_extents(img, guide=np.full(40, 45.0)).centre))
    45.0
    """
    s = settings
    work, sm, first, measured = _prepared(frame, background, estimate, measured, s)
    noise = measured.noise_dn
    H, W = work.shape
    if guide is not None:
        guide = np.asarray(guide, dtype=np.float64)
        if guide.shape != (H,):
            raise ValueError(f"`guide` must have one column per row of `frame`, shape {(H,)}, got {guide.shape}")
        guide = np.where(np.isfinite(guide), np.clip(guide, 0, W - 1), np.nan)
    else:
        guide = _estimated_guide(sm, np.median(work, axis=1), noise, estimate, measured,
                                 clipped_pixels(frame, noise, settings=s), s)
    peak = first.copy()
    visible = np.zeros(H, bool)
    lo, hi = peak.copy(), peak.copy()
    centre = np.full(H, np.nan)
    heights = np.full(H, np.nan)
    for r in range(H):
        if not np.isfinite(guide[r]):
            continue
        g = int(round(guide[r]))
        w0, w1 = max(g - s.guide_half_px, 0), min(g + s.guide_half_px, W - 1)
        c = w0 + int(np.argmax(sm[r, w0:w1 + 1]))
        row = work[r]
        base = float(np.median(row[w0:w1 + 1]))
        height = row[c] - base
        peak[r], heights[r] = c, height
        v0, v1 = max(c - s.centre_half_px, 0), min(c + s.centre_half_px, W - 1)
        seg = row[v0:v1 + 1] - base
        wts = np.clip(seg - 0.5 * height, 0.0, None)
        centre[r] = float(np.sum(wts * np.arange(v0, v1 + 1)) / np.sum(wts)) if wts.sum() > 0 else float(c)
        if height < s.visible_k * noise:
            continue
        visible[r] = True
        edge, hump = base + s.edge_k * noise, base + s.dip_share * height
        a, b = _reach(row, c, -1, edge, hump, s), _reach(row, c, 1, edge, hump, s)
        lo[r], hi[r] = max(a - s.pad_px, c - s.max_half_px, 0), min(b + s.pad_px, c + s.max_half_px, W - 1)
    return Extents(peak=peak, visible=visible, lo=lo, hi=hi, centre=centre, noise_dn=float(noise), height=heights)


def _reach(row, c: int, step: int, edge: float, hump: float, s: PredictSettings) -> int:
    """The last column of a stripe's run from its peak ``c`` along ``row`` (W,; DN) in direction ``step`` (+1 or -1):
    it goes on while the row stands over ``edge`` (DN), at most ``max_half_px`` from ``c``, and across a dip to a
    pixel standing at least ``hump`` (DN) within ``guide_half_px`` of ``c`` (``dip_share``)."""
    W, k = row.shape[0], c
    while True:
        nxt = k + step
        if not 0 <= nxt < W or abs(nxt - c) > s.max_half_px:
            return k
        if row[nxt] > edge:
            k = nxt
            continue
        ahead = [j for j in range(nxt + step, c + step * (s.guide_half_px + 1), step) if 0 <= j < W and row[j] >= hump]
        if not ahead:
            return k
        k = ahead[0]


def estimate_guide(frame, background=None, *, estimate: str = "auto", measured=None,
                   settings: PredictSettings = DEFAULT) -> np.ndarray:
    """The columns :func:`stripe_extents` follows when it estimates them, shape (H,), px (NaN: no stripe
    found in that row); the arguments are :func:`stripe_extents`'.

    Examples
    --------
    >>> img = np.full((40, 60), 10.0)
    >>> img[:, 15] += 120.0
    >>> float(np.nanmedian(estimate_guide(img)))
    15.0
    """
    work, sm, _, measured = _prepared(frame, background, estimate, measured, settings)
    return _estimated_guide(sm, np.median(work, axis=1), measured.noise_dn, estimate, measured,
                            clipped_pixels(frame, measured.noise_dn, settings=settings), settings)


def _prepared(frame, background, estimate: str, measured, settings: PredictSettings):
    """The checked inputs of :func:`stripe_extents` and :func:`estimate_guide`: ``(work, sm, first, measured)``,
    the frame less its laser-off frame (float64, H x W, DN), that smoothed along each row, each row's argmax
    of it, and the frame's conditions."""
    if estimate not in ESTIMATES:
        raise ValueError(f"`estimate` must be one of {', '.join(ESTIMATES)}, got {estimate!r}")
    work, sm = working_frame(frame, background)
    measured = cond.measure(frame, background, settings=settings) if measured is None else measured
    return work, sm, np.argmax(sm, axis=1), measured


def working_frame(frame, background) -> tuple[np.ndarray, np.ndarray]:
    """``(work, sm)``: the frame less its laser-off frame (float64, H x W, DN; both checked) and that smoothed along
    each row (:func:`bench.evaluate.conditions.row_smoothed`), what the stripe and its rivals are read on."""
    raw = np.asarray(frame, dtype=np.float64)
    if raw.ndim != 2 or raw.shape[0] < 2 or raw.shape[1] < 8:
        raise ValueError(f"`frame` must be 2-D, at least 2x8, got shape {raw.shape}")
    work = raw if background is None else raw - np.asarray(background, dtype=np.float64)
    if work.shape != raw.shape:
        raise ValueError(f"`background` must have the shape of `frame` {raw.shape}, got {np.shape(background)}")
    return work, cond.row_smoothed(work)


def _estimated_guide(sm, med, noise: float, estimate: str, measured, clipped, s: PredictSettings) -> np.ndarray:
    """:func:`stripe_extents`' guide by ``estimate`` (``auto``, ``path`` or ``argmax``), NaN where no stripe:
    ``sm`` the row-smoothed frame (H, W), ``med`` its rows' medians, ``clipped`` the frame's clipped pixels (H, W;
    :func:`clipped_pixels`; None: none), read by the argmax guide (:func:`argmax_pick`); ``s`` the settings."""
    if estimate == "auto":
        narrow = math.isfinite(measured.width_px) and measured.width_px <= s.auto_width_px
        estimate = "argmax" if narrow or capped_share(sm, med, noise, settings=s) >= s.auto_capped else "path"
    rows = np.arange(sm.shape[0])
    window = np.ones(2 * s.support_rows + 1, int)
    if estimate == "path":
        lift = sm - med[:, None]
        path = _path(np.clip(lift / (s.path_cap_k * noise), 0.0, 1.0) + tie_break(lift, settings=s), s.path_jump)
        on = sm[rows, path] - med >= s.visible_k * noise
        return _guide(path, on & (np.convolve(on.astype(int), window, mode="same") >= s.support_min), s.guide_rows)
    lift = window_lift(sm, settings=s)
    first = argmax_pick(lift, clipped, s.visible_k * noise)
    strong = lift[rows, first] >= s.visible_k * noise
    near = np.abs(first - np.nan_to_num(_guide(first, strong, s.guide_rows), nan=-1e9)) <= s.jump_px
    kept = strong & near
    return _guide(first, kept & (np.convolve(kept.astype(int), window, mode="same") >= s.support_min), s.guide_rows)


def clipped_pixels(frame, noise_dn: float, *, settings: PredictSettings = DEFAULT) -> np.ndarray:
    """The pixels of ``frame`` (H, W) at its clipping level (:func:`clipped_at`, with ``noise_dn``), shape (H, W), bool:
    within ``clip_noise_k`` of ``noise_dn`` (DN; at least 1 DN) of the top of an integer frame's range; none in a
    float frame (no known top).

    Examples
    --------
    >>> clipped_pixels(np.array([[10, 254, 255]], np.uint8), 0.5).tolist()
    [[False, True, True]]
    >>> bool(clipped_pixels(np.ones((1, 3)), 0.5).any())
    False
    """
    img = np.asarray(frame)
    return img >= clipped_at(img, float(noise_dn), settings=settings)[0]  # inf on a float frame: none


def clipped_at(image, noise_dn=None, *, settings: PredictSettings = DEFAULT) -> np.ndarray:
    """Each channel's clipping level, shape (C,), DN: at or above it a pixel counts as clipped, within
    ``clip_noise_k`` of the channel's noise units (``noise_dn``, :func:`channel_noise` when None; at least 1 DN) of
    the top of an integer image's range; +inf on a float image (no known top)."""
    img = np.asarray(image)
    C = 1 if img.ndim == 2 else img.shape[2]
    if not np.issubdtype(img.dtype, np.integer):
        return np.full(C, np.inf)
    noise = channel_noise(img, settings=settings) if noise_dn is None else np.broadcast_to(np.asarray(noise_dn, np.float64), (C,))
    return float(np.iinfo(img.dtype).max) - np.maximum(settings.clip_noise_k * noise, 1.0)


def channel_noise(original, *, settings: PredictSettings = DEFAULT) -> np.ndarray:
    """The sensor noise of each channel of a photograph (DN, shape (C,); one value for a grey one), as
    :func:`bench.evaluate.conditions.measure` reads it: the clean plate's noise (:func:`bench.evaluate.transplant.transplant`)."""
    f = np.asarray(original, dtype=np.float64)
    planes = f[..., None] if f.ndim == 2 else f
    return np.array([cond.sensor_noise(planes[..., k], settings=settings) for k in range(planes.shape[-1])])


def argmax_pick(lift, clipped, level: float) -> np.ndarray:
    """Each row's pick for the argmax guide, shape (H,), px: of the clipped pixels standing at least ``level`` (DN)
    over the window around them (``lift``, :func:`window_lift`; ``clipped``, :func:`clipped_pixels`, or None), the
    one standing highest; in a row without one, the pixel standing highest. A stripe's clipped core is the brightest it gets; a glow's shoulder beside a dip
    can stand higher over its window than the core over a window the core and its glow fill.

    Examples
    --------
    Part of a row of a photograph of a hand (``bb_hand``, row 201, red channel): a glow of 200-240 DN, a dip to 184
    and a core clipped at 253-255. The glow's shoulder stands highest over its window, the core is the pick.

    >>> row = np.array([[199, 208, 226, 228, 231, 233, 234, 236, 237, 223, 197, 184, 194, 253, 255, 255, 252, 249,
    ...                  252, 250, 248, 241, 230, 224, 219, 207, 192, 187, 180]], float)
    >>> lift = window_lift(row)
    >>> int(np.argmax(lift[0])), int(argmax_pick(lift, row >= 253, 4.0)[0])
    (6, 14)
    """
    lift = np.asarray(lift, dtype=np.float64)
    first = np.argmax(lift, axis=1)
    if clipped is None:
        return first
    clipped = np.asarray(clipped, bool)
    if clipped.shape != lift.shape:
        raise ValueError(f"`clipped` must have the shape of `lift` {lift.shape}, got {clipped.shape}")
    standing = np.where(clipped & (lift >= level), lift, -np.inf)
    pick = np.argmax(standing, axis=1)
    return np.where(np.isfinite(standing[np.arange(lift.shape[0]), pick]), pick, first)


def window_lift(smoothed, *, settings: PredictSettings = DEFAULT) -> np.ndarray:
    """Each pixel's height over the median of the reference window around it, shape (H, W), DN: ``smoothed`` (H, W;
    DN) less its running median along the row over ``2 * guide_half_px + 1`` px (edges: the nearest pixel repeated).
    What the argmax guide reads: a reference
    sees a stripe where its peak stands over the median of the window around it, so a glow or a lit patch wider than
    the window stands low however bright it is, and a thin stripe beside it or inside it stands high.

    Examples
    --------
    A stripe 1 px wide of 40 DN beside a glow 30 px wide of 100 DN: the row's maximum is the glow, the highest over
    the window is the stripe.

    >>> row = np.zeros((1, 80)); row[0, 10:40] = 100.0; row[0, 60] = 40.0
    >>> int(np.argmax(row[0])), int(np.argmax(window_lift(row)[0])), float(window_lift(row)[0, 60])
    (10, 60, 40.0)
    """
    from scipy.ndimage import median_filter

    sm = np.asarray(smoothed, dtype=np.float64)
    return sm - median_filter(sm, size=(1, 2 * settings.guide_half_px + 1), mode="nearest")


def tie_break(lift, *, settings: PredictSettings = DEFAULT) -> np.ndarray:
    """The path's tie-breaker (``path_tie``), shape (H, W): ``lift`` (H, W; DN over each row's median), clipped at
    0, smoothed along each row by a Gaussian of ``tie_sigma_px``, divided by its largest value and times
    ``path_tie / H``; zeros where nothing stands over its row.

    Examples
    --------
    A clipped plateau five columns wide: its middle column gets the most.

    >>> lift = np.zeros((2, 12)); lift[:, 3:8] = 200.0
    >>> t = tie_break(lift)
    >>> int(np.argmax(t[0])), round(float(t.sum(axis=0).max()), 3)
    (5, 0.1)
    """
    from scipy.ndimage import gaussian_filter1d

    lift = np.clip(np.asarray(lift, dtype=np.float64), 0.0, None)
    mean = gaussian_filter1d(lift, settings.tie_sigma_px, axis=1, mode="nearest")
    top = float(mean.max()) if mean.size else 0.0
    return mean * (settings.path_tie / (mean.shape[0] * top)) if top > 0 else np.zeros_like(mean)


def capped_share(smoothed, row_median, noise_dn: float, *, settings: PredictSettings = DEFAULT) -> float:
    """The share of pixels whose path score is capped: ``smoothed`` (H, W; DN) standing at least
    ``path_cap_k`` x ``noise_dn`` over ``row_median`` (H,; DN).

    Examples
    --------
    >>> f = np.zeros((4, 10)); f[:, 3] = 50.0; f[:, 6:] = 8.0
    >>> capped_share(f, np.median(f, axis=1), 1.0), capped_share(f, np.median(f, axis=1), 0.3)
    (0.1, 0.5)
    """
    lift = np.asarray(smoothed, dtype=np.float64) - np.asarray(row_median, dtype=np.float64)[:, None]
    return float(np.mean(lift >= settings.path_cap_k * float(noise_dn)))


def _path(score, jump_cost: float) -> np.ndarray:
    """The column per row of the path through ``score`` (H, W) with the largest sum, moving at most
    1 px between rows for free and anywhere for ``jump_cost`` (free start and end)."""
    H, W = score.shape
    acc = score[0].copy()
    back = np.zeros((H, W), np.int64)
    cols = np.arange(W)
    for r in range(1, H):
        left = np.r_[-np.inf, acc[:-1]]
        right = np.r_[acc[1:], -np.inf]
        stack = np.vstack([left, acc, right])
        k = np.argmax(stack, axis=0)
        best = stack[k, cols]
        src = cols + k - 1
        j = int(np.argmax(acc))
        jump = acc[j] - jump_cost
        use_jump = jump > best
        back[r] = np.where(use_jump, j, src)
        acc = score[r] + np.where(use_jump, jump, best)
    out = np.empty(H, np.int64)
    out[-1] = int(np.argmax(acc))
    for r in range(H - 1, 0, -1):
        out[r - 1] = back[r, out[r]]
    return out


def _guide(peak, strong, guide_rows: int) -> np.ndarray:
    """Each row's guide column: the median of the strong rows' path columns within ``guide_rows``
    rows either side (NaN where there is none)."""
    H = peak.shape[0]
    out = np.full(H, np.nan)
    idx = np.flatnonzero(strong)
    if idx.size == 0:
        return out
    vals = np.asarray(peak, dtype=np.float64)[idx]
    lo = np.searchsorted(idx, np.arange(H) - guide_rows)
    hi = np.searchsorted(idx, np.arange(H) + guide_rows + 1)
    for r in np.flatnonzero(hi > lo):  # np.median's value, without its overhead on a few numbers
        v = np.sort(vals[lo[r]:hi[r]])
        n = v.size
        out[r] = v[n // 2] if n % 2 else (v[n // 2 - 1] + v[n // 2]) / 2.0
    return out


def out_of_range(measured, *, settings: PredictSettings = DEFAULT) -> tuple:
    """The measures that put a frame out of the transplant's range: ``("width_px",)`` for a stripe wider
    than ``max_width_px`` (``measured``: its :func:`bench.evaluate.conditions.measure`), else ``()``.

    Examples
    --------
    >>> thin = np.full((20, 60), 10.0); thin[:, 30] = 200.0
    >>> wide = np.full((20, 60), 10.0); wide[:, 20:40] = 200.0
    >>> out_of_range(cond.measure(thin)), out_of_range(cond.measure(wide))
    ((), ('width_px',))
    """
    w = measured.width_px
    return ("width_px",) if math.isfinite(w) and w > settings.max_width_px else ()


def span_extents(ext: Extents, W: int) -> tuple[np.ndarray, np.ndarray]:
    """The extents of every row between the first and the last visible one (-1 elsewhere): a
    visible row's own; an invisible row's centred on the straight line between its nearest visible
    rows' peaks, as wide as the median visible extent (the stripe's faint stretches move with it)."""
    H = ext.peak.shape[0]
    lo, hi = np.full(H, -1), np.full(H, -1)
    vis = np.flatnonzero(ext.visible)
    if vis.size == 0:
        return lo, hi
    lo[vis], hi[vis] = ext.lo[vis], ext.hi[vis]
    left = int(np.median(ext.peak[vis] - ext.lo[vis]))
    right = int(np.median(ext.hi[vis] - ext.peak[vis]))
    inner = np.arange(vis[0], vis[-1] + 1)
    faint = np.union1d(inner[~ext.visible[inner]], np.flatnonzero(np.isfinite(ext.centre) & ~ext.visible))
    if faint.size:
        guided = np.isfinite(ext.centre[faint])
        c = np.where(guided, ext.peak[faint],
                     np.rint(np.interp(faint, vis, ext.peak[vis].astype(float)))).astype(int)
        lo[faint], hi[faint] = np.clip(c - left, 0, W - 1), np.clip(c + right, 0, W - 1)
    return lo, hi


def shrink_for(width_px: float, downscale: int = 1, *, settings: PredictSettings = DEFAULT) -> int | None:
    """The least of :data:`SHRINKS` above ``downscale`` that brings a stripe ``width_px`` wide (FWHM, px, measured on
    a photograph already shrunk by ``downscale``) within ``max_width_px``, or None when none does.

    Examples
    --------
    >>> shrink_for(18.4), shrink_for(40.0), shrink_for(18.4, 2), shrink_for(400.0)
    (2, 4, 4, None)
    """
    return next((n for n in SHRINKS if n > downscale and width_px * downscale / n <= settings.max_width_px), None)


def why_left_out(codes, *, width_px: float = float("nan"), settings: PredictSettings = DEFAULT) -> str:
    """The reason a photograph has no prediction at its own size, in words (:data:`LEFT_OUT`; ``codes``: the
    measures that put it out of range, e.g. ``("width_px",)``, with its stripe's ``width_px`` where that is one).

    Examples
    --------
    >>> why_left_out(("width_px",), width_px=18.66)
    "its stripe is 18.7 px wide, wider than the reference window's 13 px"
    >>> why_left_out(["visible"])
    'its moved stripe is seen in fewer than 10 rows'
    """
    return "; ".join(LEFT_OUT[c].format(width=width_px, window=settings.max_width_px, min_rows=settings.min_rows)
                     for c in codes)
