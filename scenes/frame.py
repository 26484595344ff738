"""What one rendered frame carries: images, radiances and the per-row ground truth."""

from __future__ import annotations

import dataclasses
from typing import Optional

import numpy as np

__all__ = ["PARTS", "Truth", "Frame"]

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
    """

    columns: np.ndarray
    points_cm: np.ndarray
    on_object: np.ndarray
    part: Optional[np.ndarray] = None

    def __post_init__(self):
        if self.part is None:
            part = np.where(self.on_object, 1, np.where(np.isfinite(self.columns), 0, -1)).astype(np.int8)
            object.__setattr__(self, "part", part)

    @property
    def valid(self) -> np.ndarray:
        """Rows with a truth point, bool (H,)."""
        return np.isfinite(self.columns)


@dataclasses.dataclass(frozen=True)
class Frame:
    """One exposure of the rig at one mirror angle.

    Attributes
    ----------
    image : ndarray (H, W), uint8
        Laser-on frame: sensor(ambient + laser), its own noise draw.
    background : ndarray (H, W), uint8
        Laser-off frame: sensor(ambient), an independent noise draw.
    radiance : ndarray (H, W), float32
        Noise-free in-band radiance (W m⁻² sr⁻¹), ambient + laser.
    laser_radiance : ndarray (H, W), float32
        Noise-free in-band radiance of the laser alone.
    truth : Truth
    mirror_angle_deg : float
    variant : str
        Mitsuba variant that rendered it.
    """

    image: np.ndarray
    background: np.ndarray
    radiance: np.ndarray
    laser_radiance: np.ndarray
    truth: Truth
    mirror_angle_deg: float
    variant: str
