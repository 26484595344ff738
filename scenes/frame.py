"""What one rendered frame carries: images, radiances and the per-row ground truth."""

from __future__ import annotations

import dataclasses
from typing import Optional

import numpy as np

__all__ = ["PARTS", "Truth", "Frame", "false_columns"]

PARTS = ("background", "object", "support")
"""Names of :attr:`Truth.part`'s values 0, 1, 2 (the scene's shape ids are ``backdrop``, ``object``,
``support``)."""


@dataclasses.dataclass(frozen=True)
class Truth:
    """Per-row ground truth of the stripe.

    Attributes
    ----------
    columns : ndarray (H,), float64
        Continuous column (pixel ``u`` has its centre at ``u``; same convention as
        :meth:`scenes.Rig.px_mm`) where the laser plane meets the visible, lit
        surface on the row's centre line; NaN where there is none.
    points_cm : ndarray (H, 3), float64
        The world point: the float64 intersection of the pixel ray through
        ``(columns[v], v)`` with the laser plane; NaN likewise.
    on_object : ndarray (H,), bool
        True where that point lies on the object (False: background, support or none).
    part : ndarray (H,), int8
        What the point lies on: an index into :data:`PARTS` (0 background, 1 object,
        2 support), -1 where there is no truth.  When not given it is derived from
        ``on_object`` (1 there, 0 on other valid rows).
    false_mask : ndarray (H, W), bool, optional
        Pixels that see the laser sheet once mirrored by the object (false stripes, see
        :func:`scenes.truth.false_stripe_mask`); computed for the shiny materials
        (:data:`scenes.materials.SHINY`), all False for the others; None when not computed.
    """

    columns: np.ndarray
    points_cm: np.ndarray
    on_object: np.ndarray
    part: Optional[np.ndarray] = None
    false_mask: Optional[np.ndarray] = None

    def __post_init__(self):
        if self.part is None:
            part = np.where(self.on_object, 1, np.where(np.isfinite(self.columns), 0, -1)).astype(np.int8)
            object.__setattr__(self, "part", part)

    @property
    def valid(self) -> np.ndarray:
        """Rows with a truth point, bool (H,)."""
        return np.isfinite(self.columns)

    @property
    def false_columns(self) -> np.ndarray:
        """Columns of :attr:`false_mask` per row, float64 (H, K), NaN-padded (K = 0 when none).

        The input of :func:`bench.evaluate.metrics.false_lock_rate`.
        """
        if self.false_mask is None:
            return np.full((len(self.columns), 0), np.nan)
        return false_columns(self.false_mask)


@dataclasses.dataclass(frozen=True)
class Frame:
    """One exposure of the rig at one mirror angle.

    Attributes
    ----------
    image : ndarray (H, W), uint8
        Laser-on frame: sensor(ambient + laser), its own noise draw.
    background : ndarray (H, W), uint8
        Laser-off frame: sensor(ambient), an independent noise draw.
        With ``camera="rgb"``: the Rec. 709 luma of :attr:`rgb` (the harness gives trackers one
        channel of :attr:`rgb` instead, by ``bench``'s channel rule).
    background : ndarray (H, W), uint8
        Laser-off frame: sensor(ambient), an independent noise draw (``camera="rgb"``: the luma of
        :attr:`rgb_background`).
    radiance : ndarray (H, W) or (H, W, 3), float32
        Noise-free in-band radiance (W m⁻² sr⁻¹), ambient + laser, before any defocus; with
        ``camera="rgb"`` the effective radiance of each colour channel (R, G, B; see
        :mod:`scenes.colour_camera`).
    laser_radiance : ndarray (H, W) or (H, W, 3), float32
        Noise-free in-band radiance of the laser alone (per channel likewise).
    truth : Truth
    mirror_angle_deg : float
    variant : str
        Mitsuba variant that rendered it.
    rgb : ndarray (H, W, 3), uint8, or None
        ``camera="rgb"``: the laser-on photograph (demosaiced, white-balanced, sRGB, JPEG if asked);
        None for the mono camera.
    rgb_background : ndarray (H, W, 3), uint8, or None
        ``camera="rgb"``: the laser-off photograph; None for the mono camera.
    """

    image: np.ndarray
    background: np.ndarray
    radiance: np.ndarray
    laser_radiance: np.ndarray
    truth: Truth
    mirror_angle_deg: float
    variant: str
    rgb: Optional[np.ndarray] = None
    rgb_background: Optional[np.ndarray] = None


def false_columns(mask: np.ndarray) -> np.ndarray:
    """Per-row columns of a false-stripe mask, NaN-padded.

    Parameters
    ----------
    mask : ndarray (H, W), bool

    Returns
    -------
    ndarray (H, K), float64
        The marked pixel columns of each row in ascending order, NaN-padded to the most marked
        pixels in a row ``K`` (``K = 0`` for an empty mask).

    Examples
    --------
    >>> false_columns(np.array([[False, True, True], [False, False, False]]))
    array([[ 1.,  2.],
           [nan, nan]])
    """
    m = np.asarray(mask, bool)
    k = int(m.sum(axis=1).max()) if m.size else 0
    out = np.full((m.shape[0], k), np.nan)
    rows, cols = np.nonzero(m)
    if len(rows):
        starts = np.searchsorted(rows, np.arange(m.shape[0]))
        out[rows, np.arange(len(rows)) - starts[rows]] = cols
    return out
