"""What a tracker sees of a photograph: one channel of a colour image, and a turned frame.

Pure pixel operations (arrays in, arrays out), used wherever a photograph or a colour render
becomes a tracker's 2-D frame: :mod:`bench.store.realset` (photographs), :mod:`bench.run.camera_view`
(colour renders), the tuning procedures and the overlays.
"""

from __future__ import annotations

import numpy as np

from bench.evaluate.colour import LASER_INDEX

__all__ = ["CHANNELS", "ROTATIONS", "LASERS", "select_channel", "rotate_image", "unrotate_points", "downscale",
           "downscale_columns"]

#: What a tracker may see of a colour image (``--channel``).
CHANNELS = ("auto", "r", "g", "b", "gray", "excess")
#: The turns a frame may take, counter-clockwise (deg).
ROTATIONS = (0, 90, 180, 270)
#: The laser colours.
LASERS = tuple(LASER_INDEX)
_CHANNEL_INDEX = {"r": 0, "g": 1, "b": 2}


def select_channel(image, channel: str = "auto", laser: str = "red") -> np.ndarray:
    """The 2-D frame a tracker sees.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, 3)
        As :func:`bench.store.realset.read_image` returns it.
    channel : {'auto', 'r', 'g', 'b', 'gray', 'excess'}
        ``r``/``g``/``b``: that colour channel; ``gray``: Rec. 709 luma
        (0.2126 R + 0.7152 G + 0.0722 B); ``excess``: the laser's channel minus
        the mean of the other two, clipped at 0; ``auto``: on a colour image the
        excess where the laser's channel is below saturation, moving to the
        laser's channel as it saturates (:func:`bench.evaluate.colour.saturation_blend`
        with its tuned knee, so a clipped white stripe core is kept), the image
        itself on a grey one (also when stored as RGB with three equal
        channels). A 2-D image is returned unchanged for every channel.
    laser : {'red', 'green', 'blue'}
        The laser's colour (for ``excess`` and ``auto``).

    Returns
    -------
    ndarray, shape (H, W)
        The channel in the image's units (DN): ``uint8``/``uint16`` for a plain
        channel, ``float64`` for ``gray``, ``excess`` and ``auto`` on colour.

    Raises
    ------
    ValueError
        An unknown ``channel`` or ``laser``.

    Examples
    --------
    >>> rgb = np.array([[[200, 100, 50]]], dtype=np.uint8)
    >>> float(select_channel(rgb, "excess", "red")[0, 0])
    125.0
    >>> int(select_channel(rgb, "g")[0, 0])
    100
    """
    if channel not in CHANNELS:
        raise ValueError(f"`channel` must be one of {', '.join(CHANNELS)}, got {channel!r}")
    if laser not in LASERS:
        raise ValueError(f"`laser` must be one of {', '.join(LASERS)}, got {laser!r}")
    img = np.asarray(image)
    if img.ndim == 2:
        return img
    if img.ndim != 3 or img.shape[2] != 3:
        raise ValueError(f"`image` must have shape (H, W) or (H, W, 3), got {img.shape}")
    if channel == "auto":
        if np.array_equal(img[..., 0], img[..., 1]) and np.array_equal(img[..., 0], img[..., 2]):
            return np.ascontiguousarray(img[..., 0])  # a grey picture stored as RGB
        from bench.evaluate.colour import saturation_blend

        return saturation_blend(img, laser)
    if channel in _CHANNEL_INDEX:
        return np.ascontiguousarray(img[..., _CHANNEL_INDEX[channel]])
    f = img.astype(np.float64)
    if channel == "gray":
        return 0.2126 * f[..., 0] + 0.7152 * f[..., 1] + 0.0722 * f[..., 2]
    k = LASER_INDEX[laser]
    others = [i for i in range(3) if i != k]
    return np.maximum(f[..., k] - 0.5 * (f[..., others[0]] + f[..., others[1]]), 0.0)


def rotate_image(image, rotate_deg: int) -> np.ndarray:
    """Turn an image counter-clockwise by ``rotate_deg`` (0, 90, 180, 270), e.g.
    so that a horizontal stripe becomes vertical.

    Examples
    --------
    >>> rotate_image(np.arange(6).reshape(2, 3), 90).tolist()
    [[2, 5], [1, 4], [0, 3]]
    """
    if rotate_deg not in ROTATIONS:
        raise ValueError(f"`rotate_deg` must be one of 0, 90, 180, 270, got {rotate_deg!r}")
    return np.ascontiguousarray(np.rot90(np.asarray(image), k=rotate_deg // 90))


def unrotate_points(rows, cols, rotate_deg: int, shape) -> tuple[np.ndarray, np.ndarray]:
    """Map (row, col) points of a frame turned by :func:`rotate_image` back to
    the original image of shape ``shape`` (H, W, ...).

    Examples
    --------
    >>> img = np.zeros((2, 3)); img[0, 2] = 1
    >>> r, c = np.nonzero(rotate_image(img, 90))
    >>> [float(v[0]) for v in unrotate_points(r, c, 90, img.shape)]
    [0.0, 2.0]
    """
    r = np.asarray(rows, dtype=np.float64)
    c = np.asarray(cols, dtype=np.float64)
    H0, W0 = shape[0], shape[1]
    k = rotate_deg // 90
    if rotate_deg not in ROTATIONS:
        raise ValueError(f"`rotate_deg` must be one of 0, 90, 180, 270, got {rotate_deg!r}")
    if k == 0:
        return r, c
    if k == 1:
        return c, (W0 - 1) - r
    if k == 2:
        return (H0 - 1) - r, (W0 - 1) - c
    return (H0 - 1) - c, r


def downscale(image, factor: int) -> np.ndarray:
    """Each ``factor`` x ``factor`` block of an image averaged into one pixel, as a camera app
    shrinks a large sensor's frame (an integer image is rounded back to its dtype); the rows and
    columns that do not fill a block are dropped.

    Examples
    --------
    >>> img = np.arange(16, dtype=np.uint8).reshape(4, 4)
    >>> downscale(img, 2).tolist()
    [[2, 4], [10, 12]]
    """
    if isinstance(factor, bool) or not isinstance(factor, (int, np.integer)) or factor < 1:
        raise ValueError(f"`factor` must be an integer >= 1, got {factor!r}")
    a = np.asarray(image)
    if factor == 1:
        return a
    H, W = (a.shape[0] // factor) * factor, (a.shape[1] // factor) * factor
    blocks = a[:H, :W].astype(np.float64).reshape(H // factor, factor, W // factor, factor, *a.shape[2:])
    out = blocks.mean(axis=(1, 3))
    if np.issubdtype(a.dtype, np.integer):
        info = np.iinfo(a.dtype)
        return np.clip(np.rint(out), info.min, info.max).astype(a.dtype)
    return out.astype(a.dtype)


def downscale_columns(columns, factor: int) -> np.ndarray:
    """Per-row columns (px, pixel-centre convention; NaN: none) of an image, for its
    :func:`downscale`: each block of ``factor`` rows gets the mean of its columns (NaN if any is
    NaN), mapped to the smaller image's columns, ``(c - (factor - 1) / 2) / factor``.

    Examples
    --------
    >>> downscale_columns([10.5, 11.5, 20.0, np.nan], 2).tolist()
    [5.25, nan]
    """
    c = np.asarray(columns, dtype=np.float64)
    n = (c.shape[0] // factor) * factor
    rows = c[:n].reshape(-1, factor).mean(axis=1)
    return (rows - (factor - 1) / 2.0) / factor
