"""Sample counts per material and pass: what ``spp = "auto"`` and ``ambient_spp = "auto"`` render.

The counts between the ``generated`` markers below are written by the committed procedure
``stripebench perf sampling --write`` (:mod:`bench.studies.perf.sampling`; do not edit them by hand):
for every opaque and shiny material it renders the laser and ambient passes of the cone and the hand
at 512x480 with several integrators and sample counts, on a seed and angles that the paper run does not
use, measures each against a high-count reference in units of the sensor noise, and keeps the
cheapest candidate whose render noise stays at most the sensor's (stripe, the rest of
the frame and the stripe's centroid) with the stripe's energy within 2 %. ``MEASURED`` holds the
chosen candidates' worst-case numbers over the procedure's cases. For the shiny materials it also
measures the object's own pass (``path`` on the object's pixels) on those pixels against a longer
reference, per object and geometry: :data:`OBJECT_SPP` holds the counts it certifies there (the others
keep the table's count), :data:`MEASURED_OBJECT` the numbers of the count each object renders with.

Of the translucent materials only the ambient pass is measured (their laser pass's ``volpath`` noise
stays above the sensor's at any affordable count: docs/translucency.md), so ``LASER_SPP`` lacks them.
A material a table lacks, and any scene whose laser passes are not the material's own (a path-traced
material on a polished table), keeps the fixed counts :data:`FIXED_SPP` and :data:`FIXED_AMBIENT_SPP`
for that pass. The counts were measured at 512x480; at other sizes ``auto`` gives the same
counts (a smaller image has wider pixels, so its stripe is sharper per pixel; rerun the procedure
there before relying on the noise claim).
"""

from __future__ import annotations

from typing import Optional, Tuple

__all__ = ["AUTO", "FIXED_SPP", "FIXED_AMBIENT_SPP", "LASER_KIND", "LASER_SPP", "AMBIENT_SPP", "MEASURED",
           "OBJECT_SPP", "MEASURED_OBJECT", "case_key", "laser_choice", "object_spp", "ambient_spp"]

AUTO = "auto"
"""The value of ``spp`` / ``ambient_spp`` that selects this table."""

FIXED_SPP = 16
"""Laser-pass spp of every material (and pass) the table lacks."""

FIXED_AMBIENT_SPP = 8
"""Ambient-pass spp of every material the table lacks."""

# --- generated: begin ---
# by `stripebench perf sampling --from results/sampling.json --write`
LASER_KIND = {'matte': 'hybrid', 'patchy': 'hybrid', 'absorbing': 'hybrid', 'glossy': 'hybrid', 'polished': 'split_hybrid', 'glazed': 'split_hybrid', 'specular': 'hybrid'}
LASER_SPP = {'matte': (4, 4), 'patchy': (4, 2), 'absorbing': (2, 1), 'glossy': (4, 1), 'polished': (16, 2, 2), 'glazed': (16, 2, 2), 'specular': (2, 1)}
AMBIENT_SPP = {'matte': 2, 'patchy': 2, 'absorbing': 1, 'glossy': 1, 'polished': 2, 'glazed': 2, 'specular': 1, 'skin': 4}
MEASURED = {'matte': {'z_stripe': 0.976, 'z_off': 0.58, 'centre': 0.66, 'energy': 0.9959, 'z_ambient': 0.692, 'cases': 4}, 'patchy': {'z_stripe': 0.971, 'z_off': 0.599, 'centre': 0.854, 'energy': 0.9965, 'z_ambient': 0.597, 'cases': 8}, 'absorbing': {'z_stripe': 0.313, 'z_off': 0.059, 'centre': 0.469, 'energy': 1.0034, 'z_ambient': 0.569, 'cases': 4}, 'glossy': {'z_stripe': 0.607, 'z_off': 0.672, 'centre': 0.608, 'energy': 0.9976, 'z_ambient': 0.775, 'cases': 4}, 'polished': {'z_stripe': 0.633, 'z_off': 0.296, 'centre': 0.687, 'energy': 1.0114, 'z_ambient': 0.759, 'cases': 4}, 'glazed': {'z_stripe': 0.659, 'z_off': 0.288, 'centre': 0.625, 'energy': 1.0142, 'z_ambient': 0.7, 'cases': 4}, 'specular': {'z_stripe': 0.335, 'z_off': 0.204, 'centre': 0.601, 'energy': 1.0071, 'z_ambient': 0.703, 'cases': 4}}
OBJECT_SPP = {'polished': {'cone/none-table': 2}, 'glazed': {'cone/none-table': 4}}
MEASURED_OBJECT = {'polished': {'cone/none-table': {'spp': 2, 'certified': True, 'z_stripe': 0.366, 'z_off': 0.968, 'centre': 0.0, 'energy': 0.9871}, 'hand/none-table': {'spp': 16, 'certified': False, 'z_stripe': 5.493, 'z_off': 0.74, 'centre': 0.419, 'energy': 1.0035}}, 'glazed': {'cone/none-table': {'spp': 4, 'certified': True, 'z_stripe': 0.859, 'z_off': 0.575, 'centre': 0.435, 'energy': 0.9978}, 'hand/none-table': {'spp': 16, 'certified': False, 'z_stripe': 0.874, 'z_off': 0.612, 'centre': 1.395, 'energy': 0.9998}}}
# --- generated: end ---


def laser_choice(material: str) -> Optional[Tuple[str, Tuple[int, ...]]]:
    """The ``auto`` laser pass of ``material``: ``(integrator, spp per pass)``, or None.

    ``integrator`` is ``"path"`` or ``"ptracer"`` (one pass over every pixel), ``"hybrid"``
    (:func:`scenes.description.hybrid_passes`: the direct light path traced, the interreflected light
    light traced; two counts), ``"split"`` (the shiny materials' ``path`` on the object's pixels and
    ``ptracer`` elsewhere: two counts) or ``"split_hybrid"`` (:func:`scenes.description.split_hybrid_passes`:
    three counts). None
    when the table lacks ``material``: the scene keeps its passes at :data:`FIXED_SPP`.

    Examples
    --------
    >>> laser_choice("skin") is None
    True
    """
    chosen = LASER_SPP.get(material)
    if chosen is None:
        return None
    return LASER_KIND[material], tuple(int(n) for n in chosen)


def case_key(obj: str, background: str, support: str) -> str:
    """The key of an object in its geometry in :data:`OBJECT_SPP`: ``"object/background-support"``.

    Examples
    --------
    >>> case_key("cone", "none", "table")
    'cone/none-table'
    """
    return f"{obj}/{background}-{support}"


def object_spp(material: str, key: str) -> Optional[int]:
    """The ``auto`` count of a shiny material's object pass (the first of its ``split`` /
    ``split_hybrid`` passes) for the object and geometry ``key`` (:func:`case_key`), or None.

    The procedure measures that pass on the object's own pixels against a longer reference, per object
    (a convex object mirrors little of the stripe into itself; the hand's fingers mirror each other),
    and writes the counts it can certify into :data:`OBJECT_SPP`. None (the count of
    :func:`laser_choice`, :data:`FIXED_SPP`) for every other object and geometry and where no count
    passes.

    Examples
    --------
    >>> object_spp("matte", case_key("cone", "none", "table")) is None
    True
    """
    n = OBJECT_SPP.get(material, {}).get(key)
    return None if n is None else int(n)


def ambient_spp(material: str) -> int:
    """The ``auto`` sample count of the ambient pass (:data:`FIXED_AMBIENT_SPP` when the table lacks it).

    Examples
    --------
    >>> ambient_spp("wax")
    8
    """
    return int(AMBIENT_SPP.get(material, FIXED_AMBIENT_SPP))
