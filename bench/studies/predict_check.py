"""Renders standing in for photographs (``stripebench predictcheck``): the prediction procedure checked where the truth is known.

:mod:`bench.run.predict` predicts the trackers' figures on a rig's photographs from frames with truth made
for them (the photograph with its stripe moved, or renders matched to its conditions). On photographs its
error cannot be told from the references' own; on renders the truth is known. This study measures the
procedure there, and chose its default (docs/predict.md).

Each *case* is a render setting that is not a grid setup. The default cases are the ``field``
profile's experiments, rendered at the grid's size with seed 1; the grid renders seed 0. A case's
frames at :data:`bench.run.predict.N_ANGLES` mirror angles, spread over the middle half of its
experiment's scan, stand in for a rig's photographs. Each frame is used without its laser-off frame,
as most photographs come.

- **Measured:** the trackers are scored on the case's frames as a photograph is: row outcomes
  against the render's truth, with stripe rows only where
  :func:`bench.evaluate.outcomes.referenced_states` sees the stripe.
- **Predicted:** the procedure (``frames``) predicts the same figures from the frame alone: with
  ``transplant``, from the frame with its own stripe moved both ways (as ``stripebench predict``
  does with a photograph; the seed seeds the clean plate's noise); with ``render``, from its grid,
  matching each frame on its own.

The two are compared per case and pooled over every case, with Spearman's rho and the mean
|difference| for hit rate and F1 (:func:`bench.evaluate.prediction.compare_by_group`), as
``stripebench real --predict`` reports them. A case whose frames the procedure predicts badly here
will be predicted no better on a photograph.
"""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

__all__ = ["DEFAULTS", "CASE_CHANNELS", "TRUTHS", "ROWS", "STATE_READINGS", "DISTRACTORS", "FAR", "BAR_OFFSET_PX",
           "BAR_SIGMA_PX", "BAR_PEAK_DN", "FRINGE_PX", "FRINGE_SHARE",
           "stripe_evidence", "with_white_bar", "with_rival_fringe", "Case", "family_scene", "shrink_frame",
           "case_frames", "study", "family_of", "objective", "PAIRED", "paired", "score", "FAMILIES", "family_options",
           "GLOW_POWER_MW", "JPEG_FAMILY_QUALITY", "scored_columns", "WHITE_CORE_POWER_MW", "WHITE_CORE_HALF_PX",
           "WHITE_CORE_CLIP_DN", "WHITE_CORE_OTHER", "white_core_share", "code_of_run"]

#: The study's defaults (the command's options).
DEFAULTS = {"profile": "field", "seed": 1, "size": 256, "grid": "default", "frames": "transplant", "downscale": 1,
            "estimate": "auto", "line_fwhm_mrad": None, "laser_power_mw": None, "channel": "auto",
            "distractor": "none", "jpeg_quality": None, "truth": "render", "rows": "clear", "states": "given",
            "family": None}

#: What the trackers see of a colour case (``--channel``): ``auto``, the laser-colour blend
#: (:func:`bench.evaluate.pixels.select_channel`), or ``laser``, the laser's own plain channel (red for a red laser),
#: as a rig whose software reads one channel does.
CASE_CHANNELS = ("auto", "laser")

#: What the measured side scores the case frames against (``--truth``): ``render``, the render's own truth (the laser
#: sheet's centre), or ``reference``, the columns a photograph's reference would give it
#: (:func:`bench.evaluate.outcomes.referenced_columns`: the intensity centre near the true column), as a photograph
#: is scored (docs/predict.md, "The renders' truth and a photograph's reference"). The row states are the same.
TRUTHS = ("render", "reference")

#: Which stripe rows the measured side scores (``--rows``): ``seen``, every row where the reference rule sees the true
#: stripe (:func:`bench.evaluate.outcomes.referenced_states`; every run before the tenth session's), or ``clear`` (the
#: default since then), those less the rows where the true stripe stands far under its typical height and its peak is
#: not clipped (:func:`bench.evaluate.transplant.unclear_rows` along the true columns; since the thirteenth session
#: ``guided``, whether or not the row stands 6 of the frame's noise units up), and with the rows whose true peak is
#: clipped scored even where the rule does not see them (:func:`bench.evaluate.transplant.seen_states`), as a
#: photograph's reference scores a clipped core in a glow; the rows left out are those a photograph's reference
#: leaves out as unclear (docs/predict.md, "Which rows a reference scores": measured on the shipped set's labels). Those
#: rows are then not scored (``UNSURE``). :func:`family_of` names a ``seen`` run's family with ``, rows seen``.
ROWS = ("seen", "clear")

#: How the rows that are not scored stripe rows are read (``--states``), on both sides: ``given`` (the default), as the
#: render's truth gives them (no stripe only where the laser is not: a reference whose file gives row states), or
#: ``fallback``, as a real set's reference without row states is read (:func:`bench.evaluate.outcomes.fallback_of`:
#: every row at least ``GAP_ROWS`` from the scored stripe rows has no stripe, a faint stretch left out included), the
#: prediction reading its frames so too (``bench.run.predict.Photo.fallback_rows``; docs/predict.md, "A set whose
#: references give no row states"). :func:`family_of` names a ``fallback`` run's family with ``, states fallback``.
STATE_READINGS = ("given", "fallback")

#: The ``marble-60mw-jpeg`` family's JPEG quality: Pillow's default, 75 (a webcam's MJPEG frames and a phone's JPEGs
#: are compressed so or harder): clipped stripes in a glow whose cores ring under the top, as a JPEG photograph's do
#: (seventeenth session, docs/predict.md, "A clipped core moves whole").
JPEG_FAMILY_QUALITY = 75

#: The ``white-core`` family's laser power (mW, every case's): the field profile's cases bright enough that the stripe's
#: core clips to white, as in about a third of the shipped photographs (a red laser's light reaches the green and blue
#: channels too, a little; overexposed, they rise near the top). Chosen from pixels alone, before any prediction ran
#: on the family: the lowest power of the doubling grid 12.5, 25, 50, ... mW at which the median
#: :func:`white_core_share` of the field cases' frames at seed 121 (21 frames) reaches the shipped photographs' median
#: among those whose laser core is clipped in at least a tenth of their referenced rows (docs/predict.md, "A stripe
#: whose core clips white: the ``white-core`` family").
WHITE_CORE_POWER_MW = 50.0
#: The ``marble-480mw`` family's laser power (mW, every marble case's): a glowing surface whose glow beside a clipped
#: core stands near the top, as the skin of the shipped ``bb_hand`` does (its clipped rows' median 4-12 px either side
#: of the core: 0.90 of the top; 0.76 of them at 0.8 or more). Chosen from pixels alone, before any prediction ran on
#: the family: the lowest power of the doubling grid from the profile's 60 mW (120, 240, 480, 960 mW) at which a
#: ``sphere-skin`` frame at seed 121 has at least ``bb_hand``'s share of its clipped rows in a glow of 0.8 of the top
#: or more: 0.32 at most at 240 mW, 0.77 at 480 mW (docs/predict.md, "A clipped core in a glow of the surface's").
GLOW_POWER_MW = 480.0
#: :func:`white_core_share`: how far from the stripe's column its core is looked for (px, each side); how near the top
#: of the range its laser channel must stand to count as clipped (DN: a fixed margin, not the transplant's noise-based
#: clipping level, so that renders and photographs of any noise are read alike); and how high the brighter of the
#: other two channels must stand there, as a share of the top, for a clipped core to count as white.
WHITE_CORE_HALF_PX = 3
WHITE_CORE_CLIP_DN = 2.0
WHITE_CORE_OTHER = 0.6

#: The named render families (``--family NAME``): each sets these options of :func:`study` (the others keep their
#: defaults or what is given; a given option that the family sets otherwise is an error). The first five are the
#: declarations' families since the eighth session, the last three (the translucent ``marble`` profile, at its own
#: laser power and brighter) since the ninth (docs/predict.md, "Ties on the path"); ``marble-60mw-jpeg`` and
#: ``fringed-bar`` since the seventeenth (the first a declaration's ninth family once, the second a measurement only);
#: ``rival-fringe`` since the eighteenth (the tenth family of that session's declarations), ``white-core`` since the
#: nineteenth (:data:`WHITE_CORE_POWER_MW`), ``marble-480mw`` since the twenty-first (:data:`GLOW_POWER_MW`).
#: :func:`family_of` names a run's family by its options, whichever way they were given.
FAMILIES = {
    "native": {},
    "phone": {"downscale": 4, "line_fwhm_mrad": 1.2},
    "third": {"downscale": 2, "line_fwhm_mrad": 1.2},
    "plain": {"channel": "laser"},
    "white-bar": {"distractor": "white-bar"},
    "marble": {"profile": "marble"},
    "marble-15mw": {"profile": "marble", "laser_power_mw": 15.0},
    "marble-60mw": {"profile": "marble", "laser_power_mw": 60.0},
    "marble-60mw-jpeg": {"profile": "marble", "laser_power_mw": 60.0, "jpeg_quality": JPEG_FAMILY_QUALITY},
    "fringed-bar": {"distractor": "fringed-bar"},
    "rival-fringe": {"distractor": "rival-fringe"},
    "white-core": {"laser_power_mw": WHITE_CORE_POWER_MW},
    "marble-480mw": {"profile": "marble", "laser_power_mw": GLOW_POWER_MW},
}


def family_options(family: str, given: dict) -> dict:
    """``given`` (option -> value, as :func:`study` takes them) with the named render family's options
    (:data:`FAMILIES`) set.

    Raises
    ------
    bench.errors.ConfigError
        An unknown ``family``, or an option given at other than its default that the family sets otherwise.

    Examples
    --------
    >>> family_options("phone", {"downscale": 1, "line_fwhm_mrad": None, "seed": 3})
    {'downscale': 4, 'line_fwhm_mrad': 1.2, 'seed': 3}
    >>> family_options("plain", {"channel": "auto"})
    {'channel': 'laser'}
    """
    from bench.errors import ConfigError

    if family not in FAMILIES:
        raise ConfigError(f"`family` must be one of {', '.join(FAMILIES)}, got {family!r}")
    for k, v in FAMILIES[family].items():
        if k in given and given[k] != DEFAULTS[k] and given[k] != v:
            raise ConfigError(f"family {family!r} sets `{k}` to {v!r}, but {given[k]!r} was given")
    return {**given, **FAMILIES[family]}


#: What a case frame may carry besides its render (``--distractor``): ``none``, or ``white-bar``: a vertical white line
#: beside the stripe in every row (a window's frame, a lamp's stem: bright in every channel, of no colour), added to
#: the rendered photograph before the trackers' channel is taken (:func:`with_white_bar`). It is not rendered: a
#: controlled distractor for the stripe estimate, which the renders otherwise lack (docs/predict.md). ``fringed-bar``
#: (seventeenth session): the same bar with the laser's channel displaced :data:`FRINGE_PX` px away from the stripe, as
#: a lens's lateral colour fringes a bright edge (``al_room7``'s window bars, green beside a green stripe): bright and
#: of the laser's colour on one side, a rival that looks like the laser (docs/predict.md, "Rows two guides contest").
#: ``rival-fringe`` (eighteenth session): the white bar with a fringe of the laser's colour :data:`FRINGE_PX` px beyond
#: it whose laser evidence is :data:`FRINGE_SHARE` of the stripe's in that frame: a rival nearly as like the laser as
#: the stripe, as ``al_room7``'s window bars are, where ``fringed-bar``'s outshines it (docs/predict.md, "A rival
#: nearly as like the laser as the stripe").
DISTRACTORS = ("none", "white-bar", "fringed-bar", "rival-fringe")
#: The white bar: its distance from the stripe's median column (px; on the side with room), its Gaussian sigma (px)
#: and its peak (DN added in every channel, clipped at the top of the range).
BAR_OFFSET_PX = 20
BAR_SIGMA_PX = 1.2
BAR_PEAK_DN = 200.0
#: ``fringed-bar``: how far the laser's channel of the bar lies from the others (px): about a pixel and a half of
#: lateral colour, as a webcam's or a phone's lens shows at a bright edge off the axis.
FRINGE_PX = 1.5
#: ``rival-fringe``: the fringe's laser evidence (:func:`bench.evaluate.transplant.laser_evidence`) as a share of the
#: stripe's median in the frame (:func:`stripe_evidence`): the middle of what ``al_room7``'s window bars carry
#: (0.8-0.95 of its stripe's, docs/predict.md), set before any run of the family.
FRINGE_SHARE = 0.85
#: The key of the false-report comparison on the stripe-less rows a photograph's reference scores, at least
#: :data:`bench.evaluate.outcomes.GAP_ROWS` rows from the stripe (:func:`bench.evaluate.outcomes.distant_states`):
#: on renders every other stripe-less row is one where the stripe jumps at an occlusion, which a photograph's
#: reference leaves unscored (docs/predict.md, "Where the false reports are measured"). In ``predict_check.json``
#: beside each case's, the pooled and the per-case figures; ``measured.csv``'s ``n_false_far`` and ``n_quiet_far``.
FAR = "false_report_rate_far"


@dataclass(frozen=True)
class Case:
    """One case frame: the photograph (``rgb`` for a colour camera, else ``image`` itself), what a
    tracker sees of it (``image``, its ``channel`` of ``rgb``) and its per-row truth (px, NaN: no stripe)."""

    image: np.ndarray
    rgb: np.ndarray | None
    truth_columns: np.ndarray
    channel: str = "auto"

    @property
    def original(self) -> np.ndarray:
        """The photograph the frame stands for."""
        return self.rgb if self.rgb is not None else self.image


def family_scene(experiment, config, *, seed: int, width: int, height: int, downscale: int = 1,
                 line_fwhm_mrad: float | None = None, laser_power_mw: float | None = None):
    """The scene of one experiment of ``config`` for a render family: ``width`` x ``height`` px rendered
    ``downscale`` times larger (to be shrunk back by :func:`shrink_frame`), with ``line_fwhm_mrad`` in place
    of the experiment's laser line width (narrower: a thinner, brighter stripe) and ``laser_power_mw`` in place of
    its laser power (with a wide line, a wide stripe as bright as a narrow one: a webcam's saturated stripe)."""
    import scenes

    n = int(downscale)
    render = {**config.render, "width": int(width) * n, "height": int(height) * n}
    overrides = dict(experiment.overrides)
    if line_fwhm_mrad is not None:
        overrides["line_fwhm_mrad"] = float(line_fwhm_mrad)
    if laser_power_mw is not None:
        overrides["laser_power_mw"] = float(laser_power_mw)
    return scenes.make(experiment.scene, material=experiment.material, seed=int(seed), **render, **overrides)


def shrink_frame(frame, downscale: int):
    """A rendered frame shrunk by ``downscale`` (:func:`bench.evaluate.pixels.downscale`, as a camera app
    shrinks a phone's frame: the noise falls): its ``image``, ``background``, ``rgb`` and ``rgb_background``
    (None stays None) and ``truth_columns`` (:func:`bench.evaluate.pixels.downscale_columns`)."""
    from types import SimpleNamespace

    from bench.evaluate.pixels import downscale as shrink
    from bench.evaluate.pixels import downscale_columns

    n = int(downscale)
    planes = {k: None if getattr(frame, k, None) is None else shrink(getattr(frame, k), n)
              for k in ("image", "background", "rgb", "rgb_background")}
    return SimpleNamespace(**planes, truth_columns=downscale_columns(frame.truth.columns, n))


def stripe_evidence(rgb, truth_columns, laser: str) -> float:
    """The stripe's laser evidence in a colour photograph (DN): the median over its rows (``truth_columns``, px, NaN:
    no stripe) of :func:`bench.evaluate.transplant.laser_evidence` near its column
    (:func:`bench.evaluate.transplant.evidence_near`), as ``arbitrate`` reads a guide's, with the
    laser-colour excess as its colour term everywhere (as the arbiter read it when ``rival-fringe`` was made; since
    then it reads none where :func:`bench.evaluate.transplant.hue_hidden`, which the family's frames are kept
    without); 0 without a stripe row.

    Examples
    --------
    >>> rgb = np.zeros((4, 30, 3), np.uint8); rgb[:, 10, 0] = 90
    >>> stripe_evidence(rgb, np.full(4, 10.0), "red")
    90.0
    """
    from bench.evaluate.pixels import LASER_INDEX, select_channel
    from bench.evaluate.transplant import evidence_near, laser_evidence

    a = np.asarray(rgb)
    t = np.asarray(truth_columns, dtype=np.float64)
    if not np.isfinite(t).any():
        return 0.0
    ev = laser_evidence(a[..., LASER_INDEX[laser]].astype(np.float64), select_channel(a, "excess", laser))
    return float(np.nanmedian(evidence_near(ev, t)))


def white_core_share(rgb, columns, laser: str) -> float:
    """The share of a colour photograph's stripe rows whose core is clipped white: rows with a column (``columns``,
    shape (H,), px, NaN: no stripe) whose brightest laser-channel pixel within :data:`WHITE_CORE_HALF_PX` px of it
    stands within :data:`WHITE_CORE_CLIP_DN` of the top of the range, with the brighter of the other two channels above
    :data:`WHITE_CORE_OTHER` of the top there; NaN without a stripe row. A condition the renders at their own laser
    powers never show and a third of the shipped photographs do (the ``white-core`` family, :data:`FAMILIES`).

    Parameters
    ----------
    rgb : array_like, shape (H, W, 3)
        The photograph, integer DN.
    columns : array_like, shape (H,)
        The stripe's column per row (px): the render's truth or a photograph's reference.
    laser : {'red', 'green', 'blue'}
        The laser's colour.

    Examples
    --------
    A red stripe clipped white in two of four rows, clipped red in one, unclipped in the last:

    >>> rgb = np.zeros((4, 20, 3), np.uint8)
    >>> rgb[:, 9] = [[255, 240, 230], [255, 200, 90], [255, 30, 20], [180, 20, 10]]
    >>> white_core_share(rgb, np.full(4, 8.0), "red")
    0.5
    """
    from bench.evaluate.pixels import LASER_INDEX

    a = np.asarray(rgb)
    if a.ndim != 3 or a.shape[2] != 3 or not np.issubdtype(a.dtype, np.integer):
        raise ValueError(f"`rgb` must be an integer (H, W, 3) image, got {a.dtype} of shape {a.shape}")
    c = np.asarray(columns, dtype=np.float64)
    if c.shape != (a.shape[0],):
        raise ValueError(f"`columns` must have one entry per row of `rgb` ({a.shape[0]}), got shape {c.shape}")
    rows = np.flatnonzero(np.isfinite(c))
    if not rows.size:
        return float("nan")
    li, top = LASER_INDEX[laser], float(np.iinfo(a.dtype).max)
    cols = np.rint(c[rows]).astype(np.int64)
    win = np.stack([a[rows, np.clip(cols + d, 0, a.shape[1] - 1)]
                    for d in range(-WHITE_CORE_HALF_PX, WHITE_CORE_HALF_PX + 1)], axis=1).astype(np.float64)
    core = win[np.arange(rows.size), win[..., li].argmax(axis=1)]
    others = np.delete(core, li, axis=1).max(axis=1)
    white = (core[:, li] >= top - WHITE_CORE_CLIP_DN) & (others > WHITE_CORE_OTHER * top)
    return float(white.mean())


def _bar_side(stripe_px: float, width: int) -> float:
    """Which side of the stripe's median column (``stripe_px``) the white bar goes in a frame ``width`` px wide: +1
    (right, :data:`BAR_OFFSET_PX` px away) where the bar and three of its sigmas fit, else -1 (left)."""
    return 1.0 if stripe_px + BAR_OFFSET_PX + 3 * BAR_SIGMA_PX <= width - 1 else -1.0


def with_white_bar(photo, truth_columns, *, fringe_channel: int | None = None, fringe_dn: float | None = None):
    """``photo`` (H, W) or (H, W, 3), integer DN, with :data:`DISTRACTORS`' white bar added: a vertical Gaussian line
    of :data:`BAR_PEAK_DN` and :data:`BAR_SIGMA_PX`, :data:`BAR_OFFSET_PX` px right of the median of
    ``truth_columns`` (px, NaN: no stripe), or left where the right has no room, in every channel and row, clipped at
    the top of the dtype's range. Unchanged where ``truth_columns`` has no column. With ``fringe_channel`` (a colour
    photograph's channel index, the laser's), that channel's line lies :data:`FRINGE_PX` px further from the stripe:
    the ``fringed-bar`` distractor, a bar with a fringe of the laser's colour on its far side. With ``fringe_dn`` as
    well (DN), that channel keeps the white bar and gains a line of ``fringe_dn`` there instead: the ``rival-fringe``
    distractor, whose fringe has ``fringe_dn`` of laser evidence (bright by it, and of the laser's colour by it).

    Examples
    --------
    >>> img = np.zeros((4, 60), np.uint8)
    >>> out = with_white_bar(img, np.full(4, 10.0))
    >>> int(np.argmax(out[0])), int(out[0, 30]), out.dtype.name
    (30, 200, 'uint8')
    >>> rgb = with_white_bar(np.zeros((4, 60, 3), np.uint8), np.full(4, 10.0), fringe_channel=0)
    >>> int(rgb[0, 33, 0]) > int(rgb[0, 33, 1]) + 50, int(rgb[0, 27, 0]) < int(rgb[0, 27, 1])
    (True, True)
    >>> rgb = with_white_bar(np.zeros((4, 60, 3), np.uint8), np.full(4, 10.0), fringe_channel=0, fringe_dn=40.0)
    >>> int(rgb[0, 30, 0]) - int(rgb[0, 30, 1]), int(rgb[0, 32, 0]) - int(rgb[0, 32, 1])
    (18, 37)
    """
    a = np.asarray(photo)
    t = np.asarray(truth_columns, dtype=np.float64)
    if not np.isfinite(t).any():
        return a.copy()
    W = a.shape[1]
    c = float(np.nanmedian(t))
    col = c + _bar_side(c, W) * BAR_OFFSET_PX
    bar = BAR_PEAK_DN * np.exp(-0.5 * ((np.arange(W) - col) / BAR_SIGMA_PX) ** 2)
    bar = bar[None, :, None] if a.ndim == 3 else bar[None, :]
    if fringe_channel is not None and a.ndim == 3:
        away = col + (FRINGE_PX if col > c else -FRINGE_PX)  # the laser's channel, further from the stripe
        bar = np.repeat(bar, a.shape[2], axis=2)
        fringe = np.exp(-0.5 * ((np.arange(W) - away) / BAR_SIGMA_PX) ** 2)[None, :]
        if fringe_dn is None:
            bar[..., fringe_channel] = BAR_PEAK_DN * fringe
        else:
            bar[..., fringe_channel] += float(fringe_dn) * fringe
    top = float(np.iinfo(a.dtype).max) if np.issubdtype(a.dtype, np.integer) else np.inf
    out = np.clip(a.astype(np.float64) + bar, 0.0, top)
    return np.rint(out).astype(a.dtype) if np.issubdtype(a.dtype, np.integer) else out.astype(a.dtype)


def with_rival_fringe(rgb, truth_columns, laser: str, share: float = FRINGE_SHARE):
    """``rgb`` (H, W, 3), integer DN, with the ``rival-fringe`` distractor: :func:`with_white_bar` with a fringe in the
    laser's channel whose laser evidence (:func:`stripe_evidence` read along the fringe's column) is ``share`` of the
    stripe's (:func:`stripe_evidence` along ``truth_columns``, px, NaN: no stripe). The fringe's peak (DN) is found by
    bisection: evidence is read over each row's median (:func:`bench.evaluate.transplant.laser_evidence`), so a fringe's
    evidence is less than its peak by what the row's noise and texture hold, and clipping bends it. Unchanged without
    a stripe row or a stripe with no evidence; the greatest fringe the range allows where ``share`` is out of reach.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> rgb = rng.integers(40, 60, (8, 60, 3)).astype(np.uint8); rgb[:, 10, 0] = 110
    >>> t = np.full(8, 10.0)
    >>> out = with_rival_fringe(rgb, t, "red", 0.5)
    >>> fringe = np.full(8, 10.0 + BAR_OFFSET_PX + FRINGE_PX)
    >>> round(stripe_evidence(out, fringe, "red") / stripe_evidence(rgb, t, "red"), 1)
    0.5
    """
    from bench.evaluate.pixels import LASER_INDEX

    a = np.asarray(rgb)
    t = np.asarray(truth_columns, dtype=np.float64)
    target = float(share) * stripe_evidence(a, t, laser)
    if target <= 0.0:
        return a.copy()
    c = float(np.nanmedian(t))
    along = np.where(np.isfinite(t), c + _bar_side(c, a.shape[1]) * (BAR_OFFSET_PX + FRINGE_PX), np.nan)
    li = LASER_INDEX[laser]

    def made(dn):
        out = with_white_bar(a, t, fringe_channel=li, fringe_dn=dn)
        return out, stripe_evidence(out, along, laser)

    lo, hi = 0.0, float(np.iinfo(a.dtype).max) if np.issubdtype(a.dtype, np.integer) else 1.0
    best = made(hi)
    if best[1] <= target:
        return best[0]
    for _ in range(16):  # evidence rises with the fringe's peak: bisect to within 1/65536 of the range
        mid = 0.5 * (lo + hi)
        out, ev = made(mid)
        if ev < target:
            lo = mid
        else:
            hi, best = mid, (out, ev)
    return best[0]


def case_frames(experiment, config, *, seed: int, width: int, height: int, n_angles: int,
                downscale: int = 1, line_fwhm_mrad: float | None = None, laser_power_mw: float | None = None,
                channel: str = "auto", distractor: str = "none", jpeg_quality: int | None = None) -> list:
    """``[(name, Case, scene params), ...]``: one experiment of ``config`` rendered with ``seed`` at
    ``width`` x ``height`` px, at ``n_angles`` mirror angles over the middle half of its scan; with
    ``downscale`` N > 1 rendered N times larger and shrunk by N (:func:`family_scene`, :func:`shrink_frame`);
    ``line_fwhm_mrad`` replaces the laser line's width of every case, ``laser_power_mw`` its laser power; ``channel``
    (:data:`CASE_CHANNELS`) is what the trackers see of a colour case; ``distractor`` (:data:`DISTRACTORS`) what is
    added to each frame's photograph (:func:`with_white_bar`, :func:`with_rival_fringe`; a grey case gets the white
    bar alone); ``jpeg_quality`` (1-95, or None) JPEG-compresses each
    frame's photograph after that, as a webcam or a phone does (:func:`scenes.jpeg_round_trip`; 8-bit
    frames only)."""
    from bench.evaluate.pixels import LASER_INDEX, select_channel
    from bench.run.camera_view import laser_colour
    from bench.run.plan import angles_for

    if channel not in CASE_CHANNELS:
        raise ValueError(f"`channel` must be one of {', '.join(CASE_CHANNELS)}, got {channel!r}")
    if distractor not in DISTRACTORS:
        raise ValueError(f"`distractor` must be one of {', '.join(DISTRACTORS)}, got {distractor!r}")
    if jpeg_quality is not None:  # before any render: the shared check of an integer option (a ValueError)
        from bench.config.options import int_in_range

        jpeg_quality = int_in_range("`jpeg_quality`", jpeg_quality, 1, 95)

    scene = family_scene(experiment, config, seed=seed, width=width, height=height, downscale=downscale,
                         line_fwhm_mrad=line_fwhm_mrad, laser_power_mw=laser_power_mw)
    a = np.asarray(angles_for(experiment, scene), float)
    lo, hi = a[len(a) // 4], a[min(len(a) - 1, (3 * len(a)) // 4)]  # as bench.run.predict's matched renders
    laser = laser_colour(scene.params["laser_wavelength_nm"])
    out = []
    for i, ang in enumerate(np.linspace(lo, hi, n_angles) if n_angles > 1 else [a[len(a) // 2]]):
        f = shrink_frame(scene.render(float(ang)), downscale)
        if distractor == "rival-fringe" and f.rgb is not None:
            f.rgb = with_rival_fringe(f.rgb, f.truth_columns, laser)
        elif distractor in ("white-bar", "fringed-bar", "rival-fringe"):
            fringe = LASER_INDEX[laser] if distractor == "fringed-bar" and f.rgb is not None else None
            f.rgb = None if f.rgb is None else with_white_bar(f.rgb, f.truth_columns, fringe_channel=fringe)
            f.image = f.image if f.rgb is not None else with_white_bar(f.image, f.truth_columns)
        if jpeg_quality is not None:
            from scenes import jpeg_round_trip

            if f.rgb is not None:
                f.rgb = jpeg_round_trip(f.rgb, jpeg_quality)
            else:
                f.image = jpeg_round_trip(f.image, jpeg_quality)
        if f.rgb is not None:
            ch = "rgb"[LASER_INDEX[laser]] if channel == "laser" else channel
            case = Case(select_channel(f.rgb, ch, laser), f.rgb, f.truth_columns, ch)
        else:
            case = Case(f.image, None, f.truth_columns)
        out.append((f"{experiment.key}@{i}", case, scene.params))
    return out


def study(*, out, profile: str = DEFAULTS["profile"], seed: int = DEFAULTS["seed"], size: int = DEFAULTS["size"],
          grid: str = DEFAULTS["grid"], frames: str = DEFAULTS["frames"], downscale: int = DEFAULTS["downscale"],
          estimate: str = DEFAULTS["estimate"], line_fwhm_mrad=DEFAULTS["line_fwhm_mrad"],
          laser_power_mw=DEFAULTS["laser_power_mw"], channel=DEFAULTS["channel"],
          distractor=DEFAULTS["distractor"], jpeg_quality=DEFAULTS["jpeg_quality"], truth=DEFAULTS["truth"],
          trackers=None, quiet: bool = False,
          family: str | None = DEFAULTS["family"], rows: str = DEFAULTS["rows"],
          states: str = DEFAULTS["states"]) -> int:
    """Run the check and write ``predict_check.json``, ``predicted.csv`` and ``measured.csv`` into ``out``.

    Parameters
    ----------
    out : path
        Output folder (created).
    profile : str
        The profile whose experiments are the cases (default ``field``).
    seed : int
        The cases' render seed. The grid renders seed 0, and the check is meant for other seeds.
    size : int
        Render width of the cases and the grid (px; the height is 15/16 of it).
    grid : str
        ``default`` or ``small`` (:data:`bench.run.predict.DEFAULT_GRID`, ``SMALL_GRID``; ``frames = "render"``).
    frames : str
        The procedure checked (:data:`bench.run.predict.FRAMES`): ``transplant`` (each case frame with
        its own stripe moved) or ``render`` (renders of the grid matched to its conditions).
    downscale : int
        Cases rendered this many times larger and shrunk back (:func:`case_frames`): stripes that
        stand as far above the noise as a phone's shrunk frames do. The grid is not shrunk.
    estimate : str
        How the transplant finds the stripe (:data:`bench.run.predict.ESTIMATES`; ``reference``: the render's
        truth, what a perfect stripe estimate would predict; ``covered``: ``auto`` in the rows where the truth's
        stripe is, only).
    line_fwhm_mrad : float, optional
        Every case's laser line width (mrad) instead of its own.
    laser_power_mw : float, optional
        Every case's laser power (mW) instead of its own.
    channel : str
        What the trackers see of a colour case (:data:`CASE_CHANNELS`): ``auto`` or ``laser``.
    distractor : str
        What each case frame carries besides its render (:data:`DISTRACTORS`): ``none``, ``white-bar`` or
        ``fringed-bar``.
    jpeg_quality : int, optional
        JPEG-compress each case frame's photograph at this quality (1-95), as a webcam or a phone does.
    truth : str
        What the measured side scores against (:data:`TRUTHS`): ``render`` (the render's truth) or ``reference``
        (the columns a photograph's reference would give). The prediction is the same either way.
    trackers : sequence of :class:`bench.config.TrackerSpec`, optional
        Default: the profile's trackers.
    quiet : bool
        No progress on stderr.
    family : str, optional
        A named render family (:data:`FAMILIES`): sets the options it names (:func:`family_options`).
    rows : str
        Which stripe rows the measured side scores (:data:`ROWS`): ``clear`` (the default: every row where the
        reference rule sees the true stripe, less those a photograph's reference leaves out as unclear) or ``seen``
        (all of them, as before the tenth session). The prediction is the same either way.

    Returns
    -------
    int
        0.
    """
    import pandas as pd

    from bench.config import profile as load_profile
    from bench.evaluate import conditions as cond
    from bench.evaluate import transplant as tp
    from bench.evaluate.outcomes import (STRIPE, UNKNOWN, UNSURE, distant_states, fallback_of, outcome_counts,
                                         referenced_states)
    from bench.evaluate.prediction import compare_by_group, comparison_doc, per_group_error
    from bench.run import predict as pr
    from bench.run.camera_view import laser_colour
    from bench.run.track import build_trackers
    from bench.store.files import atomic_write_text

    if truth not in TRUTHS:
        raise ValueError(f"`truth` must be one of {', '.join(TRUTHS)}, got {truth!r}")
    if rows not in ROWS:
        raise ValueError(f"`rows` must be one of {', '.join(ROWS)}, got {rows!r}")
    if states not in STATE_READINGS:
        raise ValueError(f"`states` must be one of {', '.join(STATE_READINGS)}, got {states!r}")
    reading = states  # the option's value: the loop below names each case's row states ``states``
    if family is not None:
        opts = family_options(family, {"profile": profile, "downscale": downscale, "line_fwhm_mrad": line_fwhm_mrad,
                                       "laser_power_mw": laser_power_mw, "channel": channel, "distractor": distractor,
                                       "jpeg_quality": jpeg_quality})
        profile, downscale, line_fwhm_mrad = opts["profile"], opts["downscale"], opts["line_fwhm_mrad"]
        laser_power_mw, channel, distractor = opts["laser_power_mw"], opts["channel"], opts["distractor"]
        jpeg_quality = opts["jpeg_quality"]
    say = (lambda m: None) if quiet else (lambda m: print(m, file=sys.stderr, flush=True))
    config = load_profile(profile)
    g = replace(pr.SMALL_GRID if grid == "small" else pr.DEFAULT_GRID, width=int(size), height=int(size) * 15 // 16)
    specs = trackers if trackers is not None else config.tracker_specs
    tr = build_trackers(specs)
    outdir = Path(out)
    outdir.mkdir(parents=True, exist_ok=True)
    tables, memos = {}, {}
    pred_rows, meas_rows, groups, frames_doc = [], [], {}, []
    for e_i, exp in enumerate(config.experiments):
        for name, case, params in case_frames(exp, config, seed=seed, width=g.width, height=g.height,
                                              n_angles=pr.N_ANGLES, downscale=downscale,
                                              line_fwhm_mrad=line_fwhm_mrad, laser_power_mw=laser_power_mw,
                                              channel=channel, distractor=distractor, jpeg_quality=jpeg_quality):
            img = case.image
            colour = params.get("camera", "mono") == "rgb"
            laser = laser_colour(params.get("laser_wavelength_nm", pr.LASER_NM["red"]))
            key = (colour, laser)
            states = referenced_states(img, case.truth_columns)
            plain = cond.measure(img, None) if rows == "clear" or frames == "transplant" else None
            if rows == "clear":  # a clipped core is seen; less the rows a photograph's reference leaves out as unclear
                along = tp.stripe_extents(img, None, measured=plain, guide=case.truth_columns)
                states = tp.seen_states(img, case.truth_columns, tp.clipped_peaks(case.original, along))
                unclear = tp.unclear_rows(along, case.original, guided=True)
                states = np.where((states == STRIPE) & unclear, UNSURE, states).astype(np.int8)
            if reading == "fallback":  # as a reference without row states: far from the scored stripe rows, none
                states = fallback_of(states)
            near = distant_states(states, case.truth_columns) != states  # stripe-less rows near the stripe
            scored = scored_columns(img, case.truth_columns, states, truth)
            for lab, codes in pr.score_frame(tr, img, scored, states=states).items():
                far = outcome_counts(np.where(near, UNKNOWN, codes))
                meas_rows.append({"experiment": name, "tracker": lab, **outcome_counts(codes),
                                  "n_false_far": far["n_false"], "n_quiet_far": far["n_quiet"]})
            if frames == "transplant":
                photo = pr.Photo(name, Path(name), img, None, case.original, laser, channel=case.channel,
                                 reference=case.truth_columns, fallback_rows=reading == "fallback")
                made, bad = pr.transplanted(photo, seed=seed, estimate=estimate, measured=plain)
                bad = list(bad)
                frames_doc.append({"name": name, "case": exp.key, "status": "out of range" if bad else "matched",
                                   "out_of_range": bad, "shift_px": made[0][4] if made else None,
                                   "width_px": plain.width_px, "contrast": plain.contrast})
                if bad:
                    say(f"stripebench predictcheck: {name}: out of range ({', '.join(bad)})")
                    continue
                per = pr.transplant_outcomes(tr, made)
                for lab in tr:
                    pred_rows.append({"name": name, "tracker": lab,
                                      **outcome_counts(np.concatenate(per[lab][:pr.N_FULL])),
                                      **pr.cut_counts(per[lab])})
                groups[name] = exp.key
                say(f"stripebench predictcheck: {name}: its stripe moved by {made[0][4]:+d} and {made[1][4]:+d} px "
                    f"[case {e_i + 1}/{len(config.experiments)}]")
                continue
            if key not in tables:
                say(f"stripebench predictcheck: grid table ({'colour' if colour else 'grey'}, {laser} laser)")
                tables[key] = pr.grid_table(g, colour=colour, laser=laser)
                memos[key] = pr.refined_memo(g, colour=colour, laser=laser)
            c = cond.measure(img, None, rgb=case.rgb, laser=laser)
            known = len(memos[key])
            m = pr.match(c, tables[key], g, colour=colour, laser=laser, memo=memos[key])
            if len(memos[key]) > known:
                pr.save_refined_memo(memos[key], g, colour=colour, laser=laser)
            doc = {"name": name, "case": exp.key, "status": "out of range" if m.out_of_range else "matched",
                   "out_of_range": list(m.out_of_range), "distance": m.distance, "point": m.point}
            frames_doc.append(doc)
            if m.out_of_range:
                say(f"stripebench predictcheck: {name}: out of range ({', '.join(m.out_of_range)})")
                continue
            res = pr.predict_outcomes({name: m.point}, g, tr, colour=colour, laser=laser, n_angles=pr.N_ANGLES,
                                      fallback_rows=reading == "fallback")
            for lab in tr:
                pred_rows.append({"name": name, "tracker": lab,
                                  **outcome_counts(np.concatenate([x.ravel() for x in res[name][lab]]))})
            groups[name] = exp.key
            say(f"stripebench predictcheck: {name}: matched (distance {m.distance:.2f}) "
                f"[case {e_i + 1}/{len(config.experiments)}]")
    predicted, measured = pd.DataFrame(pred_rows), pd.DataFrame(meas_rows)
    cases = compare_by_group(predicted, measured, groups) if pred_rows else {}
    pooled = compare_by_group(predicted, measured, {n: "all" for n in groups}) if pred_rows else {}
    # the false-report rate again on the stripe-less rows a photograph's reference scores (docs/predict.md)
    distant = measured.assign(n_false=measured["n_false_far"], n_quiet=measured["n_quiet_far"])
    far = compare_by_group(predicted, distant, groups) if pred_rows else {}
    far_pooled = compare_by_group(predicted, distant, {n: "all" for n in groups}) if pred_rows else {}
    doc = {"kind": "predict_check", "profile": profile, "seed": int(seed), "procedure": frames,
           "downscale": int(downscale), "estimate": estimate, "line_fwhm_mrad": line_fwhm_mrad,
           "laser_power_mw": laser_power_mw, "channel": channel, "distractor": distractor,
           "jpeg_quality": jpeg_quality, "truth": truth,
           "rows": rows, "states": reading, "grid": g.to_value() if frames == "render" else None,
           "trackers": list(tr), "frames": frames_doc,
           "cases": {k: {**comparison_doc(v), FAR: comparison_doc(far[k])["false_report_rate"]}
                     for k, v in cases.items()},
           "pooled": {**comparison_doc(pooled["all"]), FAR: comparison_doc(far_pooled["all"])["false_report_rate"]}
           if pooled else None,
           "per_case": {**per_group_error(cases), FAR: per_group_error(far)["false_report_rate"]} if cases else None,
           "code": code_of_run()}
    atomic_write_text(outdir / "predict_check.json", json.dumps(doc, indent=1, default=float))
    atomic_write_text(outdir / "predicted.csv", predicted.to_csv(index=False))
    atomic_write_text(outdir / "measured.csv", measured.to_csv(index=False))
    print(f"{'case':<28}{'frames':>7}{'hit rate rho / |diff|':>24}{'F1 rho / |diff|':>20}"
          f"{'mean hit rate pred / meas':>28}")
    rows = list(cases.items()) + ([("all (pooled)", pooled["all"])] if pooled else [])
    for k, v in rows:
        h = v["hit_rate"]
        cells = "".join(f"{v[f]['spearman_rho']:>11.2f} / {v[f]['mean_abs_diff']:.3f}" for f in ("hit_rate", "f1"))
        means = (f"{np.mean([r['synthetic'] for r in h['table']]):>15.3f} / "
                 f"{np.mean([r['real'] for r in h['table']]):.3f}") if h["table"] else ""
        print(f"{k:<28}{len(v['photographs']):>7}{cells:>44}{means:>28}")
    if cases:
        err = doc["per_case"]
        cells = "".join(f"{'|diff|':>11} {err[f]:>7.3f}" for f in ("hit_rate", "f1"))
        print(f"{'mean over the cases':<28}{'':>7}{cells}   (false-report rate {err['false_report_rate']:.3f}; "
              f"on the rows a photograph's reference scores {err[FAR]:.3f})")
    n_out = sum(1 for d in frames_doc if d["status"] != "matched")
    print(f"stripebench: predictcheck in {outdir} ({len(frames_doc)} frames, {n_out} out of range)")
    return 0


def scored_columns(image, truth_columns, states, truth: str = "render") -> np.ndarray:
    """The columns the measured side scores a case frame against (``truth``, :data:`TRUTHS`), shape (H,), px (NaN: no
    stripe): ``render``, ``truth_columns`` (the render's truth); ``reference``, the columns a photograph's reference
    would give (:func:`bench.evaluate.outcomes.referenced_columns` of ``image``), and in a row ``states`` calls a
    stripe row where the reference rule gives none (a clipped core in a glow, read as seen:
    :func:`bench.evaluate.transplant.seen_states`, ``--rows clear``), the true column.

    Examples
    --------
    A stripe on column 10 in rows 0-1; row 1's truth 2 px off; row 2 a stripe row the rule does not see:

    >>> img = np.zeros((3, 20)); img[:2, 9:12] = [40.0, 80.0, 40.0]; img[2, 9:12] = 1.0
    >>> scored_columns(img, [10.0, 12.0, 10.5], np.array([1, 1, 1]), "reference").tolist()
    [10.0, 10.0, 10.5]
    >>> scored_columns(img, [10.0, 12.0, 10.5], np.array([1, 1, 1])).tolist()
    [10.0, 12.0, 10.5]
    """
    from bench.evaluate.outcomes import STRIPE, referenced_columns

    if truth not in TRUTHS:
        raise ValueError(f"`truth` must be one of {', '.join(TRUTHS)}, got {truth!r}")
    t = np.asarray(truth_columns, dtype=np.float64)
    if truth == "render":
        return t
    cols = referenced_columns(image, t)
    seen = (np.asarray(states) == STRIPE) & ~np.isfinite(cols)
    return np.where(seen, t, cols)


def family_of(doc: dict) -> str:
    """The render family of a ``predict_check.json`` document: ``native``, or its ``--downscale``, ``--line-fwhm``
    ``--laser-power``, ``--channel``, ``--distractor``, ``--truth`` and ``--rows`` (docs/predict.md: the phone-like
    family is ``downscale 4, line 1.2 mrad``), after its ``--profile`` where that is not ``field`` (the cases' own
    profile).

    Examples
    --------
    >>> now = {"downscale": 1, "line_fwhm_mrad": None, "rows": "clear"}
    >>> family_of(now), family_of({**now, "downscale": 4, "line_fwhm_mrad": 1.2})
    ('native', 'downscale 4, line 1.2 mrad')
    >>> family_of({**now, "line_fwhm_mrad": 20.0, "laser_power_mw": 100.0})
    'downscale 1, line 20 mrad, 100 mW'
    >>> family_of({**now, "channel": "laser"})
    'downscale 1, channel laser'
    >>> family_of({**now, "downscale": 4, "line_fwhm_mrad": 1.2, "truth": "reference"})
    'downscale 4, line 1.2 mrad, truth reference'
    >>> family_of({**now, "profile": "marble"}), family_of({**now, "profile": "marble", "laser_power_mw": 15.0})
    ('marble: native', 'marble: downscale 1, 15 mW')

    A run scored on every row where the rule sees the stripe (``--rows seen``; every run from before the tenth
    session, whose document has no ``rows``):

    >>> family_of({**now, "rows": "seen"}), family_of({"downscale": 1, "line_fwhm_mrad": None})
    ('native, rows seen', 'native, rows seen')

    Rows read as a reference without row states reads them (``--states fallback``):

    >>> family_of({**now, "states": "fallback"})
    'native, states fallback'

    Frames JPEG-compressed (``--jpeg-quality``):

    >>> family_of({**now, "profile": "marble", "laser_power_mw": 60.0, "jpeg_quality": 75})
    'marble: downscale 1, 60 mW, JPEG 75'
    """
    d, lw, mw = int(doc.get("downscale", 1)), doc.get("line_fwhm_mrad"), doc.get("laser_power_mw")
    ch, dis, tr = doc.get("channel", "auto"), doc.get("distractor", "none"), doc.get("truth", "render")
    jq = doc.get("jpeg_quality")
    profile = doc.get("profile", "field")
    if d == 1 and lw is None and mw is None and ch == "auto" and dis == "none" and tr == "render" and jq is None:
        family = "native"
    else:
        family = (f"downscale {d}" + ("" if lw is None else f", line {float(lw):g} mrad")
                  + ("" if mw is None else f", {float(mw):g} mW") + ("" if ch == "auto" else f", channel {ch}")
                  + ("" if dis == "none" else f", {dis}") + ("" if jq is None else f", JPEG {int(jq)}")
                  + ("" if tr == "render" else f", truth {tr}"))
    if doc.get("rows", "seen") != DEFAULTS["rows"]:  # a run from before the tenth session has no key: ``seen``
        family += f", rows {doc.get('rows', 'seen')}"
    if doc.get("states", "given") != DEFAULTS["states"]:  # before the fifteenth session: ``given``
        family += f", states {doc['states']}"
    return family if profile == "field" else f"{profile}: {family}"


def objective(docs: dict, min_rows: int = 0) -> dict:
    """The declared objective of docs/predict.md over finished ``predictcheck`` runs (name -> its
    ``predict_check.json``): per run, the *per-case score* (each case's mean |predicted - measured| of hit rate
    and F1, averaged: :func:`bench.evaluate.prediction.per_group_error`), the per-case false-report |difference|,
    the pooled score and the pooled false-report |difference|; then their means over the runs, and the per-case
    score's mean per family (:func:`family_of`). With ``min_rows`` > 0 the per-case figures leave out the cases
    whose frames hold fewer measured stripe rows (a document's ``_case_rows``, case -> rows, which
    :func:`_read_runs` adds from its ``measured.csv``): a hit rate on 15 rows is mostly its own noise (docs/predict.md,
    "Ties on the path"); the pooled figures keep every case, and each run says how many it left out (``n_left_out``).

    Examples
    --------
    >>> case = lambda h, f, r: {"hit_rate": {"mean_abs_diff": h}, "f1": {"mean_abs_diff": f},
    ...                         "false_report_rate": {"mean_abs_diff": r}}
    >>> doc = {"downscale": 1, "line_fwhm_mrad": None, "rows": "clear", "seed": 1,
    ...        "cases": {"a": case(0.02, 0.04, 0.1), "b": case(0.06, 0.08, 0.3)}, "pooled": case(0.01, 0.03, 0.2)}
    >>> o = objective({"r1": doc})
    >>> round(o["per_case"], 6), round(o["false_report_per_case"], 6), round(o["pooled"], 6), o["families"]
    (0.05, 0.2, 0.02, {'native': 0.05})
    >>> o = objective({"r1": {**doc, "_case_rows": {"a": 600, "b": 15}}}, min_rows=100)
    >>> round(o["per_case"], 6), o["runs"]["r1"]["n_left_out"], round(o["pooled"], 6)
    (0.03, 1, 0.02)
    """
    from bench.evaluate.prediction import per_group_error

    if not docs:
        raise ValueError("`docs` must hold at least one predictcheck run, got none")
    if isinstance(min_rows, bool) or not isinstance(min_rows, (int, np.integer)) or min_rows < 0:
        raise ValueError(f"`min_rows` must be an integer >= 0, got {min_rows!r}")
    runs = {}
    for name, doc in docs.items():
        if not doc.get("cases") or not doc.get("pooled"):
            raise ValueError(f"{name}: a predictcheck run with no case predicted")
        cases = doc["cases"]
        if min_rows:
            if "_case_rows" not in doc:
                raise ValueError(f"{name}: leaving out cases by their rows needs the run's measured.csv")
            cases = {k: v for k, v in cases.items() if doc["_case_rows"].get(k, 0) >= min_rows}
            if not cases:
                raise ValueError(f"{name}: no case measured on {min_rows} stripe rows or more")
        err = per_group_error(cases)
        # the false-report |difference| on the rows a reference scores, over the same cases (runs before the seventh
        # session have no such figure: NaN)
        far_vals = [float(v[FAR]["mean_abs_diff"]) for v in cases.values()
                    if FAR in v and np.isfinite(v[FAR]["mean_abs_diff"])]
        far = float(np.mean(far_vals)) if far_vals else float("nan")
        pooled = doc["pooled"]
        runs[name] = {"family": family_of(doc), "seed": doc.get("seed"), "estimate": doc.get("estimate"),
                      "n_left_out": len(doc["cases"]) - len(cases),
                      "per_case": 0.5 * (err["hit_rate"] + err["f1"]), "per_case_hit_rate": err["hit_rate"],
                      "per_case_f1": err["f1"], "false_report_per_case": err["false_report_rate"],
                      "false_report_far_per_case": far,
                      "pooled": 0.5 * (pooled["hit_rate"]["mean_abs_diff"] + pooled["f1"]["mean_abs_diff"]),
                      "pooled_hit_rate": pooled["hit_rate"]["mean_abs_diff"],
                      "pooled_f1": pooled["f1"]["mean_abs_diff"],
                      "pooled_false_report": pooled["false_report_rate"]["mean_abs_diff"]}

    def mean(k):  # over the runs that have the figure (no false-report rows: NaN)
        vals = [r[k] for r in runs.values() if np.isfinite(r[k])]
        return float(np.mean(vals)) if vals else float("nan")

    families: dict = {}
    for r in runs.values():
        families.setdefault(r["family"], []).append(r["per_case"])
    keys = ("per_case", "per_case_hit_rate", "per_case_f1", "false_report_per_case", "false_report_far_per_case",
            "pooled", "pooled_hit_rate", "pooled_f1", "pooled_false_report")
    return {"runs": runs, **{k: mean(k) for k in keys},
            "families": {f: float(np.mean(v)) for f, v in families.items()}}


#: :func:`paired`'s figures (:func:`objective`'s per-run keys), each with its column's header in ``predictscore``.
PAIRED = {"per_case": "per case", "false_report_per_case": "false-report |diff|", "false_report_far_per_case": "far",
          "pooled": "pooled", "pooled_false_report": "pooled false-report"}


def code_of_run() -> dict:
    """What code a run was made by: ``revision`` (``git describe``, :func:`bench.store.provenance.git_revision`) and
    ``fingerprint``, a hash of the ``bench``, ``trackers`` and ``scenes`` source that ran
    (:func:`bench.store.provenance.source_fingerprint`): :func:`paired` refuses two runs of the same code."""
    from bench.store.provenance import git_revision, source_fingerprint

    return {"revision": git_revision(), "fingerprint": source_fingerprint(("bench", "trackers", "scenes"))}


def paired(docs: dict, against: dict, min_rows: int = 0) -> dict:
    """Each run of ``docs`` beside the run of ``against`` of its family and seed (name -> ``predict_check.json``):
    the differences (this minus that) of :func:`objective`'s per-run figures (with ``min_rows``), per pair, and per
    family their mean, least and greatest over the seeds, so that a choice between two versions of the procedure
    sees how far its difference moves from seed to seed (docs/predict.md, "Paired differences").

    Raises
    ------
    ValueError
        A run with no partner of its family and seed in the other set, two runs of one family and seed in one set,
        or a pair made by the same code (both record ``code``, :func:`code_of_run`, with one ``fingerprint``: their
        differences are nought by construction, not a finding; e.g. a candidate run from the base's folder, where
        ``python -m`` imports the folder's ``bench`` before ``PYTHONPATH``'s).

    Examples
    --------
    >>> case = lambda h: {"hit_rate": {"mean_abs_diff": h}, "f1": {"mean_abs_diff": h},
    ...                   "false_report_rate": {"mean_abs_diff": 0.1}}
    >>> doc = lambda seed, h: {"downscale": 1, "line_fwhm_mrad": None, "rows": "clear", "seed": seed,
    ...                        "cases": {"a": case(h)}, "pooled": case(h)}
    >>> p = paired({"n1": doc(1, 0.03), "n2": doc(2, 0.05)}, {"o1": doc(1, 0.02), "o2": doc(2, 0.02)})
    >>> [round(v, 3) for v in p["families"]["native"]["per_case"]], round(p["per_case"], 3)
    ([0.02, 0.01, 0.03], 0.02)
    """
    def keyed(group, which):
        out = {}
        for name, r in objective(group, min_rows)["runs"].items():
            k = (r["family"], r["seed"])
            if k in out:
                raise ValueError(f"{which}: two runs of family {k[0]!r} and seed {k[1]}: {out[k][0]} and {name}")
            out[k] = (name, r)
        return out

    mine, theirs = keyed(docs, "the RUNs"), keyed(against, "--against")
    if set(mine) != set(theirs):
        k = sorted(set(mine) ^ set(theirs), key=str)[0]
        where = "--against has" if k in mine else "the RUNs have"
        raise ValueError(f"{where} no run of family {k[0]!r} and seed {k[1]} to pair with")
    for k in sorted(mine, key=str):
        a, b = (docs[mine[k][0]].get("code") or {}), (against[theirs[k][0]].get("code") or {})
        if a.get("fingerprint") and a.get("fingerprint") == b.get("fingerprint"):
            raise ValueError(f"{mine[k][0]} and {theirs[k][0]} were made by the same code (fingerprint "
                             f"{a['fingerprint']}, revision {a.get('revision', 'unknown')}): a pair compares two "
                             "versions (run each from its own folder: `python -m` imports the folder's `bench` first)")
    keys = tuple(PAIRED)
    pairs = {k: {f: mine[k][1][f] - theirs[k][1][f] for f in keys} | {"runs": (mine[k][0], theirs[k][0])}
             for k in sorted(mine, key=str)}

    def spread(vals):  # mean, least, greatest of the finite ones (a run without the figure: NaN)
        v = [x for x in vals if np.isfinite(x)]
        return (float(np.mean(v)), float(min(v)), float(max(v))) if v else (float("nan"),) * 3

    families: dict = {}
    for (fam, _), d in pairs.items():
        families.setdefault(fam, []).append(d)
    fam_out = {fam: {f: spread([d[f] for d in ds]) for f in keys} | {"n": len(ds)} for fam, ds in families.items()}
    return {"pairs": pairs, "families": fam_out, **{f: spread([d[f] for d in pairs.values()])[0] for f in keys}}


def _read_runs(runs, rows: bool = False) -> dict:
    """Run folder -> its ``predict_check.json``; with ``rows``, each with ``_case_rows`` (case -> the measured stripe
    rows of its frames, from ``measured.csv``: hit, wrong and missed rows of its first tracker, the same for every
    tracker since the row states are the frame's)."""
    import pandas as pd

    docs = {}
    for run in runs:
        path = Path(run) / "predict_check.json"
        try:
            doc = json.loads(path.read_text(encoding="utf-8"))
            if rows:
                m = pd.read_csv(Path(run) / "measured.csv")
                m = m[m["tracker"] == m["tracker"].iloc[0]]
                n = (m["n_hit"] + m["n_wrong"] + m["n_missed"]).groupby(m["experiment"].str.rsplit("@", n=1).str[0])
                doc["_case_rows"] = {str(k): int(v) for k, v in n.sum().items()}
        except (OSError, ValueError, KeyError, IndexError) as exc:
            raise ValueError(f"{str(run)!r} is not a finished predictcheck run ({type(exc).__name__}: {exc})") from None
        docs[str(run)] = doc
    return docs


def score(*, runs, against=None, min_rows: int = 0) -> int:
    """``stripebench predictscore RUN [RUN ...] [--against RUN ...] [--min-rows N]``: :func:`objective` over finished
    ``predictcheck`` runs, printed (the numbers docs/predict.md decides the prediction's procedure by); with
    ``against``, each run's difference from its partner of the same family and seed (:func:`paired`); with
    ``min_rows``, the per-case figures without the cases measured on fewer stripe rows. 0, or 2 with one line on
    stderr for a folder that is not a finished run or a run without a partner."""
    try:
        docs = _read_runs(runs, rows=bool(min_rows))
        o = objective(docs, min_rows)
        pair = paired(docs, _read_runs(against, rows=bool(min_rows)), min_rows) if against else None
    except ValueError as exc:
        print(f"stripebench predictscore: {exc}", file=sys.stderr)
        return 2
    fw = max(28, 2 + max(len(r["family"]) for r in o["runs"].values()))
    print(f"{'run':<44}{'family':<{fw}}{'seed':>5}{'per case':>10}{'hit / F1':>16}{'false':>8}{'far':>8}{'pooled':>9}")
    for name, r in o["runs"].items():
        print(f"{name[-43:]:<44}{r['family']:<{fw}}{str(r['seed']):>5}{r['per_case']:>10.4f}"
              f"{r['per_case_hit_rate']:>8.4f} {r['per_case_f1']:.4f}{r['false_report_per_case']:>8.4f}"
              f"{r['false_report_far_per_case']:>8.4f}{r['pooled']:>9.4f}")
    fam = ", ".join(f"{f} {v:.5f}" for f, v in o["families"].items())
    print(f"per-case score {o['per_case']:.5f} ({fam}); false-report |diff| per case {o['false_report_per_case']:.5f} "
          f"(on the rows a photograph's reference scores: {o['false_report_far_per_case']:.5f}); "
          f"pooled score {o['pooled']:.4f} ({len(o['runs'])} runs)")
    print(f"mean |predicted - measured| per case: hit rate {o['per_case_hit_rate']:.4f}, F1 {o['per_case_f1']:.4f}; "
          f"pooled: hit rate {o['pooled_hit_rate']:.4f}, F1 {o['pooled_f1']:.4f}")
    if min_rows:
        left = sum(r["n_left_out"] for r in o["runs"].values())
        total = sum(len(d["cases"]) for d in docs.values())
        print(f"per-case figures without the cases measured on fewer than {min_rows} stripe rows: {left} of {total} "
              "left out (the pooled figures keep them)")
    if pair is not None:
        print(f"paired with --against (these minus those, per family: mean [least, greatest] over "
              f"{len(pair['pairs'])} pairs):")
        print(f"{'family':<{fw}}{'pairs':>6}" + "".join(f"{h:>30}" for h in PAIRED.values()))
        for fam, d in pair["families"].items():
            cells = "".join(f"{d[k][0]:>+12.5f} [{d[k][1]:+.5f}, {d[k][2]:+.5f}]".rjust(30) for k in PAIRED)
            print(f"{fam:<{fw}}{d['n']:>6}{cells}")
        print(f"per-case score {pair['per_case']:+.5f}; false-report |diff| per case "
              f"{pair['false_report_per_case']:+.5f} (far {pair['false_report_far_per_case']:+.5f}); "
              f"pooled score {pair['pooled']:+.5f}, pooled false-report |diff| {pair['pooled_false_report']:+.5f}")
    return 0
