"""What one rendered frame carries: images, radiances and the per-row ground truth."""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["Truth", "Frame"]


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
        True where that point lies on the object (False: backdrop or none).
    """

    columns: np.ndarray
    points_cm: np.ndarray
    on_object: np.ndarray

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
