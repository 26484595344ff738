"""Robust image statistics shared by the threshold-type trackers."""

from __future__ import annotations

from math import gcd

import numpy as np

__all__ = ["robust_level", "row_peaks", "noise_floor", "default_threshold"]

_SAMPLES = 8192
_MAD_TO_SIGMA = 1.482602218505602


def _stride(n: int, width: int) -> int:
    """A sampling stride of about n / _SAMPLES that is coprime with the image
    width, so the samples do not fall on the same few columns in every row."""
    step = max(1, n // _SAMPLES)
    while width > 1 and gcd(step, width) != 1:
        step += 1
    return step


def robust_level(image: np.ndarray) -> tuple[float, float, float]:
    """Background level, noise and maximum of a frame.

    The background is the median and the noise the scaled median absolute
    deviation (``1.4826 * MAD``) of a deterministic sample of about 8192
    pixels taken with a stride coprime with the width (all pixels for small
    frames). The stripe covers a few percent of the pixels at most, so neither
    statistic sees it. Computed in float64, so a ``uint8`` image and its
    ``float64`` copy give identical values.

    Parameters
    ----------
    image : ndarray, shape (H, W)

    Returns
    -------
    background, sigma, maximum : float
        In image units.
    """
    flat = image.reshape(-1)
    sample = flat[:: _stride(flat.size, image.shape[1])].astype(np.float64)
    med = float(np.median(sample))
    sigma = _MAD_TO_SIGMA * float(np.median(np.abs(sample - med)))
    return med, sigma, float(image.max())


def row_peaks(image: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Column (leftmost on ties) and value of each row's maximum, (H,) each."""
    cols = np.argmax(image, axis=1)
    vals = np.take_along_axis(image, cols[:, None], axis=1)[:, 0].astype(np.float64)
    return cols, vals


def noise_floor(sigma: float, background: float, maximum: float) -> float:
    """Noise used to express contrasts in noise units: ``sigma``, but never
    below 1e-3 of the frame's dynamic range (noise-free renders and quantised
    flat backgrounds have a MAD of zero) nor below the smallest float."""
    return max(sigma, 1e-3 * (maximum - background), np.finfo(np.float64).tiny)


def default_threshold(background: float, sigma: float, maximum: float, k_sigma: float, rel: float) -> float:
    """``background + max(k_sigma * sigma, rel * (maximum - background))``."""
    return background + max(k_sigma * sigma, rel * (maximum - background))
