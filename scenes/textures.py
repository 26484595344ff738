"""Procedural albedo textures of the surroundings and the object (seeded, periodic tiles).

A texture is a square **tile** of linear-sRGB reflectances, shape (N, N, 3) float32 in [0, 1],
that covers ``tile_cm`` x ``tile_cm`` of a surface and repeats (Mitsuba's ``bitmap`` with
``wrap_mode = "repeat"``); every tile is periodic, so the repeats have no seams.  Its features
are sized by the scene parameter ``texture_scale_cm`` (``s`` below, default 2 cm):

=========  ===========================================================================  ========
name       what it is                                                                   tile
=========  ===========================================================================  ========
wood       planks 5 s wide, dark grain lines every s/4 distorted by smooth noise         10 s
floor      speckled grey floor (terrazzo / concrete): mottling at s, grain at s/20,       8 s
           dark and light speckles of ~s/20
carpet     dark beige loop pile: strong fibre noise at s/20, tufts at s/4                 4 s
checker    black (0.04) and white (0.85) squares of side s                               2 s
charuco    a ChArUco-like board: checker squares of side s, every white square holds     4 s
           a black marker (0.7 s) with a seeded 4x4 bit pattern
paper      plain white paper (0.85, 1 % fibre noise)                                      4 s
print      white paper with coloured patches (s to 2 s) and rows of text-like marks       8 s
=========  ===========================================================================  ========

Colours are linear sRGB reflectances; the spectral reflectance of a texel is the linear
combination ``ρ(λ) = Σ_k c_k B_k(λ)`` of Mallett and Yuksel's (2019) sRGB basis spectra
(``colour.recovery.MSDS_BASIS_FUNCTIONS_sRGB_MALLETT2019``; they sum to 1, so a grey ``c``
is spectrally flat).  Each render pass sees one scalar albedo per texel, ``Σ_k c_k w_k`` with
the pass's weights ``w_k`` (:func:`band_weights`): the basis averaged over the pass's
spectral weighting (the laser line; illuminant x filter; illuminant x filter x a camera
channel).  That is exact for light that reflects once off a textured surface and an
approximation for light reflected off two textured surfaces (the product of two spectra is
not the product of their band averages).

Reference: I. Mallett and C. Yuksel, "Spectral Primary Decomposition for Rendering with sRGB
Reflectance", Eurographics Symposium on Rendering, 2019.
"""

from __future__ import annotations

import functools
import math
from typing import Optional

import numpy as np

__all__ = ["TEXTURES", "TEXTURE_VERSION", "TILE_TEXELS", "TILE_SCALES", "tile", "tile_cm", "basis_spectra", "band_weights",
           "albedo_map", "bitmap"]

TEXTURES = ("none", "wood", "floor", "carpet", "checker", "charuco", "paper", "print")
#: In the render cache key of every textured frame: bump it whenever a pattern changes.
TEXTURE_VERSION = 1
#: Texels along a tile side.
TILE_TEXELS = {"wood": 1024, "floor": 1024, "carpet": 1024, "checker": 512, "charuco": 1024, "paper": 512,
               "print": 1024}
#: Tile side in units of ``texture_scale_cm``.
TILE_SCALES = {"wood": 10.0, "floor": 8.0, "carpet": 4.0, "checker": 2.0, "charuco": 4.0, "paper": 4.0,
               "print": 8.0}
BLACK_INK = 0.04  # matte printed black (laser-printer toner on paper is about 0.03-0.05)
WHITE_PAPER = 0.85
_SURFACE_INDEX = {"backdrop": 0, "object": 1, "support": 2}


def tile_cm(name: str, scale_cm: float) -> float:
    """Side of one tile of ``name`` (cm) at feature scale ``scale_cm``."""
    return TILE_SCALES[_checked(name)] * float(scale_cm)


def _checked(name: str) -> str:
    if name not in TEXTURES or name == "none":
        raise ValueError(f"`texture` must be one of {', '.join(map(repr, TEXTURES[1:]))}, got {name!r}")
    return name


def _noise(rng: np.random.Generator, n: int, feature_texels: float) -> np.ndarray:
    """Periodic Gaussian noise (n, n), zero mean, unit standard deviation, correlation length
    ``feature_texels`` (a Gaussian low-pass of white noise in the Fourier domain)."""
    white = rng.standard_normal((n, n))
    f = np.fft.fftfreq(n)
    k2 = f[:, None] ** 2 + f[None, :] ** 2
    sigma_f = 1.0 / (2.0 * math.pi * max(feature_texels, 0.5))
    out = np.fft.ifft2(np.fft.fft2(white) * np.exp(-0.5 * k2 / sigma_f ** 2)).real
    out -= out.mean()
    sd = out.std()
    return out / sd if sd > 0 else out


def _grey(a) -> np.ndarray:
    a = np.asarray(a, np.float64)
    return np.repeat(a[..., None], 3, axis=-1)


def _wood(rng, n):
    x, y = np.meshgrid(np.arange(n) / n, np.arange(n) / n)  # tile units; rows = y
    planks = 2  # planks 5 s wide in a 10 s tile, running along x
    plank = np.floor(y * planks).astype(int)
    warp = 0.012 * _noise(rng, n, n / 6) + 0.003 * _noise(rng, n, n / 40)
    lines = 40  # grain every s/4 in a 10 s tile
    phase = rng.uniform(0, 1, planks)[plank]
    g = 0.5 + 0.5 * np.cos(2 * math.pi * (lines * (y + warp) + phase))
    grain = g ** 6  # thin dark lines
    tone = rng.uniform(0.85, 1.15, planks)[plank] * (1.0 + 0.06 * _noise(rng, n, n / 80))
    light, dark = np.array([0.45, 0.26, 0.12]), np.array([0.22, 0.11, 0.045])
    rgb = (light * (1 - grain[..., None]) + dark * grain[..., None]) * tone[..., None]
    frac = (y * planks) % 1.0
    seam = (frac < 1.5 * planks / n) | (frac > 1.0 - 1.5 * planks / n)  # a dark joint between planks
    rgb[seam] = dark * 0.5
    return rgb


def _floor(rng, n):
    base = 0.30 * (1.0 + 0.18 * _noise(rng, n, n / 8) + 0.10 * _noise(rng, n, n / 160))
    rgb = _grey(base) * np.array([1.04, 1.0, 0.94])
    dark = _noise(rng, n, n / 200) > 2.3
    light = _noise(rng, n, n / 200) > 2.3
    rgb[dark] = [0.05, 0.05, 0.05]
    rgb[light] = [0.70, 0.68, 0.62]
    return rgb


def _carpet(rng, n):
    fibre = _noise(rng, n, n / 80)
    tufts = _noise(rng, n, n / 16)
    a = 1.0 + 0.40 * fibre + 0.15 * tufts
    return _grey(np.clip(a, 0.2, 2.0)) * np.array([0.20, 0.16, 0.12])


def _checker_tile(n, squares):
    i = (np.arange(n) * squares // n)
    black = (i[:, None] + i[None, :]) % 2 == 0
    return black


def _checker(rng, n):
    black = _checker_tile(n, 2)
    return _grey(np.where(black, BLACK_INK, WHITE_PAPER))


def _charuco(rng, n):
    squares = 4
    black = _checker_tile(n, squares)
    a = np.where(black, BLACK_INK, WHITE_PAPER)
    sq = n // squares
    m = int(round(0.7 * sq))  # marker side
    cells = 6  # a one-cell black border around 4 x 4 bits
    cell = m // cells
    m = cell * cells
    off = (sq - m) // 2
    for r in range(squares):
        for c in range(squares):
            if black[r * sq, c * sq]:
                continue
            bits = np.ones((cells, cells), bool)  # True = black
            bits[1:-1, 1:-1] = rng.random((4, 4)) < 0.5
            marker = np.repeat(np.repeat(bits, cell, 0), cell, 1)
            r0, c0 = r * sq + off, c * sq + off
            a[r0:r0 + m, c0:c0 + m] = np.where(marker, BLACK_INK, WHITE_PAPER)
    return _grey(a)


def _paper(rng, n):
    return _grey(WHITE_PAPER * (1.0 + 0.01 * _noise(rng, n, n / 100)))


_PRINT_COLOURS = np.array([[0.75, 0.05, 0.04], [0.03, 0.25, 0.60], [0.04, 0.40, 0.08], [0.85, 0.60, 0.02],
                           [0.55, 0.08, 0.35], [0.02, 0.45, 0.55], [0.15, 0.15, 0.15], [0.80, 0.30, 0.02]])


def _print(rng, n):
    rgb = _grey(np.full((n, n), WHITE_PAPER))
    s = n / TILE_SCALES["print"]  # texels per scale unit
    for _ in range(10):  # colour patches, s to 2 s, wrapping round the tile
        h, w = (rng.uniform(1.0, 2.0, 2) * s).astype(int)
        r0, c0 = rng.integers(0, n, 2)
        rows, cols = (r0 + np.arange(h)) % n, (c0 + np.arange(w)) % n
        rgb[np.ix_(rows, cols)] = _PRINT_COLOURS[rng.integers(len(_PRINT_COLOURS))]
    line_h, pitch = max(2, int(s / 8)), max(4, int(s / 3))
    for _ in range(4):  # blocks of text-like marks
        r0, c0 = rng.integers(0, n, 2)
        width = int(rng.uniform(2.0, 3.5) * s)
        for k in range(int(rng.integers(4, 9))):
            rows = (r0 + k * pitch + np.arange(line_h)) % n
            pos = 0
            while pos < width:
                word = int(rng.uniform(0.3, 1.0) * s * 0.6)
                cols = (c0 + pos + np.arange(word)) % n
                ink = rng.random((line_h, word)) < 0.7  # broken strokes, like letters
                block = rgb[np.ix_(rows, cols)]
                block[ink] = BLACK_INK
                rgb[np.ix_(rows, cols)] = block
                pos += word + int(0.15 * s)
    return rgb


_MAKERS = {"wood": _wood, "floor": _floor, "carpet": _carpet, "checker": _checker, "charuco": _charuco,
           "paper": _paper, "print": _print}


@functools.lru_cache(maxsize=32)
def _tile(name: str, seed: int, surface: str) -> np.ndarray:
    rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence(
        [int(seed), _SURFACE_INDEX[surface], TEXTURES.index(name)])))
    out = np.clip(_MAKERS[name](rng, TILE_TEXELS[name]), 0.0, 1.0).astype(np.float32)
    out.setflags(write=False)
    return out


def tile(name: str, seed: int = 0, surface: str = "backdrop") -> np.ndarray:
    """One periodic tile of the texture ``name``.

    Parameters
    ----------
    name : str
        One of :data:`TEXTURES` except ``"none"``.
    seed : int
        Texture seed (scene parameter ``texture_seed``), >= 0.
    surface : {'backdrop', 'object', 'support'}
        Which surface it covers: each surface draws its own pattern from the seed.

    Returns
    -------
    ndarray (N, N, 3), float32
        Linear-sRGB reflectances in [0, 1]; row index along the surface's ``v`` (top to
        bottom), column along ``u``. N is :data:`TILE_TEXELS` of the texture.

    Examples
    --------
    >>> t = tile("checker")
    >>> t.shape, round(float(t.min()), 3), round(float(t.max()), 3)
    ((512, 512, 3), 0.04, 0.85)
    """
    _checked(name)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"`seed` must be an integer >= 0, got {seed!r}")
    if surface not in _SURFACE_INDEX:
        raise ValueError(f"`surface` must be one of {', '.join(map(repr, _SURFACE_INDEX))}, got {surface!r}")
    return _tile(name, int(seed), surface).copy()


# -- spectra --------------------------------------------------------------------------------------------------


@functools.lru_cache(maxsize=None)
def _basis() -> np.ndarray:
    from .radiometry import WAVELENGTHS_NM, _colour

    b = _colour().recovery.MSDS_BASIS_FUNCTIONS_sRGB_MALLETT2019
    out = np.stack([np.interp(WAVELENGTHS_NM, np.asarray(b.wavelengths, float), np.asarray(b.values[:, k], float))
                    for k in range(3)], axis=1)
    out.setflags(write=False)
    return out


def basis_spectra() -> np.ndarray:
    """Mallett-Yuksel (2019) sRGB basis reflectances on :data:`scenes.radiometry.WAVELENGTHS_NM`, (421, 3).

    Outside their 380-780 nm table they are held constant.
    """
    return _basis().copy()


def band_weights(weighting: Optional[np.ndarray] = None, wavelength_nm: Optional[float] = None) -> np.ndarray:
    """The basis averaged over a pass's spectral weighting: the (3,) weights ``w`` of
    ``albedo = c · w``.

    Give either ``weighting`` (W(λ) >= 0 on :data:`scenes.radiometry.WAVELENGTHS_NM`, shape (421,),
    not all zero): ``w_k = ∫ B_k W dλ / ∫ W dλ``; or ``wavelength_nm`` (a line):
    ``w_k = B_k(λ)``.

    Examples
    --------
    >>> w = band_weights(wavelength_nm=650.0)
    >>> [round(float(x), 3) for x in w], round(float(w.sum()), 6)
    ([0.905, 0.063, 0.032], 1.0)
    """
    from .radiometry import WAVELENGTHS_NM

    B = _basis()
    if (weighting is None) == (wavelength_nm is None):
        raise ValueError("give exactly one of `weighting` and `wavelength_nm`")
    if wavelength_nm is not None:
        return np.array([np.interp(float(wavelength_nm), WAVELENGTHS_NM, B[:, k]) for k in range(3)])
    W = np.asarray(weighting, float)
    if W.shape != WAVELENGTHS_NM.shape or not np.all(np.isfinite(W)) or W.min() < 0 or W.sum() <= 0:
        raise ValueError(f"`weighting` must be finite, >= 0, not all zero, shape {WAVELENGTHS_NM.shape}; "
                         f"got shape {W.shape}")
    den = np.trapezoid(W, WAVELENGTHS_NM)
    return np.array([np.trapezoid(B[:, k] * W, WAVELENGTHS_NM) / den for k in range(3)])


def albedo_map(rgb_tile: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """The scalar albedo of one pass: ``rgb_tile @ weights`` as (N, N, 1) float32 in [0, 1]."""
    a = np.asarray(rgb_tile, np.float64) @ np.asarray(weights, np.float64)
    return np.clip(a, 0.0, 1.0).astype(np.float32)[..., None]


def bitmap(albedo: np.ndarray, uv_to_cm: np.ndarray, tile_side_cm: float) -> dict:
    """A Mitsuba ``bitmap`` texture dict (raw values, repeating) of a (N, N, 1) albedo tile.

    ``uv_to_cm`` (3, 3) maps the surface's homogeneous texture coordinates ``(u, v, 1)`` to cm in
    the surface; the texture's ``to_uv`` is that map divided by ``tile_side_cm`` (one tile per
    ``tile_side_cm``), as a 4x4 matrix in the ``u, v`` plane.
    """
    m = np.asarray(uv_to_cm, float) / float(tile_side_cm)
    to_uv = np.eye(4)
    to_uv[:2, :2] = m[:2, :2]
    to_uv[:2, 3] = m[:2, 2]
    return {"type": "bitmap", "bitmap": np.asarray(albedo, np.float32), "raw": True, "wrap_mode": "repeat",
            "filter_type": "bilinear", "to_uv": to_uv}
