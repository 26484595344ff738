"""Surface materials as Mitsuba BSDF dicts (mono: every reflectance is a grey scalar).

``matte``
    White Lambertian paint, albedo 0.85.
``absorbing``
    Dark Lambertian, albedo 0.05 (black cloth/rubber): the stripe is ~17x dimmer.
``glossy``
    GGX rough plastic (alpha 0.1, IOR 1.5, diffuse albedo 0.45): a highlight on top of a dimmer
    diffuse stripe.
``specular``
    Smooth aluminium (conductor, ``eta = 1.47``, ``k = 7.79`` at 650 nm; R ≈ 0.91): the true stripe is
    invisible to a pinhole camera and the reflected laser lands on other surfaces (false stripes).
``polished``
    Polished / machined aluminium: a rough conductor (GGX, ``alpha = 0.1``) with the ``specular``
    material's optical constants (Rakić 1998, 650 nm). The true stripe is a narrow, very bright
    highlight (it saturates where the half vector meets the normal) and the reflected sheet throws
    blurred false stripes onto the backdrop.
``glazed``
    Glazed white ceramic: a slightly rough dielectric coating (GGX ``alpha = 0.02``, IOR 1.5, soda-lime /
    ceramic glaze) over a white diffuse body (albedo 0.8): the diffuse stripe plus a sharp highlight,
    and a ~4 % (normal incidence, more at grazing) reflection of the sheet onto other surfaces.
``patchy``
    The ``matte`` white with dark (albedo 0.03) horizontal bands and blotches from a bitmap in the
    object's planar (front-projected) texture coordinates: the paper's partly invisible stripe.
``skin``, ``marble``, ``wax``
    Translucent: a homogeneous scattering medium inside the object behind an index-matched
    (``null``) boundary, rendered with ``volpath`` (see :data:`TRANSLUCENT` and
    :func:`integrator_for`). The laser light enters, scatters under the surface and leaves
    around where it entered: a wider, dimmer stripe whose centre is not the surface point.

The backdrop and the table are grey Lambertian, albedo :data:`BACKDROP_ALBEDO` and
:data:`SUPPORT_ALBEDO` (0.5) unless the scene parameters ``background_albedo`` and
``support_albedo`` say otherwise.

Bitmaps appear in the dicts as numpy arrays; :mod:`scenes.backend` turns them into ``mi.Bitmap``.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

__all__ = ["MATERIALS", "BACKDROP_ALBEDO", "bsdf", "backdrop_bsdf", "support_bsdf", "patchy_texture", "uses_delta_bsdf",
           "TEXTURABLE", "SUPPORT_FINISHES", "POLISHED_FLOOR_ALPHA", "with_albedo",
           "integrator_for", "SHINY", "Translucent", "TRANSLUCENT", "medium", "is_translucent", "MEDIUM_MAX_DEPTH",
           "TRANSLUCENCY", "stand_in_bsdf"]

MATERIALS = ("matte", "absorbing", "glossy", "specular", "patchy", "polished", "glazed", "skin", "marble", "wax")
BACKDROP_ALBEDO = 0.5
SUPPORT_ALBEDO = 0.5
WHITE_ALBEDO = 0.85
DARK_ALBEDO = 0.03
ALUMINIUM_ETA_K = (1.47, 7.79)  # Rakić (1998) Al at 650 nm (refractiveindex.info)
POLISHED_ALPHA = 0.1
GLAZE_IOR = 1.5
GLAZE_ALPHA = 0.02
GLAZE_BODY_ALBEDO = 0.8


@functools.lru_cache(maxsize=None)
def _patchy(size: int) -> np.ndarray:
    v, u = np.meshgrid((np.arange(size) + 0.5) / size, (np.arange(size) + 0.5) / size, indexing="ij")
    dark = np.zeros((size, size), bool)
    for lo, hi in [(0.18, 0.25), (0.47, 0.53), (0.70, 0.80)]:  # horizontal bands (rows of the image)
        dark |= (v >= lo) & (v < hi)
    for cu, cv, ru, rv in [(0.30, 0.36, 0.10, 0.06), (0.62, 0.40, 0.06, 0.05),
                           (0.45, 0.62, 0.08, 0.05), (0.78, 0.88, 0.09, 0.05),
                           (0.15, 0.90, 0.07, 0.05), (0.85, 0.12, 0.06, 0.05)]:
        dark |= ((u - cu) / ru) ** 2 + ((v - cv) / rv) ** 2 < 1.0
    tex = np.where(dark, DARK_ALBEDO, WHITE_ALBEDO).astype(np.float32)[..., None]
    tex.setflags(write=False)
    return tex


def patchy_texture(size: int = 256) -> np.ndarray:
    """Albedo bitmap (size, size, 1) float32: white 0.85 with dark 0.03 bands and blotches.

    Row index follows ``v`` (top to bottom of the object), column follows ``u``.
    """
    return _patchy(int(size)).copy()


def bsdf(material: str) -> dict:
    """Mitsuba BSDF dict for ``material`` (one of :data:`MATERIALS`)."""
    if material == "matte":
        return {"type": "diffuse", "reflectance": WHITE_ALBEDO}
    if material == "absorbing":
        return {"type": "diffuse", "reflectance": 0.05}
    if material == "glossy":
        return {"type": "roughplastic", "distribution": "ggx", "alpha": 0.1, "int_ior": 1.5,
                "diffuse_reflectance": 0.45}
    if material == "specular":
        return {"type": "conductor", "eta": 1.47, "k": 7.79}
    if material == "patchy":
        return {"type": "diffuse",
                "reflectance": {"type": "bitmap", "bitmap": patchy_texture(), "raw": True}}
    if material == "polished":
        return {"type": "roughconductor", "distribution": "ggx", "alpha": POLISHED_ALPHA,
                "eta": ALUMINIUM_ETA_K[0], "k": ALUMINIUM_ETA_K[1]}
    if material == "glazed":
        return {"type": "roughplastic", "distribution": "ggx", "alpha": GLAZE_ALPHA, "int_ior": GLAZE_IOR,
                "diffuse_reflectance": GLAZE_BODY_ALBEDO}
    if material in TRANSLUCENT:
        return {"type": "null"}
    raise KeyError(f"unknown `material` {material!r}; valid: {', '.join(MATERIALS)}")


#: Materials whose diffuse albedo an ``object_texture`` can replace (the key it replaces).
TEXTURABLE = {"matte": "reflectance", "glossy": "diffuse_reflectance", "glazed": "diffuse_reflectance"}
#: Table finishes: ``matte`` (Lambertian) or ``polished`` (a clear coat over the albedo: a polished
#: stone or lacquered floor that mirrors the object and its stripe).
SUPPORT_FINISHES = ("matte", "polished")
#: GGX roughness of the ``polished`` finish's coat (IOR :data:`GLAZE_IOR`): a sharp but not perfect
#: reflection (a perfect mirror would need light tracing for the laser's reflection, see ``specular``).
POLISHED_FLOOR_ALPHA = 0.03


def with_albedo(material: str, reflectance: dict) -> dict:
    """:func:`bsdf` of a :data:`TEXTURABLE` material with its diffuse albedo replaced by ``reflectance``
    (a texture dict, e.g. :func:`scenes.textures.bitmap`)."""
    if material not in TEXTURABLE:
        raise ValueError(f"an `object_texture` needs one of the materials {', '.join(map(repr, TEXTURABLE))}, "
                         f"got material {material!r}")
    return {**bsdf(material), TEXTURABLE[material]: reflectance}


def backdrop_bsdf(albedo: float = BACKDROP_ALBEDO, reflectance: dict = None) -> dict:
    """The grey Lambertian backdrop (scene parameter ``background_albedo``), or with a texture
    ``reflectance`` dict instead of the albedo."""
    return {"type": "diffuse", "reflectance": float(albedo) if reflectance is None else reflectance}


def support_bsdf(albedo: float = SUPPORT_ALBEDO, reflectance: dict = None, finish: str = "matte") -> dict:
    """The grey Lambertian table top (scene parameter ``support_albedo``), or with a texture
    ``reflectance`` dict instead of the albedo; ``finish="polished"`` puts a clear coat over it
    (``roughplastic``, GGX :data:`POLISHED_FLOOR_ALPHA`, IOR :data:`GLAZE_IOR`)."""
    value = float(albedo) if reflectance is None else reflectance
    if finish == "matte":
        return {"type": "diffuse", "reflectance": value}
    if finish == "polished":
        return {"type": "roughplastic", "distribution": "ggx", "alpha": POLISHED_FLOOR_ALPHA, "int_ior": GLAZE_IOR,
                "diffuse_reflectance": value}
    raise ValueError(f"`support_finish` must be one of {', '.join(map(repr, SUPPORT_FINISHES))}, got {finish!r}")


def uses_delta_bsdf(material: str) -> bool:
    """True when the material is a perfect mirror (needs light tracing for laser -> mirror -> diffuse)."""
    return material == "specular"


SHINY = ("specular", "polished", "glazed")
"""Materials whose specular lobe throws the laser sheet onto other surfaces (false stripes)."""


# -- translucent materials ----------------------------------------------------------------------------

@dataclasses.dataclass(frozen=True)
class Translucent:
    """Optical coefficients of a translucent material at the laser's wavelength.

    Attributes
    ----------
    sigma_s_reduced_per_mm : float
        Reduced scattering coefficient ``sigma_s' = (1 - g) sigma_s``, mm⁻¹.
    sigma_a_per_mm : float
        Absorption coefficient, mm⁻¹.
    source : str
        Where the numbers come from.
    """

    sigma_s_reduced_per_mm: float
    sigma_a_per_mm: float
    source: str

    @property
    def sigma_t_reduced_per_mm(self) -> float:
        """Reduced extinction ``sigma_s' + sigma_a``, mm⁻¹."""
        return self.sigma_s_reduced_per_mm + self.sigma_a_per_mm

    @property
    def albedo_reduced(self) -> float:
        """Reduced single-scattering albedo ``sigma_s' / sigma_t'``."""
        return self.sigma_s_reduced_per_mm / self.sigma_t_reduced_per_mm

    @property
    def diffusion_length_mm(self) -> float:
        """``1 / sigma_tr`` with ``sigma_tr = sqrt(3 sigma_a sigma_t')`` (Jensen et al. 2001, eq. 5), mm:
        the e-folding distance of the diffuse glow around the entry point."""
        return 1.0 / math.sqrt(3.0 * self.sigma_a_per_mm * self.sigma_t_reduced_per_mm)


_JENSEN = ("Jensen, Marschner, Levoy, Hanrahan (2001), A Practical Model for Subsurface Light Transport, "
           "SIGGRAPH, Table 1 (sigma_s', sigma_a in mm^-1 for R, G, B); R channel used for 650 nm")

#: The translucent materials. ``skin`` is Jensen et al.'s "Skin1" and ``marble`` their "Marble"
#: (Table 1, R/G/B: Skin1 sigma_s' = 0.74, 0.88, 1.01, sigma_a = 0.032, 0.17, 0.48; Marble
#: sigma_s' = 2.19, 2.62, 3.00, sigma_a = 0.0021, 0.0041, 0.0071 mm⁻¹); their R channel is taken
#: for the 650 nm laser (the R coefficient is the nearest of the three; no interpolation).
#: ``wax`` is an **assumption**, not a measurement: no published sigma_s'/sigma_a of paraffin
#: or candle wax at 650 nm was found for this project; the numbers give a material that scatters
#: half as strongly as marble with a similar diffuse reach (diffusion length ~ 9 mm).
TRANSLUCENT = {
    "skin": Translucent(0.74, 0.032, _JENSEN + ", Skin1"),
    "marble": Translucent(2.19, 0.0021, _JENSEN + ", Marble"),
    "wax": Translucent(1.0, 0.004, "assumed (no published measurement found)"),
}

#: Henyey-Greenstein anisotropy of the rendered media. Jensen et al. give only the *reduced*
#: coefficient sigma_s' = (1 - g) sigma_s; by the similarity relation a medium with g = 0 and
#: sigma_s = sigma_s' has the same diffuse transport, and its random walks are 1/(1 - g) times
#: shorter (skin's real g ~ 0.8-0.9 would cost 5-10x more scattering events per path).
PHASE_G = 0.0

#: Maximum path length (surface and medium interactions) of ``volpath`` for the translucent
#: materials. Measured (plane, 128x120, middle angle): 64 keeps 90 % of marble's laser energy
#: against 1024 (skin: 99.5 % against 256); 256 keeps 100 % but leaves fireflies of 100-900x the
#: median in marble and wax (long paths), which trackers take for the stripe. See docs/translucency.md.
MEDIUM_MAX_DEPTH = 64

_MM_PER_M = 1000.0


def is_translucent(material: str) -> bool:
    """True for the materials with a participating medium inside (:data:`TRANSLUCENT`)."""
    return material in TRANSLUCENT


def medium(material: str):
    """Mitsuba ``homogeneous`` medium dict of a translucent material (scene units: metres), else None.

    ``sigma_t`` (m⁻¹) = 1000 (sigma_s' + sigma_a) (mm⁻¹) with ``g`` = :data:`PHASE_G`, so the
    medium's sigma_s equals the published sigma_s'; ``albedo = sigma_s' / sigma_t``.

    Examples
    --------
    >>> m = medium("marble")
    >>> round(m["sigma_t"], 1), round(m["albedo"], 5)
    (2192.1, 0.99904)
    >>> medium("matte") is None
    True
    """
    t = TRANSLUCENT.get(material)
    if t is None:
        return None
    return {"type": "homogeneous", "sigma_t": t.sigma_t_reduced_per_mm * _MM_PER_M, "albedo": t.albedo_reduced,
            "phase": {"type": "hg", "g": PHASE_G}}


#: How a translucent material is rendered (scene parameter ``translucency``): ``"volpath"``, the medium
#: path traced (the reference), or ``"profile"``, an opaque stand-in whose laser stripe is spread by the
#: material's line-spread profile (:mod:`scenes.subsurface`).
TRANSLUCENCY = ("volpath", "profile")


def stand_in_bsdf(albedo: float) -> dict:
    """The ``translucency = "profile"`` stand-in of a translucent object: Lambertian of ``albedo`` (the
    material's :attr:`scenes.subsurface.LineSpread.diffuse_reflectance`)."""
    return {"type": "diffuse", "reflectance": float(albedo)}


def integrator_for(material: str, light: str = "laser", translucency: str = "volpath") -> str:
    """How one pass (``light``: ``"laser"`` or ``"ambient"``) renders ``material``.

    ``translucency`` (:data:`TRANSLUCENCY`) applies to the translucent materials only: ``"profile"``
    renders them as their opaque stand-in, with ``"path"`` in both passes.

    Returns
    -------
    str
        * ``"volpath"``: the translucent materials (:data:`TRANSLUCENT`) with ``translucency = "volpath"``,
          both passes, with :data:`MEDIUM_MAX_DEPTH`. The boundary is ``null`` (index-matched) because ``volpath``'s
          next-event estimation reaches a delta light (the pinhole projector) from a point inside a
          medium only through null interfaces: a ``dielectric`` or ``roughdielectric`` boundary
          blocks the shadow ray, leaving only the connection from the boundary's last vertex (rough)
          or none at all (smooth).
        * ``"path"`` (path tracing, max depth 3): every other material's ambient pass and the laser
          pass of the diffuse and glossy materials.
        * ``"ptracer"`` (light tracing, laser pass of ``specular``, whose laser -> mirror -> diffuse
          paths a path tracer cannot find).
        * ``"split"`` (laser pass of ``polished``, ``glazed``): path tracing on the pixels that see
          the object, where it renders the highlight and the lit wall seen in the object, light
          tracing on all other pixels, where it renders the sheet reflected onto them; see
          :func:`scenes.description.laser_passes`.

    Examples
    --------
    >>> integrator_for("matte"), integrator_for("specular"), integrator_for("polished")
    ('path', 'ptracer', 'split')
    >>> integrator_for("polished", "ambient"), integrator_for("skin"), integrator_for("skin", "ambient")
    ('path', 'volpath', 'volpath')
    >>> integrator_for("skin", translucency="profile"), integrator_for("matte", translucency="profile")
    ('path', 'path')
    """
    if light not in ("laser", "ambient"):
        raise ValueError(f"`light` must be 'laser' or 'ambient', got {light!r}")
    if material not in MATERIALS:
        raise KeyError(f"unknown `material` {material!r}; valid: {', '.join(MATERIALS)}")
    if translucency not in TRANSLUCENCY:
        raise ValueError(f"`translucency` must be one of {', '.join(map(repr, TRANSLUCENCY))}, got {translucency!r}")
    if is_translucent(material):
        return "volpath" if translucency == "volpath" else "path"
    if light == "ambient":
        return "path"
    if uses_delta_bsdf(material):
        return "ptracer"
    if material in ("polished", "glazed"):
        return "split"
    return "path"
