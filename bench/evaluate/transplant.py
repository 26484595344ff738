"""A photograph's own stripe, moved to a known place: frames with truth made from one photograph.

A rig's photographs carry what renders may lack (their clutter, rivals, printed edges, the camera's
own processing) but no truth. A *transplant* keeps all of the photograph except the stripe's place:

1. **The stripe** (:func:`stripe_extents`): the working frame (the tracker's frame, minus its
   laser-off frame where given, smoothed ``[1, 2, 1] / 4`` along the row), as
   :func:`bench.evaluate.conditions.measure` smooths it, and the most continuous bright *path*
   through it (:data:`PATH_CAP`, :data:`PATH_JUMP`: a dynamic programme over rows, heights capped at
   ``PATH_CAP`` noise units, so that a rival
   brighter than the stripe in a few rows does not pull the estimate off it; ties broken by brightness,
   :func:`tie_break`). Path rows standing
   :data:`bench.evaluate.conditions.VISIBLE_K` noise units over the row's median, with
   :data:`SUPPORT_MIN` such rows within :data:`SUPPORT_ROWS`, are *strong*. A row's *guide* is the
   median path column of the strong rows within :data:`GUIDE_ROWS` rows; its stripe
   is the maximum within :data:`GUIDE_HALF_PX` px of the guide, *visible* where it stands
   ``VISIBLE_K`` noise units over the window's median (the real set's reference rule, with the
   guide read from the frame instead of drawn by hand, docs/real.md; a stripe much wider than the
   window is not visible by this rule, as it is not to the references'). Its *extent* is the run of
   columns around the peak above that level by :data:`EDGE_K` noise units (and on across a dip to a
   second hump of at least :data:`DIP_SHARE` of the peak's height within the window), widened by
   :data:`PAD_PX` px each side and at most :data:`MAX_HALF_PX` px each side of the peak; its
   *centre* is the centroid of the pixels' excess over half the peak's contrast within 3 px of the
   peak (biased by under 0.1 px on a sampled Gaussian).
2. **The clean plate** (:func:`transplant`): in each row from the first visible one to the last
   (an invisible row between them: an extent as wide as the median one, on the line between its
   nearest visible rows' peaks, so that the stripe's faint stretches move with it), every channel of the photograph
   is replaced over the extent by the straight line between the medians of the
   :data:`SIDE_PX` pixels either side of it, plus Gaussian noise of that channel's sensor noise;
   with a laser-off photograph, by its pixels.
3. **The stripe, moved:** the photograph minus that line over the extent (the stripe's own
   profile, clipping, colour and noise; with a laser-off photograph, minus its pixels) is added to
   the photograph ``shift_px`` columns away, and the result is clipped to the photograph's range (a
   pixel of the stripe clipped, or within :data:`CLIP_NOISE_K` of its channel's noise units of the top,
   stays clipped). The two moved frames' shifts (:func:`shifts_for`) keep the moved stripe off *rivals*, pixels as
   high over their row as the stripe (:func:`rival_mask`). A row whose moved extent would leave the frame or
   meet its old extent is cleaned, not moved. The truth is the centre plus ``shift_px`` in the
   moved rows that have a guide; NaN in the others. :func:`row_states` then reads the moved stripe
   as the real set's references would be read, leaving unscored the rows where the stripe stands far
   lower than its typical height (:func:`dim_rows`), as a reference leaves unclear rows out, and scoring a
   clipped core in a glow near the top (:func:`glow_rows`), as a reference scores it.
4. **The photograph in place:** the photograph itself is a frame too, its truth the estimated centre in the rows
   from the first visible one to the last (:func:`in_place_truth`), read by :func:`row_states` as a moved
   frame's: its glow, rivals and surroundings stay where they are, as no moved frame carries them.

The moved stripe keeps the photograph's stripe (width, contrast, saturation, colour, speckle) and
its surroundings keep everything else; what changes is where the stripe crosses them. Pure
functions: arrays in, arrays out.

Examples
--------
>>> rng = np.random.default_rng(0)
>>> x = np.arange(120.0)
>>> photo = np.clip(30 + 150 * np.exp(-0.5 * ((x - 50.3) / 1.5) ** 2) + rng.normal(0, 2, (40, 120)), 0, 255)
>>> photo = np.rint(photo).astype(np.uint8)
>>> ext = stripe_extents(photo)
>>> int(ext.visible.sum()), bool(abs(np.nanmedian(ext.centre) - 50.3) < 0.2)
(40, True)
>>> moved, truth = transplant(photo, ext, 30, seed=1)
>>> bool(np.allclose(truth, ext.centre + 30)), int(np.argmax(moved[0])), int(moved[:, 45:56].max()) < 60
(True, 80, True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bench.evaluate import conditions as cond
from bench.evaluate.outcomes import REFERENCE_HALF_WIDTH

__all__ = ["Extents", "stripe_extents", "estimate_guide", "laser_evidence", "arbitrate", "capped_share", "cut_ends",
           "out_of_range", "shift_for", "channel_noise", "transplant", "row_states", "MIN_ROWS", "EDGE_K", "PAD_PX",
           "MAX_HALF_PX", "SIDE_PX", "GUIDE_ROWS", "GUIDE_HALF_PX", "PATH_CAP", "PATH_JUMP", "ESTIMATES",
           "AUTO_WIDTH_PX", "AUTO_CAPPED", "MAX_WIDTH_PX", "END_CUT", "END_CUT_MIN_ROWS", "SUPPORT_ROWS",
           "SUPPORT_MIN", "ARBITER_HALF_PX", "evidence_near", "hue_hidden", "CLIP_NOISE_K", "RIVAL_SEARCH_PX",
           "RIVAL_SHARE", "rival_mask", "shifts_for", "EVIDENCE_SHARE", "DIM_SHARE", "dim_rows", "clipped_peaks",
           "unclear_rows", "tie_break", "glow_rows", "GLOW_SHARE", "GLOW_NEAR_PX", "GLOW_FAR_PX", "clipped_pixels",
           "argmax_pick", "PATH_TIE", "TIE_SIGMA_PX", "DIP_SHARE", "landed_rows", "window_lift"]

#: A clipped core *in a glow*: a row whose stripe's peak is clipped and whose frame stands, over
#: :data:`GLOW_NEAR_PX` to :data:`GLOW_FAR_PX` px either side of the peak (median), at least this share of the top of
#: its range (:func:`glow_rows`). The shipped set's ``bb_hand`` (a hand, its skin glowing in the laser's light) has
#: such a glow at a median 0.90 of the top; the renders' marble and skin at 60 mW at most 0.18 (docs/predict.md, "A
#: clipped core in a glow of the surface's").
GLOW_SHARE = 0.8
#: The nearest and farthest columns from the peak (px) over which :func:`glow_rows` reads the glow.
GLOW_NEAR_PX, GLOW_FAR_PX = 4, 12

#: A row's stripe extends over the columns around its peak that stand this many noise units above the window's median.
EDGE_K = 2.0
#: An extent that falls under ``EDGE_K`` reaches on across the dip to a second hump standing at least this share of the
#: stripe's height over the window's median, where one lies within the reference window (:data:`GUIDE_HALF_PX`) of the
#: peak: a stripe split in two humps (by a core clipped white in every channel, which has no laser colour in the
#: laser-colour blend, or by a darker line along its middle) would otherwise be moved one hump at a time, leaving the
#: other in place (docs/predict.md, "A stripe split by its white core"). A half, as the centre's rule reads the stripe
#: over half its peak.
DIP_SHARE = 0.5
#: The extent is widened by this many px each side (the stripe's tails below ``EDGE_K``).
PAD_PX = 2
#: The most an extent reaches either side of the peak (px): a bloom or a lit surface beyond is left in place.
MAX_HALF_PX = 30
#: A photograph is predicted from its transplants only when the moved stripe is seen (the reference rule) in at
#: least this many rows of its two moved frames together.
MIN_ROWS = 10
#: The guide of a row is the median path column of the strong path rows within this many rows either side.
GUIDE_ROWS = 7
#: The stripe's path: each pixel scores its smoothed height over the row's median as a fraction of PATH_CAP noise
#: units, capped at 1 (a rival far brighter than the stripe counts no more than a clear stripe). The path pays
#: PATH_JUMP (rows of a clear stripe) to move more than 1 px between rows (an object's edge): the most continuous
#: bright path, not each row's maximum. (A cap at the stripe's own typical height instead predicted renders worse:
#: docs/predict.md.)
PATH_CAP = 2.0 * cond.VISIBLE_K
PATH_JUMP = 2.0
#: Where paths tie on their capped scores (a stripe, or its halo, wider than the cap's reach: every column of it scores
#: 1), the path takes the brighter one instead of the leftmost: each pixel adds its height over the row's median,
#: smoothed along the row by a Gaussian of TIE_SIGMA_PX (so that a clipped plateau's middle stands highest) and
#: divided by the frame's largest such value, times PATH_TIE / H. All the rows together add at most PATH_TIE of one
#: clear row, so only near-ties turn on it (docs/predict.md, "Ties on the path").
PATH_TIE = 0.1
TIE_SIGMA_PX = 2.0
#: A row of the path guides only with at least SUPPORT_MIN rows (itself included) within SUPPORT_ROWS rows where
#: the path stands VISIBLE_K noise units over the row's median: a stripe is a run, a stray bright pixel is not.
SUPPORT_ROWS = 3
SUPPORT_MIN = 4
#: The ways :func:`stripe_extents` finds the stripe's guide (the first is the default).
ESTIMATES = ("auto", "path", "argmax")
#: ``estimate="auto"``: the argmax guide for a stripe at most this wide (FWHM, px; ``conditions.measure``'s
#: ``width_px``), else the path. Between the two render families of docs/predict.md: the native ``field`` cases'
#: stripes (about 4-5 px; the path predicts them better) and the phone-like ones (about 2 px; the argmax does).
AUTO_WIDTH_PX = 3.0
#: ``estimate="auto"``: also the argmax guide where at least this share of the frame's pixels stand ``PATH_CAP``
#: noise units over their row's median (the path's score capped): then the cap is a few DN (a smooth, nearly
#: noiseless JPEG, whose noise is the quantisation floor) and the path's score is a mask of everything slightly
#: brighter than its row, so its most continuous path may be a wall's. On the renders of docs/predict.md every frame
#: at the quantisation floor has 15-34 % capped, every other at most 11 %; chosen there as a guard that changes no
#: render frame's estimate.
AUTO_CAPPED = 0.12
#: Each row's stripe is looked for within this many px of its guide: the real set's reference window.
GUIDE_HALF_PX = REFERENCE_HALF_WIDTH
#: :func:`arbitrate`: where two guides of a row lie more than ``conditions.JUMP_PX`` apart, each is scored by the most
#: laser evidence within this many px of it (a guide is a median of peaks, so the peak may lie a px or two off it).
ARBITER_HALF_PX = 2
#: A stripe pixel within this many of its channel's noise units (at least 1 DN) of the top of the range counts as
#: clipped and stays at the top when moved: a JPEG's clipped core decodes to a few DN below the top, and the laser's
#: true addition there is hidden (docs/predict.md, "A stripe clipped within its noise of the top").
CLIP_NOISE_K = 2.0
#: Pixels either side of an extent whose median anchors the clean plate's line (px).
SIDE_PX = 3
#: :func:`shifts_for`: each direction's shift is sought among ``shift_for`` .. ``shift_for + RIVAL_SEARCH_PX`` px, so
#: that the moved stripe lands on as few *rivals* as it can: pixels standing over their row's median by at least
#: RIVAL_SHARE x the stripe's height in that row (1: as high as the stripe, what a tracker taking a row's brightest
#: pixel takes instead of it), outside its own extent and its own glow (:func:`rival_mask`). A stripe moved onto a
#: rival is found where the rival is, which the photograph's stripe, beside it, is not (docs/predict.md, "Shifts
#: that do not land the stripe on a rival"); the rows where it still lands on one are not scored
#: (:func:`landed_rows`; "Where a moved stripe lands on a rival").
RIVAL_SEARCH_PX = 16
RIVAL_SHARE = 1.0
#: The false-report frames of a transplant (``bench.run.predict.transplant_frames``) cut this share of the stripe's
#: visible span (rows) off each end: cleaned, not moved, so those rows keep the photograph's clutter without a stripe
#: and are scored as a real set's rows beyond the stripe's end are. Chosen on renders (docs/predict.md: 0.15, 0.25,
#: 0.35 tried; 0.15 predicts the false-report rate best).
END_CUT = 0.15
#: ... and only where at least this many rows of the span stay moved.
END_CUT_MIN_ROWS = 40
#: :func:`arbitrate`: where the laser's colour shows no stripe, the frame's own guide is kept only where the laser
#: evidence near it is at least this share of its typical value along the colour's guide (docs/predict.md, "The
#: frame's own guide where the colour shows no stripe"), and where the two guides part, neither is kept unless one has
#: that share (twelfth session: "Where two guides part and neither looks like the laser"); a fifth, as :data:`DIM_SHARE`.
EVIDENCE_SHARE = 0.2
#: :func:`dim_rows`: a visible row of a stripe standing under this share of the median height of its visible rows is
#: one a photograph's reference leaves out as unclear (a reflection in line with the stripe, a glow, a faint stretch).
#: Measured on the shipped set's labels (``scripts/reference_rows.py``; docs/predict.md, "Which rows a reference
#: scores"): 3 % of the rows the references score stand so low, 44 % of those they leave out, and 64 % of the rows
#: standing so low are left out; not counting rows whose peak is clipped (:func:`clipped_peaks`), 1.5 %, 41 % and 78 %.
#: 0.2 is the eighth session's (docs/predict.md, "Rows far dimmer than the stripe").
DIM_SHARE = 0.2
#: A stripe wider (FWHM, px; ``conditions.measure``'s ``width_px``) than the reference window cannot be read by the
#: reference rule (the window's median is then the stripe itself, and its "centre" is wherever its brightest pixel
#: is): such a photograph is out of range (``width_px``). A phone's full-size frame is one; shrunk, it may not be.
MAX_WIDTH_PX = 2 * GUIDE_HALF_PX + 1


@dataclass(frozen=True)
class Extents:
    """The stripe of one frame (:func:`stripe_extents`); arrays of shape (H,).

    ``peak``: in a guided row the maximum within :data:`GUIDE_HALF_PX` px of its guide, else the row's
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


def stripe_extents(frame, background=None, *, estimate: str = "auto", measured=None, guide=None) -> Extents:
    """The stripe of a frame: visible rows, their extents and centres (module docstring, step 1).

    Parameters
    ----------
    frame : array_like, shape (H, W)
        What the tracker sees (DN), stripe running top to bottom.
    background : array_like, shape (H, W), optional
        Its laser-off frame (DN).
    estimate : {'auto', 'path', 'argmax'}
        How the guide is found (:data:`ESTIMATES`): ``path``, the DP path (module docstring);
        ``argmax``, each row's pixel standing highest over the median of the reference window around it
        (:func:`window_lift`; of its clipped pixels standing out, the highest, where it has one: :func:`argmax_pick`), kept where it stands ``VISIBLE_K`` noise units up within
        ``conditions.JUMP_PX`` px of the median of such rows within :data:`GUIDE_ROWS` rows and has
        :data:`SUPPORT_MIN` such rows within :data:`SUPPORT_ROWS` (the first version); or ``auto``
        (the default), ``argmax`` for a stripe at most :data:`AUTO_WIDTH_PX` wide or a frame with at
        least :data:`AUTO_CAPPED` of its pixels at the path's cap, else ``path``
        (docs/predict.md compares the three).
    measured : bench.evaluate.conditions.Conditions, optional
        The frame's conditions (``conditions.measure(frame, background)``, with or without its colour
        photograph: only ``width_px`` and ``noise_dn`` are read), when the caller has them; measured otherwise.
    guide : array_like, shape (H,), optional
        The stripe's columns (px, NaN where a row has none) to follow instead of estimating them
        (``estimate`` is then not used): a labelled photograph's reference, for the ablation that
        predicts with a perfect stripe estimate (``predict --estimate reference``, docs/predict.md). Each row's
        peak is still sought within :data:`GUIDE_HALF_PX` of it, as around an estimated guide.

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
    work, sm, first, measured = _prepared(frame, background, estimate, measured)
    noise = measured.noise_dn
    H, W = work.shape
    if guide is not None:
        guide = np.asarray(guide, dtype=np.float64)
        if guide.shape != (H,):
            raise ValueError(f"`guide` must have one column per row of `frame`, shape {(H,)}, got {guide.shape}")
        guide = np.where(np.isfinite(guide), np.clip(guide, 0, W - 1), np.nan)
    else:
        guide = _estimated_guide(sm, np.median(work, axis=1), noise, estimate, measured, clipped_pixels(frame, noise))
    peak = first.copy()
    visible = np.zeros(H, bool)
    lo, hi = peak.copy(), peak.copy()
    centre = np.full(H, np.nan)
    heights = np.full(H, np.nan)
    for r in range(H):
        if not np.isfinite(guide[r]):
            continue
        g = int(round(guide[r]))
        w0, w1 = max(g - GUIDE_HALF_PX, 0), min(g + GUIDE_HALF_PX, W - 1)
        c = w0 + int(np.argmax(sm[r, w0:w1 + 1]))
        row = work[r]
        base = float(np.median(row[w0:w1 + 1]))
        height = row[c] - base
        peak[r], heights[r] = c, height
        v0, v1 = max(c - 3, 0), min(c + 3, W - 1)
        seg = row[v0:v1 + 1] - base
        wts = np.clip(seg - 0.5 * height, 0.0, None)
        centre[r] = float(np.sum(wts * np.arange(v0, v1 + 1)) / np.sum(wts)) if wts.sum() > 0 else float(c)
        if height < cond.VISIBLE_K * noise:
            continue
        visible[r] = True
        edge, hump = base + EDGE_K * noise, base + DIP_SHARE * height
        a, b = _reach(row, c, -1, edge, hump), _reach(row, c, 1, edge, hump)
        lo[r], hi[r] = max(a - PAD_PX, c - MAX_HALF_PX, 0), min(b + PAD_PX, c + MAX_HALF_PX, W - 1)
    return Extents(peak=peak, visible=visible, lo=lo, hi=hi, centre=centre, noise_dn=float(noise), height=heights)


def _reach(row, c: int, step: int, edge: float, hump: float) -> int:
    """The last column of a stripe's run from its peak ``c`` along ``row`` (W,; DN) in direction ``step`` (+1 or -1):
    it goes on while the row stands over ``edge`` (DN), at most :data:`MAX_HALF_PX` from ``c``, and across a dip to a
    pixel standing at least ``hump`` (DN) within :data:`GUIDE_HALF_PX` of ``c`` (:data:`DIP_SHARE`)."""
    W, k = row.shape[0], c
    while True:
        nxt = k + step
        if not 0 <= nxt < W or abs(nxt - c) > MAX_HALF_PX:
            return k
        if row[nxt] > edge:
            k = nxt
            continue
        ahead = [j for j in range(nxt + step, c + step * (GUIDE_HALF_PX + 1), step) if 0 <= j < W and row[j] >= hump]
        if not ahead:
            return k
        k = ahead[0]


def estimate_guide(frame, background=None, *, estimate: str = "auto", measured=None) -> np.ndarray:
    """The columns :func:`stripe_extents` follows when it estimates them, shape (H,), px (NaN: no stripe
    found in that row); the arguments are :func:`stripe_extents`'.

    Examples
    --------
    >>> img = np.full((40, 60), 10.0)
    >>> img[:, 15] += 120.0
    >>> float(np.nanmedian(estimate_guide(img)))
    15.0
    """
    work, sm, _, measured = _prepared(frame, background, estimate, measured)
    return _estimated_guide(sm, np.median(work, axis=1), measured.noise_dn, estimate, measured,
                            clipped_pixels(frame, measured.noise_dn))


def _clipped_at(image, noise_dn=None) -> np.ndarray:
    """Each channel's clipping level, shape (C,), DN: at or above it a pixel counts as clipped, within
    :data:`CLIP_NOISE_K` of the channel's noise units (``noise_dn``, :func:`channel_noise` when None; at least 1 DN) of
    the top of an integer image's range; +inf on a float image (no known top)."""
    img = np.asarray(image)
    C = 1 if img.ndim == 2 else img.shape[2]
    if not np.issubdtype(img.dtype, np.integer):
        return np.full(C, np.inf)
    noise = channel_noise(img) if noise_dn is None else np.broadcast_to(np.asarray(noise_dn, np.float64), (C,))
    return float(np.iinfo(img.dtype).max) - np.maximum(CLIP_NOISE_K * noise, 1.0)


def hue_hidden(image, laser: str, noise_dn=None) -> np.ndarray:
    """Pixels whose hue is not seen, shape (H, W) bool: the laser's channel and at least one other stand within
    :data:`CLIP_NOISE_K` of that channel's noise units (:func:`channel_noise`, at least 1 DN) of the top of an integer
    image's range, as the transplant reads clipping. There the laser-colour excess reads a glare clipped in green and
    blue (cyan-white) as green; light of the laser's colour keeps the others under it (docs/predict.md, "Two clipped
    channels hide the hue"). All False on a float or grey image.

    Parameters
    ----------
    image : array_like, shape (H, W, 3) or (H, W)
        The photograph (DN).
    laser : {'red', 'green', 'blue'}
        The laser's colour.
    noise_dn : array_like, shape (3,), optional
        Each channel's noise (DN); :func:`channel_noise` when None.

    Examples
    --------
    A green stripe clipped in green alone, a cyan glare clipped in green and blue, and a white core clipped in all:

    >>> rgb = np.full((4, 8, 3), 40, np.uint8)
    >>> rgb[:, 1] = [120, 255, 90]; rgb[:, 2] = [200, 255, 255]; rgb[:, 3] = [255, 255, 255]
    >>> hue_hidden(rgb, "green")[0, :5].tolist()
    [False, False, True, True, False]
    """
    from bench.evaluate.pixels import LASER_INDEX

    a = np.asarray(image)
    if a.ndim != 3 or not np.issubdtype(a.dtype, np.integer):
        return np.zeros(a.shape[:2], bool)
    clipped = a >= _clipped_at(a, noise_dn)[None, None, :]
    li = LASER_INDEX[laser]
    return clipped[..., li] & np.delete(clipped, li, axis=2).any(axis=2)


def laser_evidence(laser_channel, excess, laser_background=None, excess_background=None, *,
                   over: str = "row") -> np.ndarray:
    """How much each pixel looks like the laser, shape (H, W), DN: the lesser of two lifts over their row's median (or,
    ``over="window"``, over the reference window around each pixel), each clipped at 0: the laser's own channel
    (bright), and the laser-colour excess (:func:`bench.evaluate.pixels.select_channel` ``excess``) at its most within
    :data:`GUIDE_HALF_PX` px along the row (coloured: a stripe's core clipped white in every channel takes its
    fringe's colour). White light (a lamp, a window) is bright without colour; a surface of the laser's hue is
    coloured without being brighter than its row; the stripe is both. The lesser, not a mean: a white bar far
    brighter than the stripe, with a few DN of colour at its edge, must not outweigh the stripe (docs/predict.md,
    "Brightness and colour, both").

    Parameters
    ----------
    laser_channel, excess : array_like, shape (H, W)
        The photograph's laser channel and its laser-colour excess (DN).
    laser_background, excess_background : array_like, shape (H, W), optional
        The same of its laser-off frame, subtracted first.
    over : {'row', 'window'}
        What each lift stands over: its row's median (``row``), or the median of the reference window around it
        (``window``, :func:`window_lift`; the colour's lift taken before it is widened). A glare or lit patch wider
        than the window stands over its row only; a bar's coloured edge beside a bright patch over its window only.
        :func:`bench.run.predict.colour_guide` reads the frame's own guide on the lesser of the two (docs/predict.md,
        "The frame's own guide must stand out of the window too").

    Examples
    --------
    A white lamp (column 5), an orange surface (column 30) and a stripe clipped white with a red fringe
    (columns 60-62):

    >>> red = np.full((3, 80), 100.0); excess = np.zeros((3, 80))
    >>> red[:, 5] = 255.0
    >>> excess[:, 30] = 80.0
    >>> red[:, 60:63] = [200.0, 255.0, 200.0]; excess[:, 60:63] = [40.0, 0.0, 40.0]
    >>> ev = laser_evidence(red, excess)
    >>> ev[0, 60:63].tolist(), float(ev[0, 5]), float(ev[0, 30])
    ([40.0, 40.0, 40.0], 0.0, 0.0)

    A white bar far brighter than a faint stripe, with a little colour at its edge: the stripe has the more evidence.

    >>> red = np.full((1, 60), 20.0); excess = np.zeros((1, 60))
    >>> red[0, 10] = 42.0; excess[0, 10] = 22.0
    >>> red[0, 40] = 255.0; excess[0, 43] = 3.0
    >>> ev = laser_evidence(red, excess)
    >>> float(ev[0, 10]), float(ev[0, 40])
    (22.0, 3.0)

    A greenish glare 30 px wide (columns 20-49): it stands over its row, not over the window around its middle; a
    thin green line (column 120) stands over either.

    >>> green = np.full((1, 200), 60.0); excess = np.zeros((1, 200))
    >>> green[0, 20:50] = 200.0; excess[0, 20:50] = 30.0
    >>> green[0, 120] = 120.0; excess[0, 120] = 40.0
    >>> [float(laser_evidence(green, excess, over=o)[0, 35]) for o in ("row", "window")]
    [30.0, 0.0]
    >>> [float(laser_evidence(green, excess, over=o)[0, 120]) for o in ("row", "window")]
    [40.0, 40.0]
    """
    lc = np.asarray(laser_channel, dtype=np.float64)
    ex = np.asarray(excess, dtype=np.float64)
    if lc.ndim != 2 or ex.shape != lc.shape:
        raise ValueError(f"`laser_channel` and `excess` must be 2-D of one shape, got {lc.shape} and {ex.shape}")
    for name, bg in (("laser_background", laser_background), ("excess_background", excess_background)):
        if bg is not None and np.shape(bg) != lc.shape:
            raise ValueError(f"`{name}` must have the shape of `laser_channel` {lc.shape}, got {np.shape(bg)}")
    if over not in ("row", "window"):
        raise ValueError(f"`over` must be 'row' or 'window', got {over!r}")
    if laser_background is not None:
        lc = lc - np.asarray(laser_background, dtype=np.float64)
    if excess_background is not None:
        ex = ex - np.asarray(excess_background, dtype=np.float64)
    from scipy.ndimage import maximum_filter1d

    widen = 2 * GUIDE_HALF_PX + 1
    if over == "window":  # the colour's lift before it is widened: a widened peak is a plateau that wide
        bright = np.clip(window_lift(lc), 0.0, None)
        coloured = maximum_filter1d(np.clip(window_lift(ex), 0.0, None), widen, axis=1, mode="nearest")
        return np.minimum(bright, coloured)
    wide = maximum_filter1d(ex, widen, axis=1, mode="nearest")
    bright = np.clip(lc - np.median(lc, axis=1, keepdims=True), 0.0, None)
    coloured = np.clip(wide - np.median(wide, axis=1, keepdims=True), 0.0, None)
    return np.minimum(bright, coloured)


def arbitrate(guide, other, evidence, other_evidence=None) -> np.ndarray:
    """Two guides made one, shape (H,), px: ``guide``, and ``other`` where ``guide`` has no stripe; where both do
    and lie more than ``conditions.JUMP_PX`` apart, the one with the more ``evidence`` (H, W; e.g.
    :func:`laser_evidence`) within :data:`ARBITER_HALF_PX` px of it (``guide`` on a tie), unless neither has
    :data:`EVIDENCE_SHARE` of the median evidence near ``guide`` in its rows: then neither (NaN; where the stripe turns
    white, the colour's guide may wander onto something else, docs/predict.md, "Where two guides part and neither
    looks like the laser"). Where ``guide`` has no stripe, ``other`` is kept only with that share (a white lamp's or
    window's edge, which the frame's own guide may follow where the colour shows no stripe, has none); with no such
    rows, as it is. ``other_evidence`` (H, W), optional: the evidence ``other`` is read on (default ``evidence``);
    the share is always of ``guide``'s.

    Examples
    --------
    >>> ev = np.zeros((3, 20)); ev[:, 12] = 5.0
    >>> arbitrate(np.array([3.0, 3.0, np.nan]), np.array([3.0, 12.0, 12.0]), ev).tolist()
    [3.0, 12.0, 12.0]

    Where the colour finds no stripe, the frame's own guide on something of no colour is dropped:

    >>> ev = np.zeros((3, 20)); ev[:, 3] = 5.0
    >>> arbitrate(np.array([3.0, 3.0, np.nan]), np.array([3.0, 3.0, 12.0]), ev).tolist()
    [3.0, 3.0, nan]

    Where the two part and neither has evidence, neither is kept:

    >>> ev = np.zeros((5, 20)); ev[:, 3] = 5.0
    >>> arbitrate(np.array([3.0, 3.0, 3.0, 12.0, 12.0]), np.array([3.0, 3.0, 3.0, 3.0, 18.0]), ev).tolist()
    [3.0, 3.0, 3.0, 3.0, nan]
    """
    guide = np.asarray(guide, dtype=np.float64)
    other = np.asarray(other, dtype=np.float64)
    evidence = np.asarray(evidence, dtype=np.float64)
    if guide.shape != other.shape or evidence.ndim != 2 or evidence.shape[0] != guide.shape[0]:
        raise ValueError(f"`guide` and `other` must have one entry per row of `evidence` {evidence.shape}, "
                         f"got {guide.shape} and {other.shape}")
    other_evidence = evidence if other_evidence is None else np.asarray(other_evidence, dtype=np.float64)
    if other_evidence.shape != evidence.shape:
        raise ValueError(f"`other_evidence` must have the shape of `evidence` {evidence.shape}, "
                         f"got {other_evidence.shape}")
    out = np.where(np.isfinite(guide), guide, other)
    both = np.isfinite(guide) & np.isfinite(other) & (np.abs(guide - other) > cond.JUMP_PX)
    eg, eo = evidence_near(evidence, guide), evidence_near(other_evidence, other)
    own = np.isfinite(guide)
    least = EVIDENCE_SHARE * float(np.median(eg[own])) if own.any() else 0.0
    with np.errstate(invalid="ignore"):
        out[both & (eo > eg)] = other[both & (eo > eg)]
        # the two part and neither looks like the laser: neither guides the row
        out[both & (np.fmax(eg, eo) < least)] = np.nan
        out[~own & np.isfinite(other) & (eo < least)] = np.nan
    return out


def evidence_near(evidence, guide) -> np.ndarray:
    """The most of ``evidence`` (H, W) within :data:`ARBITER_HALF_PX` px of each row's ``guide`` (H,), px, shape (H,)
    (NaN where the guide has none): how :func:`arbitrate` reads a guide's laser evidence (a guide is a median of peaks,
    so the peak may lie a px or two off it).

    Examples
    --------
    >>> ev = np.zeros((2, 10)); ev[:, 6] = [3.0, 5.0]
    >>> evidence_near(ev, np.array([4.0, np.nan])).tolist()
    [3.0, nan]
    """
    from scipy.ndimage import maximum_filter1d

    ev = np.asarray(evidence, dtype=np.float64)
    g = np.asarray(guide, dtype=np.float64)
    if ev.ndim != 2 or g.shape != (ev.shape[0],):
        raise ValueError(f"`guide` must have one entry per row of `evidence` {ev.shape}, got {g.shape}")
    out = np.full(g.shape, np.nan)
    rows = np.flatnonzero(np.isfinite(g))
    if rows.size:
        near = maximum_filter1d(ev, 2 * ARBITER_HALF_PX + 1, axis=1, mode="nearest")  # the edge: a shorter window
        out[rows] = near[rows, np.clip(np.rint(g[rows]).astype(np.int64), 0, ev.shape[1] - 1)]
    return out


def _prepared(frame, background, estimate: str, measured):
    """The checked inputs of :func:`stripe_extents` and :func:`estimate_guide`: ``(work, sm, first, measured)``,
    the frame less its laser-off frame (float64, H x W, DN), that smoothed along each row, each row's argmax
    of it, and the frame's conditions."""
    if estimate not in ESTIMATES:
        raise ValueError(f"`estimate` must be one of {', '.join(ESTIMATES)}, got {estimate!r}")
    work, sm = _working(frame, background)
    measured = cond.measure(frame, background) if measured is None else measured
    return work, sm, np.argmax(sm, axis=1), measured


def _working(frame, background) -> tuple[np.ndarray, np.ndarray]:
    """``(work, sm)``: the frame less its laser-off frame (float64, H x W, DN; both checked) and that smoothed along
    each row (:func:`bench.evaluate.conditions.row_smoothed`), what the stripe and its rivals are read on."""
    raw = np.asarray(frame, dtype=np.float64)
    if raw.ndim != 2 or raw.shape[0] < 2 or raw.shape[1] < 8:
        raise ValueError(f"`frame` must be 2-D, at least 2x8, got shape {raw.shape}")
    work = raw if background is None else raw - np.asarray(background, dtype=np.float64)
    if work.shape != raw.shape:
        raise ValueError(f"`background` must have the shape of `frame` {raw.shape}, got {np.shape(background)}")
    return work, cond.row_smoothed(work)


def _estimated_guide(sm, med, noise: float, estimate: str, measured, clipped=None) -> np.ndarray:
    """:func:`stripe_extents`' guide by ``estimate`` (``auto``, ``path`` or ``argmax``), NaN where no stripe:
    ``sm`` the row-smoothed frame (H, W), ``med`` its rows' medians, ``clipped`` the frame's clipped pixels (H, W;
    :func:`clipped_pixels`; None: none), read by the argmax guide (:func:`argmax_pick`)."""
    if estimate == "auto":
        narrow = math.isfinite(measured.width_px) and measured.width_px <= AUTO_WIDTH_PX
        estimate = "argmax" if narrow or capped_share(sm, med, noise) >= AUTO_CAPPED else "path"
    rows = np.arange(sm.shape[0])
    window = np.ones(2 * SUPPORT_ROWS + 1, int)
    if estimate == "path":
        lift = sm - med[:, None]
        path = _path(np.clip(lift / (PATH_CAP * noise), 0.0, 1.0) + tie_break(lift))
        on = sm[rows, path] - med >= cond.VISIBLE_K * noise
        return _guide(path, on & (np.convolve(on.astype(int), window, mode="same") >= SUPPORT_MIN))
    lift = window_lift(sm)
    first = argmax_pick(lift, clipped, cond.VISIBLE_K * noise)
    strong = lift[rows, first] >= cond.VISIBLE_K * noise
    near = np.abs(first - np.nan_to_num(_guide(first, strong), nan=-1e9)) <= cond.JUMP_PX
    kept = strong & near
    return _guide(first, kept & (np.convolve(kept.astype(int), window, mode="same") >= SUPPORT_MIN))


def clipped_pixels(frame, noise_dn: float) -> np.ndarray:
    """The pixels of ``frame`` (H, W) at its clipping level (:func:`_clipped_at`, with ``noise_dn``), shape (H, W), bool:
    within :data:`CLIP_NOISE_K` of ``noise_dn`` (DN; at least 1 DN) of the top of an integer frame's range; none in a
    float frame (no known top).

    Examples
    --------
    >>> clipped_pixels(np.array([[10, 254, 255]], np.uint8), 0.5).tolist()
    [[False, True, True]]
    >>> bool(clipped_pixels(np.ones((1, 3)), 0.5).any())
    False
    """
    img = np.asarray(frame)
    return img >= _clipped_at(img, float(noise_dn))[0]  # inf on a float frame: none


def argmax_pick(lift, clipped, level: float) -> np.ndarray:
    """Each row's pick for the argmax guide, shape (H,), px: of the clipped pixels standing at least ``level`` (DN)
    over the window around them (``lift``, :func:`window_lift`; ``clipped``, :func:`clipped_pixels`, or None), the
    one standing highest; in a row without one, the pixel standing highest (docs/predict.md, "A clipped core in a
    glow of the surface's", (aw)). A stripe's clipped core is the brightest it gets; a glow's shoulder beside a dip
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


def window_lift(smoothed) -> np.ndarray:
    """Each pixel's height over the median of the reference window around it, shape (H, W), DN: ``smoothed`` (H, W;
    DN) less its running median along the row over ``2 * GUIDE_HALF_PX + 1`` px (edges: the nearest pixel repeated).
    What the argmax guide reads (docs/predict.md, "The argmax guide on the reference window's height"): a reference
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
    return sm - median_filter(sm, size=(1, 2 * GUIDE_HALF_PX + 1), mode="nearest")


def tie_break(lift) -> np.ndarray:
    """The path's tie-breaker (:data:`PATH_TIE`), shape (H, W): ``lift`` (H, W; DN over each row's median), clipped at
    0, smoothed along each row by a Gaussian of :data:`TIE_SIGMA_PX`, divided by its largest value and times
    ``PATH_TIE / H``; zeros where nothing stands over its row.

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
    mean = gaussian_filter1d(lift, TIE_SIGMA_PX, axis=1, mode="nearest")
    top = float(mean.max()) if mean.size else 0.0
    return mean * (PATH_TIE / (mean.shape[0] * top)) if top > 0 else np.zeros_like(mean)


def capped_share(smoothed, row_median, noise_dn: float) -> float:
    """The share of pixels whose path score is capped: ``smoothed`` (H, W; DN) standing at least
    :data:`PATH_CAP` x ``noise_dn`` over ``row_median`` (H,; DN).

    Examples
    --------
    >>> f = np.zeros((4, 10)); f[:, 3] = 50.0; f[:, 6:] = 8.0
    >>> capped_share(f, np.median(f, axis=1), 1.0), capped_share(f, np.median(f, axis=1), 0.3)
    (0.1, 0.5)
    """
    lift = np.asarray(smoothed, dtype=np.float64) - np.asarray(row_median, dtype=np.float64)[:, None]
    return float(np.mean(lift >= PATH_CAP * float(noise_dn)))


def _path(score) -> np.ndarray:
    """The column per row of the path through ``score`` (H, W) with the largest sum, moving at most
    1 px between rows for free and anywhere for :data:`PATH_JUMP` (free start and end)."""
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
        jump = acc[j] - PATH_JUMP
        use_jump = jump > best
        back[r] = np.where(use_jump, j, src)
        acc = score[r] + np.where(use_jump, jump, best)
    out = np.empty(H, np.int64)
    out[-1] = int(np.argmax(acc))
    for r in range(H - 1, 0, -1):
        out[r - 1] = back[r, out[r]]
    return out


def _guide(peak, strong) -> np.ndarray:
    """Each row's guide column: the median of the strong rows' path columns within :data:`GUIDE_ROWS`
    rows (NaN where there is none)."""
    H = peak.shape[0]
    out = np.full(H, np.nan)
    idx = np.flatnonzero(strong)
    if idx.size == 0:
        return out
    for r in range(H):
        i0, i1 = np.searchsorted(idx, [r - GUIDE_ROWS, r + GUIDE_ROWS + 1])
        if i1 > i0:
            out[r] = float(np.median(peak[idx[i0:i1]]))
    return out


def out_of_range(measured) -> tuple:
    """The measures that put a frame out of the transplant's range: ``("width_px",)`` for a stripe wider
    than :data:`MAX_WIDTH_PX` (``measured``: its :func:`bench.evaluate.conditions.measure`), else ``()``.

    Examples
    --------
    >>> thin = np.full((20, 60), 10.0); thin[:, 30] = 200.0
    >>> wide = np.full((20, 60), 10.0); wide[:, 20:40] = 200.0
    >>> out_of_range(cond.measure(thin)), out_of_range(cond.measure(wide))
    ((), ('width_px',))
    """
    w = measured.width_px
    return ("width_px",) if math.isfinite(w) and w > MAX_WIDTH_PX else ()


def shift_for(ext: Extents) -> int:
    """A shift (px) that moves most extents clear of themselves: the 90th-percentile extent width
    plus ``2 * SIDE_PX + 1``, at least 12 (rows whose extent is wider are not moved).

    Examples
    --------
    >>> e = Extents(np.zeros(3, int), np.array([True, True, False]), np.array([8, 9, 0]), np.array([14, 15, 0]),
    ...             np.array([11.0, 12.0, np.nan]), 2.0)
    >>> shift_for(e)
    14
    """
    if not ext.visible.any():
        return 12
    widths = (ext.hi - ext.lo + 1)[ext.visible]
    return int(max(12, math.ceil(np.percentile(widths, 90)) + 2 * SIDE_PX + 1))


def rival_mask(frame, background, ext: Extents) -> np.ndarray:
    """The frame's *rivals* to its stripe, shape (H, W) bool: in each row with a visible stripe, the pixels of the
    working frame (``frame`` less ``background``, smoothed along the row as :func:`stripe_extents` smooths it) standing
    over the row's median by at least :data:`RIVAL_SHARE` x the stripe's height there, outside the row's extent and
    outside the run of such pixels that continues it either side (the stripe's own glow or bloom, which moves with it
    in the photograph's light, is not something else beside it; docs/predict.md, "Where a moved stripe lands on a
    rival").

    Examples
    --------
    >>> img = np.full((20, 80), 10.0); img[:, 20] += 100.0; img[:, 44:47] += 150.0
    >>> e = stripe_extents(img, guide=np.full(20, 20.0))
    >>> m = rival_mask(img, None, e)
    >>> np.flatnonzero(m[5]).tolist()  # the rival, brighter than the stripe; the stripe's own extent is not one
    [44, 45, 46]
    """
    work, sm = _working(frame, background)
    lift = sm - np.median(work, axis=1)[:, None]
    height = np.nan_to_num(np.asarray(ext.height if ext.height is not None else np.zeros(work.shape[0]), float))
    out = ext.visible[:, None] & (lift >= RIVAL_SHARE * np.maximum(height, 0.0)[:, None]) & (height > 0)[:, None]
    W = work.shape[1]
    for r in np.flatnonzero(ext.visible):  # the extent, and what stands as high next to it: the stripe's own glow
        a, b = int(ext.lo[r]), int(ext.hi[r])
        while a > 0 and out[r, a - 1]:
            a -= 1
        while b < W - 1 and out[r, b + 1]:
            b += 1
        out[r, a:b + 1] = False
    return out


def landed_rows(ext: Extents, rivals, shift_px: int) -> np.ndarray:
    """The visible rows of ``ext`` whose extent, moved by ``shift_px`` (px, signed) and widened by :data:`SIDE_PX`
    either side, meets ``rivals`` (:func:`rival_mask`, (H, W) bool), shape (H,) bool: where the moved stripe lands on
    a rival, which the photograph's stripe, beside it, does not (a row whose moved extent falls wholly outside the
    frame does not count; one only partly outside is counted on its part inside).

    Examples
    --------
    >>> img = np.full((20, 80), 10.0); img[:, 20] += 100.0; img[:10, 34:37] += 150.0  # a rival 15 px right, rows 0-9
    >>> e = stripe_extents(img, guide=np.full(20, 20.0))
    >>> r = rival_mask(img, None, e)
    >>> int(landed_rows(e, r, 12).sum()), int(landed_rows(e, r, 22).sum())
    (10, 0)
    """
    return _landed(ext, _row_cumsum(rivals), shift_px)


def _row_cumsum(rivals) -> np.ndarray:
    """Each row's running count of ``rivals`` (H, W) bool, shape (H, W + 1), a leading 0: what :func:`_landed` reads."""
    rivals = np.asarray(rivals, bool)
    return np.concatenate([np.zeros((rivals.shape[0], 1), int), np.cumsum(rivals, axis=1)], axis=1)


def _landed(ext: Extents, csum, shift_px: int) -> np.ndarray:
    """:func:`landed_rows` from the rivals' running counts ``csum`` (:func:`_row_cumsum`), read once per frame."""
    H, W = csum.shape[0], csum.shape[1] - 1
    out = np.zeros(H, bool)
    rows = np.flatnonzero(ext.visible)
    if rows.size == 0:
        return out
    a = np.clip(ext.lo[rows].astype(int) + shift_px - SIDE_PX, 0, W)
    b = np.clip(ext.hi[rows].astype(int) + shift_px + SIDE_PX + 1, 0, W)
    out[rows] = (b > a) & (csum[rows, b] - csum[rows, a] > 0)
    return out


def shifts_for(ext: Extents, rivals) -> tuple[int, int]:
    """The two moved frames' shifts (px), ``(right, left)`` (both > 0; the second frame moves by ``-left``): in each
    direction the least of ``shift_for(ext)`` .. ``shift_for(ext) + RIVAL_SEARCH_PX`` whose moved extents meet
    ``rivals`` (:func:`rival_mask`, (H, W) bool) in the fewest visible rows (:func:`landed_rows`).

    Examples
    --------
    >>> img = np.full((20, 80), 10.0); img[:, 20] += 100.0; img[:, 34:37] += 150.0  # a rival 15 px right
    >>> e = stripe_extents(img, guide=np.full(20, 20.0))
    >>> shift_for(e), shifts_for(e, rival_mask(img, None, e))  # to the right, past the rival
    (12, (22, 12))
    """
    base = shift_for(ext)
    if not ext.visible.any():
        return base, base
    csum = _row_cumsum(rivals)  # once, for every shift tried
    out = []
    for sign in (1, -1):
        best = None
        for s in range(base, base + RIVAL_SEARCH_PX + 1):
            met = int(_landed(ext, csum, sign * s).sum())
            if best is None or met < best[0]:
                best = (met, s)
            if met == 0:
                break
        out.append(best[1])
    return out[0], out[1]


def channel_noise(original) -> np.ndarray:
    """The sensor noise of each channel of a photograph (DN, shape (C,); one value for a grey one), as
    :func:`bench.evaluate.conditions.measure` reads it: the clean plate's noise (:func:`transplant`)."""
    f = np.asarray(original, dtype=np.float64)
    planes = f[..., None] if f.ndim == 2 else f
    return np.array([cond.measure(planes[..., k]).noise_dn for k in range(planes.shape[-1])])


def transplant(original, ext: Extents, shift_px: int, *, background_original=None, seed: int = 0,
               noise_dn=None, keep=None, laser_channel: int | None = None):
    """The photograph with its stripe moved ``shift_px`` columns (module docstring, steps 2-3).

    Parameters
    ----------
    original : ndarray, shape (H, W) or (H, W, C), integer or float
        The photograph, turned as the tracker's frame (its rows and columns are ``ext``'s).
    ext : Extents
        :func:`stripe_extents` of the tracker's frame of ``original``.
    shift_px : int
        Columns to move the stripe by (either sign, non-zero).
    background_original : ndarray like ``original``, optional
        The laser-off photograph: the clean plate is taken from it.
    seed : int
        Seed of the clean plate's noise.
    noise_dn : array_like, shape (C,), optional
        :func:`channel_noise` of ``original``, when the caller has it (it is measured otherwise).
    keep : array_like of bool, shape (H,), optional
        The rows whose stripe is moved (default: all); the others are cleaned, not moved (:func:`cut_ends`).
    laser_channel : int, optional
        The laser's channel of a colour ``original``: where it stands at or above the ``auto`` knee
        (:data:`bench.evaluate.colour.AUTO_KNEE` of the top), its moved lift is at least the greatest of the other
        channels' (under the laser's light its own channel rises most; near the top it shows less only because it
        clips: a white core in a red glow, docs/predict.md, "A near-clipped laser channel rises most").

    Returns
    -------
    moved : ndarray like ``original`` (same dtype)
    truth : ndarray of float64, shape (H,)
        The moved stripe's centre (px), NaN in rows where it was not moved.
    """
    img = np.asarray(original)
    if img.ndim not in (2, 3) or img.shape[0] != ext.peak.shape[0]:
        raise ValueError(f"`original` must be (H, W) or (H, W, C) with H = {ext.peak.shape[0]}, got {img.shape}")
    if isinstance(shift_px, bool) or not isinstance(shift_px, (int, np.integer)) or shift_px == 0:
        raise ValueError(f"`shift_px` must be a non-zero integer, got {shift_px!r}")
    f = img.astype(np.float64)
    planes = f[..., None] if f.ndim == 2 else f
    H, W, C = planes.shape
    if background_original is not None:
        bgp = np.asarray(background_original, dtype=np.float64)
        bgp = bgp[..., None] if bgp.ndim == 2 else bgp
        if bgp.shape != planes.shape:
            raise ValueError(f"`background_original` must have shape {img.shape}, got {np.shape(background_original)}")
    # each channel's noise: the clean plate's (without a laser-off photograph) and the clipping margin
    noise = channel_noise(img) if noise_dn is None else np.broadcast_to(np.asarray(noise_dn, np.float64), (C,))
    rng = np.random.default_rng(seed)
    if np.issubdtype(img.dtype, np.integer):
        lo_v, hi_v = float(np.iinfo(img.dtype).min), float(np.iinfo(img.dtype).max)
    else:
        lo_v, hi_v = -np.inf, np.inf
    clipped_at = _clipped_at(img, noise)  # (C,): at or above it, a pixel counts as clipped
    li, knee = None, None  # the laser's channel, lifted at least as the others at or above the knee
    if laser_channel is not None and C > 1:
        if isinstance(laser_channel, bool) or not isinstance(laser_channel, (int, np.integer)) or \
                not 0 <= laser_channel < C:
            raise ValueError(f"`laser_channel` must be a channel of `original` (0-{C - 1}), got {laser_channel!r}")
        if np.isfinite(hi_v):
            from bench.evaluate.colour import AUTO_KNEE

            li, knee = int(laser_channel), AUTO_KNEE * hi_v
    out = planes.copy()
    truth = np.full(H, np.nan)
    s = int(shift_px)
    lo, hi = _span_extents(ext, W)
    kept = np.ones(H, bool) if keep is None else np.asarray(keep, bool)
    for r in np.flatnonzero(lo >= 0):
        a, b = int(lo[r]), int(hi[r])
        if background_original is None:
            line = _line(planes[r], a, b)
            out[r, a:b + 1] = line + rng.normal(0.0, 1.0, line.shape) * noise[None, :]
        else:
            line = bgp[r, a:b + 1]
            out[r, a:b + 1] = line
        if not kept[r] or a + s - SIDE_PX < 0 or b + s + SIDE_PX > W - 1 or abs(s) < b - a + 1 + SIDE_PX:
            continue  # the moved extent would leave the frame or meet the old one: removed, not moved
        src = planes[r, a:b + 1]
        lift = src - line
        if li is not None:
            near_top = src[:, li] >= knee
            lift[near_top, li] = np.maximum(lift[near_top, li], np.delete(lift[near_top], li, axis=1).max(axis=1))
        out[r, a + s:b + s + 1] = np.where(src >= clipped_at[None, :], hi_v, planes[r, a + s:b + s + 1] + lift)
        if np.isfinite(ext.centre[r]):
            truth[r] = ext.centre[r] + s
    out = np.clip(out, lo_v, hi_v)
    if np.issubdtype(img.dtype, np.integer):
        out = np.rint(out)
    out = out.astype(img.dtype)
    return (out[..., 0] if img.ndim == 2 else out), truth


def in_place_truth(ext: Extents) -> np.ndarray:
    """The estimated stripe's centre in the rows :func:`transplant` would clean or move, from the first visible row
    to the last, shape (H,), px (NaN elsewhere): the truth of the photograph itself as a frame of the prediction,
    read with :func:`row_states` (docs/predict.md, "The photograph in place").

    Examples
    --------
    >>> vis = np.r_[False, True, True, False]
    >>> e = Extents(np.full(4, 5), vis, np.full(4, 3), np.full(4, 7), np.array([np.nan, 5.2, 5.4, 6.0]), 1.0)
    >>> in_place_truth(e).tolist()
    [nan, 5.2, 5.4, nan]
    """
    vis = np.flatnonzero(ext.visible)
    span = np.zeros(ext.visible.shape[0], bool)
    if vis.size:
        span[vis[0]:vis[-1] + 1] = True
    return np.where(span & np.isfinite(ext.centre), ext.centre, np.nan)


def cut_ends(ext: Extents, share: float = END_CUT, min_rows: int = END_CUT_MIN_ROWS):
    """The rows whose stripe a false-report frame moves: the visible span without ``share`` of it at each end.

    Returns
    -------
    numpy.ndarray of bool, shape (H,), or None
        True from the first visible row + k to the last - k (k = ``share`` x the span, rounded), or None when
        fewer than ``min_rows`` rows would stay (or no row is visible).

    Examples
    --------
    >>> vis = np.r_[np.zeros(10, bool), np.ones(100, bool), np.zeros(10, bool)]
    >>> e = Extents(np.zeros(120, int), vis, np.zeros(120, int), np.zeros(120, int), np.full(120, np.nan), 1.0)
    >>> k = cut_ends(e); int(np.argmax(k)), int(k.sum()), cut_ends(e, 0.35, min_rows=40) is None
    (25, 70, True)
    """
    vis = np.flatnonzero(ext.visible)
    if vis.size == 0:
        return None
    span = int(vis[-1] - vis[0] + 1)
    k = int(round(float(share) * span))
    if span - 2 * k < min_rows:
        return None
    keep = np.zeros(ext.visible.shape[0], bool)
    keep[vis[0] + k:vis[-1] - k + 1] = True
    return keep


def _span_extents(ext: Extents, W: int) -> tuple[np.ndarray, np.ndarray]:
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


def _few_median(pixels) -> np.ndarray:
    """``np.median(pixels, axis=0)`` of a few pixels (k, C), the same float64 values, without its overhead (the
    clean plate takes two per row).

    Examples
    --------
    >>> px = np.array([[3, 9], [1, 7], [2, 250]], dtype=np.uint8)
    >>> [bool(np.array_equal(_few_median(px[:k]), np.median(px[:k], axis=0))) for k in (1, 2, 3)]
    [True, True, True]
    """
    v = np.sort(np.asarray(pixels, dtype=np.float64), axis=0)
    n = v.shape[0]
    if n == 0:  # np.median's NaN (a stripe across the whole row), without its warning
        return np.full(v.shape[1:], np.nan)
    return v[n // 2] if n % 2 else (v[n // 2 - 1] + v[n // 2]) / 2.0


def _line(row, a: int, b: int) -> np.ndarray:
    """Row ``row`` (W, C) over columns ``a..b``: the line between the medians of the
    :data:`SIDE_PX` pixels either side (shape (b - a + 1, C))."""
    W = row.shape[0]
    left = row[max(a - SIDE_PX, 0):a] if a > 0 else row[b + 1:b + 1 + SIDE_PX]
    right = row[b + 1:min(b + 1 + SIDE_PX, W)] if b < W - 1 else left
    ml, mr = _few_median(left), _few_median(right)
    t = (np.arange(a, b + 1) - (a - 1)) / float(b - a + 2)
    return ml[None, :] + t[:, None] * (mr - ml)[None, :]


def dim_rows(ext: Extents, clipped=None, *, guided: bool = False) -> np.ndarray:
    """The visible rows of ``ext`` whose stripe stands under :data:`DIM_SHARE` of the median height (``ext.height``,
    the peak over the reference window's median) of its visible rows, shape (H,) bool: the rows a photograph's
    reference leaves out as unclear (docs/predict.md, "Which rows a reference scores"); none without heights.
    ``clipped`` (H,) bool, optional: rows whose peak is clipped (:func:`clipped_peaks`), which are never dim: a
    clipped core stands low over its window's median only where a glow as bright fills the window. ``guided``: every
    row with a height, visible or not (the stripe's rows under 6 of the frame's noise units that the reference rule,
    with its own noise unit, still sees: the renders' measured side since the thirteenth session, docs/predict.md,
    "Faint rows the extent does not call visible").

    Examples
    --------
    >>> vis = np.ones(6, bool)
    >>> e = Extents(np.zeros(6), vis, np.zeros(6), np.zeros(6), np.zeros(6), 1.0,
    ...             height=np.array([50.0, 48.0, 52.0, 9.0, 11.0, 50.0]))
    >>> dim_rows(e).tolist()
    [False, False, False, True, False, False]
    >>> dim_rows(e, clipped=np.array([0, 0, 0, 1, 0, 0], bool)).tolist()
    [False, False, False, False, False, False]
    >>> e.visible[3] = False
    >>> dim_rows(e).tolist(), dim_rows(e, guided=True).tolist()
    ([False, False, False, False, False, False], [False, False, False, True, False, False])
    """
    out = np.zeros(np.shape(ext.visible), bool)
    if ext.height is None or not np.any(ext.visible):
        return out
    h = np.asarray(ext.height, dtype=np.float64)
    typical = np.nanmedian(h[ext.visible])
    if not np.isfinite(typical) or typical <= 0:
        return out
    with np.errstate(invalid="ignore"):
        out = (np.isfinite(h) if guided else ext.visible) & (h < DIM_SHARE * typical)
    if clipped is not None:
        clipped = np.asarray(clipped, bool)
        if clipped.shape != out.shape:
            raise ValueError(f"`clipped` must have one entry per row, shape {out.shape}, got {clipped.shape}")
        out &= ~clipped
    return out


def clipped_peaks(original, ext: Extents, noise_dn=None) -> np.ndarray:
    """The rows whose stripe peak (``ext.peak``) is clipped in ``original``, shape (H,) bool: a channel there stands
    within :data:`CLIP_NOISE_K` of its noise units (at least 1 DN) of the top of an integer image's range, as
    :func:`transplant` keeps a clipped pixel clipped; none for a float image (no known top).

    Parameters
    ----------
    original : array_like, shape (H, W) or (H, W, C)
        The photograph (DN), turned as the frame ``ext`` was read from.
    ext : Extents
        Its stripe.
    noise_dn : array_like, shape (C,), optional
        Each channel's noise (DN); :func:`channel_noise` when None.

    Examples
    --------
    >>> img = np.full((3, 8), 40, np.uint8); img[:, 4] = [255, 200, 254]
    >>> e = Extents(np.full(3, 4), np.ones(3, bool), np.zeros(3), np.zeros(3), np.zeros(3), 1.0)
    >>> clipped_peaks(img, e, noise_dn=[1.0]).tolist()
    [True, False, True]
    """
    img = np.asarray(original)
    planes = img[..., None] if img.ndim == 2 else img
    H, W = planes.shape[:2]
    if np.shape(ext.peak) != (H,):
        raise ValueError(f"`original` must have the frame's {np.shape(ext.peak)[0]} rows, got shape {img.shape}")
    if not np.issubdtype(img.dtype, np.integer):
        return np.zeros(H, bool)
    top = _clipped_at(img, noise_dn)
    cols = np.clip(np.asarray(ext.peak, dtype=np.int64), 0, W - 1)
    return np.any(planes[np.arange(H), cols, :].astype(np.float64) >= top, axis=-1)


def unclear_rows(ext: Extents, original=None, noise_dn=None, *, guided: bool = False) -> np.ndarray:
    """The rows of ``ext`` a photograph's reference leaves out as unclear, shape (H,) bool: its :func:`dim_rows`
    (``guided`` as there), less those whose peak is clipped in ``original`` (:func:`clipped_peaks`, with ``noise_dn``)
    when it is given.
    The one home of the convention, read on a transplant's estimate (:func:`row_states`) and on a render's truth
    (``stripebench predictcheck --rows clear``; docs/predict.md, "Which rows a reference scores").

    Examples
    --------
    A clipped core standing low in a glow (row 0), a faint stretch (row 1), a clear stripe:

    >>> img = np.full((5, 8), 40, np.uint8); img[:, 4] = [255, 60, 200, 200, 200]
    >>> e = Extents(np.full(5, 4), np.ones(5, bool), np.zeros(5), np.zeros(5), np.zeros(5), 1.0,
    ...             height=np.array([10.0, 20.0, 150.0, 160.0, 155.0]))
    >>> unclear_rows(e).tolist()
    [True, True, False, False, False]
    >>> unclear_rows(e, img, noise_dn=[1.0]).tolist()
    [False, True, False, False, False]
    """
    return dim_rows(ext, None if original is None else clipped_peaks(original, ext, noise_dn), guided=guided)


def glow_rows(frame, ext: Extents) -> np.ndarray:
    """The rows of ``ext`` whose stripe stands in a glow, shape (H,) bool: the median of ``frame`` (H, W; DN, an
    integer image) over :data:`GLOW_NEAR_PX` to :data:`GLOW_FAR_PX` px either side of the row's peak is at least
    :data:`GLOW_SHARE` of the top of its range; none in a float frame (no known top) or a row without a guide. With
    :func:`clipped_peaks` these are the rows :func:`row_states` reads as :func:`seen_states` does.

    Examples
    --------
    A core at 255 in a glow of 230 (row 0) and of 120 (row 1):

    >>> img = np.full((2, 40), 120, np.uint8); img[0, 5:35] = 230; img[:, 20] = 255
    >>> e = Extents(np.full(2, 20), np.ones(2, bool), np.zeros(2), np.zeros(2), np.full(2, 20.0), 1.0)
    >>> glow_rows(img, e).tolist()
    [True, False]
    """
    img = np.asarray(frame)
    if img.ndim != 2:
        raise ValueError(f"`frame` must be 2-D, got shape {img.shape}")
    H, W = img.shape
    if np.shape(ext.peak) != (H,):
        raise ValueError(f"`frame` must have the stripe's {np.shape(ext.peak)[0]} rows, got shape {img.shape}")
    out = np.zeros(H, bool)
    if not np.issubdtype(img.dtype, np.integer):
        return out
    level = GLOW_SHARE * float(np.iinfo(img.dtype).max)
    for r in np.flatnonzero(np.isfinite(ext.centre)):
        c = int(ext.peak[r])
        side = np.r_[img[r, max(c - GLOW_FAR_PX, 0):max(c - GLOW_NEAR_PX + 1, 0)],
                     img[r, min(c + GLOW_NEAR_PX, W):min(c + GLOW_FAR_PX + 1, W)]]
        out[r] = side.size > 0 and float(np.median(side)) >= level
    return out


def seen_states(image, truth, clipped=None) -> np.ndarray:
    """The states a photograph's reference gives the rows of ``truth`` (px, shape (H,), NaN: no stripe), shape (H,)
    int8: :func:`~bench.evaluate.outcomes.referenced_states`, and with ``clipped`` ((H,) bool: rows whose stripe's peak
    is clipped, :func:`clipped_peaks`) such a row is a stripe row even where the reference rule does not see it: a
    clipped core in a glow that fills the reference window, which the shipped set's references score (412 of the 469
    such rows of its estimates; docs/predict.md, "A clipped core in a glow is seen"). The one home of that reading,
    used on a render's truth (``predictcheck --rows clear``) and, in the rows whose glow is the surface's
    (:func:`glow_rows`), on a transplant's frames (:func:`row_states`' ``seen``); on every clipped row of the frames,
    (ae), it was rejected on renders.

    Examples
    --------
    A clipped core standing 5 DN over a glow as wide as the window (row 0), and a faint unclipped row (row 1):

    >>> img = np.full((2, 20), 30, np.uint8); img[0, 4:17] = 250; img[0, 10] = 255; img[1, 10] = 33
    >>> seen_states(img, [10.0, 10.0]).tolist(), seen_states(img, [10.0, 10.0], np.array([True, False])).tolist()
    ([-1, -1], [1, -1])
    """
    from bench.evaluate.outcomes import STRIPE, UNSURE, referenced_states

    states = referenced_states(image, truth)
    if clipped is not None:
        clipped = np.asarray(clipped, bool)
        if clipped.shape != states.shape:
            raise ValueError(f"`clipped` must have one entry per row, shape {states.shape}, got {clipped.shape}")
        states[(states == UNSURE) & clipped] = STRIPE
    return states


def row_states(ext: Extents, truth, image, keep=None, unclear=None, seen=None) -> np.ndarray:
    """The row states of a transplant, read as a photograph's reference would be, shape (H,) int8.

    A row with a moved centre is :data:`bench.evaluate.outcomes.STRIPE` where the real set's
    reference rule sees the moved stripe in ``image`` (:func:`~bench.evaluate.outcomes.referenced_states`) and the
    row is not one left out (``unclear``, shape (H,) bool: :func:`unclear_rows` of ``ext`` and its photograph, which a
    reference leaves out, and ``bench.run.predict.transplant_frames`` adds :func:`landed_rows`; without it,
    :func:`dim_rows` of ``ext``), else ``UNSURE``; a row the stripe
    crosses without a moved centre is ``UNSURE``; every other row is
    ``NO_STRIPE`` at least ``GAP_ROWS`` rows from the stripe and ``UNSURE`` nearer
    (:func:`~bench.evaluate.outcomes.fallback_states`, the real set's rule for references without states).
    With ``keep`` (:func:`transplant`'s), the rows it leaves out hold no stripe and count as rows without one.
    With ``seen`` (shape (H,) bool: rows whose stripe is a clipped core in a glow, :func:`clipped_peaks` and
    :func:`glow_rows` of the photograph), those rows are read as :func:`seen_states` reads them, a stripe row where
    the reference rule does not see the core in its glow, as the shipped set's references score them
    (docs/predict.md, "A clipped core in a glow of the surface's").

    Examples
    --------
    >>> vis = np.r_[np.zeros(10, bool), np.ones(10, bool), np.zeros(20, bool)]
    >>> e = Extents(np.full(40, 5), vis, np.full(40, 3), np.full(40, 7), np.where(vis, 5.0, np.nan), 1.0)
    >>> img = np.zeros((40, 30)); img[10:20, 25] = 100.0
    >>> s = row_states(e, np.r_[np.full(10, np.nan), np.full(10, 25.0), np.full(20, np.nan)], img)
    >>> s[10:20].tolist() == [1] * 10, s[20:34].tolist() == [-1] * 14, s[34:].tolist() == [0] * 6
    (True, True, True)
    """
    from bench.evaluate.outcomes import STRIPE, UNSURE, fallback_states, referenced_states

    t = np.asarray(truth, dtype=np.float64)
    unclear = dim_rows(ext) if unclear is None else np.asarray(unclear, bool)
    if unclear.shape != t.shape:
        raise ValueError(f"`unclear` must have one entry per row, shape {t.shape}, got {unclear.shape}")
    lo, _ = _span_extents(ext, np.shape(image)[1])
    crossed = (lo >= 0) | np.isfinite(ext.centre)
    if keep is not None:
        crossed &= np.asarray(keep, bool)
    states = fallback_states(np.where(crossed, 0.0, np.nan))
    states[states == STRIPE] = UNSURE
    moved = np.isfinite(t)
    if seen is not None and np.shape(seen) != t.shape:
        raise ValueError(f"`seen` must have one entry per row, shape {t.shape}, got {np.shape(seen)}")
    if moved.any():
        states[moved] = (referenced_states(image, t) if seen is None else seen_states(image, t, seen))[moved]
        states[moved & unclear] = UNSURE  # as a reference leaves an unclear row out
    return states.astype(np.int8)
