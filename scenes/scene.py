"""``Scene``: one object x material with its parameters; a facade over the modules that render its frames.

A :class:`Scene` holds its name and parameters and what it keeps between frames (the loaded Mitsuba
scenes, the last angle's first hits through the pixel centres); plain functions do the work:
:mod:`scenes.passes` (laser passes, sample counts), :mod:`scenes.masks` (lit, support, split and
pass pixels), :mod:`scenes.loading` (the Mitsuba scenes, textures included), :mod:`scenes.render_key`
(the render cache's key) and :mod:`scenes.rendering` (a frame's walk: seeds, cache, sensor).
"""

from __future__ import annotations

import sys
from typing import Any, Dict, Iterable, Iterator, Optional, Tuple

import numpy as np

from . import _checks, colour_camera, loading, masks, objects, rendering
from .frame import Frame, Truth
from .laser import profile as _laser_profile
from .masks import PARTS as _PARTS
from .params import SENSOR_KEYS
from .passes import sample_counts
from .render_key import cache_fields
from .rig import Rig
from .sensor import SensorModel
# this module's names from before the split, which tests and bench import from here
from .masks import SILHOUETTE_JUMP_CM, SILHOUETTE_MARGIN  # noqa: E402,F401
from .passes import CAMERA_PATHS_VERSION, render_pass  # noqa: E402,F401
from .rendering import angle_words as _angle_words  # noqa: E402,F401

__all__ = ["Scene", "render_pass"]


class Scene:
    """An object in front of its background, on its support, with material, light and sensor parameters.

    Use :func:`scenes.make` to build one (it validates the parameters).

    Attributes
    ----------
    name : str
    params : dict
        All parameters, defaults filled in.

    Examples
    --------
    >>> import scenes
    >>> s = scenes.make("cone", material="skin", spp="auto", ambient_spp=4)
    >>> s.sample_counts()[1:], s.sample_counts(32)[1]
    (((16,), 4), (32,))
    """

    def __init__(self, name: str, params: Dict[str, Any]):
        self.name = name
        self.params = dict(params)
        self._loaded = None

    def __getstate__(self):  # pickling drops the Mitsuba objects
        state = self.__dict__.copy()
        state["_loaded"] = None
        state.pop("_visible_memo", None)
        return state

    def __repr__(self) -> str:
        return f"Scene({self.name!r}, material={self.params['material']!r})"

    # -- derived, cheap -----------------------------------------------------------------
    @property
    def rig(self) -> Rig:
        """The rig at this scene's image size."""
        return Rig().with_size(self.params["width"], self.params["height"])

    @property
    def sensor(self) -> SensorModel:
        """The sensor model (nominal 10 µm pixels whatever the image size)."""
        return SensorModel(pixel_pitch_um=1000.0 * Rig().pitch_x_mm, wavelength_nm=self.params["filter_center_nm"],
                           **{k: self.params[k] for k in SENSOR_KEYS})

    @property
    def object(self) -> objects.SceneObject:
        """Geometry of the object, its background and its support (world cm)."""
        p = self.params
        return objects.build(self.name, self.rig.zeta_deg, p["background"], p["background_distance_cm"], p["support"])

    @property
    def colour_camera(self) -> Optional[colour_camera.ColourCamera]:
        """The colour camera (``camera="rgb"``), else None."""
        p = self.params
        if p["camera"] != "rgb":
            return None
        return colour_camera.ColourCamera(self.sensor, p["ambient_illuminant"], p["defocus_px"], p["jpeg_quality"])

    def default_angles(self) -> np.ndarray:
        """``n_angles`` mirror angles (deg, ascending) sweeping the stripe over the whole object."""
        return self.object.default_angles(self.rig.zeta_deg, self.params["n_angles"])

    def laser_power_inband_w(self) -> float:
        """Laser power through the filter (W)."""
        return rendering.laser_power_inband_w(self.params)

    def sky_radiance_inband(self) -> float:
        """In-band ambient sky radiance (W m⁻² sr⁻¹)."""
        return rendering.sky_radiance_inband(self.params)

    def channel_laser_power_w(self) -> np.ndarray:
        """``camera="rgb"``: effective laser power per colour channel (W), (3,)."""
        return rendering.channel_laser_power_w(self.params)

    def channel_sky_radiance(self) -> np.ndarray:
        """``camera="rgb"``: effective ambient sky radiance per colour channel (W m⁻² sr⁻¹), (3,)."""
        return rendering.channel_sky_radiance(self.params)

    def band_weights(self) -> Dict[str, Any]:
        """The textured surfaces' albedo weights per pass (:func:`scenes.loading.band_weights`)."""
        return loading.band_weights(self.params)

    # -- passes -------------------------------------------------------------------------
    def laser_passes(self) -> tuple:
        """The laser pass(es) of this scene (:func:`scenes.passes.own_passes`)."""
        return self.sample_counts()[0]

    def sample_counts(self, spp=None) -> Tuple[tuple, Tuple[int, ...], int]:
        """``(passes, laser_spp, ambient_spp)`` of a render at ``spp`` (:func:`scenes.passes.sample_counts`)."""
        return sample_counts(self.name, self.params, spp)

    # -- what is kept between frames ------------------------------------------------------
    def _load(self, spp=None):
        """The loaded Mitsuba scenes (:func:`scenes.loading.load`; loaded once, re-posed for every frame)."""
        if self._loaded is None:
            self._loaded = loading.load(self.name, self.params, self.rig, self.object, spp)
        return self._loaded

    def _visible(self, mirror_angle_deg: float):
        """:func:`scenes.masks.visible` at ``mirror_angle_deg``; the last angle's result is kept (a frame
        asks for it up to three times: :meth:`split_pixels`, :meth:`lit_pixels`, the truth)."""
        theta = _checks.real("mirror_angle_deg", mirror_angle_deg)
        memo = self.__dict__.get("_visible_memo")
        if memo is None or memo[0] != theta:
            memo = self._visible_memo = (theta, masks.visible(self._load()[0], self.rig, theta))
        return memo[1]

    # -- pixel masks ----------------------------------------------------------------------
    def visible_points(self, mirror_angle_deg: float):
        """First surface hit through every pixel centre: points_cm (H, W, 3) float64 (NaN on a miss) and
        on_object (H, W) bool."""
        points, part, _ = self._visible(mirror_angle_deg)
        return points, part == _PARTS.index("object")

    def lit_pixels(self, mirror_angle_deg: float) -> np.ndarray:
        """Pixels that can see a point inside the laser's frustum, (H, W) bool (:func:`scenes.masks.lit_pixels`)."""
        theta = _checks.real("mirror_angle_deg", mirror_angle_deg)
        return masks.lit_pixels(self._visible(theta), self.rig, theta, self._tan_half_x())

    def support_pixels(self, mirror_angle_deg: float) -> np.ndarray:
        """Pixels that see the table, grown by one pixel, (H, W) bool (:func:`scenes.masks.support_pixels`)."""
        return masks.support_pixels(self._visible(mirror_angle_deg)[1])

    def split_pixels(self, mirror_angle_deg: float) -> np.ndarray:
        """Pixels a ``"split"`` pass path traces, (H, W) bool (:func:`scenes.masks.split_pixels`)."""
        return masks.split_pixels(self._visible(mirror_angle_deg)[1])

    def pass_pixels(self, mirror_angle_deg: float, passes: Optional[tuple] = None) -> list:
        """Each laser pass's (H, W) bool pixels, or None for the whole image (:func:`scenes.masks.pass_pixels`;
        ``passes`` default :meth:`laser_passes`)."""
        theta = _checks.real("mirror_angle_deg", mirror_angle_deg)
        passes = self.laser_passes() if passes is None else passes
        return masks.pass_pixels(passes, lambda: self._visible(theta), self.rig, theta, self._tan_half_x())

    def _tan_half_x(self) -> float:
        return _laser_profile(self.params["line_fwhm_mrad"], self.params["laser_fan_deg"]).tan_half_x

    # -- truth, cache, frames ---------------------------------------------------------------
    def _truth(self, laser_scene, theta: float) -> Truth:
        points = self._visible(theta)[0] if laser_scene is self._load()[0] else None
        return rendering.truth(laser_scene, self.rig, theta, self.params["laser_fan_deg"], points)

    def truth(self, mirror_angle_deg: float) -> Truth:
        """The ground truth of the frame at ``mirror_angle_deg`` without rendering it (ray casting only).

        The same arrays as ``render(mirror_angle_deg).truth`` (not cached; about 0.05 s at 512x480).
        """
        theta = _checks.real("mirror_angle_deg", mirror_angle_deg)
        return rendering.cast_truth(self.params, self.rig, theta, self._load()[0], self._visible)

    def _cache_fields(self, theta: float, spp, seed: int, variant: str) -> Dict[str, Any]:
        return cache_fields(self.name, self.params, self.rig, theta, spp, seed, variant)

    def render(self, mirror_angle_deg: float, *, spp: Optional[int] = None, seed: Optional[int] = None,
               noise_draw: int = 0) -> Frame:
        """Render one frame (:func:`scenes.rendering.render`).

        Parameters
        ----------
        mirror_angle_deg : float
            Mirror angle θ (deg); the camera and the laser sheet turn by 2θ.
        spp : int or "auto", optional
            Samples per pixel of every laser pass (default ``params['spp']``; ``"auto"``: :meth:`sample_counts`).
        seed : int, optional
            Seed (default ``params['seed']``); with the angle it fixes every random number.
        noise_draw : int, optional
            Which independent draw of the sensor noise to take, >= 0 (0: the one fixed by ``seed`` and the
            angle; ``k > 0``: seeded by ``SeedSequence([seed, angle bits..., k])``); every draw reuses the
            same (cached) unit renders.

        Returns
        -------
        Frame
        """
        return rendering.render(self.name, self.params, self.rig, mirror_angle_deg, spp, seed, noise_draw,
                                sensor=self.sensor, camera=self.colour_camera, load=self._load, visible=self._visible)

    def is_cached(self, mirror_angle_deg: float, *, spp: Optional[int] = None, seed: Optional[int] = None) -> bool:
        """Whether the render cache holds a file for :meth:`render`'s frame at these arguments.

        False when the cache is off. Checks only that the file exists (no loading: a damaged file
        still counts; :meth:`render` re-renders it). Imports Mitsuba (the key names its version).
        """
        return rendering.is_cached(self.name, self.params, self.rig, mirror_angle_deg, spp, seed)

    def scan(self, angles: Iterable[float], *, spp: Optional[int] = None, seed: Optional[int] = None,
             progress: bool = True) -> Iterator[Frame]:
        """Yield :meth:`render` frames for each mirror angle, with a tqdm bar on stderr."""
        from tqdm import tqdm

        angles = [float(a) for a in np.atleast_1d(np.asarray(angles, float))]
        bar = tqdm(angles, desc=f"{self.name}/{self.params['material']}", unit="frame", file=sys.stderr,
                   disable=not progress, leave=False)
        for a in bar:
            yield self.render(a, spp=spp, seed=seed)
