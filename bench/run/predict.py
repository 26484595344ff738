"""Predict the trackers' figures on a rig's photographs from frames with truth made for them.

Two sources of such frames (:data:`FRAMES`, ``stripebench predict --frames``):

- ``transplant`` (the default): each photograph with its own stripe moved to a known place, both
  ways, and itself in place (:func:`transplant_frames`, :mod:`bench.evaluate.transplant`); the photograph's
  clutter, rivals and camera stay, and the truth is where the stripe was put (in place: where the estimate finds it).
- ``render``: renders matched to the photograph's conditions, below.

The default was chosen on renders (``stripebench predictcheck``: frames with known truth predicted
by each procedure), never on the shipped photographs (docs/predict.md).

The render procedure (committed; its settings were chosen on renders, never on the shipped photographs):

1. **Measure** the photograph's image conditions (:func:`bench.evaluate.conditions.measure`) on
   what the trackers see of it (its channel, turned), with its laser-off frame where it has one and
   the colour photograph where it is one.
2. **A seeded grid of small renders** (:class:`Grid`): a few *setups* (object, material, support,
   textures: what re-renders) x laser line widths, each rendered once at the middle mirror angle
   (the render cache keeps the passes), then every combination of the knobs that only rescale or
   post-process those passes (laser power, ambient lux, exposure, filter, defocus, JPEG): cheap.
   The camera follows the photograph: a colour photograph gets the Bayer colour camera
   (``camera = "rgb"``), a grey one the band-pass mono camera; the laser's wavelength follows its
   colour (:data:`LASER_NM`). Each grid point's conditions are measured exactly as the photograph's
   and kept in a JSON table beside the render cache (:func:`grid_table`), keyed by the grid.
3. **Nearest point**: the grid point with the least :func:`bench.evaluate.conditions.distance`
   (RMS over the matched measures in scale units), then **refined** by a coordinate search over
   the rescaling knobs (power, lux, exposure: factors of 1.4 then 1.15; defocus: steps of 0.5 then
   0.25 px), each within the grid's range, accepting only improvements (:func:`match`).
4. A photograph with a measure outside what the grid shows (more than one scale unit beyond its
   least or largest value, :func:`bench.evaluate.conditions.out_of_range`) is **out of range**:
   named with that measure and left out.

:func:`predict_outcomes` then renders each matched setting at :data:`N_ANGLES` mirror angles and
scores the trackers on them with the row outcomes of :mod:`bench.evaluate.outcomes` (truth: the
render's per-row columns), pooled over the photographs' matched frames.
"""

from __future__ import annotations

import itertools
import json
import math
import sys
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from bench.evaluate import conditions as cond
from bench.evaluate.transplant import ESTIMATES as _STRIPE_ESTIMATES

__all__ = ["LASER_NM", "N_ANGLES", "Grid", "DEFAULT_GRID", "SMALL_GRID", "Match", "photo_conditions",
           "point_params", "render_point", "grid_table", "refined_memo", "save_refined_memo", "match",
           "score_frame", "transplant_frames", "photo_extents", "transplanted", "colour_guide", "COLOUR_GUIDED",
           "transplant_outcomes", "cut_counts", "N_MOVED", "N_FULL", "predict_outcomes", "TABLE_VERSION", "Photo", "collect_photos",
           "run_predict", "FRAMES", "ESTIMATES", "PREDICTED_NAMES", "DOWNSCALES", "downscale_for", "MIN_FRAME_PX"]

#: Each laser colour's wavelength in the renders (nm); the band-pass filter is centred on it.
LASER_NM = {"red": 650.0, "green": 532.0, "blue": 450.0}
#: Mirror angles rendered per matched photograph for the prediction (spread over the middle half of the scan).
N_ANGLES = 3
#: The least tracker frame predicted for (rows, columns): the stripe estimate's support window along the rows
#: (``2 * transplant.SUPPORT_ROWS + 1``) and its smoothing along a row (``transplant.stripe_extents``: 8 columns).
#: A smaller photograph is one line and left out (:func:`collect_photos`).
MIN_FRAME_PX = (7, 8)
#: The version of the grid tables' format and of the measures they hold (bump when either changes).
TABLE_VERSION = 1

_REFINED = ("laser_power_mw", "ambient_lux", "exposure_ms", "defocus_px")


@dataclass(frozen=True)
class Grid:
    """The renders the match searches.

    ``setups`` maps a name to the scene parameters that re-render (``scene`` names the object);
    ``line_fwhm_mrad`` multiplies them; the other tuples are the rescaling knobs, every
    combination of which is measured (``filters`` applies to colour photographs only: a grey
    photograph gets the band-pass mono camera). ``width`` x ``height`` in px (16:15).
    """

    setups: dict = field(default_factory=dict)
    line_fwhm_mrad: tuple = (1.5, 4.0)
    laser_power_mw: tuple = (0.3, 1.0, 3.0, 10.0, 30.0)
    ambient_lux: tuple = (0.0, 100.0, 400.0, 1500.0, 5000.0)
    exposure_ms: tuple = (3.0, 15.0)
    filters: tuple = ("none", "bandpass")
    defocus_px: tuple = (0.0, 1.5)
    jpeg_quality: tuple = (None, 75)
    width: int = 256
    height: int = 240
    seed: int = 0

    def to_value(self) -> dict:
        """The grid as plain data (its identity in the table's key).

        Examples
        --------
        >>> SMALL_GRID.to_value()["width"]
        128
        """
        return json.loads(json.dumps(asdict(self)))


#: The default grid: an untextured board, a floor-textured board (texture, rivals) and a hand on a
#: wooden table before a wall (an object's edges, gaps, a second surface), each at two line widths.
DEFAULT_GRID = Grid(setups={
    "plane": {"scene": "plane", "material": "matte"},
    "plane-floor": {"scene": "plane", "material": "matte", "object_texture": "floor", "background": "none"},
    "hand-table": {"scene": "hand", "material": "matte", "support": "table", "support_texture": "wood"},
})
#: A grid small enough for tests: one setup, one line width, 128x120.
SMALL_GRID = Grid(setups={"plane": {"scene": "plane", "material": "matte"}}, line_fwhm_mrad=(3.0,),
                  laser_power_mw=(0.3, 3.0, 30.0), ambient_lux=(0.0, 400.0, 5000.0), exposure_ms=(10.0,),
                  filters=("none",), defocus_px=(0.0,), jpeg_quality=(None,), width=128, height=120)


@dataclass(frozen=True)
class Match:
    """One photograph's match: the grid point's (refined) knobs, its conditions, the distance
    (scale units) and the measures out of range (empty: in range)."""

    point: dict
    conditions: cond.Conditions | None
    distance: float
    out_of_range: tuple


def photo_conditions(frame, background=None, original=None, *, rotate_deg: int = 0, laser: str = "red"):
    """The conditions of a photograph as the trackers see it.

    Parameters
    ----------
    frame, background : ndarray (H, W)
        The tracker's frame and laser-off frame (:func:`bench.store.realset.load_frame`).
    original : ndarray (H0, W0) or (H0, W0, 3)
        The photograph as read; a colour one is turned by ``rotate_deg`` and measured for colour.
    """
    from bench.evaluate.pixels import rotate_image

    rgb = None
    if original is not None and np.ndim(original) == 3:
        rgb = rotate_image(original, rotate_deg)
    return cond.measure(frame, background, rgb=rgb, laser=laser)


def point_params(point: dict, grid: Grid, *, colour: bool, laser: str) -> tuple[str, dict]:
    """The scene name and :func:`scenes.make` parameters of a grid point."""
    setup = dict(grid.setups[point["setup"]])
    name = setup.pop("scene")
    nm = LASER_NM[laser]
    p = {**setup, "width": grid.width, "height": grid.height, "spp": "auto", "ambient_spp": "auto",
         "seed": grid.seed, "line_fwhm_mrad": float(point["line_fwhm_mrad"]),
         "laser_power_mw": float(point["laser_power_mw"]), "ambient_lux": float(point["ambient_lux"]),
         "exposure_ms": float(point["exposure_ms"]), "defocus_px": float(point["defocus_px"]),
         "jpeg_quality": point["jpeg_quality"], "laser_wavelength_nm": nm, "filter_center_nm": nm}
    if colour:
        p.update(camera="rgb", filter=point["filter"])
    return name, p


def _angles(scene, n: int) -> list[float]:
    a = np.asarray(scene.default_angles(), float)
    if n == 1:
        return [float(a[len(a) // 2])]
    lo, hi = a[len(a) // 4], a[(3 * len(a)) // 4]
    return [float(v) for v in np.linspace(lo, hi, n)]


def render_point(point: dict, grid: Grid, *, colour: bool, laser: str, n_angles: int = 1) -> list:
    """``[(frame, image, background, scene params), ...]``: the grid point rendered at ``n_angles``
    mirror angles (1: the middle one), with what a tracker sees of each frame (``auto`` channel)."""
    import scenes
    from bench.run.camera_view import tracker_images

    name, params = point_params(point, grid, colour=colour, laser=laser)
    scene = scenes.make(name, **params)
    out = []
    for a in _angles(scene, n_angles):
        f = scene.render(a)
        img, bg = tracker_images(f, scene.params)
        out.append((f, img, bg, scene.params))
    return out


def _measure_point(point, grid, colour, laser, use_background, memo: dict | None = None) -> cond.Conditions:
    key = json.dumps(point, sort_keys=True)
    if memo is not None and key in memo:
        return memo[key]
    f, img, bg, _ = render_point(point, grid, colour=colour, laser=laser)[0]
    c = cond.measure(img, bg if use_background else None, rgb=f.rgb, laser=laser)
    if memo is not None:
        memo[key] = c
    return c


def _table_path(grid: Grid, colour: bool, laser: str, use_background: bool, suffix: str = "") -> Path:
    from scenes import cache

    ident = {"predict_table": TABLE_VERSION, "grid": grid.to_value(), "colour": bool(colour), "laser": laser,
             "use_background": bool(use_background)}
    return cache.cache_root() / "predict" / f"{cache.key(ident)}{suffix}.json"


def refined_memo(grid: Grid, *, colour: bool, laser: str = "red", use_background: bool = False) -> dict:
    """The conditions already measured at refined (off-grid) points of this grid's table, as a dict
    for :func:`match`'s ``memo``: JSON point -> Conditions, read from beside the table
    (``predict/<key>-refined.json``); empty when there is none or it is damaged.
    :func:`save_refined_memo` writes it back."""
    path = _table_path(grid, colour, laser, use_background, "-refined")
    try:
        rows = json.loads(path.read_text(encoding="utf-8"))
        return {k: cond.Conditions(**_from_json(v)) for k, v in rows.items()}
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return {}


def save_refined_memo(memo: dict, grid: Grid, *, colour: bool, laser: str = "red",
                      use_background: bool = False) -> None:
    """Write :func:`refined_memo`'s dict back (atomically), so that a second match of the same
    photographs renders nothing."""
    from bench.store.files import atomic_write_text

    path = _table_path(grid, colour, laser, use_background, "-refined")
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(path, json.dumps({k: _finite(c.as_dict()) for k, c in sorted(memo.items())}))


def _points(grid: Grid, colour: bool):
    filters = grid.filters if colour else ("bandpass",)
    for setup, lw in itertools.product(grid.setups, grid.line_fwhm_mrad):
        for pw, lux, exp, flt, dfc, jq in itertools.product(grid.laser_power_mw, grid.ambient_lux, grid.exposure_ms,
                                                            filters, grid.defocus_px, grid.jpeg_quality):
            yield {"setup": setup, "line_fwhm_mrad": lw, "laser_power_mw": pw, "ambient_lux": lux,
                   "exposure_ms": exp, "filter": flt, "defocus_px": dfc, "jpeg_quality": jq}


def grid_table(grid: Grid, *, colour: bool, laser: str = "red", use_background: bool = False,
               say=None) -> list[tuple[dict, cond.Conditions]]:
    """Every grid point with its measured conditions, cached as JSON under the render cache
    (``predict/<key>.json``, keyed by the grid, the camera, the laser, the laser-off use and
    :data:`TABLE_VERSION`); ``say(done, total)`` is called as points are measured."""
    from bench.store.files import atomic_write_text

    path = _table_path(grid, colour, laser, use_background)
    if path.is_file():
        try:
            rows = json.loads(path.read_text(encoding="utf-8"))
            return [(r["point"], cond.Conditions(**_from_json(r["conditions"]))) for r in rows]
        except (ValueError, KeyError, TypeError):
            pass  # a damaged table is measured again
    points = list(_points(grid, colour))
    table = []
    for i, pt in enumerate(points):
        table.append((pt, _measure_point(pt, grid, colour, laser, use_background)))
        if say is not None:
            say(i + 1, len(points))
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(path, json.dumps([{"point": p, "conditions": _finite(c.as_dict())} for p, c in table]))
    return table


def _finite(d: dict) -> dict:
    return {k: (v if math.isfinite(v) else None) for k, v in d.items()}


def _from_json(d: dict) -> dict:
    return {k: (float("nan") if v is None else v) for k, v in d.items()}


def match(target: cond.Conditions, table, grid: Grid, *, colour: bool, laser: str = "red",
          use_background: bool = False, refine: bool = True, memo: dict | None = None) -> Match:
    """The grid point nearest ``target`` (refined unless ``refine`` is false), or the measures out of range.

    Parameters
    ----------
    target : Conditions
        The photograph's conditions.
    table : list of (point, Conditions)
        :func:`grid_table` of the same grid, camera, laser and laser-off use.
    memo : dict, optional
        Conditions of refined points measured before (:func:`refined_memo`); points the search
        measures are added to it.
    """
    conds = [c for _, c in table]
    bad = tuple(cond.out_of_range(target, conds))
    if bad:
        return Match(point={}, conditions=None, distance=float("nan"), out_of_range=bad)
    d = np.array([cond.distance(target, c) for c in conds])
    d = np.where(np.isfinite(d), d, np.inf)
    k = int(np.argmin(d))
    best, best_c, best_d = dict(table[k][0]), table[k][1], float(d[k])
    if refine:
        best, best_c, best_d = _refine(target, best, best_c, best_d, grid, colour, laser, use_background, memo)
    return Match(point=best, conditions=best_c, distance=best_d, out_of_range=())


def _refine(target, point, c, d, grid, colour, laser, use_background, memo=None, rounds: int = 6):
    bounds = {k: (min(getattr(grid, k)), max(getattr(grid, k))) for k in _REFINED}
    for steps in ((1.4, 0.5), (1.15, 0.25)):
        for _ in range(rounds):
            improved = False
            for key in _REFINED:
                lo, hi = bounds[key]
                if lo == hi:
                    continue
                v = float(point[key])
                if key == "defocus_px":
                    cands = (v - steps[1], v + steps[1])
                elif v == 0.0:
                    cands = (min(x for x in getattr(grid, key) if x > 0) / 2.0,)
                else:
                    cands = (v / steps[0], v * steps[0])
                for nv in cands:
                    if not lo <= nv <= hi:
                        continue
                    cand = {**point, key: round(nv, 6)}
                    cc = _measure_point(cand, grid, colour, laser, use_background, memo)
                    dd = cond.distance(target, cc)
                    if math.isfinite(dd) and dd < d - 1e-9:
                        point, c, d, improved = cand, cc, dd, True
                        break
            if not improved:
                break
    return point, c, d


def score_frame(trackers: dict, image, truth_columns, background=None, states=None) -> dict:
    """Label -> row outcomes (int8, shape (H,)) of each tracker on one frame with truth, scored as a
    photograph is: by default a stripe row only where the real set's reference rule sees the stripe
    in ``image`` (:func:`bench.evaluate.outcomes.referenced_states`), else not scored; rows without a
    stripe are scored. ``states`` (shape (H,)) replaces that reading. A tracker that fails reports nothing."""
    from bench.evaluate.outcomes import referenced_states, row_outcomes
    from bench.run.track import track_frame

    states = referenced_states(image, truth_columns) if states is None else states
    out = {}
    for lab, t in trackers.items():
        r = track_frame(t, image, background)
        cols = r.columns if r.ok else np.full(np.shape(image)[0], np.nan)
        out[lab] = row_outcomes(cols, truth_columns, states)
    return out


def transplant_frames(photo: "Photo", *, seed: int = 0, estimate: str = "auto", measured=None) -> list:
    """The photograph with its own stripe moved, both ways (:mod:`bench.evaluate.transplant`; ``estimate``:
    how the stripe is found, :data:`ESTIMATES`: ``auto`` on a colour photograph whose trackers see the laser's
    colour (:data:`COLOUR_GUIDED`) follows :func:`colour_guide`,
    ``reference`` follows ``photo.reference``, the ablation with a perfect estimate); the photograph itself, its
    stripe where the estimate puts it (:func:`bench.evaluate.transplant.in_place_truth`: its own glow, rivals and
    surroundings, which a moved frame does not carry whole); and, where the stripe is long enough, two
    *false-report frames*: moved the same ways with its ends cut off (:func:`bench.evaluate.transplant.cut_ends`),
    in which only the stripe-less rows are scored (their stripe rows are ``UNSURE``): the hit rate is read from
    the first three frames alone (:data:`N_FULL`), the false-report rate from the stripe-less rows of all five
    (docs/predict.md). ``measured``: the frame's conditions, when
    the caller has them (:func:`bench.evaluate.transplant.stripe_extents`). A frame out of the transplant's
    range (:func:`bench.evaluate.transplant.out_of_range`) is the caller's to leave out, with its reason.

    Returns
    -------
    list
        ``[(image, truth, states, moved, shift_px), ...]`` (three or five; the photograph in place third, with
        ``shift_px`` 0): the tracker's frame of the moved
        photograph (:func:`bench.evaluate.pixels.select_channel` with the photograph's channel and
        laser), the moved stripe's columns (px, NaN where not moved), its row states
        (:func:`bench.evaluate.transplant.row_states`; with :attr:`Photo.fallback_rows`, read by
        :func:`bench.evaluate.outcomes.fallback_of`), the moved photograph (turned as the frame) and
        the shift; empty when the moved stripe is seen (by the reference rule) in fewer than
        :data:`bench.evaluate.transplant.MIN_ROWS` rows of the two moved frames together: too few to
        predict from (no visible stripe, or one much wider than the reference window).
    """
    from bench.evaluate import transplant as tp
    from bench.evaluate.outcomes import STRIPE, UNSURE, fallback_of
    from bench.evaluate.pixels import LASER_INDEX, select_channel

    ext, original, bg_original = photo_extents(photo, estimate=estimate, measured=measured)
    if not ext.visible.any():
        return []
    rivals = tp.rival_mask(photo.frame, photo.background, ext)
    right, left = tp.shifts_for(ext, rivals)
    noise = tp.channel_noise(original)  # the clean plate's noise and the clipping margin (transplant)
    # the moved rows a reference would leave out (row_states): dim ones, visible or not (docs/predict.md, (ad))
    unclear = tp.unclear_rows(ext, original, noise, guided=True)
    # a clipped core in a glow of the surface's is a stripe row, as the references read it (docs/predict.md, (ae'))
    seen = tp.clipped_peaks(original, ext, noise) & tp.glow_rows(photo.frame, ext)

    def read(states):  # as the photograph's references read rows without a stripe (Photo.fallback_rows)
        return fallback_of(states) if photo.fallback_rows else states

    out = []
    # the laser's channel: near the top its moved lift is at least the others' (transplant's laser_channel)
    li = LASER_INDEX[photo.laser] if np.ndim(original) == 3 else None
    for j, s in enumerate((right, -left)):
        moved, truth = tp.transplant(original, ext, s, background_original=bg_original, seed=seed + j,
                                     noise_dn=noise, laser_channel=li)
        image = select_channel(moved, photo.channel, photo.laser)
        # rows where the moved stripe lands on a rival are not scored: the photograph's stripe stands beside it
        landed = tp.landed_rows(ext, rivals, s)
        out.append((image, truth, read(tp.row_states(ext, truth, image, unclear=unclear | landed, seen=seen)), moved,
                    s))
    # the photograph itself, its stripe where the estimate puts it: its own glow, rivals and surroundings, which no
    # moved frame carries whole (docs/predict.md, "The photograph in place")
    truth = tp.in_place_truth(ext)
    out.append((photo.frame, truth, read(tp.row_states(ext, truth, photo.frame, unclear=unclear, seen=seen)), original,
                0))
    keep = tp.cut_ends(ext)
    if keep is not None:  # the false-report frames: the stripe's ends cut off, only stripe-less rows scored
        for j, s in enumerate((right, -left)):
            moved, truth = tp.transplant(original, ext, s, background_original=bg_original, seed=seed + 2 + j,
                                         noise_dn=noise, keep=keep, laser_channel=li)
            image = select_channel(moved, photo.channel, photo.laser)
            states = read(tp.row_states(ext, truth, image, keep, unclear, seen))
            states[states == STRIPE] = UNSURE
            out.append((image, truth, states, moved, s))
    return out if sum(int(np.sum(st == STRIPE)) for _, _, st, _, _ in out[:N_MOVED]) >= tp.MIN_ROWS else []


def photo_extents(photo: "Photo", *, estimate: str = "auto", measured=None) -> tuple:
    """A photograph's stripe as :func:`transplant_frames` finds it (``estimate``, :data:`ESTIMATES`: ``auto`` on a
    colour photograph whose trackers see the laser's colour, :data:`COLOUR_GUIDED`, follows :func:`colour_guide`, on
    another the frame's own guide; ``reference`` and ``covered`` need ``photo.reference``). ``measured``: the frame's
    conditions, when the caller has them.

    Returns
    -------
    tuple
        ``(ext, original, background_original)``: the :class:`bench.evaluate.transplant.Extents` and the photograph
        and its laser-off frame (None without) turned as the frame.
    """
    from bench.evaluate import transplant as tp
    from bench.evaluate.pixels import rotate_image

    original = rotate_image(photo.original, photo.rotate_deg)
    bg_original = (None if photo.background_original is None
                   else rotate_image(photo.background_original, photo.rotate_deg))
    if estimate in ABLATIONS and photo.reference is None:
        raise ValueError(f"{photo.name}: `estimate` {estimate!r} needs the photograph's reference (a real set's "
                         "NAME_ref.csv, photographs at their own size)")
    if estimate == "reference":
        ext = tp.stripe_extents(photo.frame, photo.background, measured=measured, guide=photo.reference)
    elif estimate in ("auto", "covered"):
        # on a colour photograph whose trackers see the laser's colour, the guide where that colour is; on one
        # whose trackers see a plain channel, that frame's own (docs/predict.md)
        guide = (colour_guide(photo, original, bg_original, measured) if photo.colour and photo.channel in COLOUR_GUIDED
                 else tp.estimate_guide(photo.frame, photo.background, measured=measured))
        if estimate == "covered":
            guide = np.where(np.isfinite(photo.reference), guide, np.nan)
        ext = tp.stripe_extents(photo.frame, photo.background, measured=measured, guide=guide)
    else:
        ext = tp.stripe_extents(photo.frame, photo.background, estimate=estimate, measured=measured)
    return ext, original, bg_original


#: The tracker frames of a colour photograph whose stripe ``estimate="auto"`` guides by the laser's colour
#: (:func:`colour_guide`): those that are the laser's colour themselves (the blend, or the excess). A frame of a plain
#: channel (``r``, ``g``, ``b``, ``gray``: a rig's software reading one, or a real set's photograph whose stripe's
#: core is clipped white, where the colour is not the stripe's signature) is guided by its own brightness
#: (docs/predict.md, "The colour guide only where the trackers see the laser's colour").
COLOUR_GUIDED = ("auto", "excess")


def colour_guide(photo: "Photo", original, background_original=None, measured=None) -> np.ndarray:
    """``estimate="auto"``'s guide of a colour photograph, shape (H,), px (NaN: no stripe): the ``auto`` guide
    found on the pure laser-colour excess (:func:`bench.evaluate.pixels.select_channel` ``excess``: white light,
    clipped or not, has none) and the ``auto`` guide of the tracker's frame (``measured``: its conditions), made one
    by :func:`bench.evaluate.transplant.arbitrate`: the colour guide, the frame's where the colour finds no stripe,
    and where the two part, the one with the more :func:`bench.evaluate.transplant.laser_evidence` (bright and of
    the laser's colour: neither a white lamp nor a surface of the laser's hue; its colour read as nought where
    :func:`bench.evaluate.transplant.hue_hidden`, a glare clipped in two channels; the frame's own guide's read over
    both its row and the reference window around it, the colour's over its row). ``original`` and
    ``background_original``: the photograph and its laser-off frame, turned as the frame (docs/predict.md, "The
    guide found on the laser's colour", "Brightness and colour together" and "The frame's own guide must stand out of
    the window too")."""
    from bench.evaluate import transplant as tp
    from bench.evaluate.pixels import LASER_INDEX, select_channel

    def parts(image):
        if image is None:
            return None, None
        return (np.asarray(image, dtype=np.float64)[..., LASER_INDEX[photo.laser]],
                select_channel(image, "excess", photo.laser))

    laser, excess = parts(original)
    laser_bg, excess_bg = parts(background_original)
    on_colour = tp.estimate_guide(excess, excess_bg)
    own = tp.estimate_guide(photo.frame, photo.background, measured=measured)
    # a pixel whose laser channel is clipped with another shows no hue: the arbiter reads no laser colour there
    # (docs/predict.md, "Two clipped channels hide the hue")
    coloured = np.where(tp.hue_hidden(original, photo.laser), 0.0, excess)
    by_row = tp.laser_evidence(laser, coloured, laser_bg, excess_bg)
    # the frame's own guide must stand out of the window around it too, not only of its row: read on the lesser (a
    # glare or lit patch wider than the window has little; docs/predict.md, "The frame's own guide must stand out of
    # the window too")
    by_window = tp.laser_evidence(laser, coloured, laser_bg, excess_bg, over="window")
    return tp.arbitrate(on_colour, own, by_row, np.minimum(by_row, by_window))


def transplanted(photo: "Photo", *, seed: int = 0, estimate: str = "auto", measured=None) -> tuple:
    """:func:`transplant_frames` of a photograph in the transplant's range, else why not: ``(frames, ())``, or
    ``([], ("width_px",))`` for a stripe wider than the reference window
    (:func:`bench.evaluate.transplant.out_of_range`, not moved at all) or ``([], ("visible",))`` for a moved
    stripe seen in too few rows. ``measured``: the photograph's conditions (measured here when None)."""
    from bench.evaluate import transplant as tp

    measured = cond.measure(photo.frame, photo.background) if measured is None else measured
    bad = tp.out_of_range(measured)
    if bad:
        return [], bad
    made = transplant_frames(photo, seed=seed, estimate=estimate, measured=measured)
    return (made, ()) if made else ([], ("visible",))


#: The first N_MOVED frames of :func:`transplant_frames` are the moved frames; the next is the photograph in place. Hit
#: rate and F1 are read from those N_FULL; any after them are false-report frames (only their stripe-less rows are
#: scored, and only the false-report rate reads them: they would change F1's mix of stripe and stripe-less rows, which
#: is the photograph's in the first N_FULL).
N_MOVED = 2
N_FULL = N_MOVED + 1


def cut_counts(per_frame: list) -> dict:
    """``n_false_cut`` and ``n_quiet_cut``: the false-report frames' stripe-less rows among one tracker's outcome
    arrays of one photograph (:func:`transplant_outcomes`; frames after :data:`N_FULL`).

    Examples
    --------
    >>> from bench.evaluate.outcomes import FALSE, HIT, QUIET
    >>> cut_counts([np.array([HIT]), np.array([HIT]), np.array([HIT]), np.array([FALSE, QUIET, QUIET])])
    {'n_false_cut': 1, 'n_quiet_cut': 2}
    """
    from bench.evaluate.outcomes import outcome_counts

    extra = [np.ravel(c) for c in per_frame[N_FULL:]]
    counts = outcome_counts(np.concatenate(extra)) if extra else {"n_false": 0, "n_quiet": 0}
    return {"n_false_cut": int(counts["n_false"]), "n_quiet_cut": int(counts["n_quiet"])}


def transplant_outcomes(trackers: dict, made: list, background=None) -> dict:
    """Label -> row outcomes (one array per frame) of each tracker on :func:`transplant_frames`' frames
    ``made``, each read with its own row states (:func:`score_frame`)."""
    per = {lab: [] for lab in trackers}
    for image, truth, states, _, _ in made:
        for lab, codes in score_frame(trackers, image, truth, background, states).items():
            per[lab].append(codes)
    return per


def predict_outcomes(points, grid: Grid, trackers: dict, *, colour: bool, laser: str = "red",
                     use_background: bool = False, n_angles: int = N_ANGLES, say=None,
                     fallback_rows: bool = False) -> dict:
    """Row outcomes of each tracker on the renders of matched points.

    A rendered row is scored as a photograph's would be (:func:`score_frame`); with ``fallback_rows``, its rows
    read as a reference without row states reads them (:attr:`Photo.fallback_rows`).

    Parameters
    ----------
    points : dict
        Photograph name -> matched grid point (:attr:`Match.point`).
    trackers : dict
        Label -> tracker (:func:`bench.run.track.build_trackers`).

    Returns
    -------
    dict
        Photograph name -> label -> list of row-outcome arrays (one per rendered frame), and
        ``"_frames"``: photograph name -> list of ``(image, truth columns)`` (for the contact sheet).
    """
    from bench.evaluate.outcomes import fallback_of, referenced_states

    out: dict = {"_frames": {}}
    for i, (name, pt) in enumerate(points.items()):
        per = {lab: [] for lab in trackers}
        frames = render_point(pt, grid, colour=colour, laser=laser, n_angles=n_angles)
        out["_frames"][name] = [(f.rgb if f.rgb is not None else img, f.truth.columns) for f, img, _, _ in frames]
        for f, img, bg, _ in frames:
            states = referenced_states(img, f.truth.columns)
            states = fallback_of(states) if fallback_rows else states
            for lab, codes in score_frame(trackers, img, f.truth.columns, bg if use_background else None,
                                          states).items():
                per[lab].append(codes)
        out[name] = per
        if say is not None:
            say(i + 1, len(points), name)
    return out


# ---------------------------------------------------------------------------------------------------- stripebench predict


@dataclass
class Photo:
    """One photograph to predict for: the frame the trackers see, its laser-off frame, the original."""

    name: str
    path: Path
    frame: np.ndarray
    background: np.ndarray | None
    original: np.ndarray
    laser: str = "red"
    rotate_deg: int = 0
    channel: str = "auto"
    background_original: np.ndarray | None = None
    reference: np.ndarray | None = None
    """A real set's reference columns per row of ``frame`` (px, NaN: no stripe), read only for the
    ablations (:data:`ABLATIONS`); None otherwise."""
    fallback_rows: bool = False
    """Whether the frames' rows are read as a reference without row states is read
    (:func:`bench.evaluate.outcomes.fallback_of`: every row not scored as a stripe row, at least ``GAP_ROWS`` from
    each that is, has no stripe): set for a real set whose ``NAME_ref.csv`` files give no ``state`` column, as
    ``stripebench real`` then scores its photographs (docs/predict.md, "A set whose references give no row
    states"); otherwise a row the stripe crosses unseen is not scored."""

    @property
    def colour(self) -> bool:
        """A colour photograph (a grey picture stored as RGB is grey)."""
        o = self.original
        return o.ndim == 3 and not (np.array_equal(o[..., 0], o[..., 1]) and np.array_equal(o[..., 0], o[..., 2]))


def collect_photos(folder, *, channel: str = "auto", laser: str = "red", rotate_deg: int = 0, downscale: int = 1,
                   references: bool = False, err=None) -> list[Photo]:
    """The photographs of ``folder``: a real set's (its manifest's laser, channel and rotation;
    references ignored unless ``references``: then read into :attr:`Photo.reference`; whether they give row states
    sets :attr:`Photo.fallback_rows`) or every image file
    (``NAME_off.EXT`` frames paired as laser-off frames, no reference), with the given ``channel``, ``laser``
    and ``rotate_deg``, each ``downscale`` x ``downscale`` block of pixels averaged into one
    (:func:`bench.store.realset.load_frame`; 1: as they are; references only at 1). An unreadable file
    gets one line on ``err`` and is left out, as is a frame smaller than :data:`MIN_FRAME_PX`; a file whose EXIF
    orientation asks for a turn its ``rotate_deg`` does not give gets one line too
    (:func:`bench.store.realset.orientation_note`: read as stored)."""
    from bench.store import realset as real

    if isinstance(downscale, bool) or not isinstance(downscale, (int, np.integer)) or downscale < 1:
        raise ValueError(f"`downscale` must be an integer >= 1, got {downscale!r}")
    if references and downscale != 1:
        raise ValueError(f"`references` needs the photographs at their own size (`downscale` 1), got {downscale!r}")
    err = sys.stderr if err is None else err
    root = Path(folder)
    if not root.is_dir():
        raise real.ImageError(f"{str(root)!r}: not a folder")
    jobs = []
    if (root / "manifest.csv").is_file():
        images, _ = real.validate_dataset(root)
        for im in images:
            jobs.append((im.name, im.image_path, im.background_path, im.channel, im.laser_colour, im.rotate_deg,
                         im.reference_path))
    if not jobs:
        files = sorted(p for p in root.iterdir() if p.is_file() and p.suffix.lower() in real.IMAGE_SUFFIXES)
        stems = {p.stem for p in files}
        for p in files:
            if p.stem.endswith("_off"):
                if p.stem[:-4] not in stems:  # a laser-off frame is no photograph: say so when it has no partner
                    print(f"stripebench predict: {p.name}: a laser-off frame with no photograph {p.stem[:-4]}.* "
                          "beside it: not predicted for", file=err)
                continue
            jobs.append((p.stem, p, real.background_for(p), channel, laser, rotate_deg, None))
    photos = []
    for name, path, bgp, ch, las, rot, refp in jobs:
        try:
            frame, original = real.load_frame(path, channel=ch, laser=las, rotate_deg=rot, downscale=downscale)
            if frame.shape[0] < MIN_FRAME_PX[0] or frame.shape[1] < MIN_FRAME_PX[1]:
                raise real.ImageError(f"{str(path)!r}: its frame is {frame.shape[0]} x {frame.shape[1]} px, too small "
                                      f"to predict for (at least {MIN_FRAME_PX[0]} rows and {MIN_FRAME_PX[1]} "
                                      "columns)")
            bg = bg_original = None
            if bgp is not None:
                bg, bg_original = real.load_frame(bgp, channel=ch, laser=las, rotate_deg=rot, downscale=downscale)
                if bg.shape != frame.shape:
                    raise real.ImageError(f"{str(path)!r}: laser-off frame {bgp.name} has shape {bg.shape}, "
                                          f"the image {frame.shape}")
            ref, given = None, True
            if refp is not None and references:  # the file read once: columns, and whether it gives states
                ref, _, given = real.read_reference_states(refp, frame.shape)
            elif refp is not None:  # the states' convention from its header alone, never the labels
                given = real.reference_gives_states(refp)
        except (real.ImageError, real.DatasetError) as exc:
            print(f"stripebench predict: {exc}", file=err)
            continue
        note = real.orientation_note(path, rot)
        if note:
            print(f"stripebench predict: {note}", file=err)
        photos.append(Photo(name, Path(path), frame, bg, original, las, rot, ch, bg_original, ref,
                            fallback_rows=not given))
    return photos


#: The shrink factors ``predict`` offers (``--downscale``): each N x N block of pixels averaged into one.
DOWNSCALES = (1, 2, 4, 8)


def downscale_for(width_px: float, downscale: int = 1) -> int | None:
    """The least of :data:`DOWNSCALES` above ``downscale`` that brings a stripe ``width_px`` wide (FWHM, px,
    measured on photographs already shrunk by ``downscale``) within the transplant's range
    (:data:`bench.evaluate.transplant.MAX_WIDTH_PX`), or None when none does: the advice given with a photograph
    left out for its width.

    Examples
    --------
    >>> downscale_for(18.4), downscale_for(40.0), downscale_for(18.4, 2), downscale_for(400.0)
    (2, 4, 4, None)
    """
    from bench.evaluate import transplant as tp

    return next((n for n in DOWNSCALES if n > downscale and width_px * downscale / n <= tp.MAX_WIDTH_PX), None)


#: Where a prediction's frames with truth come from (``--frames``): ``transplant``, the photograph with its own
#: stripe moved (the default: it predicts renders far better than matched renders do, ``stripebench
#: predictcheck``, docs/predict.md), or ``render``, renders matched to the photograph's conditions.
FRAMES = ("transplant", "render")

#: How a transplant finds each photograph's stripe (``--estimate``): the estimates of
#: :data:`bench.evaluate.transplant.ESTIMATES` (``auto``, the default, first), or one of :data:`ABLATIONS`.
#: The ablations read a labelled photograph's reference: ``reference`` takes the stripe from it, what a perfect
#: stripe estimate would predict; ``covered`` takes ``auto``'s guide in the rows the reference covers and none
#: elsewhere, the stripe where ``auto`` puts it but only in the rows a measurement scores (docs/predict.md).
ABLATIONS = ("reference", "covered")
ESTIMATES = (*_STRIPE_ESTIMATES, *ABLATIONS)

#: The names the prediction's tables give :func:`bench.evaluate.outcomes.bootstrap_frames`' figures.
PREDICTED_NAMES = {"recall": "hit_rate", "false_report_rate": "false_report_rate", "f1": "f1"}


def run_predict(folder, out_dir, specs, *, frames: str = "transplant", estimate: str = "auto",
                grid: Grid = DEFAULT_GRID,
                channel: str = "auto", laser: str = "red", rotate_deg: int = 0, downscale: int = 1,
                n_angles: int = N_ANGLES, n_boot: int = 1000, seed: int = 0, say=None, err=None) -> dict:
    """``stripebench predict``: measure the photographs, make frames with truth for them, score the trackers.

    ``frames`` (:data:`FRAMES`): ``transplant``, each photograph with its own stripe moved both ways, and in place
    (:func:`transplant_frames`; ``seed`` seeds the clean plate's noise, ``estimate`` finds the stripe,
    :data:`ESTIMATES`: ``reference`` takes each photograph's reference, a real set's at ``downscale`` 1 only);
    ``render``, renders of
    ``grid`` matched to its conditions at ``n_angles`` mirror angles. A photograph whose moved stripe is
    seen in too few rows (transplant: :func:`transplant_frames`) or with a measure outside the grid's
    range (render) is left out, named with the measure (``visible``, or the measure out of range); so is, with
    transplants, a photograph whose stripe is wider than the reference window
    (:data:`bench.evaluate.transplant.MAX_WIDTH_PX`: ``width_px``). ``downscale``: each photograph (and
    laser-off frame) is shrunk by this factor first (:func:`collect_photos`), for trackers run on shrunk frames.

    Writes ``conditions.csv`` (one line per photograph and side, ``photo`` or ``render``: every
    measure, the distance, the matched knobs, ``status`` matched / out of range and the measures
    out of range), ``predicted.csv`` (per tracker: ``hit_rate``, ``false_report_rate``, ``f1``
    with 95 % bootstrap intervals over the matched photographs, ``n_photos``, ``n_frames``),
    ``predicted_photos.csv`` (per matched photograph and tracker: the three figures on its renders'
    rows and the row-outcome counts ``n_hit`` ...) and ``predict.json`` (the settings) into ``out_dir``;
    returns what the report needs (:func:`bench.report.predict.build_predict_report`).

    Raises
    ------
    bench.store.realset.ImageError
        ``folder`` is not a folder, or holds no readable photograph.
    """
    import pandas as pd

    from bench.evaluate import overlay
    from bench.evaluate import transplant as tp
    from bench.evaluate.outcomes import COUNT_KEYS, bootstrap_frames, outcome_counts
    from bench.evaluate.pixels import rotate_image
    from bench.evaluate.prediction import predicted_figures
    from bench.run.track import build_trackers
    from bench.store import realset as real
    from bench.store.files import atomic_write_text

    if frames not in FRAMES:
        raise ValueError(f"`frames` must be one of {', '.join(FRAMES)}, got {frames!r}")
    if estimate not in ESTIMATES:
        raise ValueError(f"`estimate` must be one of {', '.join(ESTIMATES)}, got {estimate!r}")
    with_references = frames == "transplant" and estimate in ABLATIONS
    say = (lambda m: print(m, file=sys.stderr, flush=True)) if say is None else say

    def warn(m):  # a photograph left out: said even when progress is not
        print(m, file=sys.stderr if err is None else err, flush=True)

    photos = collect_photos(folder, channel=channel, laser=laser, rotate_deg=rotate_deg, downscale=downscale,
                            references=with_references, err=err)
    if not photos:
        raise real.ImageError(f"{str(folder)!r}: no readable photograph (PNG, JPEG, TIFF)")
    if with_references and any(ph.reference is None for ph in photos):
        raise real.ImageError(f"{str(folder)!r}: --estimate {estimate} needs a real set (a manifest and each "
                              "photograph's NAME_ref.csv); this folder has photographs without one")
    trackers = build_trackers(specs)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    tables, memos, matches, conds, moved = {}, {}, {}, {}, {}

    def measured(ph):  # the photograph's conditions, and one line each where its stripe seems to run across the
        # frame or to be of another colour than the laser's, or a line seems drawn over it (docs/predict.md,
        # `stripebench predict`)
        c = photo_conditions(ph.frame, ph.background, ph.original, rotate_deg=ph.rotate_deg, laser=ph.laser)
        turned = rotate_image(ph.original, ph.rotate_deg)  # the stripe runs down it, as the frame's
        drawn = overlay.drawn_over(turned) if ph.colour else 0  # the line's rows, where it counts as drawn over
        if drawn:
            warn(f"stripebench predict: {ph.name}: a thin dark line seems drawn over it in {drawn} "
                 f"of its {turned.shape[0]} rows (a tracker's output saved with the frame?): the trackers and the "
                 "prediction read that line, not the camera's pixels alone (docs/real.md, \"A line drawn over "
                 "`ag_tape`'s stripe\")")
        if cond.runs_across(ph.frame, ph.background, c):
            warn(f"stripebench predict: {ph.name}: its stripe seems to run across the frame, not down it (the "
                 "trackers read one column per row): if it does, give `--rotate 90` or `--rotate 270`")
        if ph.colour and ph.channel in COLOUR_GUIDED:
            other = cond.likelier_laser(turned, ph.laser)
            if other is not None:
                warn(f"stripebench predict: {ph.name}: its stripe stands out far more in the {other} excess than in "
                     f"the {ph.laser} one the trackers see: if the laser is {other}, give `--laser {other}` (a real "
                     "set: its manifest's laser_colour)")
        return c

    for ph in photos:
        if frames == "transplant":
            conds[ph.name] = measured(ph)
            made, bad = transplanted(ph, seed=seed, estimate=estimate, measured=conds[ph.name])
            moved[ph.name] = made
            if bad:
                matches[ph.name] = Match({"frames": "transplant"}, None, float("nan"), bad)
                w = conds[ph.name].width_px
                n = downscale_for(w, downscale) if bad == ("width_px",) else None
                shrink = ("shrink the photographs" if n is None else
                          f"shrink the photographs: by {n} (`predict --downscale {n}`) it is about "
                          f"{w * downscale / n:.1f} px")
                why = (f"width_px: its stripe is {w:.1f} px wide, wider than the reference window's "
                       f"{tp.MAX_WIDTH_PX} px; {shrink}" if bad == ("width_px",) else
                       f"visible: the moved stripe is seen in fewer than {tp.MIN_ROWS} rows")
                warn(f"stripebench predict: {ph.name}: out of range ({why}): left out")
                continue
            image, _, _, rgb, shift = made[0]
            back = made[1][4]
            c = cond.measure(image, ph.background, rgb=rgb if ph.colour else None, laser=ph.laser)
            matches[ph.name] = Match({"frames": "transplant", "shift_px": shift, "shift_back_px": back}, c,
                                     cond.distance(conds[ph.name], c), ())
            say(f"stripebench predict: {ph.name}: its stripe moved by {shift:+d} and {back:+d} px "
                f"(distance {matches[ph.name].distance:.2f})")
            continue
        key = (ph.colour, ph.laser, ph.background is not None)
        if key not in tables:
            step = max(1, len(list(_points(grid, ph.colour))) // 10)

            def tick(i, n, key=key):
                if i % step == 0 or i == n:
                    say(f"stripebench predict: grid ({'colour' if key[0] else 'grey'}, {key[1]} laser"
                        f"{', laser-off' if key[2] else ''}): {i}/{n} renders measured")
            tables[key] = grid_table(grid, colour=key[0], laser=key[1], use_background=key[2], say=tick)
            memos[key] = refined_memo(grid, colour=key[0], laser=key[1], use_background=key[2])
        conds[ph.name] = measured(ph)
        known = len(memos[key])
        matches[ph.name] = match(conds[ph.name], tables[key], grid, colour=key[0], laser=key[1],
                                 use_background=key[2], memo=memos[key])
        if len(memos[key]) > known:  # kept after each photograph: an interrupted run loses nothing measured
            save_refined_memo(memos[key], grid, colour=key[0], laser=key[1], use_background=key[2])
        m = matches[ph.name]
        if m.out_of_range:
            warn(f"stripebench predict: {ph.name}: out of range ({', '.join(m.out_of_range)}): left out")
        else:
            say(f"stripebench predict: {ph.name}: matched (distance {m.distance:.2f}): {m.point['setup']}, "
                f"{m.point['laser_power_mw']:.3g} mW, {m.point['ambient_lux']:.4g} lux")
    matched = [ph for ph in photos if not matches[ph.name].out_of_range]
    per_photo, sheet = {}, {}
    for i, ph in enumerate(matched):
        if frames == "transplant":
            per_photo[ph.name] = transplant_outcomes(trackers, moved[ph.name], ph.background)
            sheet[ph.name] = [(rgb if rgb.ndim == 3 else image, truth) for image, truth, _, rgb, _ in moved[ph.name]]
            say(f"stripebench predict: tracked {i + 1}/{len(matched)} ({ph.name})")
            continue
        key = (ph.colour, ph.laser, ph.background is not None)
        res = predict_outcomes({ph.name: matches[ph.name].point}, grid, trackers, colour=key[0], laser=key[1],
                               use_background=key[2], n_angles=n_angles, fallback_rows=ph.fallback_rows)
        per_photo[ph.name] = res[ph.name]
        sheet[ph.name] = res["_frames"][ph.name]
        say(f"stripebench predict: rendered and tracked {i + 1}/{len(matched)} ({ph.name})")
    rows = []
    n_main = N_FULL if frames == "transplant" else None  # the false-report frames feed the false-report rate only
    for j, lab in enumerate(trackers):
        codes = [np.concatenate([c.ravel() for c in per_photo[ph.name][lab][:n_main]]) for ph in matched]
        every = [np.concatenate([c.ravel() for c in per_photo[ph.name][lab]]) for ph in matched]
        extra = n_main is not None and any(len(per_photo[ph.name][lab]) > n_main for ph in matched)
        rec = {"tracker": lab, "n_photos": len(matched), "n_frames": sum(len(sheet[ph.name]) for ph in matched)}
        if codes:
            b = bootstrap_frames(codes, n_boot=n_boot, seed=seed + j)
            # the false-report rate from every frame: a second bootstrap only where there are more frames
            b_all = bootstrap_frames(every, n_boot=n_boot, seed=seed + j) if extra else b
            for k, name in PREDICTED_NAMES.items():
                src = b_all if k == "false_report_rate" else b
                rec[name], rec[f"{name}_lo"], rec[f"{name}_hi"] = src[k], src[f"{k}_lo"], src[f"{k}_hi"]
        else:
            for name in PREDICTED_NAMES.values():
                rec[name] = rec[f"{name}_lo"] = rec[f"{name}_hi"] = float("nan")
        rows.append(rec)
    predicted = pd.DataFrame.from_records(rows)
    photo_rows = []
    for ph in matched:
        for lab in trackers:
            counts = outcome_counts(np.concatenate([c.ravel() for c in per_photo[ph.name][lab][:n_main]]))
            cut = cut_counts(per_photo[ph.name][lab]) if frames == "transplant" else {"n_false_cut": 0,
                                                                                       "n_quiet_cut": 0}
            fig = predicted_figures({**counts, **cut})
            photo_rows.append({"name": ph.name, "tracker": lab, **{n: fig[k] for k, n in PREDICTED_NAMES.items()},
                               **counts, **cut})
    per_photo_table = pd.DataFrame.from_records(
        photo_rows, columns=["name", "tracker", *PREDICTED_NAMES.values(), *COUNT_KEYS, "n_false_cut", "n_quiet_cut"])
    crow = []
    for ph in photos:
        m = matches[ph.name]
        status = "out of range" if m.out_of_range else "matched"
        base = {"name": ph.name, "status": status, "out_of_range": " ".join(m.out_of_range),
                "distance": m.distance, "frames": frames,
                **{k: m.point.get(k) for k in ("shift_px", "setup", "line_fwhm_mrad", "laser_power_mw", "ambient_lux",
                                               "exposure_ms", "filter", "defocus_px", "jpeg_quality")}}
        crow.append({**base, "side": "photo", **conds[ph.name].as_dict()})
        if m.conditions is not None:
            crow.append({**base, "side": "render", **m.conditions.as_dict()})
    conditions_table = pd.DataFrame.from_records(crow)
    atomic_write_text(out / "predicted.csv", predicted.to_csv(index=False, float_format="%.6g"))
    atomic_write_text(out / "conditions.csv", conditions_table.to_csv(index=False, float_format="%.6g"))
    atomic_write_text(out / "predicted_photos.csv", per_photo_table.to_csv(index=False, float_format="%.6g"))
    settings = {"kind": "predict", "folder": str(Path(folder)), "trackers": [s.to_value() for s in specs],
                "frames": frames, "estimate": estimate if frames == "transplant" else None,
                "grid": grid.to_value() if frames == "render" else None, "channel": channel,
                "laser": laser, "rotate_deg": int(rotate_deg), "downscale": int(downscale),
                "n_angles": n_angles, "n_boot": n_boot, "seed": seed,
                "fallback_rows": [ph.name for ph in photos if ph.fallback_rows],
                "out_of_range": {ph.name: list(matches[ph.name].out_of_range) for ph in photos
                                 if matches[ph.name].out_of_range}}
    atomic_write_text(out / "predict.json", json.dumps(settings, indent=1))
    return {"out": out, "photos": photos, "matches": matches, "conditions": conds, "frames": sheet,
            "predicted": predicted, "predicted_photos": per_photo_table, "conditions_table": conditions_table,
            "settings": settings}
