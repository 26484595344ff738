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

The backdrop and the table are grey Lambertian, albedo :data:`BACKDROP_ALBEDO` and
:data:`SUPPORT_ALBEDO` (0.5) unless the scene parameters ``background_albedo`` and
``support_albedo`` say otherwise.

Bitmaps appear in the dicts as numpy arrays; :mod:`scenes.backend` turns them into ``mi.Bitmap``.
"""

from __future__ import annotations

import functools

import numpy as np

__all__ = ["MATERIALS", "BACKDROP_ALBEDO", "bsdf", "backdrop_bsdf", "support_bsdf", "patchy_texture", "uses_delta_bsdf",
           "integrator_for", "SHINY"]

MATERIALS = ("matte", "absorbing", "glossy", "specular", "patchy", "polished", "glazed")
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
    raise KeyError(f"unknown `material` {material!r}; valid: {', '.join(MATERIALS)}")


def backdrop_bsdf(albedo: float = BACKDROP_ALBEDO) -> dict:
    """The grey Lambertian backdrop (scene parameter ``background_albedo``)."""
    return {"type": "diffuse", "reflectance": float(albedo)}


def support_bsdf(albedo: float = SUPPORT_ALBEDO) -> dict:
    """The grey Lambertian table top (scene parameter ``support_albedo``)."""
    return {"type": "diffuse", "reflectance": float(albedo)}


def uses_delta_bsdf(material: str) -> bool:
    """True when the material is a perfect mirror (needs light tracing for laser -> mirror -> diffuse)."""
    return material == "specular"


SHINY = ("specular", "polished", "glazed")
"""Materials whose specular lobe throws the laser sheet onto other surfaces (false stripes)."""


def integrator_for(material: str) -> str:
    """How the laser pass renders ``material``.

    Returns
    -------
    str
        ``"path"`` (path tracing, the default), ``"ptracer"`` (light tracing: ``specular``, whose
        laser -> mirror -> diffuse paths a path tracer cannot find) or ``"split"`` (``polished``,
        ``glazed``: path tracing on the pixels that see the object, where it renders the highlight and
        the lit wall seen in the object, light tracing on all other pixels, where it renders the
        sheet reflected onto them; see :func:`scenes.description.laser_passes`).

    Examples
    --------
    >>> integrator_for("matte"), integrator_for("specular"), integrator_for("polished")
    ('path', 'ptracer', 'split')
    """
    if material not in MATERIALS:
        raise KeyError(f"unknown `material` {material!r}; valid: {', '.join(MATERIALS)}")
    if uses_delta_bsdf(material):
        return "ptracer"
    if material in ("polished", "glazed"):
        return "split"
    return "path"

