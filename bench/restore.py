"""Restored surfaces: fill the rows a tracker missed from their neighbours."""

from __future__ import annotations

import numpy as np

__all__ = ["fill_rows", "fill_depth_map"]


def fill_rows(values) -> np.ndarray:
    """Fill NaNs of a 1-D profile by linear interpolation between the nearest
    valid entries (constant beyond the first and last); all-NaN stays NaN.

    >>> fill_rows([np.nan, 1.0, np.nan, 3.0, np.nan]).tolist()
    [1.0, 1.0, 2.0, 3.0, 3.0]
    """
    v = np.asarray(values, dtype=np.float64)
    ok = ~np.isnan(v)
    if ok.all() or not ok.any():
        return v.copy()
    idx = np.arange(v.size)
    return np.interp(idx, idx[ok], v[ok])


def fill_depth_map(depth) -> tuple[np.ndarray, np.ndarray]:
    """Fill a (frames, rows) depth map for figures and samples.

    Each frame is filled along its rows (:func:`fill_rows`); a frame with no
    value at all takes, row by row, the nearest frame's filled values.

    Returns
    -------
    filled : ndarray (F, H)
    was_filled : ndarray (F, H) bool
        Cells that were NaN and now hold a value.
    """
    d = np.asarray(depth, dtype=np.float64)
    if d.ndim != 2:
        raise ValueError(f"`depth` must be 2-D (frames, rows), got shape {d.shape}")
    out = np.array([fill_rows(row) for row in d]) if d.size else d.copy()
    empty = np.isnan(out).all(axis=1)
    if empty.any() and not empty.all():
        have = np.flatnonzero(~empty)
        for f in np.flatnonzero(empty):
            out[f] = out[have[np.argmin(np.abs(have - f))]]
    return out, np.isnan(d) & ~np.isnan(out)
