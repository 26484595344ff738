"""A CCD-like sensor: in-band radiance (W m⁻² sr⁻¹) -> noisy 8-bit digital numbers.

Pure numpy.  The chain, per pixel:

1. camera equation: sensor irradiance ``E = L · τ_lens · π / (4 N²)`` (W m⁻²; no
   cos⁴ vignetting, the field is only ±12°);
2. mean photo-electrons ``μ = E · A_pix · t · QE · λ / (h c)`` with the *nominal*
   full-size pixel area ``A_pix = pixel_pitch_um²`` whatever the rendered image
   size, so DN levels are comparable across ``width``/``height`` (a 64x60 render
   is a down-sampled view of the same camera, not a camera with huge pixels);
3. Poisson shot noise, clipped at the full well;
4. Gaussian read noise (e⁻ rms);
5. gain (e⁻/DN), black level, rounding and clipping to 0..255 (8-bit ADC).

Defaults (10 µm pixels, f/4, τ 0.9, 5 ms, QE 0.35, full well 40 ke⁻,
157 e⁻/DN = full well / 255, read noise 20 e⁻, black level 0) put the default
3 mW stripe on a white (0.85) object about 35 cm from the axis near 95 DN and
400 lux of D65 on the same white surface near 2 DN (see the report in
``tests/scenes/test_sensor.py`` for the independent check of the chain).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from . import _checks

__all__ = ["SensorModel", "PLANCK_J_S", "LIGHT_SPEED_M_S"]

PLANCK_J_S = 6.62607015e-34
LIGHT_SPEED_M_S = 299792458.0


@dataclasses.dataclass(frozen=True)
class SensorModel:
    """Camera-equation sensor with shot noise, read noise, full well and an 8-bit ADC.

    Parameters
    ----------
    f_number : float
        Lens f-number ``N`` (> 0).
    lens_transmission : float
        Lens transmission τ in (0, 1] (the band-pass filter is already in the radiance).
    exposure_ms : float
        Exposure time (ms, > 0).
    quantum_efficiency : float
        Electrons per photon at ``wavelength_nm``, in (0, 1].
    pixel_pitch_um : float
        Nominal pixel pitch (µm) of the full-size sensor; sets the pixel area.
    full_well_e : float
        Full-well capacity (e⁻, > 0).
    gain_e_per_dn : float
        Conversion gain (e⁻ per DN, > 0).
    read_noise_e : float
        Read noise (e⁻ rms, >= 0).
    black_level_dn : float
        Offset added before quantisation (DN, >= 0).
    wavelength_nm : float
        Wavelength for the photon energy (the filter centre).
    """

    f_number: float = 4.0
    lens_transmission: float = 0.9
    exposure_ms: float = 5.0
    quantum_efficiency: float = 0.35
    pixel_pitch_um: float = 10.0
    full_well_e: float = 40000.0
    gain_e_per_dn: float = 157.0
    read_noise_e: float = 20.0
    black_level_dn: float = 0.0
    wavelength_nm: float = 650.0

    def __post_init__(self):
        for name in ("f_number", "exposure_ms", "pixel_pitch_um", "full_well_e", "gain_e_per_dn",
                     "wavelength_nm"):
            _checks.positive(name, getattr(self, name))
        for name in ("lens_transmission", "quantum_efficiency"):
            _checks.in_range(name, getattr(self, name), 0.0, 1.0, lo_open=True)
        for name in ("read_noise_e", "black_level_dn"):
            _checks.non_negative(name, getattr(self, name))

    @property
    def electrons_per_radiance(self) -> float:
        """Mean electrons per unit in-band radiance (e⁻ per W m⁻² sr⁻¹)."""
        irradiance_per_l = self.lens_transmission * math.pi / (4.0 * self.f_number ** 2)
        area_m2 = (self.pixel_pitch_um * 1e-6) ** 2
        photons_per_j = self.wavelength_nm * 1e-9 / (PLANCK_J_S * LIGHT_SPEED_M_S)
        return irradiance_per_l * area_m2 * self.exposure_ms * 1e-3 * self.quantum_efficiency * photons_per_j

    def mean_electrons(self, radiance) -> np.ndarray:
        """Noise-free electrons (float64, not clipped) for radiance (any shape, W m⁻² sr⁻¹)."""
        return np.clip(np.asarray(radiance, float), 0.0, None) * self.electrons_per_radiance

    def expected_dn(self, radiance) -> np.ndarray:
        """Noise-free DN (float64) before rounding, clipped to 0..255 and at the full well."""
        e = np.minimum(self.mean_electrons(radiance), self.full_well_e)
        return np.clip(e / self.gain_e_per_dn + self.black_level_dn, 0.0, 255.0)

    def noise_dn(self, level_dn) -> np.ndarray:
        """The noise (DN rms) of a capture at a noise-free level above black: shot and read noise plus
        the ADC's quantisation, 1/sqrt(12) DN. The unit in which render noise is compared with the
        sensor's (``stripebench perf sampling``, ``perf shiny``, the translucency studies).

        Parameters
        ----------
        level_dn : array_like
            Noise-free level above the black level (DN), any shape; negative values count as 0.

        Returns
        -------
        ndarray of float64, the shape of ``level_dn``

        Examples
        --------
        >>> s = SensorModel()
        >>> bool(abs(s.noise_dn(0.0) - (s.read_noise_e / s.gain_e_per_dn + 12 ** -0.5)) < 1e-12)
        True
        """
        e = np.clip(np.asarray(level_dn, float), 0.0, None) * self.gain_e_per_dn
        return np.sqrt(e + self.read_noise_e ** 2) / self.gain_e_per_dn + 1.0 / math.sqrt(12.0)

    def capture(self, radiance, rng: np.random.Generator) -> np.ndarray:
        """One noisy 8-bit exposure.

        Parameters
        ----------
        radiance : array_like, shape (H, W)
            In-band radiance behind the filter (W m⁻² sr⁻¹), >= 0.
        rng : numpy.random.Generator
            Source of the shot and read noise (the caller seeds it).

        Returns
        -------
        ndarray of uint8, shape (H, W)
        """
        mu = self.mean_electrons(radiance)
        electrons = np.minimum(rng.poisson(mu).astype(np.float64), self.full_well_e)
        if self.read_noise_e > 0:
            electrons = electrons + rng.normal(0.0, self.read_noise_e, size=electrons.shape)
        dn = np.rint(electrons / self.gain_e_per_dn + self.black_level_dn)
        return np.clip(dn, 0, 255).astype(np.uint8)
