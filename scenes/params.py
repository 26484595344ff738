"""Scene parameters: defaults, groups and validation at the boundary.

Every parameter has a default (:data:`DEFAULTS`).  Groups:

* :data:`RENDER_KEYS` change the cached unit renders and truth (with the name,
  mirror angle, spp and seed);
* :data:`SCALE_KEYS` only scale the unit renders (laser power, ambient,
  spectra, filter): changing them never re-renders;
* :data:`SENSOR_KEYS` feed :class:`scenes.sensor.SensorModel`;
* ``n_angles`` (default scan length), ``cache`` and ``cache_dir`` change nothing
  rendered.

Background and support (:mod:`scenes.objects`; all in :data:`RENDER_KEYS`):

* ``background``: ``"wall"`` (default) or ``"none"``;
* ``background_distance_cm``: the wall's distance from the mirror axis, in
  (0, 1000] cm, default 55 (inside the imaged range 18.8-65.8 cm; see
  :func:`scenes.objects.out_of_range_distance_cm` for one outside it); the object
  must stand in front of it (checked by :func:`scenes.make`);
* ``background_albedo``: the wall's Lambertian albedo in [0, 1], default 0.5;
* ``support``: ``"none"`` (default: the object floats) or ``"table"``;
* ``support_albedo``: the table's Lambertian albedo in [0, 1], default 0.5.

Textures (:mod:`scenes.textures`; :data:`TEXTURE_KEYS`, in the render cache key only when a
texture is not ``"none"``, so untextured keys stay what they were):

* ``support_texture``, ``background_texture``, ``object_texture``: one of
  :data:`scenes.textures.TEXTURES`, default ``"none"``; a texture replaces that surface's albedo
  (``support_albedo``, ``background_albedo`` or the material's diffuse albedo: ``object_texture``
  needs a material of :data:`scenes.materials.TEXTURABLE`);
* ``texture_scale_cm``: the textures' feature size (checker square, ...), in (0, 100] cm, default 2;
* ``texture_seed``: seed of the procedural patterns, integer >= 0, default 0 (independent of ``seed``);
* ``support_finish``: ``"matte"`` (default) or ``"polished"`` (a clear coat: the table mirrors the
  object and its stripe).

A textured surface's albedo depends on the spectrum each pass sees, so with a texture the laser
wavelength, the illuminant, the filter and the camera also enter the render cache key (through the
texture's band weights).

Camera (:mod:`scenes.colour_camera`; :data:`CAMERA_KEYS`, applied after rendering):

* ``camera``: ``"mono"`` (default: the band-pass-filtered monochrome camera) or ``"rgb"`` (Bayer colour
  camera; the frame then carries ``rgb`` images);
* ``filter``: ``"bandpass"`` (default: the ``filter_*`` Gaussian) or ``"none"`` (``"rgb"`` only);
* ``jpeg_quality``: None (default: lossless) or an integer 1-95;
* ``defocus_px``: pillbox defocus radius in [0, 20] px, default 0.

Distractors (:mod:`scenes.distractors`; :data:`DISTRACTOR_KEYS`, applied after the render cache, so never in
its key):

* ``distractor``: one of :data:`scenes.distractors.DISTRACTORS`, default ``"none"`` (the frame as rendered):
  a lit door edge, a lamp, LED clusters, a window, a lit sphere in front, a grey frame and line drawn on the
  recording, or ``"short"``; each cuts the stripe from the top or the bottom rows (the object is short) and
  stands mostly in those rows. Placed from ``seed``; the truth loses the rows whose stripe they remove.

Sample counts: ``spp`` (every laser pass, default 16) and ``ambient_spp`` (default 8) are integers
>= 1 or ``"auto"``: the per-material, per-pass counts that the committed procedure chose
(:mod:`scenes.sampling`; the experiment profiles use it).

``ambient_illuminant`` also accepts ``"daylight"`` (CIE D75, :data:`scenes.radiometry.ALIASES`).

Translucent materials (``skin``, ``marble``, ``wax``; :data:`scenes.materials.TRANSLUCENCY`):

* ``translucency``: ``"volpath"`` (default: the medium, path traced with ``volpath``, the reference) or
  ``"profile"`` (an opaque stand-in whose laser stripe is spread by the material's line-spread profile,
  :mod:`scenes.subsurface`; several times cheaper). It enters the render cache key only as ``"profile"``
  and only for a translucent material (every other key stays what it was); the opaque materials ignore it.

``width`` x ``height`` must keep the default 16:15 square-pixel aspect (64x60,
128x120, 256x240, 512x480, ...): Mitsuba's pinhole camera has square pixels.
"""

from __future__ import annotations

import math
import numbers
from typing import Any, Dict

from . import _checks, radiometry
from .colour_camera import CAMERAS, FILTERS
from .distractors import DISTRACTORS
from .materials import BACKDROP_ALBEDO, MATERIALS, SUPPORT_ALBEDO, SUPPORT_FINISHES, TEXTURABLE, TRANSLUCENCY
from .textures import TEXTURES
from .objects import BACKDROP_DISTANCE_CM, BACKGROUNDS, SUPPORTS
from .rig import Rig
from .sampling import AUTO
from .sensor import SensorModel

__all__ = ["DEFAULTS", "RENDER_KEYS", "SCALE_KEYS", "SENSOR_KEYS", "TEXTURE_KEYS", "CAMERA_KEYS", "DISTRACTOR_KEYS",
           "MAX_SIZE",
           "MAX_SAMPLES", "MAX_DEFOCUS_PX", "MAX_TEXTURE_SCALE_CM", "validate", "textured"]

# upper bounds that keep Mitsuba and memory sane: image sides, spp, and the
# samples of one pass (Mitsuba's wavefront counts them in 32 bits)
MAX_SIZE = {"width": 8192, "height": 7680, "spp": 65536, "ambient_spp": 65536, "n_angles": 100000}
MAX_SAMPLES = 2**32 - 1

SENSOR_KEYS = ("f_number", "lens_transmission", "exposure_ms", "quantum_efficiency", "full_well_e",
               "gain_e_per_dn", "read_noise_e", "black_level_dn")
RENDER_KEYS = ("material", "line_fwhm_mrad", "laser_fan_deg", "width", "height", "spp", "ambient_spp", "seed",
               "background", "background_distance_cm", "background_albedo", "support", "support_albedo")
SCALE_KEYS = ("ambient_lux", "ambient_illuminant", "laser_power_mw", "laser_wavelength_nm",
              "filter_center_nm", "filter_fwhm_nm", "filter_peak")

TEXTURE_KEYS = ("support_texture", "background_texture", "object_texture", "texture_scale_cm", "texture_seed",
                "support_finish")
CAMERA_KEYS = ("camera", "filter", "jpeg_quality", "defocus_px")
DISTRACTOR_KEYS = ("distractor",)
TEXTURED = ("support_texture", "background_texture", "object_texture")
MAX_DEFOCUS_PX = 20.0
MAX_TEXTURE_SCALE_CM = 100.0

_SENSOR_DEFAULTS = SensorModel()
MAX_BACKGROUND_DISTANCE_CM = 1000.0  # 10 m; the camera's far clip is 100 m

DEFAULTS: Dict[str, Any] = {
    "material": "matte",
    "ambient_lux": 400.0,
    "ambient_illuminant": "D65",
    "laser_power_mw": 3.0,
    "laser_wavelength_nm": 650.0,
    "line_fwhm_mrad": 3.0,
    "laser_fan_deg": 90.0,
    "filter_center_nm": 650.0,
    "filter_fwhm_nm": 10.0,
    "filter_peak": 0.9,
    "width": 512,
    "height": 480,
    "spp": 16,
    "ambient_spp": 8,
    "seed": 0,
    "n_angles": 48,
    "background": "wall",
    "background_distance_cm": BACKDROP_DISTANCE_CM,
    "background_albedo": BACKDROP_ALBEDO,
    "support": "none",
    "support_albedo": SUPPORT_ALBEDO,
    **{k: getattr(_SENSOR_DEFAULTS, k) for k in SENSOR_KEYS},
    "support_texture": "none",
    "background_texture": "none",
    "object_texture": "none",
    "texture_scale_cm": 2.0,
    "texture_seed": 0,
    "support_finish": "matte",
    "camera": "mono",
    "filter": "bandpass",
    "jpeg_quality": None,
    "defocus_px": 0.0,
    "translucency": "volpath",
    "distractor": "none",
    "cache": True,
    "cache_dir": None,
}


def _choice(name: str, value, valid) -> str:
    if not isinstance(value, str) or value not in valid:
        raise ValueError(f"`{name}` must be one of {', '.join(map(repr, valid))}, got {value!r}")
    return value


def _seed(value, name: str = "seed") -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 0:
        raise ValueError(f"`{name}` must be an integer >= 0, got {value!r}")
    return int(value)


def textured(params: Dict[str, Any]) -> bool:
    """True when a validated parameter set has a texture on some surface."""
    return any(params[k] != "none" for k in TEXTURED)


def validate(params: Dict[str, Any]) -> Dict[str, Any]:
    """Fill defaults and check every value; returns a new dict.

    Raises
    ------
    TypeError
        An unknown parameter name (the message lists the valid ones).
    KeyError
        An unknown ``material`` or ``ambient_illuminant``.
    ValueError
        A value out of range or not among the choices; the message names the parameter and echoes
        the value.
    """
    unknown = sorted(set(params) - set(DEFAULTS))
    if unknown:
        raise TypeError(f"unknown scene parameter(s) {', '.join(map(repr, unknown))}; "
                        f"valid: {', '.join(sorted(DEFAULTS))}")
    p = {**DEFAULTS, **params}
    if p["material"] not in MATERIALS:
        raise KeyError(f"unknown `material` {p['material']!r}; valid: {', '.join(MATERIALS)}")
    p["ambient_lux"] = _checks.non_negative("ambient_lux", p["ambient_lux"])
    p["laser_power_mw"] = _checks.non_negative("laser_power_mw", p["laser_power_mw"])
    p["laser_wavelength_nm"] = _checks.in_range("laser_wavelength_nm", p["laser_wavelength_nm"], 360.0, 780.0)
    p["line_fwhm_mrad"] = _checks.in_range("line_fwhm_mrad", p["line_fwhm_mrad"], 0.0, 100.0, lo_open=True)
    p["laser_fan_deg"] = _checks.in_range("laser_fan_deg", p["laser_fan_deg"], 0.0, 170.0, lo_open=True)
    p["filter_center_nm"] = _checks.in_range("filter_center_nm", p["filter_center_nm"], 380.0, 760.0)
    p["filter_fwhm_nm"] = _checks.in_range("filter_fwhm_nm", p["filter_fwhm_nm"], 0.0, 400.0, lo_open=True)
    p["filter_peak"] = _checks.in_range("filter_peak", p["filter_peak"], 0.0, 1.0, lo_open=True)
    for k in ("width", "height", "spp", "ambient_spp", "n_angles"):
        if k in ("spp", "ambient_spp") and p[k] == AUTO:
            continue
        if k in ("spp", "ambient_spp") and (isinstance(p[k], bool) or not isinstance(p[k], numbers.Integral)
                                            or p[k] < 1):
            raise ValueError(f"`{k}` must be an integer >= 1 or {AUTO!r} (scenes.sampling), got {p[k]!r}")
        p[k] = _checks.positive_int(k, p[k])
        if p[k] > MAX_SIZE[k]:
            raise ValueError(f"`{k}` must be at most {MAX_SIZE[k]}, got {p[k]!r}")
    for k in ("spp", "ambient_spp"):
        if p[k] != AUTO and p["width"] * p["height"] * p[k] > MAX_SAMPLES:
            raise ValueError(f"`width` x `height` x `{k}` must be at most 2**32 - 1 samples (Mitsuba's limit), "
                             f"got {p['width']}x{p['height']}x{p[k]}")
    rig = Rig()
    if not math.isclose(rig.sensor_width_mm / p["width"], rig.sensor_height_mm / p["height"], rel_tol=1e-9):
        raise ValueError(f"`width` x `height` must keep square pixels ({rig.width}:{rig.height}, e.g. 64x60, "
                         f"128x120, 256x240, 512x480), got {p['width']!r}x{p['height']!r}")
    p["seed"] = _seed(p["seed"])
    p["background"] = _choice("background", p["background"], BACKGROUNDS)
    p["background_distance_cm"] = _checks.in_range("background_distance_cm", p["background_distance_cm"],
                                                   0.0, MAX_BACKGROUND_DISTANCE_CM, lo_open=True)
    p["background_albedo"] = _checks.in_range("background_albedo", p["background_albedo"], 0.0, 1.0)
    p["support"] = _choice("support", p["support"], SUPPORTS)
    p["support_albedo"] = _checks.in_range("support_albedo", p["support_albedo"], 0.0, 1.0)
    if p["ambient_illuminant"] not in radiometry.illuminant_names():
        raise KeyError(f"unknown `ambient_illuminant` {p['ambient_illuminant']!r}; "
                       f"valid: {', '.join(radiometry.illuminant_names())}")
    for k in TEXTURED:
        p[k] = _choice(k, p[k], TEXTURES)
    if p["object_texture"] != "none" and p["material"] not in TEXTURABLE:
        raise ValueError(f"`object_texture` needs one of the materials {', '.join(map(repr, TEXTURABLE))}, "
                         f"got material {p['material']!r} with object_texture {p['object_texture']!r}")
    p["texture_scale_cm"] = _checks.in_range("texture_scale_cm", p["texture_scale_cm"], 0.0, MAX_TEXTURE_SCALE_CM,
                                             lo_open=True)
    p["texture_seed"] = _seed(p["texture_seed"], "texture_seed")
    p["support_finish"] = _choice("support_finish", p["support_finish"], SUPPORT_FINISHES)
    p["camera"] = _choice("camera", p["camera"], CAMERAS)
    p["filter"] = _choice("filter", p["filter"], FILTERS)
    if p["filter"] == "none" and p["camera"] != "rgb":
        raise ValueError(f"`filter` \"none\" needs `camera` \"rgb\" (the mono camera's response is defined "
                         f"through its band-pass filter), got camera {p['camera']!r}")
    q = p["jpeg_quality"]
    if q is not None and (isinstance(q, bool) or not isinstance(q, numbers.Integral) or not 1 <= q <= 95):
        raise ValueError(f"`jpeg_quality` must be None (lossless) or an integer in [1, 95], got {q!r}")
    p["jpeg_quality"] = None if q is None else int(q)
    p["defocus_px"] = _checks.in_range("defocus_px", p["defocus_px"], 0.0, MAX_DEFOCUS_PX)
    p["translucency"] = _choice("translucency", p["translucency"], TRANSLUCENCY)
    p["distractor"] = _choice("distractor", p["distractor"], DISTRACTORS)
    if p["camera"] == "rgb" and (p["width"] % 2 or p["height"] % 2):
        raise ValueError(f"`camera` \"rgb\" needs an even `width` and `height` (a whole Bayer pattern), "
                         f"got {p['width']}x{p['height']}")
    SensorModel(**{k: p[k] for k in SENSOR_KEYS})  # validates
    for k in SENSOR_KEYS:
        p[k] = float(p[k])
    if not isinstance(p["cache"], bool):
        raise ValueError(f"`cache` must be True or False, got {p['cache']!r}")
    return p
