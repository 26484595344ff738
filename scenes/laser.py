"""The line laser as a Mitsuba ``projector``: a thin Gaussian line in a vertical fan.

The projector is a pinhole with an irradiance texture on its image plane at
``z = 1``.  The texture is ``n_x`` texels wide and covers ``±4σ`` of the
Gaussian horizontal profile (σ = FWHM / 2.3548, profile in angle); its height
``n_y`` is chosen so that the texture's aspect ratio gives the requested full fan
angle exactly (Mitsuba derives the vertical field from the aspect ratio,
``tan(fov_y/2) = tan(fov_x/2) · n_y / n_x``).  Every row is the same profile: the
fan is uniform with hard edges.  The texture is bilinearly interpolated.

Power: Mitsuba 3.9's projector emits ``π · scale · mean(texture) · (2 tan(fov_x/2)) · (2 tan(fov_y/2))``
W; :func:`projector_scale` inverts that, so a unit-power render scales
linearly to any laser power.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from . import radiometry

__all__ = ["LaserProfile", "profile"]

_SIGMAS = 4.0
_N_X = 33


@dataclasses.dataclass(frozen=True)
class LaserProfile:
    """Projector texture and fields of a Gaussian line laser.

    Attributes
    ----------
    texture : ndarray, shape (n_y, n_x, 1), float32
        Relative irradiance (peak 1).
    tan_half_x, tan_half_y : float
        Tangents of the half fields of view (horizontal: profile window; vertical: half fan).
    fwhm_mrad, fan_deg : float
        The line's angular full width at half maximum and its full fan angle.
    """

    texture: np.ndarray
    tan_half_x: float
    tan_half_y: float
    fwhm_mrad: float
    fan_deg: float

    @property
    def fov_x_deg(self) -> float:
        """Horizontal field of view (deg) for the projector's ``fov`` with ``fov_axis = 'x'``."""
        return math.degrees(2.0 * math.atan(self.tan_half_x))

    def scale_for_power(self, power_w: float) -> float:
        """Projector ``scale`` that emits ``power_w`` watts."""
        return radiometry.projector_scale(power_w, float(self.texture.mean(dtype=np.float64)),
                                          self.tan_half_x, self.tan_half_y)

    def relative_irradiance(self, horizontal_angle_rad) -> np.ndarray:
        """Normalised Gaussian profile ``exp(-θ²/2σ²)`` at horizontal angles (rad), for tests."""
        sigma = self.fwhm_mrad * 1e-3 / (2.0 * math.sqrt(2.0 * math.log(2.0)))
        return np.exp(-0.5 * (np.asarray(horizontal_angle_rad, float) / sigma) ** 2)


@functools.lru_cache(maxsize=16)
def profile(fwhm_mrad: float = 3.0, fan_deg: float = 90.0) -> LaserProfile:
    """The projector texture of a line of angular FWHM ``fwhm_mrad`` and full fan ``fan_deg``."""
    sigma = fwhm_mrad * 1e-3 / (2.0 * math.sqrt(2.0 * math.log(2.0)))
    tan_y = math.tan(math.radians(0.5 * fan_deg))
    tan_x0 = math.tan(_SIGMAS * sigma)
    n_y = max(1, int(round(_N_X * tan_y / tan_x0)))
    tan_x = tan_y * _N_X / n_y  # exact fan; window within a texel of ±4σ
    x = ((np.arange(_N_X) + 0.5) / _N_X * 2.0 - 1.0) * tan_x
    row = np.exp(-0.5 * (np.arctan(x) / sigma) ** 2).astype(np.float32)
    tex = np.ascontiguousarray(np.broadcast_to(row[None, :, None], (n_y, _N_X, 1)))
    tex.setflags(write=False)
    return LaserProfile(tex, tan_x, tan_y, float(fwhm_mrad), float(fan_deg))
