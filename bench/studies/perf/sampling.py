"""The committed procedure that chooses each material's sample counts (``spp = "auto"``).

Usage: ``stripebench perf sampling [--angles 2] [--ref-spp 144] [--ref-ambient-spp 144] [--ref-object-spp 1024]
[--write]``

For every opaque and shiny material (:data:`MATERIALS`) and each case of :data:`CASES` (the cone and
the hand on the table, and for ``patchy`` also before the in-range wall: the paper profile's
geometries), at 512x480, seed :data:`SEED` and ``--angles`` mirror angles that the paper run does not
use (:func:`calibration_angles`), it renders

* the **laser pass** with every candidate of :func:`laser_candidates`: for the path-traced materials
  ``path`` (camera paths, every pixel), ``ptracer`` (light paths from the projector, splatted to the
  camera) and ``hybrid`` (the direct light path traced, the interreflected light light traced:
  :func:`scenes.description.hybrid_passes`) at several sample counts; the ``split`` of the shiny
  materials (``path`` on the pixels that see the object, ``ptracer`` on the others) at several counts
  per half, and their ``split_hybrid`` (the others' direct light path traced, what reaches them after
  a bounce light traced: :func:`scenes.description.split_hybrid_passes`); ``ptracer`` and ``hybrid``
  for ``specular``;
* the **ambient pass** (``path``) at :data:`AMBIENT_CANDIDATES` samples per pixel,

and compares each with a high-count reference (``--ref-spp``, ``--ref-ambient-spp``): for the
path-traced materials and ``specular`` the ``hybrid`` at that count (each half by the integrator that
converges there; the material's own integrator at the same count is printed beside it as a check: the
stripe's energy ratio and ``z_off``), for the split the split (each reference pixel from the half that
converges there).  All
renders are converted to noise-free DN by the default sensor at the scene's laser power and ambient, and
measured in units of the **sensor noise** (shot + read noise at the reference level plus the ADC's
1/sqrt(12) DN, :meth:`scenes.sensor.SensorModel.noise_dn`):

``z_stripe``, ``z_off``
    rms of (render - reference) / sensor noise over the pixels within 3 px of the true stripe, and over
    the other pixels that see a surface (where only interreflected laser light lands);
``energy``
    the laser energy on the stripe pixels relative to the reference;
``centre``
    rms over the well-lit rows (reference peak >= 5 DN) of the shift of the stripe's centroid
    (11-px window on the true column) against the reference, divided by the rms of the centroid's
    standard deviation that the sensor noise alone causes (:func:`centroid_sd_px`).

For ``polished`` and ``glazed`` the laser candidates vary only the passes of the pixels that do not see
the object (the table's stripe, the mirrored sheet), measured on those pixels and on the rows whose
truth is not on the object: the object's glossy highlight's rare bright paths dominate any rms there at
the references' count (a first run of this procedure measured every count on all pixels and could
certify none, not even 16 + 16). The **object pass** (``path`` on the object's pixels, the first of
the split's passes) is measured on its own, per object and geometry (:func:`scenes.sampling.case_key`):
at :data:`OBJECT_SPP` samples, on the object's pixels (within 3 px of the truth, the rest) and the
rows whose truth is on the object, against the same pass at ``--ref-object-spp`` (default
:data:`REF_OBJECT_SPP`, affordable on those pixels alone), the other pixels at their reference. Its
count is chosen per object by the same rule (:func:`choose_objects`), since the light an object mirrors
into itself depends on its shape; an object where no count passes keeps the table's.

A candidate passes when, on every case, ``z_stripe``, ``z_off`` and ``centre`` are at most
:data:`Z_MAX` (1: the render noise at most the sensor's; the total noise then at most sqrt(2) times
the sensor's) and ``energy``
is within :data:`ENERGY_TOL`; for the ambient pass ``z`` over every surface pixel.  A candidate
qualifies when it passes and so does every candidate with the same integrators and at least its
count in every pass (:func:`choose`); the cheapest qualifying one (mean CPU seconds of its renders,
kernels compiled beforehand; of two with the same integrators, the one with at most the other's count in
every pass) is chosen. ``--save FILE`` keeps every measurement as JSON and
``--from FILE`` chooses (and writes) from such a file without rendering.
``--write`` writes the choices and their worst-case numbers into :mod:`scenes.sampling`, which
``spp = "auto"`` and ``ambient_spp = "auto"`` read.  Of the translucent materials
(:data:`AMBIENT_ONLY`) only the ambient pass (``volpath``) is measured, by the same rule; their laser
pass keeps its fixed count (``volpath``'s render noise on the stripe stays above the sensor's at any
affordable count: docs/translucency.md). ``--write`` needs every opaque and shiny material and writes
the ambient count of each translucent one measured.
"""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import numpy as np

__all__ = ["MATERIALS", "AMBIENT_ONLY", "CASES", "SEED", "Z_MAX", "ENERGY_TOL", "AMBIENT_CANDIDATES", "REF_OBJECT_SPP",
           "OBJECT_SPP", "calibration_angles",
           "laser_candidates", "centroid_sd_px", "measure", "choose", "choose_objects", "study"]

MATERIALS = ("matte", "patchy", "absorbing", "glossy", "polished", "glazed", "specular")
"""The materials the procedure measures (every opaque and shiny one)."""

_TABLE = {"background": "none", "support": "table"}
_WALL = {"background": "wall", "support": "none"}
AMBIENT_ONLY = ("skin", "marble", "wax")
"""The translucent materials: only their ambient pass is measured (their laser pass keeps its fixed
count: module docstring)."""
CASES = {m: (("cone", _TABLE), ("hand", _TABLE)) + ((("cone", _WALL), ("hand", _WALL)) if m == "patchy" else ())
         for m in MATERIALS + AMBIENT_ONLY}
"""Per material, the (object, geometry) cases: the paper profile's geometries."""

SEED = 1
"""The renders' seed (the paper run uses 0)."""

Z_MAX = 1.0
"""Largest accepted render noise in units of the sensor noise (the issue's rule: below the sensor's)."""

ENERGY_TOL = 0.02
"""Largest accepted relative error of the stripe's laser energy."""

AMBIENT_CANDIDATES = (1, 2, 4, 8)
"""Samples per pixel tried for the ambient pass."""

REF_OBJECT_SPP = 1024
"""Default ``--ref-object-spp``: the shiny object's own reference (module docstring)."""

OBJECT_SPP = (2, 4, 8, 16)
"""Samples per pixel tried for a shiny material's object pass."""

_PATH_SPP = (4, 8, 16)
_PTRACER_SPP = (16,)
_HYBRID_DIRECT_SPP = (2, 4, 8, 16)
_HYBRID_INDIRECT_SPP = (1, 2, 4)
_SPLIT_SPP = (4, 8, 16)
_WINDOW_PX = 5
_LIT_DN = 5.0
_STRIPE_PX = 3


def calibration_angles(scene, n: int) -> np.ndarray:
    """``n`` mirror angles (deg) inside the object's sweep that a 12-angle scan does not use.

    The midpoints between consecutive angles of the scene's 12-angle default sweep, ``n`` of them
    spread from the second to the second-last midpoint.

    Parameters
    ----------
    scene : scenes.Scene
    n : int
        Number of angles, >= 1.

    Returns
    -------
    ndarray (n,), float64
    """
    grid = scene.object.default_angles(scene.rig.zeta_deg, 12)
    mids = 0.5 * (grid[1:] + grid[:-1])
    return mids[np.unique(np.linspace(1, len(mids) - 2, n).round().astype(int))]


def laser_candidates(material: str) -> List[Tuple[str, Tuple[int, ...]]]:
    """The laser-pass candidates of ``material``: ``(integrator label, spp per pass)``.

    Labels (:func:`scenes.sampling.laser_choice`): ``path`` and ``ptracer`` (one pass over every
    pixel) and ``hybrid`` (``path`` count of the direct light, ``ptracer`` count of the
    interreflections: :func:`scenes.description.hybrid_passes`) for the path-traced materials;
    ``split`` (``path`` count, ``ptracer`` count) and ``split_hybrid`` (three counts) for ``polished``
    and ``glazed``; ``ptracer`` and ``hybrid`` for ``specular``.

    Examples
    --------
    >>> laser_candidates("specular")[:4]
    [('ptracer', (4,)), ('ptracer', (8,)), ('ptracer', (16,)), ('hybrid', (2, 1))]
    >>> laser_candidates("glazed")[:2]
    [('split', (16, 4)), ('split', (16, 8))]
    >>> laser_candidates("matte")[:3]
    [('path', (4,)), ('path', (8,)), ('path', (16,))]
    """
    from scenes import description, sampling

    kinds = [p.kind for p in description.laser_passes(material)]
    if kinds == ["path", "ptracer"]:
        fixed = sampling.FIXED_SPP  # the object's pixels: module docstring
        return ([("split", (fixed, b)) for b in _SPLIT_SPP]
                + [("split_hybrid", (fixed, b, c)) for b in _HYBRID_DIRECT_SPP[:2] for c in _HYBRID_INDIRECT_SPP[1:]])
    if kinds == ["ptracer"]:
        return ([("ptracer", (k,)) for k in _SPLIT_SPP]
                + [("hybrid", (a, b)) for a in _HYBRID_DIRECT_SPP for b in _HYBRID_INDIRECT_SPP])
    return ([("path", (k,)) for k in _PATH_SPP] + [("ptracer", (k,)) for k in _PTRACER_SPP]
            + [("hybrid", (a, b)) for a in _HYBRID_DIRECT_SPP for b in _HYBRID_INDIRECT_SPP])


def _windows(columns: np.ndarray, width: int):
    rows = np.nonzero(np.isfinite(columns))[0]
    centre = np.rint(columns[rows]).astype(int)
    cols = centre[:, None] + np.arange(-_WINDOW_PX, _WINDOW_PX + 1)[None, :]
    keep = (cols[:, 0] >= 0) & (cols[:, -1] < width)
    return rows[keep], cols[keep]


def _centroids(laser_dn: np.ndarray, rows, cols) -> np.ndarray:
    w = laser_dn[rows[:, None], cols]
    with np.errstate(invalid="ignore", divide="ignore"):
        return (w * cols).sum(axis=1) / w.sum(axis=1)


def centroid_sd_px(laser_dn: np.ndarray, sigma_dn: np.ndarray, columns: np.ndarray) -> np.ndarray:
    """Standard deviation (px) of each row's stripe centroid that the sensor noise alone causes.

    The centroid ``c = sum(u L_u) / sum(L_u)`` over an 11-px window on the true column; to first order
    ``var(c) = sum((u - c)^2 sigma_u^2) / (sum L_u)^2``.

    Parameters
    ----------
    laser_dn : ndarray (H, W)
        Noise-free laser level (DN).
    sigma_dn : ndarray (H, W)
        Sensor noise (DN rms) per pixel.
    columns : ndarray (H,)
        True stripe column per row (NaN: none).

    Returns
    -------
    ndarray (H,), float64
        NaN on rows without a full window.

    Examples
    --------
    >>> L = np.zeros((1, 21)); L[0, 10] = 100.0
    >>> float(centroid_sd_px(L, np.ones((1, 21)), np.array([10.0]))[0]) == math.sqrt(110) / 100
    True
    """
    out = np.full(len(columns), np.nan)
    rows, cols = _windows(np.asarray(columns, float), laser_dn.shape[1])
    if len(rows):
        c = _centroids(laser_dn, rows, cols)
        num = (((cols - c[:, None]) ** 2) * sigma_dn[rows[:, None], cols] ** 2).sum(axis=1)
        out[rows] = np.sqrt(num) / laser_dn[rows[:, None], cols].sum(axis=1)
    return out


class _Measure:
    """A reference laser image and the regions it is measured on (:meth:`metrics`).

    Parameters
    ----------
    ref : ndarray (H, W)
        Reference laser DN (noise-free).
    sigma : ndarray (H, W)
        Sensor noise (DN rms) at the reference level.
    regions : dict of str to ndarray (H, W) bool
        ``stripe`` (within 3 px of the truth) and ``off`` (the other measured surface pixels).
    columns : ndarray (H,)
        True stripe column of the rows whose centroid is measured (NaN: not measured).
    """

    def __init__(self, ref, sigma, regions, columns):
        self.ref, self.sigma, self.regions = ref, sigma, regions
        h, w = ref.shape
        sd = centroid_sd_px(ref, sigma, columns)
        rows, cols_w = _windows(columns, w)
        lit = np.zeros(h, bool)
        lit[rows] = ref[rows[:, None], cols_w].max(axis=1) >= _LIT_DN
        self.lit = lit & np.isfinite(sd)
        self.centroid_sd = float(np.sqrt(np.mean(sd[self.lit] ** 2))) if self.lit.any() else math.nan
        self.centroid_ref = _centroids(ref, rows, cols_w)
        self._rows, self._cols = rows, cols_w

    def metrics(self, img: np.ndarray) -> Dict[str, float]:
        """``stripe``, ``off``, ``energy`` and ``centre`` of ``img`` (laser DN) against the reference."""
        z = (img - self.ref) / self.sigma
        out = {name: float(np.sqrt(np.mean(z[m] ** 2))) if m.any() else 0.0 for name, m in self.regions.items()}
        e_ref = self.ref[self.regions["stripe"]].sum()
        out["energy"] = float(img[self.regions["stripe"]].sum() / e_ref) if e_ref > 0 else 1.0
        c = _centroids(img, self._rows, self._cols)
        lit = self.lit[self._rows]
        shift = c[lit] - self.centroid_ref[lit]
        out["centre"] = (float(np.sqrt(np.mean(shift ** 2)) / self.centroid_sd)
                         if lit.any() and self.centroid_sd > 0 else 0.0)
        return out


class _Case:
    """One (material, object, geometry, angle): its loaded scene, references and regions."""

    def __init__(self, material, obj, geometry, theta, ref_spp, ref_ambient_spp, ref_object_spp=REF_OBJECT_SPP):
        import scenes
        from scenes import description, sampling

        self.label = f"{obj}/{material}/{geometry['background']}-{geometry['support']}@{theta:.2f}"
        self.key = sampling.case_key(obj, geometry["background"], geometry["support"])
        self.scene = s = scenes.make(obj, material=material, cache=False, seed=SEED, **geometry)
        self.theta = theta
        self.laser_scene, self.ambient_scene = s._load(16)
        self.pose = description.pose_updates(s.rig, theta)
        self.sensor = s.sensor
        per_unit = s.sensor.electrons_per_radiance / s.sensor.gain_e_per_dn
        self.laser_scale = s.laser_power_inband_w() * per_unit
        self.ambient_scale = s.sky_radiance_inband() * per_unit
        kinds = [p.kind for p in description.laser_passes(material)]
        self.split = s.split_pixels(theta) if kinds == ["path", "ptracer"] else None
        self.object = None
        if material in AMBIENT_ONLY:  # the ambient pass alone, on every surface pixel
            points, _ = s.visible_points(theta)
            self.surface = np.isfinite(points[..., 0])
            self.ambient_ref = self.ambient(ref_ambient_spp, 1001)
            self.check, self.others = None, None
            return
        truth = s.truth(theta)
        columns = truth.columns
        points, _ = s.visible_points(theta)
        surface = np.isfinite(points[..., 0])
        h, w = surface.shape
        cols = np.arange(w)[None, :]
        with np.errstate(invalid="ignore"):
            near = np.abs(cols - columns[:, None]) <= _STRIPE_PX
        self.surface = surface  # the ambient pass is measured on every surface pixel
        self.ambient_ref = self.ambient(ref_ambient_spp, 1001)
        self.check = None
        if self.split is not None:
            # the others' passes are measured on the others' pixels and rows, the object's pass on the
            # object's (module docstring)
            self.laser_ref = self.laser("split", (ref_spp, ref_spp), 1002)
            on_object = truth.part == 1
            others = np.where(self.split, 0.0, self.laser_ref)
            self.object_pass = description.laser_passes(material)[0]
            object_ref = others + self.render(self.object_pass, ref_object_spp, 1004) * self.laser_scale
            sigma = self.sensor.noise_dn(object_ref + self.ambient_ref)
            self.object = _Measure(object_ref, sigma,
                                   {"stripe": near & self.split, "off": surface & self.split & ~near},
                                   np.where(on_object, columns, np.nan))
            self._others_ref = others
            near, surface = near & ~self.split, surface & ~self.split
            columns = np.where(on_object, np.nan, columns)
        else:
            # each half by the integrator that converges there; the material's own integrator at the
            # same count is kept as a check that the two agree (:attr:`check`)
            self.laser_ref = self.laser("hybrid", (ref_spp, ref_spp), 1002)
        self.sigma = self.sensor.noise_dn(self.laser_ref + self.ambient_ref)
        self.others = _Measure(self.laser_ref, self.sigma, {"stripe": near, "off": surface & ~near}, columns)
        if self.split is None:
            path_ref = self.laser(kinds[0], (ref_spp,), 1003)
            stripe = self.others.regions["stripe"]
            self.check = {"energy": float(path_ref[stripe].sum() / self.laser_ref[stripe].sum()),
                          "z_off": float(np.sqrt(np.mean(((path_ref - self.laser_ref) / self.sigma)[
                              self.others.regions["off"]] ** 2)))}

    @property
    def lit(self) -> np.ndarray:
        """Rows whose stripe centroid the laser candidates are measured on."""
        return np.zeros(0, bool) if self.others is None else self.others.lit

    @property
    def centroid_sd(self) -> float:
        return math.nan if self.others is None else self.others.centroid_sd

    def render(self, laser_pass, spp: int, seed: int) -> np.ndarray:
        """One laser pass (:class:`scenes.description.LaserPass`) as ``Scene.render`` renders it: on
        its pixels (:meth:`scenes.Scene.pass_pixels`), zero elsewhere."""
        from scenes import render_pass

        mask = self.scene.pass_pixels(self.theta, (laser_pass,))[0]
        return render_pass(self.laser_scene, self.pose, laser_pass, mask, spp, seed)

    def components(self, label: str, spps: Tuple[int, ...]):
        """The renders ``(laser pass, spp)`` a candidate is made of: its
        :class:`scenes.description.LaserPass` es, as ``Scene.render`` makes them."""
        from scenes import description

        if label == "split":
            passes = description.laser_passes(self.scene.params["material"])
        elif label == "split_hybrid":
            passes = description.split_hybrid_passes()
        elif label == "hybrid":
            passes = description.hybrid_passes()
        else:
            passes = (description.LaserPass(label, description.MAX_DEPTH, "all"),)
        return list(zip(passes, spps))

    def combine(self, parts) -> np.ndarray:
        """Noise-free laser DN of a candidate from its component renders (each zero off its pixels):
        their sum, as ``Scene.render`` sums its passes."""
        return np.add.reduce(parts) * self.laser_scale

    def laser(self, label: str, spps: Tuple[int, ...], seed: int) -> np.ndarray:
        """Noise-free laser DN of a candidate."""
        return self.combine([self.render(p, n, seed) for p, n in self.components(label, spps)])

    def ambient(self, spp: int, seed: int) -> np.ndarray:
        return self.ambient_scene.render(self.pose, spp, seed).astype(np.float64) * self.ambient_scale

    def laser_metrics(self, img: np.ndarray) -> Dict[str, float]:
        """A laser candidate's metrics (for a shiny material on the others' pixels and rows)."""
        return self.others.metrics(img)

    def object_metrics(self, render: np.ndarray) -> Dict[str, float]:
        """The object pass's metrics (shiny materials): ``render`` (unit radiance, zero off the object's
        pixels) with the others' pixels at their reference, on the object's pixels and rows."""
        return self.object.metrics(self._others_ref + render * self.laser_scale)

    def ambient_metrics(self, img: np.ndarray) -> float:
        z = (img - self.ambient_ref) / self.sensor.noise_dn(self.ambient_ref)
        return float(np.sqrt(np.mean(z[self.surface] ** 2)))


def _timed(fn):
    c0 = time.process_time()
    out = fn()
    return out, time.process_time() - c0


def _passes(metrics: Dict[str, float]) -> bool:
    return (metrics["stripe"] <= Z_MAX and metrics["off"] <= Z_MAX and metrics["centre"] <= Z_MAX
            and abs(metrics["energy"] - 1.0) <= ENERGY_TOL)


def _worst(w: Optional[dict], m: dict) -> dict:
    """The worst of two metric records: the largest z's, the energy farthest from 1."""
    if w is None:
        return m
    return {"stripe": max(w["stripe"], m["stripe"]), "off": max(w["off"], m["off"]),
            "centre": max(w["centre"], m["centre"]),
            "energy": max(w["energy"], m["energy"], key=lambda e: abs(e - 1.0))}


def measure(material: str, n_angles: int, ref_spp: int, ref_ambient_spp: int, progress: bool = True,
            ref_object_spp: int = REF_OBJECT_SPP) -> dict:
    """Every candidate of one material on its cases.

    Returns
    -------
    dict
        ``{"laser": {(label, spps): {"worst": metrics, "cost_s": float, "pass": bool}}, "ambient":
        {spp: {"z": float, "cost_s": float, "pass": bool}}, "object": {case key: {("path", (spp,)):
        {...}}}, "cases": [labels]}``; ``worst`` holds the largest ``stripe``/``off``/``centre`` and the
        energy farthest from 1 over the cases (``object``, the shiny materials' object pass, over each
        object's cases: :func:`scenes.sampling.case_key`; empty for the others).
    """
    import scenes

    laser: Dict[tuple, dict] = {}
    ambient: Dict[int, dict] = {}
    objects: Dict[str, Dict[tuple, dict]] = {}
    labels, checks = [], []
    for obj, geometry in CASES[material]:
        probe = scenes.make(obj, material=material, cache=False, seed=SEED, **geometry)
        for theta in calibration_angles(probe, n_angles):
            case = _Case(material, obj, geometry, float(theta), ref_spp, ref_ambient_spp, ref_object_spp)
            labels.append(case.label)
            if progress and material in AMBIENT_ONLY:
                print(f"  {case.label}: ambient pass only", file=sys.stderr, flush=True)
            elif progress:
                check = ("" if case.check is None else
                         f"; own integrator @ref / reference: stripe energy {case.check['energy']:.4f}, z off "
                         f"{case.check['z_off']:.2f}")
                if case.object is not None:
                    n_lit = int(case.object.lit.sum())
                    check += f"; object: {n_lit} lit rows" + (
                        f", sensor centroid sd {case.object.centroid_sd:.3f} px" if n_lit
                        else " (no centroid measured)")
                print(f"  {case.label}: {int(case.lit.sum())} lit rows, sensor centroid sd "
                      f"{case.centroid_sd:.3f} px{check}", file=sys.stderr, flush=True)
            checks.append(case.check)
            done: Dict[tuple, tuple] = {}  # component render -> (image, CPU s), shared by the candidates

            def rendered(comp):
                if comp not in done:
                    case.render(*comp, 7)  # compile the kernels first
                    done[comp] = _timed(lambda: case.render(*comp, 11))
                return done[comp]

            for cand in (() if material in AMBIENT_ONLY else laser_candidates(material)):
                parts = [rendered(c) for c in case.components(*cand)]
                img, cost = case.combine([p[0] for p in parts]), sum(p[1] for p in parts)
                rec = laser.setdefault(cand, {"worst": None, "costs": []})
                rec["costs"].append(cost)
                rec["worst"] = _worst(rec["worst"], case.laser_metrics(img))
            if case.object is not None:
                for spp in OBJECT_SPP:
                    img, cost = rendered((case.object_pass, spp))
                    rec = objects.setdefault(case.key, {}).setdefault(("path", (spp,)), {"worst": None, "costs": []})
                    rec["costs"].append(cost)
                    rec["worst"] = _worst(rec["worst"], case.object_metrics(img))
            for spp in AMBIENT_CANDIDATES:
                case.ambient(spp, 7)
                img, cost = _timed(lambda: case.ambient(spp, 11))
                rec = ambient.setdefault(spp, {"z": 0.0, "costs": []})
                rec["z"] = max(rec["z"], case.ambient_metrics(img))
                rec["costs"].append(cost)
    for rec in list(laser.values()) + [r for o in objects.values() for r in o.values()]:
        rec["cost_s"] = float(np.mean(rec.pop("costs")))
        rec["pass"] = _passes(rec["worst"])
    for rec in ambient.values():
        rec["cost_s"] = float(np.mean(rec.pop("costs")))
        rec["pass"] = rec["z"] <= Z_MAX
    return {"laser": laser, "ambient": ambient, "object": objects, "cases": labels, "checks": checks}


def _dominates(a, b) -> bool:
    """Whether candidate ``a`` has the same integrators as ``b`` and at least its count in every pass."""
    return a[0] == b[0] and all(x >= y for x, y in zip(a[1], b[1]))


def _cheapest(cands: dict):
    """The cheapest qualifying key of ``{candidate: {"cost_s", "pass"}}`` (None where none qualifies).

    A candidate qualifies when it passes and so does every candidate with the same integrators and
    at least its count in every pass (a pass that more samples would lose is the measurement's noise,
    not a margin). Of two qualifying candidates with the same integrators, the one with at most the
    other's count in every pass is the cheaper by construction, whatever the CPU seconds measured
    say (their noise once swapped 16+2+2 and 16+4+2); the measured cost decides between the others.
    """
    ok = [cand for cand, rec in cands.items() if all(cands[c]["pass"] for c in cands if _dominates(c, cand))]
    ok = [cand for cand in ok if not any(o != cand and _dominates(cand, o) for o in ok)]
    return min(ok, key=lambda c: (cands[c]["cost_s"], c)) if ok else None


def choose(result: dict):
    """The chosen laser candidate and ambient count of :func:`measure`'s result (None where none
    qualifies): the cheapest qualifying one of each (:func:`_cheapest`)."""
    amb = {("path", (n,)): rec for n, rec in result["ambient"].items()}
    chosen_amb = _cheapest(amb)
    return _cheapest(result["laser"]), (None if chosen_amb is None else chosen_amb[1][0])


def choose_objects(result: dict) -> Dict[str, Optional[int]]:
    """Per case key (:func:`scenes.sampling.case_key`), the object pass's chosen count of a shiny
    material (None where none qualifies: the object keeps :data:`scenes.sampling.FIXED_SPP`)."""
    out = {}
    for key, cands in result.get("object", {}).items():
        chosen = _cheapest(cands)
        out[key] = None if chosen is None else chosen[1][0]
    return out


def _table(material: str, result: dict, chosen) -> str:
    lines = [f"| `{material}` laser | z stripe | z off | centre | energy | CPU s | passes |",
             "| --- | --- | --- | --- | --- | --- | --- |"]
    for cand, rec in result["laser"].items():
        w = rec["worst"]
        mark = " **chosen**" if cand == chosen[0] else ""
        lines.append(f"| {cand[0]} {'+'.join(map(str, cand[1]))} spp{mark} | {w['stripe']:.2f} | {w['off']:.2f} | "
                     f"{w['centre']:.2f} | {w['energy']:.3f} | {rec['cost_s']:.2f} | {'yes' if rec['pass'] else 'no'} |")
    for spp, rec in result["ambient"].items():
        mark = " **chosen**" if spp == chosen[1] else ""
        lines.append(f"| ambient path {spp} spp{mark} | z {rec['z']:.2f} | | | | {rec['cost_s']:.2f} | "
                     f"{'yes' if rec['pass'] else 'no'} |")
    objects = choose_objects(result)
    for key, cands in result.get("object", {}).items():
        for cand, rec in cands.items():
            w = rec["worst"]
            mark = " **chosen**" if cand[1][0] == objects[key] else ""
            lines.append(f"| object pass {key}: {cand[0]} {cand[1][0]} spp{mark} | {w['stripe']:.2f} | "
                         f"{w['off']:.2f} | {w['centre']:.2f} | {w['energy']:.3f} | {rec['cost_s']:.2f} | "
                         f"{'yes' if rec['pass'] else 'no'} |")
    return "\n".join(lines)


def study(*, angles: int = 2, ref_spp: int = 144, ref_ambient_spp: int = 144, ref_object_spp: int = REF_OBJECT_SPP,
          materials=None, write: bool = False, save=None, from_file=None) -> int:
    """Measure (or read) every material's candidates, print the tables and the choices, and with ``write``
    write them into :mod:`scenes.sampling` (``stripebench perf sampling``).

    Parameters
    ----------
    angles : int
        Calibration angles per case (:func:`calibration_angles`).
    ref_spp, ref_ambient_spp : int
        Sample counts of the laser and ambient references.
    ref_object_spp : int
        Sample count of a shiny object's own reference, on its pixels.
    materials : str, optional
        Comma-separated materials (default :data:`MATERIALS` and :data:`AMBIENT_ONLY`; with ``from_file``,
        those the file has).
    write : bool
        Write the choices into ``scenes/sampling.py`` (:func:`bench.studies.perf.sampling_tables.write_tables`);
        needs every one of :data:`MATERIALS`.
    save : path, optional
        Also write the measurements (every candidate, every material) as JSON.
    from_file : path, optional
        Choose (and write) from measurements saved by ``save`` instead of rendering.

    Returns
    -------
    int
        0; bad values raise :class:`bench.errors.InputError`.
    """
    from bench.errors import InputError
    from bench.studies.perf import sampling_tables as tables
    from scenes import sampling

    known = MATERIALS + AMBIENT_ONLY
    saved = None
    if from_file:
        from bench.store.textfiles import read_json

        saved = read_json(from_file, "--from")  # a regular file (never waits on a FIFO), bounded size and depth
        try:
            options = saved["options"]
            saved_results = {m: tables.from_json(r) for m, r in saved["results"].items()}
        except (ValueError, KeyError, TypeError, AttributeError, IndexError) as exc:
            from bench.errors import quoted

            raise InputError(f"--from {from_file}: not a file of `stripebench perf sampling --save` "
                             f"({type(exc).__name__}: {quoted(str(exc))})") from None
    if materials is None:
        materials = ",".join(m for m in known if saved is None or m in saved_results)
    materials_text = materials
    materials = [m for m in materials_text.split(",") if m]
    bad = [m for m in materials if m not in known]
    if bad or not materials:
        raise InputError(f"--materials must name some of {', '.join(MATERIALS + AMBIENT_ONLY)}, "
                         f"got {materials_text!r}")
    if write and not set(MATERIALS) <= set(materials):
        raise InputError(f"--write needs every one of {', '.join(MATERIALS)} in --materials")
    results, chosen = {}, {}
    if saved is not None:
        angles, ref_spp, ref_ambient_spp = options["angles"], options["ref_spp"], options["ref_ambient_spp"]
        ref_object_spp = options.get("ref_object_spp")
        missing = [m for m in materials if m not in saved_results]
        if missing:
            raise InputError(f"--from {from_file} lacks the material(s) {', '.join(missing)}")
    for material in materials:
        if saved is not None:
            results[material] = saved_results[material]
        else:
            print(f"{material}:", file=sys.stderr, flush=True)
            results[material] = measure(material, angles, ref_spp, ref_ambient_spp,
                                        ref_object_spp=ref_object_spp)
        chosen[material] = choose(results[material])
        print(_table(material, results[material], chosen[material]) + "\n", flush=True)
    if save:
        from bench.store.files import atomic_write_text

        doc = {"format": 1, "options": {"angles": angles, "ref_spp": ref_spp,
                                        "ref_ambient_spp": ref_ambient_spp,
                                        "ref_object_spp": ref_object_spp},
               "results": {m: tables.to_json(r) for m, r in results.items()}}
        if saved is not None and "provenance" in saved:
            doc["provenance"] = saved["provenance"]
        atomic_write_text(Path(save), json.dumps(doc, indent=1) + "\n")
    print("| material | laser pass(es) | ambient spp |\n| --- | --- | --- |")
    for m, (laser, amb) in chosen.items():
        text = "none passes (fixed counts kept)" if laser is None else f"{laser[0]} {'+'.join(map(str, laser[1]))}"
        print(f"| `{m}` | {text} | {amb if amb is not None else 'none passes'} |")
    for m in chosen:
        for key, n in choose_objects(results[m]).items():
            print(f"| `{m}` object pass, {key} | "
                  f"{'none passes (fixed count kept)' if n is None else f'path {n}'} | |")
    if write:
        argv = (f"stripebench perf sampling --from {from_file} --write" if from_file else
                f"stripebench perf sampling --angles {angles} --ref-spp {ref_spp} "
                f"--ref-ambient-spp {ref_ambient_spp} --ref-object-spp {ref_object_spp} --write")
        objects = {m: choose_objects(results[m]) for m in chosen}
        tables.write_tables(Path(sampling.__file__), results, chosen, objects, argv)
        print(f"wrote {sampling.__file__}", file=sys.stderr)
    return 0
