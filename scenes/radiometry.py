"""In-band radiometry: what reaches the sensor through the camera's band-pass filter.

The scenes are rendered in a *mono* Mitsuba variant.  Every surface is grey
(spectrally flat over the narrow filter band), so the spectral problem collapses
to two scalars computed here:

* the in-band **sky radiance** (W m⁻² sr⁻¹) of a uniform ambient of
  ``ambient_lux`` lux with the relative spectrum ``S(λ)`` of a named CIE
  illuminant::

      L(λ) = ambient_lux / (π · 683 lm/W · ∫ S V dλ) · S(λ)        (E_v = π L_v)
      L_in = ∫ L(λ) T(λ) dλ

* the in-band **laser power** ``P_in = P · T(λ_laser)`` (W), a monochromatic line.

``T(λ)`` is the filter: a Gaussian of centre ``filter_center_nm``, full width at
half maximum ``filter_fwhm_nm`` and peak transmission ``filter_peak``.  ``V(λ)``
is the CIE 1924 photopic luminous efficiency.  Spectra come from
colour-science (imported lazily) and are integrated with the trapezoid rule on a
1 nm grid over 360-780 nm (D65 and the other 5 nm tables are interpolated
linearly, as CIE recommends).  Rendered radiances therefore mean "in-band
radiance behind the filter"; the sensor model (:mod:`scenes.sensor`) converts
them to electrons with the photon energy at ``filter_center_nm``.

Measured by these functions: 400 lux of D65 is ``L(650 nm) ≈ 1.4e-3`` W m⁻² sr⁻¹ nm⁻¹
and ``L_in ≈ 1.3e-2`` W m⁻² sr⁻¹ through the default filter.
"""

from __future__ import annotations

import functools
import math

import numpy as np

__all__ = [
    "LUMINOUS_EFFICACY_LM_PER_W",
    "ALIASES",
    "WAVELENGTHS_NM",
    "illuminant_names",
    "illuminant_spd",
    "photopic_efficiency",
    "filter_transmission",
    "sky_spectral_radiance",
    "inband_sky_radiance",
    "inband_laser_power_w",
    "projector_scale",
]

LUMINOUS_EFFICACY_LM_PER_W = 683.0
WAVELENGTHS_NM = np.arange(360.0, 781.0, 1.0)


def _colour():
    """colour-science, imported lazily (~1 s). Its import switches numpy's
    print options to the 1.13 legacy style for the whole process; they are
    restored, so importing scenes changes nothing else."""
    import sys

    if "colour" not in sys.modules:
        saved = np.get_printoptions()
        try:
            import colour  # noqa: F401
        finally:
            np.set_printoptions(**saved)
    return sys.modules["colour"]


#: Illuminant aliases: ``daylight`` is daylight through a window, bluer than D65: CIE D75
#: (the 7500 K daylight phase, north-sky light; CIE 15:2004).
ALIASES = {"daylight": "D75"}


@functools.lru_cache(maxsize=None)
def illuminant_names() -> tuple:
    """Sorted names of the CIE illuminants colour-science provides (``'D65'``, ``'A'``, ...) and
    :data:`ALIASES` (``'daylight'``)."""
    return tuple(sorted(set(_colour().SDS_ILLUMINANTS.keys()) | set(ALIASES)))


@functools.lru_cache(maxsize=None)
def _spd(name: str) -> np.ndarray:
    names = illuminant_names()
    if name not in names:
        raise KeyError(f"unknown `ambient_illuminant` {name!r}; valid: {', '.join(names)}")
    sd = _colour().SDS_ILLUMINANTS[ALIASES.get(name, name)]
    vals = np.interp(WAVELENGTHS_NM, np.asarray(sd.wavelengths, float), np.asarray(sd.values, float),
                     left=0.0, right=0.0)
    vals.setflags(write=False)
    return vals


def illuminant_spd(name: str = "D65") -> np.ndarray:
    """Relative spectral power of a CIE illuminant on :data:`WAVELENGTHS_NM`, shape (421,)."""
    return _spd(name).copy()


@functools.lru_cache(maxsize=None)
def _v() -> np.ndarray:
    sd = _colour().colorimetry.SDS_LEFS_PHOTOPIC["CIE 1924 Photopic Standard Observer"]
    vals = np.interp(WAVELENGTHS_NM, np.asarray(sd.wavelengths, float), np.asarray(sd.values, float),
                     left=0.0, right=0.0)
    vals.setflags(write=False)
    return vals


def photopic_efficiency() -> np.ndarray:
    """CIE 1924 photopic ``V(λ)`` on :data:`WAVELENGTHS_NM`, shape (421,)."""
    return _v().copy()


def filter_transmission(wavelength_nm, center_nm: float = 650.0, fwhm_nm: float = 10.0,
                        peak: float = 0.9) -> np.ndarray:
    """Gaussian band-pass transmission ``peak · exp(-4 ln2 (λ-λ0)²/FWHM²)`` (dimensionless)."""
    x = (np.asarray(wavelength_nm, float) - center_nm) / fwhm_nm
    return peak * np.exp(-4.0 * math.log(2.0) * x * x)


def sky_spectral_radiance(ambient_lux: float, illuminant: str = "D65") -> np.ndarray:
    """Spectral radiance (W m⁻² sr⁻¹ nm⁻¹) of a uniform sky giving ``ambient_lux`` on an open surface.

    Returns an array on :data:`WAVELENGTHS_NM`, shape (421,).
    """
    spd = _spd(illuminant)
    lum = LUMINOUS_EFFICACY_LM_PER_W * np.trapezoid(spd * _v(), WAVELENGTHS_NM)
    return float(ambient_lux) / (math.pi * lum) * spd


def inband_sky_radiance(ambient_lux: float, illuminant: str = "D65", *, filter_center_nm: float = 650.0,
                        filter_fwhm_nm: float = 10.0, filter_peak: float = 0.9) -> float:
    """In-band radiance (W m⁻² sr⁻¹) of the ambient sky behind the filter."""
    t = filter_transmission(WAVELENGTHS_NM, filter_center_nm, filter_fwhm_nm, filter_peak)
    return float(np.trapezoid(sky_spectral_radiance(ambient_lux, illuminant) * t, WAVELENGTHS_NM))


def inband_laser_power_w(laser_power_mw: float, laser_wavelength_nm: float = 650.0, *,
                         filter_center_nm: float = 650.0, filter_fwhm_nm: float = 10.0,
                         filter_peak: float = 0.9) -> float:
    """Laser power (W) that the filter passes: ``P · T(λ_laser)``."""
    t = filter_transmission(laser_wavelength_nm, filter_center_nm, filter_fwhm_nm, filter_peak)
    return float(laser_power_mw) * 1e-3 * float(t)


def projector_scale(power_w: float, texture_mean: float, tan_half_x: float, tan_half_y: float) -> float:
    """Mitsuba ``projector`` ``scale`` that emits ``power_w`` in total.

    Mitsuba 3.9's projector emits ``π · scale · mean(texture) · (2 tan(fov_x/2)) · (2 tan(fov_y/2))``
    watts (its irradiance on the plane ``z = 1`` is ``π · scale · texture``).
    """
    if texture_mean <= 0:
        raise ValueError(f"`texture_mean` must be > 0, got {texture_mean!r}")
    return float(power_w) / (math.pi * texture_mean * 4.0 * tan_half_x * tan_half_y)
