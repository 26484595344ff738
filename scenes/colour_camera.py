"""A colour camera: RGB spectral sensitivities, Bayer mosaic, blooming, demosaicing, white balance,
colour matrix, sRGB gamma, JPEG; plus the defocus and JPEG steps both cameras can use.

Pure numpy/scipy (Pillow for JPEG, colour-science for the spectra).  The chain of
:meth:`ColourCamera.capture`, per frame:

1. **Channel radiance** (computed by :class:`scenes.Scene`): the effective radiance of channel ``c``,
   ``L_c = ∫ L(λ) T(λ) s_c(λ) dλ`` (W m⁻² sr⁻¹), with ``T`` the band-pass filter (or 1 without one)
   and ``s_c`` the camera's relative spectral sensitivity (:func:`sensitivities`: the Nikon D5100 of
   Darrodi et al. 2015, colour-science's ``MSDS_CAMERA_SENSITIVITIES['Nikon 5100 (NPL)']``, each
   channel normalised to a peak of 1; the data include the camera's infrared-cut filter). They are
   taken as response per unit spectral *radiance* (energy), each channel's quantum efficiency at its
   peak wavelength being the sensor's ``quantum_efficiency``: ``electrons = L_c · A τ π/(4N²) t ·
   QE · λ_peak,c/(h c)``. (The published curves do not give the channels' relative heights; equal
   peaks are an assumption.)
2. optional **defocus**: a pillbox blur of radius ``defocus_px`` (:func:`defocus`) on the radiance;
3. **RGGB Bayer mosaic** (:func:`cfa_channels`): each pixel keeps its own channel;
4. Poisson shot noise; **blooming** (:func:`bloom`): charge above the full well spills up and down
   the pixel's column into the next pixels that have room (a CCD-like sensor without anti-blooming
   drain); charge that reaches the top or bottom edge is lost;
5. Gaussian read noise, gain and a **12-bit raw** (4095 = the full well, 16 raw steps per output DN);
6. **demosaicing**: Malvar, He and Cutler (2004), "High-quality linear interpolation for demosaicing
   of Bayer-patterned color images", ICASSP (:func:`demosaic`);
7. **white balance** (:func:`white_balance_gains`): the camera's preset for the scene's illuminant,
   computed from a perfect white diffuser *without* the band-pass filter (a preset does not know about
   an added filter); green gain 1;
8. **colour matrix** (:func:`colour_matrix`): white-balanced camera RGB to linear sRGB, the least-squares
   fit over the 24 ColorChecker patches (colour-science's ``ColorChecker N Ohta``) under the illuminant,
   CAT02-adapted to D65, constrained to map white to white;
9. **sRGB encoding** (IEC 61966-2-1 piecewise gamma) to 8 bits, 255 = the full well;
10. optional **JPEG** (:func:`jpeg_round_trip`, Pillow/libjpeg, 4:2:0 chroma subsampling).
"""

from __future__ import annotations

import dataclasses
import functools
import io
import math
from typing import Optional

import numpy as np

from . import _checks, radiometry
from .sensor import SensorModel

__all__ = ["CAMERA", "CAMERAS", "FILTERS", "RAW_BITS", "sensitivities", "peak_wavelengths_nm", "channel_weighting",
           "channel_sky_radiance", "channel_laser_power_w", "white_balance_gains", "colour_matrix", "cfa_channels",
           "mosaic", "bloom", "demosaic", "srgb_encode", "luma", "defocus", "jpeg_round_trip", "ColourCamera"]

CAMERA = "Nikon 5100 (NPL)"
CAMERAS = ("mono", "rgb")
FILTERS = ("bandpass", "none")
RAW_BITS = 12
_CHECKER = "ColorChecker N Ohta"


@functools.lru_cache(maxsize=None)
def _sens() -> np.ndarray:
    m = radiometry._colour().MSDS_CAMERA_SENSITIVITIES[CAMERA]
    w = np.asarray(m.wavelengths, float)
    out = np.stack([np.interp(radiometry.WAVELENGTHS_NM, w, np.asarray(m.values[:, k], float), left=0.0, right=0.0)
                    for k in range(3)], axis=1)
    out.setflags(write=False)
    return out


def sensitivities() -> np.ndarray:
    """Relative spectral sensitivities (R, G, B) of :data:`CAMERA` on
    :data:`scenes.radiometry.WAVELENGTHS_NM`, shape (421, 3), each peaking at 1 (0 outside 380-780 nm).

    Examples
    --------
    >>> s = sensitivities()
    >>> s.shape, [round(float(v), 3) for v in s[650 - 360]]
    ((421, 3), [0.343, 0.027, 0.006])
    """
    return _sens().copy()


def peak_wavelengths_nm() -> np.ndarray:
    """Wavelength (nm) of each channel's peak sensitivity, shape (3,)."""
    return radiometry.WAVELENGTHS_NM[np.argmax(_sens(), axis=0)].astype(float)


def _filter(filter_kind: str, center_nm: float, fwhm_nm: float, peak: float) -> np.ndarray:
    if filter_kind not in FILTERS:
        raise ValueError(f"`filter` must be one of {', '.join(map(repr, FILTERS))}, got {filter_kind!r}")
    if filter_kind == "none":
        return np.ones_like(radiometry.WAVELENGTHS_NM)
    return radiometry.filter_transmission(radiometry.WAVELENGTHS_NM, center_nm, fwhm_nm, peak)


def channel_weighting(illuminant: str, filter_kind: str = "none", *, filter_center_nm: float = 650.0,
                      filter_fwhm_nm: float = 10.0, filter_peak: float = 0.9) -> np.ndarray:
    """``S(λ) T(λ) s_c(λ)``: how each channel weights the ambient's spectrum, (421, 3).

    ``S`` is the relative spectrum of ``illuminant`` (:func:`scenes.radiometry.illuminant_spd`).
    """
    t = _filter(filter_kind, filter_center_nm, filter_fwhm_nm, filter_peak)
    return radiometry.illuminant_spd(illuminant)[:, None] * t[:, None] * _sens()


def channel_sky_radiance(ambient_lux: float, illuminant: str = "D65", filter_kind: str = "none", *,
                         filter_center_nm: float = 650.0, filter_fwhm_nm: float = 10.0,
                         filter_peak: float = 0.9) -> np.ndarray:
    """Effective radiance ``∫ L(λ) T(λ) s_c(λ) dλ`` (W m⁻² sr⁻¹) of the uniform sky per channel, (3,)."""
    L = radiometry.sky_spectral_radiance(ambient_lux, illuminant)
    t = _filter(filter_kind, filter_center_nm, filter_fwhm_nm, filter_peak)
    return np.array([np.trapezoid(L * t * _sens()[:, k], radiometry.WAVELENGTHS_NM) for k in range(3)])


def channel_laser_power_w(laser_power_mw: float, laser_wavelength_nm: float = 650.0, filter_kind: str = "none", *,
                          filter_center_nm: float = 650.0, filter_fwhm_nm: float = 10.0,
                          filter_peak: float = 0.9) -> np.ndarray:
    """Effective laser power ``P T(λ_L) s_c(λ_L)`` (W) per channel, (3,)."""
    t = float(np.interp(laser_wavelength_nm, radiometry.WAVELENGTHS_NM,
                        _filter(filter_kind, filter_center_nm, filter_fwhm_nm, filter_peak)))
    s = np.array([np.interp(laser_wavelength_nm, radiometry.WAVELENGTHS_NM, _sens()[:, k]) for k in range(3)])
    return float(laser_power_mw) * 1e-3 * t * s


def _white_response(illuminant: str) -> np.ndarray:
    """Electrons-proportional response of each channel to a perfect white diffuser (no filter)."""
    e = channel_sky_radiance(1.0, illuminant, "none") * peak_wavelengths_nm()
    return e


@functools.lru_cache(maxsize=None)
def _wb(illuminant: str) -> tuple:
    r = _white_response(illuminant)
    return tuple(float(r[1] / r[k]) for k in range(3))


def white_balance_gains(illuminant: str) -> np.ndarray:
    """Per-channel gains (green = 1) that make a white diffuser under ``illuminant`` grey, (3,).

    Examples
    --------
    >>> g = white_balance_gains("A")
    >>> bool(g[0] < 1.0 < g[2]), float(g[1])
    (True, 1.0)
    """
    return np.array(_wb(illuminant))


@functools.lru_cache(maxsize=None)
def _ccm(illuminant: str) -> np.ndarray:
    colour = radiometry._colour()
    wl = radiometry.WAVELENGTHS_NM
    S = radiometry.illuminant_spd(illuminant)
    patches = colour.SDS_COLOURCHECKERS[_CHECKER]
    refl = np.stack([np.interp(wl, np.asarray(sd.wavelengths, float), np.asarray(sd.values, float))
                     for sd in patches.values()])  # (24, 421)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    xyz_bar = np.stack([np.interp(wl, np.asarray(cmfs.wavelengths, float), np.asarray(cmfs.values[:, k], float),
                                  left=0.0, right=0.0) for k in range(3)], axis=1)
    white_xyz = np.trapezoid(S[:, None] * xyz_bar, wl, axis=0)
    xyz = np.trapezoid(refl[:, :, None] * (S[:, None] * xyz_bar)[None], wl, axis=1) / white_xyz[1]
    white_xyz = white_xyz / white_xyz[1]
    d65 = np.asarray(colour.xy_to_XYZ(colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]))
    cat = colour.adaptation.matrix_chromatic_adaptation_VonKries(white_xyz, d65, transform="CAT02")
    srgb = (np.asarray(colour.RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB) @ (cat @ xyz.T))  # (3, 24)
    srgb_white = np.asarray(colour.RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB) @ (cat @ white_xyz)
    srgb = srgb / srgb_white[:, None]  # white -> (1, 1, 1) exactly
    w = _sens() * S[:, None]  # response per channel (its constant photons-per-joule factor cancels below)
    cam = np.trapezoid(refl[:, :, None] * w[None], wl, axis=1)  # (24, 3)
    cam = cam / np.trapezoid(w, wl, axis=0)  # white-balanced: white -> (1, 1, 1)
    C = cam.T  # (3, 24)
    G = np.linalg.inv(C @ C.T)
    one = np.ones(3)
    M = np.empty((3, 3))
    for i in range(3):  # least squares m C ~ t subject to m . 1 = 1
        m = srgb[i] @ C.T @ G
        M[i] = m + (1.0 - m @ one) * (one @ G) / (one @ G @ one)
    M.setflags(write=False)
    return M


def colour_matrix(illuminant: str) -> np.ndarray:
    """3x3 matrix from white-balanced camera RGB to linear sRGB under ``illuminant``; rows sum to 1.

    Examples
    --------
    >>> M = colour_matrix("D65")
    >>> [round(float(v), 6) for v in M.sum(axis=1)]
    [1.0, 1.0, 1.0]
    """
    return _ccm(illuminant).copy()


def cfa_channels(height: int, width: int) -> np.ndarray:
    """The RGGB Bayer pattern: each pixel's channel (0 R, 1 G, 2 B), (H, W) int8.

    Examples
    --------
    >>> cfa_channels(2, 4).tolist()
    [[0, 1, 0, 1], [1, 2, 1, 2]]
    """
    r = np.arange(height)[:, None] % 2
    c = np.arange(width)[None, :] % 2
    return (r + c).astype(np.int8)


def mosaic(rgb: np.ndarray) -> np.ndarray:
    """Keep each pixel's own channel of an (H, W, 3) image: the (H, W) RGGB mosaic."""
    a = np.asarray(rgb)
    if a.ndim != 3 or a.shape[2] != 3:
        raise ValueError(f"`rgb` must have shape (H, W, 3), got {a.shape}")
    idx = cfa_channels(a.shape[0], a.shape[1]).astype(np.intp)
    return np.take_along_axis(a, idx[..., None], axis=2)[..., 0]


def bloom(electrons: np.ndarray, full_well_e: float) -> np.ndarray:
    """Spill the charge above the full well along each column (half up, half down).

    Parameters
    ----------
    electrons : ndarray (H, W), float
        Collected charge (e⁻) per pixel, >= 0.
    full_well_e : float
        Capacity (e⁻).

    Returns
    -------
    ndarray (H, W), float64
        At most ``full_well_e`` everywhere; each pixel's excess fills the nearest pixels above and
        below with room, the rest leaves at the top and bottom edges (total charge kept otherwise).

    Examples
    --------
    >>> bloom(np.array([[0.0], [25.0], [0.0], [0.0]]), 10.0)[:, 0].tolist()
    [7.5, 10.0, 7.5, 0.0]
    """
    e = np.array(electrons, np.float64)
    over = np.maximum(e - full_well_e, 0.0)
    if not over.any():
        return e
    e = np.minimum(e, full_well_e)
    return _spill(e, 0.5 * over, float(full_well_e))


def _spill(e: np.ndarray, half: np.ndarray, fw: float) -> np.ndarray:
    """Carry ``half`` of each pixel's excess down and the other half up the column, filling room."""
    H = e.shape[0]
    for order in (range(H), range(H - 1, -1, -1)):
        carry = np.zeros(e.shape[1])
        for v in order:
            take = np.minimum(carry, fw - e[v])
            e[v] += take
            carry = carry - take + half[v]
    return e


_K_G = np.array([[0, 0, -1, 0, 0], [0, 0, 2, 0, 0], [-1, 2, 4, 2, -1], [0, 0, 2, 0, 0], [0, 0, -1, 0, 0]]) / 8.0
_K_ROW = np.array([[0, 0, 0.5, 0, 0], [0, -1, 0, -1, 0], [-1, 4, 5, 4, -1], [0, -1, 0, -1, 0],
                   [0, 0, 0.5, 0, 0]]) / 8.0  # the other colour at green, its neighbours left and right
_K_COL = _K_ROW.T  # ... its neighbours above and below
_K_DIAG = np.array([[0, 0, -1.5, 0, 0], [0, 2, 0, 2, 0], [-1.5, 0, 6, 0, -1.5], [0, 2, 0, 2, 0],
                    [0, 0, -1.5, 0, 0]]) / 8.0  # red at blue and blue at red


def demosaic(raw: np.ndarray) -> np.ndarray:
    """Malvar-He-Cutler (2004) linear demosaicing of an RGGB mosaic.

    Parameters
    ----------
    raw : ndarray (H, W), float
        The mosaic (any linear unit); H and W even.

    Returns
    -------
    ndarray (H, W, 3), float64
        Edges are handled by mirror reflection (which keeps the Bayer phase), so a flat
        field of any colour comes back flat.

    Examples
    --------
    >>> flat = mosaic(np.broadcast_to([0.2, 0.5, 0.1], (6, 8, 3)))
    >>> np.allclose(demosaic(flat), [0.2, 0.5, 0.1])
    True
    """
    from scipy.ndimage import convolve

    m = np.asarray(raw, np.float64)
    if m.ndim != 2 or m.shape[0] % 2 or m.shape[1] % 2:
        raise ValueError(f"`raw` must be an (H, W) mosaic with even H and W, got shape {m.shape}")
    cfa = cfa_channels(*m.shape)
    r_row = (np.arange(m.shape[0]) % 2 == 0)[:, None]  # rows holding red (and green)
    is_r, is_b, is_g = cfa == 0, cfa == 2, cfa == 1
    g = np.where(is_g, m, convolve(m, _K_G, mode="mirror"))
    row, col, diag = (convolve(m, k, mode="mirror") for k in (_K_ROW, _K_COL, _K_DIAG))
    r = np.where(is_r, m, np.where(is_b, diag, np.where(r_row, row, col)))
    b = np.where(is_b, m, np.where(is_r, diag, np.where(r_row, col, row)))
    return np.stack([r, g, b], axis=-1)


def srgb_encode(linear) -> np.ndarray:
    """The sRGB transfer function (IEC 61966-2-1) of linear values in [0, 1] (clipped), float64."""
    x = np.clip(np.asarray(linear, np.float64), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def luma(rgb: np.ndarray) -> np.ndarray:
    """Rec. 709 luma ``0.2126 R' + 0.7152 G' + 0.0722 B'`` of an (H, W, 3) uint8 image, rounded, uint8."""
    f = np.asarray(rgb, np.float64)
    return np.clip(np.rint(0.2126 * f[..., 0] + 0.7152 * f[..., 1] + 0.0722 * f[..., 2]), 0, 255).astype(np.uint8)


@functools.lru_cache(maxsize=16)
def _pillbox(radius_px: float) -> np.ndarray:
    n = int(math.ceil(radius_px))
    sub = 8
    g = (np.arange(-n * sub - sub // 2, (n + 1) * sub - sub // 2) + 0.5) / sub
    x, y = np.meshgrid(g, g)
    inside = (x * x + y * y <= radius_px * radius_px).astype(np.float64)
    k = inside.reshape(2 * n + 1, sub, 2 * n + 1, sub).sum(axis=(1, 3))
    k /= k.sum()
    k.setflags(write=False)
    return k


def defocus(image: np.ndarray, radius_px: float) -> np.ndarray:
    """Blur with a uniform disc (pillbox) of radius ``radius_px`` (the geometric defocus PSF).

    Parameters
    ----------
    image : ndarray (H, W) or (H, W, C), float
    radius_px : float
        >= 0; 0 returns the image unchanged (as float64).

    Returns
    -------
    ndarray, same shape, float64; edges extended (``nearest``); the total is kept away from edges.
    """
    from scipy.ndimage import convolve

    r = _checks.non_negative("defocus_px", radius_px)
    a = np.asarray(image, np.float64)
    if r == 0:
        return a.copy()
    k = _pillbox(r)
    if a.ndim == 2:
        return convolve(a, k, mode="nearest")
    return np.stack([convolve(a[..., c], k, mode="nearest") for c in range(a.shape[2])], axis=-1)


def jpeg_round_trip(image: np.ndarray, quality: int) -> np.ndarray:
    """Encode an 8-bit grey (H, W) or RGB (H, W, 3) image as JPEG at ``quality`` (1-95) and decode it.

    Pillow's libjpeg with its defaults (4:2:0 chroma subsampling for RGB); deterministic.
    """
    from PIL import Image

    q = int(quality)
    a = np.asarray(image)
    if a.dtype != np.uint8 or a.ndim not in (2, 3):
        raise ValueError(f"`image` must be a uint8 (H, W) or (H, W, 3) array, got {a.dtype} {a.shape}")
    buf = io.BytesIO()
    Image.fromarray(a).save(buf, format="JPEG", quality=q)
    buf.seek(0)
    with Image.open(buf) as im:
        return np.asarray(im.convert("L" if a.ndim == 2 else "RGB")).copy()


@dataclasses.dataclass(frozen=True)
class ColourCamera:
    """The colour camera of the module docstring, steps 2-10.

    Parameters
    ----------
    sensor : SensorModel
        Optics, exposure, quantum efficiency (at each channel's peak), full well, gain (e⁻ per output
        DN: 255 output DN = ``255 * gain`` e⁻), read noise and black level; its ``wavelength_nm`` is
        replaced by each channel's peak wavelength.
    illuminant : str
        The white-balance preset and colour matrix (the scene's ambient illuminant).
    defocus_px : float
        Pillbox radius (px), 0 = in focus.
    jpeg_quality : int or None
        1-95, or None for a lossless image.
    """

    sensor: SensorModel
    illuminant: str = "D65"
    defocus_px: float = 0.0
    jpeg_quality: Optional[int] = None

    def electrons_per_radiance(self) -> np.ndarray:
        """Mean electrons per unit effective channel radiance, (3,)."""
        return np.array([dataclasses.replace(self.sensor, wavelength_nm=float(w)).electrons_per_radiance
                         for w in peak_wavelengths_nm()])

    def raw(self, radiance_rgb: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """Steps 2-5: the 12-bit raw mosaic, (H, W) uint16."""
        rad = np.asarray(radiance_rgb, np.float64)
        if rad.ndim != 3 or rad.shape[2] != 3:
            raise ValueError(f"`radiance_rgb` must have shape (H, W, 3), got {rad.shape}")
        if self.defocus_px > 0:
            rad = defocus(rad, self.defocus_px)
        H, W = rad.shape[:2]
        cfa = cfa_channels(H, W)
        mu = mosaic(np.clip(rad, 0.0, None)) * self.electrons_per_radiance()[cfa]
        e = bloom(rng.poisson(mu).astype(np.float64), self.sensor.full_well_e)
        if self.sensor.read_noise_e > 0:
            e = e + rng.normal(0.0, self.sensor.read_noise_e, size=e.shape)
        steps = 2 ** (RAW_BITS - 8)
        raw = np.rint((e / self.sensor.gain_e_per_dn + self.sensor.black_level_dn) * steps)
        return np.clip(raw, 0, 2 ** RAW_BITS - 1).astype(np.uint16)

    def develop(self, raw: np.ndarray) -> np.ndarray:
        """Steps 6-10: raw mosaic to the 8-bit sRGB image, (H, W, 3) uint8."""
        steps = 2 ** (RAW_BITS - 8)
        lin = np.asarray(raw, np.float64) / steps - self.sensor.black_level_dn  # output DN, linear
        rgb = demosaic(lin) * white_balance_gains(self.illuminant)
        rgb = rgb @ colour_matrix(self.illuminant).T
        out = np.clip(np.rint(255.0 * srgb_encode(rgb / 255.0)), 0, 255).astype(np.uint8)
        if self.jpeg_quality is not None:
            out = jpeg_round_trip(out, self.jpeg_quality)
        return out

    def capture(self, radiance_rgb: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """One noisy exposure: (H, W, 3) effective channel radiance (W m⁻² sr⁻¹) -> (H, W, 3) uint8 sRGB."""
        return self.develop(self.raw(radiance_rgb, rng))
