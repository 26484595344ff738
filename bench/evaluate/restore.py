"""Restored surfaces: fill the rows a tracker missed from their neighbours.

The restoration is an explicit setting of an experiment configuration
(``restore``, recorded in ``summary.json``), one of :data:`METHODS`:

``"rows"`` (default)
    Linear interpolation along the rows of each frame between the nearest
    reported rows (constant beyond the first and last); a frame with nothing
    reported takes the nearest frame's values (:func:`fill_depth_map`). This is
    itself a bridging tracker: a threshold tracker that misses a dim stretch
    gets it back by interpolation.
``"none"``
    Nothing is filled: a row the tracker missed has no depth, and a sample
    point there counts as a miss (outside every error band) in the robust
    statistics and is dropped from the paper's ratio.
"""

from __future__ import annotations

import numpy as np

__all__ = ["fill_rows", "fill_depth_map", "restore_depth_map", "METHODS"]

METHODS = ("rows", "none")


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


def restore_depth_map(depth, method: str = "rows") -> tuple[np.ndarray, np.ndarray]:
    """Restore a (frames, rows) depth map by ``method`` (one of :data:`METHODS`).

    Returns
    -------
    restored : ndarray (F, H)
    was_filled : ndarray (F, H) bool

    Examples
    --------
    >>> d = np.array([[1.0, np.nan, 3.0]])
    >>> restore_depth_map(d, "rows")[0].tolist(), restore_depth_map(d, "none")[0].tolist()
    ([[1.0, 2.0, 3.0]], [[1.0, nan, 3.0]])
    """
    if method == "rows":
        return fill_depth_map(depth)
    if method == "none":
        d = np.asarray(depth, dtype=np.float64)
        if d.ndim != 2:
            raise ValueError(f"`depth` must be 2-D (frames, rows), got shape {d.shape}")
        return d.copy(), np.zeros(d.shape, bool)
    raise ValueError(f"`method` must be one of {', '.join(METHODS)}, got {method!r}")
