"""``steger``: Steger's unbiased detector of curvilinear structures (1998)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from scipy import ndimage as ndi

from ._base import Track
from ._params import Real
from .threshold import DEFAULT_K_SIGMA, DEFAULT_PROMINENCE, ThresholdTracker

#: Steger's detection defaults: the noise multiple and prominence of its per-row rule on
#: the ridge strength and the intensity, and the least chain of rows (chosen by
#: ``stripebench tune threshold``, stage 3: the objective of the threshold family's stage, steger alone).
DEFAULT_STEGER = {"k_sigma": 8.0, "prominence": 1.25, "min_run": 5}

__all__ = ["StegerTracker", "DEFAULT_STEGER", "gaussian_derivatives", "default_sigma", "acceptance", "estimate_width",
           "WIDTH_RANGE", "FALLBACK_WIDTH", "SCALE_PER_WIDTH"]

#: Range of the stripe width (px) that :func:`estimate_width` returns.
WIDTH_RANGE = (1.0, 48.0)
#: Width (px) assumed when no row of a frame is detected.
FALLBACK_WIDTH = 4.0
#: Scale per px of the width measured on a frame (above Steger's bound
#: ``1 / (2 sqrt(3)) = 0.29``: at the bound the smoothed top of a wide clipped
#: plateau is so flat that noise moves the Newton step out of the pixel; 0.4
#: reported every row of plateaus of 19 and 30 px where 0.29 reported 96 % and
#: 28 %, in a small seeded check on synthetic stripes).
SCALE_PER_WIDTH = 0.4


def default_sigma(width: float) -> float:
    """Steger's scale for a line of full width ``width`` px: ``width / (2 sqrt(3))``.

    Steger (1998, sec. 3) shows that a bar-shaped line of half width ``w``
    gives a single, well-separated ridge in the Gaussian-smoothed image when
    ``sigma >= w / sqrt(3)``; the default takes the smallest such scale (the
    least smoothing, best localisation) for ``w = width / 2``.
    """
    return width / (2.0 * math.sqrt(3.0))


def estimate_width(image: np.ndarray, k_sigma: float = DEFAULT_K_SIGMA,
                   prominence: float = DEFAULT_PROMINENCE, quantum=None) -> float:
    """The stripe's full width at half its contrast, px, measured on a frame.

    The median, over the rows that the threshold trackers' per-row rule
    (:func:`trackers._detect.detect_rows`, every candidate row) reports, of the length of the run
    of pixels around the row's peak brighter than half its contrast over the
    row's median (a clipped plateau and its flanks included), clipped to
    :data:`WIDTH_RANGE`; :data:`FALLBACK_WIDTH` if no row is reported.

    Parameters
    ----------
    image : ndarray, shape (H, W), uint8 or float64
    k_sigma, prominence : float
        As for :class:`~trackers.threshold.ThresholdTracker`.
    quantum : float or None
        The frame's quantisation step (:func:`trackers._detect.detect_rows`).

    Examples
    --------
    >>> img = np.zeros((4, 30)); img[:, 10:17] = 100.0  # a 7 px plateau
    >>> estimate_width(img)
    7.0
    """
    from ._detect import noise_level, row_statistics

    H = image.shape[0]
    col, mid, lo, hi = (np.empty(H, np.int64) for _ in range(4))
    peak, bg, noise, runner = (np.empty(H) for _ in range(4))
    integral = row_statistics(image, col, mid, peak, bg, noise, runner, lo, hi)
    c = peak - bg
    hit = (c > 0) & (c > k_sigma * noise_level(noise, peak, bg, integral, quantum)) & \
        (c > prominence * (runner - bg))
    if not hit.any():
        return FALLBACK_WIDTH
    return float(np.clip(np.median((hi - lo + 1)[hit]), *WIDTH_RANGE))


def acceptance(sigma: float) -> float:
    """Half side of the square around a pixel centre where a ridge point is accepted, px.

    Steger accepts the point ``t n`` when it lies in the pixel, ``|t n_x|``
    and ``|t n_y| <= 1/2``. But ``t`` is a Newton step on the smoothed
    profile, which overshoots: on a Gaussian ridge of standard deviation
    ``w`` (``w >= sigma`` after smoothing) a pixel at distance ``x`` from the
    centre gets ``t = x w^2 / (w^2 - x^2)``, so a ridge lying near a pixel
    boundary is rejected by *both* pixels (measured: about 10 % of the rows
    of a sharp stripe at sigma = 1.15). For ``|x| <= 1/2`` the overshoot is
    at most ``(1/8) / (sigma^2 - 1/4)``; the acceptance is widened by that
    bound, ``1/2 + (1/8) / (sigma^2 - 1/4)`` (0.62 at the default scale),
    and capped at 1 px.
    """
    return min(1.0, 0.5 + 0.125 / (sigma * sigma - 0.25))


def gaussian_derivatives(image: np.ndarray, sigma: float) -> np.ndarray:
    """Gaussian-derivative images of a frame, with SciPy's Gaussian filters.

    ``scipy.ndimage.gaussian_filter1d`` (order 0, 1, 2, ``mode='nearest'``,
    truncated at 4 sigma) along the rows, then along the columns: the five
    separable products give the first and second partial derivatives of the
    image smoothed with a Gaussian of standard deviation ``sigma``. Computed
    in float32 (a uint8 frame and its float64 copy give identical results);
    the column pass works on transposed copies, which is four times faster
    than filtering along axis 0 of a C-ordered array.

    Parameters
    ----------
    image : ndarray, shape (H, W)
    sigma : float
        Scale in pixels.

    Returns
    -------
    ndarray of float32, shape (5, W, H)
        ``rx, ry, rxx, rxy, ryy`` (x = column, y = row, both increasing),
        each *transposed*: ``out[k, j, r]`` is the value at row r, column j.
    """
    f = np.asarray(image, dtype=np.float32)
    H, W = f.shape
    # one buffer of 8 planes (fewer fresh pages than separate arrays): the
    # row passes in planes 0-2, their transposes in 5-7, the outputs in 0-4
    buf = np.empty((8, H * W), np.float32)
    for order in range(3):
        ndi.gaussian_filter1d(f, sigma, axis=1, order=order, mode="nearest", output=buf[order].reshape(H, W))
    for order in range(3):
        buf[5 + order].reshape(W, H)[...] = buf[order].reshape(H, W).T
    # (output plane, source plane = 5 + x order, y order): rx, ry, rxx, rxy, ryy
    for plane, src, yo in ((0, 6, 0), (1, 5, 1), (2, 7, 0), (3, 6, 1), (4, 5, 2)):
        ndi.gaussian_filter1d(buf[src].reshape(W, H), sigma, axis=1, order=yo, mode="nearest",
                              output=buf[plane].reshape(W, H))
    return buf[:5].reshape(5, W, H)


@njit(cache=True, nogil=True)
def _principal_value(a, b, c):
    """Eigenvalue of largest magnitude of ``[[a, b], [b, c]]`` (as :func:`_principal`)."""
    half = 0.5 * (a + c)
    dd = math.sqrt(0.25 * (a - c) * (a - c) + b * b)
    lm = half - dd
    lp = half + dd
    return lm if abs(lm) >= abs(lp) else lp


@njit(cache=True, nogil=True)
def _principal(a, b, c):
    """Eigenvalue of largest magnitude of ``[[a, b], [b, c]]`` and its unit
    eigenvector ``(nx, ny)`` (``(1, 0)`` when the matrix is isotropic)."""
    lam = _principal_value(a, b, c)
    # two forms of the eigenvector; the longer is the better conditioned
    x1 = lam - c
    y1 = b
    x2 = b
    y2 = lam - a
    n1 = x1 * x1 + y1 * y1
    n2 = x2 * x2 + y2 * y2
    if n1 >= n2:
        if n1 == 0.0:
            return lam, 1.0, 0.0
        s = math.sqrt(n1)
        return lam, x1 / s, y1 / s
    s = math.sqrt(n2)
    return lam, x2 / s, y2 / s


@njit(cache=True, nogil=True)
def ridge_strength(d, strength, best_col):
    """``strength = -lambda`` (eigenvalue of largest magnitude of the
    Hessian) at every pixel, and each row's column of greatest strength
    (leftmost on ties). ``d`` and ``strength`` are transposed (W, H) arrays."""
    W = d.shape[1]
    H = d.shape[2]
    best = np.full(H, -np.inf)
    for j in range(W):
        for r in range(H):
            s = -_principal_value(float(d[2, j, r]), float(d[3, j, r]), float(d[4, j, r]))
            strength[j, r] = s
            if s > best[r]:
                best[r] = s
                best_col[r] = j


@njit(cache=True, nogil=True)
def ridge_rows(image, d, best_col, strong, img_thr, min_nx, half, columns, score):
    """Per row, the accepted ridge point nearest the strongest response.

    Candidates: the row's strongest-response column ``j*`` and its two
    neighbours, in that order of preference (then greater strength, then
    left). A candidate is a ridge point if ``lambda < 0``, its offset
    ``t = -(g . n) / lambda`` along the normal ``n`` satisfies
    ``|t nx| <= half`` and ``|t ny| <= half``, and ``|nx| >= min_nx``. The row
    reports ``j + t / nx``, where the ridge's tangent line crosses the row,
    and score ``-lambda``, if ``strong[r]`` (the row's strength passed the
    detection) and ``image[r, j] > img_thr[r]``.
    """
    W = d.shape[1]
    H = d.shape[2]
    for r in range(H):
        columns[r] = np.nan
        score[r] = np.nan
        jc = best_col[r]
        bj = -1
        bdist = 2
        bs = -np.inf
        bcol = 0.0
        for k in range(3):
            j = jc if k == 0 else (jc - 1 if k == 1 else jc + 1)
            if j < 0 or j >= W:
                continue
            lam, nx, ny = _principal(float(d[2, j, r]), float(d[3, j, r]), float(d[4, j, r]))
            if lam >= 0.0 or abs(nx) < min_nx:
                continue
            t = -(float(d[0, j, r]) * nx + float(d[1, j, r]) * ny) / lam
            if abs(t * nx) > half or abs(t * ny) > half:
                continue
            dist = 0 if k == 0 else 1
            s = -lam
            if dist < bdist or (dist == bdist and s > bs):
                bj = j
                bdist = dist
                bs = s
                bcol = j + t / nx
        if bj >= 0 and strong[r] and image[r, bj] > img_thr[r]:
            columns[r] = bcol
            score[r] = bs


class StegerTracker(ThresholdTracker):
    """Steger's curvilinear structure detector, reporting the stripe's column in each row.

    Steger, C. (1998), "An unbiased detector of curvilinear structures",
    *IEEE Trans. PAMI* 20(2), 113-125. At every pixel the image is
    differentiated with Gaussian-derivative filters of scale ``sigma``
    (SciPy, :func:`gaussian_derivatives`); the Hessian's eigenvalue of
    largest magnitude ``lambda`` and its unit eigenvector ``n`` give the
    ridge normal, and the second-order Taylor expansion along ``n`` puts the
    ridge's centre at ``t n`` from the pixel centre,
    ``t = -(r_x n_x + r_y n_y) / lambda``. A bright line pixel has
    ``lambda < 0``, and the point is accepted when it lies within the pixel,
    ``|t n_x| <= h`` and ``|t n_y| <= h``: Steger's rule has ``h = 1/2``;
    here ``h`` is widened by the largest overshoot of the Taylor step
    (:func:`acceptance`: 0.62 px at sigma = 1.15 px), without which a
    ridge near a pixel boundary is rejected by both pixels. The ridge
    strength ``-lambda`` is the score.

    The stripe is roughly vertical, so one point is reported per row: the
    accepted ridge point at the row's strongest response ``j*`` (the column
    of greatest ``-lambda``) or, failing that, at a neighbour of ``j*``
    (the greater strength first); its position is converted to the column
    where the ridge's tangent line crosses the row's centre line,
    ``j + t / n_x`` (exact for a straight stripe of any tilt).

    Scale: ``sigma`` if given, else Steger's scale :func:`default_sigma` of
    ``width`` if given, else :data:`SCALE_PER_WIDTH` (0.4) times the width
    measured on the frame (:func:`estimate_width`: the median width at half
    contrast of the rows the threshold trackers report, 1-48 px); floored at
    0.6 px. A clipped plateau wider than about ``2 sqrt(3) sigma`` has no
    ridge at its centre at that scale (two at its edges instead), which is
    why the scale follows the stripe.

    Detection: a row is reported only where, at the chosen point,

    * the ridge strength passes the threshold trackers' per-row rule
      (:func:`trackers._detect.detect_rows`) on the row of the strength
      image: above the row's median by ``k_sigma`` times the pixel noise
      and ``prominence`` times above any ridge elsewhere in the row, in a
      chain of at least ``min_run`` such rows;
    * the pixel's intensity stands ``k_sigma`` times the pixel noise
      above the row's median (an explicit ``threshold``: exceeds it), which
      also keeps flat frames, where the filters leave rounding-level
      curvature, empty;
    * the ridge is within ``max_tilt`` of the vertical (``|n_x| >= cos``),
      beyond which a row crossing is ill-defined.

    With a laser-off frame (``background``) the detector runs on
    ``max(image - background, 0)``; without, on the image.

    Parameters
    ----------
    threshold : float or None, default None
        Explicit intensity threshold in image units (the per-row intensity
        test otherwise).
    k_sigma, prominence, min_run
        As for :class:`~trackers.threshold.ThresholdTracker` (for the
        intensity and the strength tests; ``min_run`` for the strength);
        defaults :data:`DEFAULT_STEGER`.
    sigma : float or None, default None
        Scale of the Gaussian derivatives in pixels, in (0.5, 64].
    width : float or None, default None
        Expected full width of the stripe in pixels (about its FWHM), in
        (0, 256]; ``None``: measured on each frame.
    max_tilt : float, default 60.0
        Largest angle between the ridge and the vertical, in degrees.
    stripe_test : dict or None, default None
        The stripe question's settings (:class:`trackers.StripeTest`; ``{}``: its
        defaults), asked of the reported rows on the frame the detector sees
        (with the laser-off frame and the colour evidence where given); a row it
        says no to reports nothing. None: not asked.

    Notes
    -----
    The crossing lies at most ``h / cos(max_tilt)^2`` px from the chosen
    pixel; columns are clipped to the image, [-0.5, W - 0.5]. The frame is
    divided by its largest absolute value before filtering (and the scores
    multiplied back), so any scale of the image units, 1e-300 or 1e300,
    gives the same rows; the derivatives are computed in float32.
    """

    name = "steger"
    subpixel = True

    def __init__(self, threshold=None, k_sigma=DEFAULT_STEGER["k_sigma"], prominence=DEFAULT_STEGER["prominence"],
                 sigma=None, width=None, max_tilt=60.0, min_run=DEFAULT_STEGER["min_run"], stripe_test=None):
        super().__init__(threshold=threshold, k_sigma=k_sigma, prominence=prominence, min_run=min_run,
                         stripe_test=stripe_test)
        self.sigma = sigma
        self.width = width
        self.max_tilt = max_tilt

    parameter_constraints = {**{k: v for k, v in ThresholdTracker.parameter_constraints.items() if k != "width_ratio"},
                             "sigma": Real(low=0.5, low_open=True, high=64, optional=True),
                             "width": Real(low=0, low_open=True, high=256, optional=True),
                             "max_tilt": Real(low=0, high=90, high_open=True)}

    def scale(self, image=None, quantum=None) -> float:
        """The derivative filters' scale in pixels (for ``image``, a validated
        frame with quantisation step ``quantum``, when neither ``sigma`` nor
        ``width`` is set; else :data:`FALLBACK_WIDTH` is assumed)."""
        if self.sigma is not None:
            return float(self.sigma)
        if self.width is not None:
            return max(0.6, default_sigma(float(self.width)))
        if image is None:
            return max(0.6, default_sigma(FALLBACK_WIDTH))
        return max(0.6, SCALE_PER_WIDTH * estimate_width(image, float(self.k_sigma), float(self.prominence), quantum))

    def find_stripe(self, image, background, colour=None):
        from ._detect import detect_rows
        from ._stripe import answer

        H, W = image.shape
        if background is not None:
            f = np.maximum(np.subtract(image, background, dtype=np.float64), 0.0)
        else:
            f = np.asarray(image, dtype=np.float64)
        top = float(np.abs(f).max())
        if top == 0.0:
            return Track.empty(H)
        whole = image.dtype.kind in "ui" and (background is None or background.dtype.kind in "ui") \
            or bool(np.array_equal(f, np.floor(f)))
        f = f / top
        quantum = 1.0 / top if whole else 0.0  # the frame's quantisation step, scaled as the frame
        k, prom = float(self.k_sigma), float(self.prominence)
        sigma = self.scale(f, quantum)
        d = gaussian_derivatives(f, sigma)
        strength = np.empty((W, H), np.float32)
        best_col = np.empty(H, np.int64)
        ridge_strength(d, strength, best_col)
        ds = detect_rows(np.ascontiguousarray(strength.T, dtype=np.float64), k, prom, min_run=int(self.min_run),
                         quantum=0.0)
        di = detect_rows(f, k, prom, quantum=quantum)
        img_thr = di.bg + k * di.noise if self.threshold is None else np.full(H, float(self.threshold) / top)
        columns = np.empty(H)
        score = np.empty(H)
        min_nx = math.cos(math.radians(float(self.max_tilt)))
        ridge_rows(f, d, best_col, ds.hit, img_thr, min_nx, acceptance(sigma), columns, score)
        np.clip(columns, -0.5, W - 0.5, out=columns)
        said = answer(self.stripe_test, f, columns, image=image, background=background, colour=colour)
        if said is not None:
            columns[~said.yes] = np.nan
            score[~said.yes] = np.nan
        return Track(columns, score * top)
