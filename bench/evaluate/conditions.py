"""Image conditions: a small vector per frame, measured the same way on renders and photographs.

What makes a stripe easy or hard to track, read from the pixels alone (no truth, no tracker):
:func:`measure` takes the frame a tracker sees (2-D, turned so the stripe runs top to bottom),
optionally its laser-off frame and the colour photograph it came from, and returns
:class:`Conditions`, the measures of :data:`MEASURES`:

================  =========  =================================================================
measure           unit       what
================  =========  =================================================================
``contrast``      noise      the stripe's peak over its row's median, in units of ``noise_dn``
                             (median over the rows with a visible stripe)
``width_px``      px         the stripe's full width at half its contrast (median over those rows)
``saturated``     fraction   of those rows whose peak pixel is clipped (laser channel of ``rgb``)
``background``    fraction   the off-stripe level of the frame (before any laser-off subtraction;
                             of ``rgb``'s mean over R, G, B where given), as a fraction of the
                             clipping level
``texture``       ratio      the off-stripe pixel-to-pixel variation against the sensor noise
                             (1: a flat surface; 5: texture five times the noise)
``rival``         ratio      the brightest off-stripe ridge over the row's median, relative to the
                             stripe's own contrast (median over visible rows; 0: none, 1: as bright)
``visible``       fraction   rows whose peak stands at least ``visible_k`` noise units above
                             the row's median
``jumps``         fraction   adjacent visible rows whose peaks are more than ``jump_px`` px apart
``gaps``          per row    runs of invisible rows between the first and last visible row, per
                             100 rows
``laser_share``   fraction   the laser channel's share of the stripe's excess over its row's
                             median, summed over R, G and B (``rgb`` only; NaN for a grey frame;
                             1: a pure laser colour, 1/3: a white stripe)
``noise_dn``      DN         the sensor noise (reported; not matched: :data:`MATCHED`)
================  =========  =================================================================

**The stripe estimate** is the per-row argmax of the working image (the frame minus its
laser-off frame where one is given, smoothed by ``[1, 2, 1] / 4`` along the row); a row has a
visible stripe when that peak is ``visible_k`` noise units above the row's median.

**The noise** is read where the frame is flattest: the horizontal adjacent-pixel differences of
the frame (not the difference image) are cut into ``tile_px``-square tiles away from the
stripe (``band_px`` px either side of each row's argmax), clipped and black pixels left out;
each tile's RMS difference / sqrt(2) is its noise, and ``noise_dn`` is the 10th percentile of the
tiles (at least ``noise_floor_dn``, the 8-bit quantisation). ``texture`` is the median tile
over ``noise_dn``.

:func:`distance` compares two vectors in normalised condition space (each measure divided by
its ``condition_scales`` entry, after the transforms of :data:`TRANSFORMS`). The tuned values are fields of
:class:`bench.evaluate.predict_settings.PredictSettings` (``settings``).

Pure functions: arrays in, numbers out.

Examples
--------
>>> rng = np.random.default_rng(0)
>>> x = np.arange(200.0)
>>> frame = 20.0 + 100.0 * np.exp(-0.5 * ((x - 90.0) / 2.0) ** 2) + rng.normal(0, 2.0, (120, 200))
>>> c = measure(frame)
>>> round(c.noise_dn, 1), round(c.width_px, 1), c.visible, round(c.background, 2)
(2.0, 4.8, 1.0, 0.08)
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from bench.evaluate.predict_settings import DEFAULT, PredictSettings

__all__ = ["Conditions", "MEASURES", "MATCHED", "TRANSFORMS", "measure", "sensor_noise", "distance", "describe",
           "row_smoothed", "runs_across", "likelier_laser"]

#: Every measure, in the order of :class:`Conditions`.
MEASURES = ("contrast", "width_px", "saturated", "background", "texture", "rival", "visible", "jumps", "gaps",
            "laser_share", "noise_dn")
#: The measures :func:`distance` compares (``noise_dn`` depends on the camera's gain and is
#: carried by ``contrast``).
MATCHED = MEASURES[:-1]
#: How a measure enters the distance before scaling: ``log10`` (ratios spanning decades) or ``lin``.
TRANSFORMS = {"contrast": "log10", "width_px": "log10", "saturated": "lin", "background": "lin",
              "texture": "log10", "rival": "lin", "visible": "lin", "jumps": "lin", "gaps": "lin",
              "laser_share": "lin", "noise_dn": "log10"}


@dataclass(frozen=True)
class Conditions:
    """One frame's image conditions (module docstring: units and definitions)."""

    contrast: float
    width_px: float
    saturated: float
    background: float
    texture: float
    rival: float
    visible: float
    jumps: float
    gaps: float
    laser_share: float
    noise_dn: float

    def as_dict(self) -> dict[str, float]:
        """The measures by name, as floats.

        Examples
        --------
        >>> list(Conditions(*range(11)).as_dict())[:3]
        ['contrast', 'width_px', 'saturated']
        """
        return {k: float(v) for k, v in asdict(self).items()}


def _sat_level(a: np.ndarray, saturation) -> float:
    if saturation is not None:
        return float(saturation)
    if a.dtype.kind in "ui":
        return float(np.iinfo(a.dtype).max)
    return 255.0 if float(np.nanmax(a)) <= 255.0 else float(np.nanmax(a))


def _band_mask(shape, cols, half) -> np.ndarray:
    H, W = shape
    j = np.arange(W)[None, :]
    return np.abs(j - cols[:, None]) <= half


def _noise_tiles(raw: np.ndarray, band: np.ndarray, sat: float, tile_px: int) -> np.ndarray:
    """Each tile's RMS horizontal difference / sqrt(2) (DN), away from the band, clipped and black pixels."""
    d = np.diff(raw, axis=1)
    ok = ~(band[:, 1:] | band[:, :-1])
    ok &= (raw[:, 1:] < sat) & (raw[:, :-1] < sat) & (raw[:, 1:] > 0) & (raw[:, :-1] > 0)
    H, W = d.shape
    t = tile_px
    nh, nw = H // t, W // t
    if nh == 0 or nw == 0:
        return np.zeros(0)
    dd = (d[:nh * t, :nw * t] ** 2).reshape(nh, t, nw, t)
    oo = ok[:nh * t, :nw * t].reshape(nh, t, nw, t)
    n = oo.sum(axis=(1, 3))
    s = np.where(oo, dd, 0.0).sum(axis=(1, 3))
    keep = n >= (t * (t - 1)) // 2  # at least half the tile's differences
    return np.sqrt(s[keep] / n[keep] / 2.0)


def _fwhm(row: np.ndarray, c: int, base: float) -> float:
    """Full width at half height (px) of the peak of ``row`` at ``c`` above ``base``; linear interpolation."""
    half = base + 0.5 * (row[c] - base)
    W = row.size
    left = c
    while left > 0 and row[left - 1] > half:
        left -= 1
    right = c
    while right < W - 1 and row[right + 1] > half:
        right += 1
    lo = float(left)
    if left > 0:
        a, b = row[left - 1], row[left]
        lo = left - (b - half) / (b - a) if b != a else float(left)
    hi = float(right)
    if right < W - 1:
        a, b = row[right], row[right + 1]
        hi = right + (a - half) / (a - b) if a != b else float(right)
    return max(hi - lo, 0.0)


def row_smoothed(work) -> np.ndarray:
    """``work`` (H, W; DN) smoothed ``[1, 2, 1] / 4`` along each row, its first and last columns kept: the frame a
    stripe's peak is read on here and in :mod:`bench.evaluate.transplant`.

    Examples
    --------
    >>> row_smoothed(np.array([[0.0, 4.0, 0.0, 0.0]])).tolist()
    [[0.0, 2.0, 1.0, 0.0]]
    """
    work = np.asarray(work, dtype=np.float64)
    sm = work.copy()
    sm[:, 1:-1] = 0.25 * work[:, :-2] + 0.5 * work[:, 1:-1] + 0.25 * work[:, 2:]
    return sm


def _noise(raw: np.ndarray, cols: np.ndarray, sat: float, s: PredictSettings) -> float:
    """The sensor noise (DN) of ``raw`` (H, W) away from the band around each row's peak ``cols`` (module docstring)."""
    band = _band_mask(raw.shape, cols, s.band_px)
    tiles = _noise_tiles(raw, band, sat, s.tile_px)
    # the 25th percentile of pure-noise tiles lies 0.674 standard errors below the noise: undone
    unbias = 1.0 - 0.674 / math.sqrt(2.0 * s.tile_px * (s.tile_px - 1))
    noise = float(np.percentile(tiles, s.noise_percentile)) / unbias if tiles.size else s.noise_floor_dn
    return max(noise, s.noise_floor_dn)


def sensor_noise(frame, *, settings: PredictSettings = DEFAULT) -> float:
    """``measure(frame).noise_dn`` alone (DN), without the other measures' cost.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> f = 20.0 + rng.normal(0, 2.0, (64, 96)); f[:, 40] += 150.0
    >>> sensor_noise(f) == measure(f).noise_dn
    True
    """
    raw = np.asarray(frame, dtype=np.float64)
    if raw.ndim != 2 or raw.shape[0] < 2 or raw.shape[1] < 3:
        raise ValueError(f"`frame` must be 2-D, at least 2x3, got shape {raw.shape}")
    cols = np.argmax(row_smoothed(raw), axis=1)
    return _noise(raw, cols, _sat_level(np.asarray(frame), None), settings)


def measure(frame, background=None, *, rgb=None, laser: str = "red", saturation=None,
            settings: PredictSettings = DEFAULT) -> Conditions:
    """The image conditions of one frame (module docstring).

    Parameters
    ----------
    frame : array_like, shape (H, W)
        What the tracker sees (DN; integer or float), stripe running top to bottom.
    background : array_like, shape (H, W), optional
        Its laser-off frame (DN): the stripe is then measured on ``frame - background``.
    rgb : array_like, shape (H, W, 3), optional
        The colour photograph ``frame`` was taken from, turned the same way (DN): the
        saturated fraction is read on its laser channel and ``laser_share`` is measured.
    laser : {'red', 'green', 'blue'}
        The laser's colour (with ``rgb``).
    saturation : float, optional
        The clipping level of ``frame`` (DN); default the integer dtype's maximum, else 255
        for a float frame whose values fit in 8 bits (else its maximum).
    settings : PredictSettings
        The tuned values (``visible_k``, ``jump_px``, ``band_px``, ``tile_px``, ``noise_percentile``,
        ``noise_floor_dn``).

    Returns
    -------
    Conditions

    Examples
    --------
    >>> f = np.full((60, 80), 10.0); f[:, 40] = 200.0
    >>> c = measure(f)
    >>> c.visible, c.jumps, c.gaps, round(c.rival, 2), math.isnan(c.laser_share)
    (1.0, 0.0, 0.0, 0.0, True)
    """
    raw = np.asarray(frame, dtype=np.float64)
    if raw.ndim != 2 or raw.shape[0] < 2 or raw.shape[1] < 3:
        raise ValueError(f"`frame` must be 2-D, at least 2x3, got shape {raw.shape}")
    H, W = raw.shape
    sat = _sat_level(np.asarray(frame), saturation)
    work = raw
    if background is not None:
        bg = np.asarray(background, dtype=np.float64)
        if bg.shape != raw.shape:
            raise ValueError(f"`background` must have the shape of `frame` {raw.shape}, got {bg.shape}")
        work = raw - bg
    sm = row_smoothed(work)
    cols = np.argmax(sm, axis=1)
    rows = np.arange(H)
    med = np.median(work, axis=1)
    peak = work[rows, cols]

    s = settings
    noise = _noise(raw, cols, sat, s)
    k = (peak - med) / noise
    vis = k >= s.visible_k
    nv = int(vis.sum())
    use = vis if nv else np.ones(H, bool)

    widths = np.array([_fwhm(work[r], int(cols[r]), med[r]) for r in np.flatnonzero(use)])
    width = float(np.median(widths)) if widths.size else float("nan")
    contrast = float(np.median(k[use]))

    # clipped peaks, on the laser channel of the colour photograph where there is one
    if rgb is not None:
        from bench.evaluate.colour import LASER_INDEX

        col = np.asarray(rgb)
        if col.shape != (H, W, 3):
            raise ValueError(f"`rgb` must have shape {(H, W, 3)}, got {col.shape}")
        lc = col[..., LASER_INDEX[laser]]
        csat = _sat_level(col, None)
        r_idx = np.flatnonzero(use)
        lo = np.clip(cols[r_idx] - 1, 0, W - 1)
        hi = np.clip(cols[r_idx] + 1, 0, W - 1)
        clipped = np.maximum(np.maximum(lc[r_idx, lo], lc[r_idx, hi]), lc[r_idx, cols[r_idx]]) >= csat
    else:
        r_idx = np.flatnonzero(use)
        clipped = raw[r_idx, cols[r_idx]] >= sat
    saturated = float(np.mean(clipped)) if nv else 0.0

    half = max(s.band_px, int(math.ceil(2.0 * width)) if math.isfinite(width) else s.band_px)
    band = _band_mask((H, W), cols, half)
    off = ~band
    if rgb is not None:  # the scene's light, not what the channel rule leaves of it
        level = np.asarray(rgb, dtype=np.float64).mean(axis=2)
        background_level = float(np.median(level[off])) / _sat_level(np.asarray(rgb), None) if off.any() else float("nan")
    else:
        background_level = float(np.median(raw[off])) / sat if off.any() else float("nan")
    tiles = _noise_tiles(raw, band, sat, s.tile_px)
    texture = float(np.median(tiles)) / noise if tiles.size else 1.0
    texture = max(texture, 1.0)

    # rival ridges: the brightest off-band pixel of the 5-row vertical mean, against the stripe
    if nv and off.any():
        v = np.cumsum(np.pad(work, ((2, 2), (0, 0)), mode="edge"), axis=0)
        v = np.vstack([v[4:5], v[5:] - v[:-5]])[:H] / 5.0
        other = np.where(off, v, -np.inf)
        top = other.max(axis=1)
        r = (top - med) / np.maximum(peak - med, noise)
        rival = float(np.clip(np.median(r[vis]), 0.0, None))
    else:
        rival = 0.0

    visible = nv / H
    pairs = vis[1:] & vis[:-1]
    jumps = float(np.mean(np.abs(np.diff(cols))[pairs] > s.jump_px)) if pairs.any() else 0.0
    if nv:
        first, last = np.flatnonzero(vis)[[0, -1]]
        inner = ~vis[first:last + 1]
        starts = np.count_nonzero(inner[1:] & ~inner[:-1]) + int(inner[0])
        gaps = 100.0 * float(starts) / H
    else:
        gaps = 0.0

    laser_share = float("nan")
    if rgb is not None:
        from bench.evaluate.colour import LASER_INDEX

        f = np.asarray(rgb, dtype=np.float64)
        if not (np.array_equal(f[..., 0], f[..., 1]) and np.array_equal(f[..., 0], f[..., 2])):
            r_idx = np.flatnonzero(use)
            exc = f[r_idx, cols[r_idx], :] - np.median(f, axis=1)[r_idx]  # (n, 3)
            exc = np.clip(exc, 0.0, None).sum(axis=0)
            tot = float(exc.sum())
            laser_share = float(exc[LASER_INDEX[laser]] / tot) if tot > 0 else float("nan")
    return Conditions(contrast=contrast, width_px=width, saturated=saturated, background=background_level,
                      texture=texture, rival=rival, visible=visible, jumps=jumps, gaps=gaps,
                      laser_share=laser_share, noise_dn=noise)


def _vector(c, keys, settings: PredictSettings) -> np.ndarray:
    d = c.as_dict() if isinstance(c, Conditions) else dict(c)
    out = []
    for k in keys:
        v = float(d[k])
        if TRANSFORMS[k] == "log10":
            v = math.log10(max(v, 1e-3)) if math.isfinite(v) else float("nan")
        out.append(v / settings.scale(k))
    return np.array(out)


def runs_across(frame, background=None, measured=None, *, settings: PredictSettings = DEFAULT) -> bool:
    """Whether the stripe of ``frame`` seems to run across it (left to right) rather than down it, as a horizontal
    stripe given without ``--rotate`` does: turned a quarter (:func:`measure` there), its peaks jump at most
    1 / ``across_jumps`` as often and it is narrower, or it is seen in ``across_seen`` as many rows or more
    and jumps no more often. ``measured``: the frame's own conditions, when the caller has them. A cue for a note,
    not a measure: the trackers read one column per row whatever it says.

    Examples
    --------
    A stripe slanting gently across the frame, then the same frame turned as ``--rotate 90`` turns it:

    >>> rng = np.random.default_rng(0)
    >>> rows, cols = np.mgrid[0:60, 0:80]
    >>> f = rng.normal(20.0, 2.0, (60, 80)) + 150.0 * np.exp(-0.5 * ((rows - 22.0 - 0.2 * cols) / 1.2) ** 2)
    >>> runs_across(f), runs_across(np.rot90(f))
    (True, False)
    >>> g = rng.normal(20.0, 2.0, (60, 80)); g[30, :] += 150.0  # along one row: seen in none as given
    >>> runs_across(g)
    True
    """
    raw = np.asarray(frame, dtype=np.float64)
    own = measure(raw, background, settings=settings) if measured is None else measured
    turned_bg = None if background is None else np.ascontiguousarray(np.rot90(np.asarray(background)))
    turned = measure(np.ascontiguousarray(np.rot90(raw)), turned_bg, settings=settings)
    if own.jumps > 0 and settings.across_jumps * turned.jumps <= own.jumps and turned.width_px < own.width_px:
        return True
    return bool(turned.jumps <= own.jumps and own.visible < settings.across_seen * turned.visible)


def likelier_laser(rgb, laser: str = "red", *, settings: PredictSettings = DEFAULT) -> str | None:
    """The laser colour whose excess (:func:`bench.evaluate.pixels.select_channel` ``excess``) shows the stripe of a
    colour photograph ``rgb`` (H, W, 3; DN, stripe running down) far more clearly than ``laser``'s, or None: a
    photograph of a green laser given as red (the default) has its stripe hidden in the red excess. Clearer: a
    contrast at least ``other_laser_contrast`` times as high (:func:`measure`), peaks jumping no more often.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> img = rng.normal(40.0, 2.0, (60, 80, 3)); img[:, 30, 1] += 120.0  # a green line
    >>> likelier_laser(img, "red"), likelier_laser(img, "green")
    ('green', None)
    """
    from bench.evaluate.pixels import LASERS, select_channel

    rgb = np.asarray(rgb)
    if rgb.ndim != 3 or rgb.shape[2] != 3:
        raise ValueError(f"`rgb` must be a colour image (H, W, 3), got shape {rgb.shape}")
    if laser not in LASERS:
        raise ValueError(f"`laser` must be one of {', '.join(LASERS)}, got {laser!r}")
    seen = {c: measure(select_channel(rgb, "excess", c), settings=settings) for c in LASERS}
    own = seen[laser]
    best = max((c for c in LASERS if c != laser), key=lambda c: seen[c].contrast)
    other = seen[best]
    if other.contrast >= settings.other_laser_contrast * max(own.contrast, 0.0) and other.jumps <= own.jumps \
            and other.visible > 0:
        return best
    return None


def distance(a, b, keys=MATCHED, *, settings: PredictSettings = DEFAULT) -> float:
    """The root-mean-square difference of two condition vectors in scale units
    (each measure transformed by :data:`TRANSFORMS` and divided by its ``condition_scales`` entry), over the measures finite on both sides (NaN when none is).

    Examples
    --------
    >>> a = {"contrast": 20.0, "visible": 0.9, "laser_share": float("nan")}
    >>> b = {"contrast": 20.0, "visible": 0.7, "laser_share": 0.8}
    >>> round(distance(a, b, keys=("contrast", "visible", "laser_share")), 3)
    1.414
    """
    x, y = _vector(a, keys, settings), _vector(b, keys, settings)
    ok = np.isfinite(x) & np.isfinite(y)
    if not ok.any():
        return float("nan")
    return float(np.sqrt(np.mean((x[ok] - y[ok]) ** 2)))


def describe(c) -> str:
    """One line of a condition vector, for captions and logs.

    Examples
    --------
    >>> describe(Conditions(20.0, 3.0, 0.0, 0.1, 1.5, 0.2, 0.9, 0.01, 0.5, float("nan"), 2.0))
    'contrast 20.0, width 3.0 px, saturated 0.00, background 0.10, texture 1.5, rival 0.20, visible 0.90, jumps 0.01, gaps 0.5, noise 2.0 DN'
    """
    d = c.as_dict() if isinstance(c, Conditions) else dict(c)
    parts = [f"contrast {d['contrast']:.1f}", f"width {d['width_px']:.1f} px", f"saturated {d['saturated']:.2f}",
             f"background {d['background']:.2f}", f"texture {d['texture']:.1f}", f"rival {d['rival']:.2f}",
             f"visible {d['visible']:.2f}", f"jumps {d['jumps']:.2f}", f"gaps {d['gaps']:.1f}"]
    if math.isfinite(d.get("laser_share", float("nan"))):
        parts.append(f"laser share {d['laser_share']:.2f}")
    parts.append(f"noise {d['noise_dn']:.1f} DN")
    return ", ".join(parts)
