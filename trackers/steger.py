"""``steger``: Steger's unbiased detector of curvilinear structures (1998)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from scipy import ndimage as ndi

from ._base import Track
from ._params import check_optional_real, check_real
from ._stats import default_threshold, robust_level
from .threshold import ThresholdTracker

__all__ = ["StegerTracker", "gaussian_derivatives", "default_sigma", "acceptance"]


def default_sigma(width: float) -> float:
    """Steger's scale for a line of full width ``width`` px: ``width / (2 sqrt(3))``.

    Steger (1998, sec. 3) shows that a bar-shaped line of half width ``w``
    gives a single, well-separated ridge in the Gaussian-smoothed image when
    ``sigma >= w / sqrt(3)``; the default takes the smallest such scale (the
    least smoothing, best localisation) for ``w = width / 2``.
    """
    return width / (2.0 * math.sqrt(3.0))


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
def ridge_rows(image, d, best_col, img_thr, s_thr, min_nx, half, columns, score):
    """Per row, the accepted ridge point nearest the strongest response.

    Candidates: the row's strongest-response column ``j*`` and its two
    neighbours, in that order of preference (then greater strength, then
    left). A candidate is a ridge point if ``lambda < 0``, its offset
    ``t = -(g . n) / lambda`` along the normal ``n`` satisfies
    ``|t nx| <= half`` and ``|t ny| <= half``, and ``|nx| >= min_nx``. The row
    reports ``j + t / nx``, where the ridge's tangent line crosses the row,
    and score ``-lambda``, if ``-lambda > s_thr`` and ``image[r, j] > img_thr``.
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
        if bj >= 0 and bs > s_thr and image[r, bj] > img_thr:
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
    (:func:`acceptance`: 0.62 px at the default scale), without which a
    ridge near a pixel boundary is rejected by both pixels. The ridge
    strength ``-lambda`` is the score.

    The stripe is roughly vertical, so one point is reported per row: the
    accepted ridge point at the row's strongest response ``j*`` (the column
    of greatest ``-lambda``) or, failing that, at a neighbour of ``j*``
    (the greater strength first); its position is converted to the column
    where the ridge's tangent line crosses the row's centre line,
    ``j + t / n_x`` (exact for a straight stripe of any tilt).

    Detection: the row reports NaN unless, at the chosen point,

    * the ridge strength exceeds ``b_s + max(k_sigma * s_s, rel * (m_s - b_s))``,
      the threshold rule of :class:`~trackers.threshold.ThresholdTracker`
      applied to the strength image (``b_s``, ``s_s``: median and
      1.4826 x MAD of a fixed sample, ``m_s`` its maximum), and
    * the pixel's intensity exceeds the ``threshold`` tracker's threshold on
      the image (same ``threshold``, ``k_sigma``, ``rel``), which also keeps
      flat frames, where the filters leave rounding-level curvature, empty;
    * the ridge is within ``max_tilt`` of the vertical (``|n_x| >= cos``),
      beyond which a row crossing is ill-defined.

    Parameters
    ----------
    threshold, k_sigma, rel
        As for :class:`~trackers.threshold.ThresholdTracker` (the image
        threshold; ``k_sigma`` and ``rel`` also set the strength threshold).
    sigma : float or None, default None
        Scale of the Gaussian derivatives in pixels, > 0.5; ``None`` uses
        :func:`default_sigma` of ``width``.
    width : float, default 4.0
        Expected full width of the stripe in pixels (about its FWHM); gives
        ``sigma = width / (2 sqrt(3)) = 1.15`` px by default (floored at
        0.6 px).
    max_tilt : float, default 60.0
        Largest angle between the ridge and the vertical, in degrees.

    Notes
    -----
    The crossing lies at most ``h / cos(max_tilt)^2`` px from the chosen
    pixel; columns are clipped to the image, [-0.5, W - 0.5]. The derivatives are
    computed in float32; the ``background`` frame is ignored.
    """

    name = "steger"
    subpixel = True

    def __init__(self, threshold=None, k_sigma=5.0, rel=0.25, sigma=None, width=4.0, max_tilt=60.0):
        super().__init__(threshold=threshold, k_sigma=k_sigma, rel=rel)
        self.sigma = sigma
        self.width = width
        self.max_tilt = max_tilt

    def _validate_params(self):
        super()._validate_params()
        check_optional_real("sigma", self.sigma, low=0.5, low_open=True)
        check_real("width", self.width, low=0, low_open=True)
        check_real("max_tilt", self.max_tilt, low=0, high=90)
        if self.max_tilt >= 90:
            raise ValueError(f"`max_tilt` must be < 90, got {self.max_tilt!r}")

    def scale(self) -> float:
        """The derivative filters' scale in pixels."""
        return float(self.sigma) if self.sigma is not None else max(0.6, default_sigma(float(self.width)))

    def _track(self, image, background):
        H, W = image.shape
        _, _, img_thr = self._level(image)
        d = gaussian_derivatives(image, self.scale())
        strength = np.empty((W, H), np.float32)
        best_col = np.empty(H, np.int64)
        ridge_strength(d, strength, best_col)
        sb, ss, sm = robust_level(strength)
        s_thr = default_threshold(sb, ss, sm, float(self.k_sigma), float(self.rel))
        columns = np.empty(H)
        score = np.empty(H)
        min_nx = math.cos(math.radians(float(self.max_tilt)))
        ridge_rows(image, d, best_col, img_thr, s_thr, min_nx, acceptance(self.scale()), columns, score)
        np.clip(columns, -0.5, W - 0.5, out=columns)
        return Track(columns, score)
