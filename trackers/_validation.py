"""Input validation shared by every tracker (the public boundary)."""

from __future__ import annotations

import numpy as np

__all__ = ["check_image", "check_background", "check_colour"]


def check_image(image, name: str = "image") -> np.ndarray:
    """Validate a camera frame and return it as ``uint8`` or ``float64``.

    Parameters
    ----------
    image : array_like, shape (H, W)
        Real-valued frame in camera units (uint8 DN or float).
    name : str
        Argument name used in error messages.

    Returns
    -------
    ndarray, shape (H, W)
        The input itself when it is already a C-contiguous ``uint8`` or
        ``float64`` array (never modified), else a contiguous copy (``uint8``
        stays ``uint8``; every other dtype becomes ``float64``).

    Raises
    ------
    ValueError
        If the array is not 2-D, is empty, is not real-numeric (bool, complex,
        strings and objects are refused) or holds NaN or infinity.

    Examples
    --------
    >>> check_image(np.zeros((3, 4, 5)))
    Traceback (most recent call last):
    ...
    ValueError: `image` must be 2-D, got shape (3, 4, 5)
    """
    try:
        arr = np.asarray(image)
    except (ValueError, TypeError) as exc:  # ragged nested sequences
        raise ValueError(f"`{name}` must be a 2-D numeric array, got {type(image).__name__}: {exc}") from None
    if arr.ndim != 2:
        raise ValueError(f"`{name}` must be 2-D, got shape {arr.shape}")
    if arr.shape[0] == 0 or arr.shape[1] == 0:
        raise ValueError(f"`{name}` must not be empty, got shape {arr.shape}")
    if arr.dtype.kind not in "iuf":
        raise ValueError(f"`{name}` must hold real numbers (integer or float), got dtype {arr.dtype}")
    if arr.dtype == np.uint8:
        return np.ascontiguousarray(arr)
    if arr.dtype.kind == "f":
        if not np.isfinite(arr).all():
            bad = int(np.size(arr) - np.count_nonzero(np.isfinite(arr)))
            raise ValueError(f"`{name}` must be finite, got {bad} NaN or infinite value(s)")
    return np.ascontiguousarray(arr, dtype=np.float64)


def check_background(background, shape: tuple[int, int]) -> np.ndarray | None:
    """Validate an optional laser-off frame against the image shape."""
    if background is None:
        return None
    bg = check_image(background, name="background")
    if bg.shape != tuple(shape):
        raise ValueError(f"`background` must have the shape of `image` {tuple(shape)}, got {bg.shape}")
    return bg


def check_colour(colour, shape) -> np.ndarray | None:
    """A frame's colour evidence, checked: None, or a real (H, W) array the frame's ``shape`` with values
    in [0, 1] (NaN allowed: no evidence there), as float64.

    Raises
    ------
    ValueError
        Another shape, a non-real array, or values outside [0, 1] (one line naming ``colour``).
    """
    if colour is None:
        return None
    try:
        c = np.asarray(colour)
    except (ValueError, TypeError) as exc:
        raise ValueError(f"`colour` must be a real array, got {type(colour).__name__}: {exc}") from None
    if c.dtype.kind not in "uif":
        raise ValueError(f"`colour` must be a real array, got dtype {c.dtype}")
    if c.shape != tuple(shape):
        raise ValueError(f"`colour` must have the frame's shape {tuple(shape)}, got {c.shape}")
    c = np.asarray(c, np.float64)
    fin = c[np.isfinite(c)]
    if np.isinf(c).any() or (fin.size and (fin.min() < 0 or fin.max() > 1)):
        raise ValueError("`colour` must hold laser shares in [0, 1] (NaN: none), got values outside")
    return c
