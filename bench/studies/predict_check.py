"""Renders standing in for photographs (``stripebench predictcheck``): the prediction checked where the truth is known.

:mod:`bench.run.predict` predicts the trackers' figures on a rig's photographs from frames made of them (each
photograph with its own stripe moved). On photographs its error cannot be told from the references' own; on renders
the truth is known. This study measures the procedure there: its rules were chosen on renders, never on the shipped
photographs (docs/predict.md).

Each *case* is one experiment of a profile (default the ``field`` profile), rendered at ``size`` with ``seed`` at
``n_angles`` mirror angles spread over the middle half of its scan; each frame stands in for a photograph, used
without its laser-off frame, as most photographs come.

- **Measured:** the trackers are scored on the case's frames as a photograph is: row outcomes against the render's
  truth, with stripe rows where :func:`bench.evaluate.outcomes.referenced_states` sees the stripe (less the rows a
  reference leaves out as unclear, ``--rows clear``).
- **Predicted:** the procedure predicts the same figures from the frame alone, as ``stripebench predict`` does with a
  photograph (the seed seeds the clean plate's noise).

The two are compared per case and pooled, with Spearman's rho and the mean |difference| for hit rate, F1 and the
false-report rate (:func:`bench.evaluate.prediction.compare_by_group`). A *family* (:data:`FAMILIES`) is a named set
of options that gives the cases a condition the shipped photographs show; ``stripebench predictscore``
(:mod:`bench.studies.predict_score`) scores finished runs by the declared objective.
"""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["DEFAULTS", "CASE_CHANNELS", "TRUTHS", "ROWS", "STATE_READINGS", "DISTRACTORS", "FAMILIES", "FAR", "Bar",
           "BAR", "stripe_evidence", "with_white_bar", "with_rival_fringe", "Case", "family_scene", "shrink_frame",
           "case_frames", "family_options", "study", "scored_columns", "check_identity", "code_of_run"]

#: The study's defaults (the command's options).
DEFAULTS = {"profile": "field", "seed": 1, "size": 256, "n_angles": 3, "downscale": 1, "line_fwhm_mrad": None,
            "laser_power_mw": None, "channel": "auto", "distractor": "none", "jpeg_quality": None, "truth": "render",
            "rows": "clear", "states": "given", "family": None}

#: What the trackers see of a colour case (``--channel``): ``auto``, the laser-colour blend
#: (:func:`bench.evaluate.pixels.select_channel`), or ``laser``, the laser's own plain channel, as a rig whose software
#: reads one channel does.
CASE_CHANNELS = ("auto", "laser")

#: What the measured side scores the case frames against (``--truth``): ``render``, the render's own truth (the laser
#: sheet's centre), or ``reference``, the columns a photograph's reference would give it
#: (:func:`bench.evaluate.outcomes.referenced_columns`: the intensity centre near the true column). The row states are
#: the same.
TRUTHS = ("render", "reference")

#: Which stripe rows the measured side scores (``--rows``): ``clear`` (the default), every row where the reference rule
#: sees the true stripe less those a photograph's reference leaves out as unclear
#: (:func:`bench.evaluate.rowstates.unclear_rows` along the true columns), with a clipped core scored where the rule
#: does not see it (:func:`bench.evaluate.rowstates.seen_states`); or ``seen``, every row where the rule sees it.
ROWS = ("seen", "clear")

#: How the rows that are not scored stripe rows are read (``--states``), on both sides: ``given`` (the default), as the
#: render's truth gives them, or ``fallback``, as a real set's reference without row states is read
#: (:func:`bench.evaluate.outcomes.fallback_of`), the prediction reading its frames so too.
STATE_READINGS = ("given", "fallback")

#: What a case frame carries besides its render (``--distractor``): ``none``; ``white-bar``, a vertical white line
#: beside the stripe in every row (a window's frame, a lamp's stem: bright in every channel, of no colour); or
#: ``rival-fringe``, that bar with a fringe of the laser's colour whose laser evidence is ``fringe_share`` of the
#: stripe's (a rival nearly as like the laser as the stripe, as a lens's lateral colour makes of a bright edge). Added
#: to the rendered photograph before the trackers' channel is taken (:func:`with_white_bar`,
#: :func:`with_rival_fringe`).
DISTRACTORS = ("none", "white-bar", "rival-fringe")

#: The named render families (``--family NAME``), each the options it sets and why the procedure needs it: a rule of
#: docs/predict.md that only this condition exercises. A given option the family sets otherwise is an error.
FAMILIES = {
    # the field profile's cases as rendered: every rule at the renders' own conditions
    "native": {},
    # thin stripes standing far above the noise, as a phone's shrunk frames: the argmax guide (``auto_width_px``)
    "phone": {"downscale": 4, "line_fwhm_mrad": 1.2},
    # trackers reading the laser's plain channel: the colour guide only where they see the laser's colour
    "plain": {"channel": "laser"},
    # a rival nearly as like the laser as the stripe: the arbiter's evidence (``evidence_share``); a measure of harm
    "rival-fringe": {"distractor": "rival-fringe"},
    # every laser at 50 mW, cores clipped white as in a third of the shipped photographs: ``dip_share`` and the
    # laser channel's lift near the top
    "white-core": {"laser_power_mw": 50.0},
    # translucent objects glowing at 60 mW, JPEG-compressed at Pillow's default 75: a clipped core ringing under the
    # top (``clip_noise_k``)
    "marble-60mw-jpeg": {"profile": "marble", "laser_power_mw": 60.0, "jpeg_quality": 75},
    # translucent objects at 480 mW: a clipped core in a glow near the top, as on the shipped ``bb_hand`` (``glow_share``)
    "marble-480mw": {"profile": "marble", "laser_power_mw": 480.0},
}

#: The key of the false-report comparison on the stripe-less rows a photograph's reference scores, at least
#: :data:`bench.evaluate.outcomes.GAP_ROWS` rows from the stripe (:func:`bench.evaluate.outcomes.distant_states`):
#: on renders every other stripe-less row is one where the stripe jumps at an occlusion, which a photograph's
#: reference leaves unscored. In ``predict_check.json`` beside each case's, the pooled and the per-case figures;
#: ``measured.csv``'s ``n_false_far`` and ``n_quiet_far``.
FAR = "false_report_rate_far"


@dataclass(frozen=True)
class Bar:
    """The distractors' white bar (:data:`DISTRACTORS`): its distance from the stripe's median column (px; on the side
    with room), its Gaussian sigma (px), its peak (DN added in every channel, clipped at the top); ``rival-fringe``'s
    fringe lies ``fringe_px`` beyond it (about a pixel and a half of a lens's lateral colour off its axis) with
    ``fringe_share`` of the stripe's laser evidence (the middle of what the shipped ``al_room7``'s window bars carry,
    0.8-0.95 of its stripe's)."""

    offset_px: float = 20.0
    sigma_px: float = 1.2
    peak_dn: float = 200.0
    fringe_px: float = 1.5
    fringe_share: float = 0.85


#: The bar the families use.
BAR = Bar()


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
    its laser power."""
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
    no stripe) of :func:`bench.evaluate.colourguide.laser_evidence` near its column
    (:func:`bench.evaluate.colourguide.evidence_near`), as the arbiter reads a guide's, with the laser-colour excess as
    its colour term; 0 without a stripe row.

    Examples
    --------
    >>> rgb = np.zeros((4, 30, 3), np.uint8); rgb[:, 10, 0] = 90
    >>> stripe_evidence(rgb, np.full(4, 10.0), "red")
    90.0
    """
    from bench.evaluate.colourguide import evidence_near, laser_evidence
    from bench.evaluate.pixels import LASER_INDEX, select_channel

    a = np.asarray(rgb)
    t = np.asarray(truth_columns, dtype=np.float64)
    if not np.isfinite(t).any():
        return 0.0
    ev = laser_evidence(a[..., LASER_INDEX[laser]].astype(np.float64), select_channel(a, "excess", laser))
    return float(np.nanmedian(evidence_near(ev, t)))


def _bar_side(stripe_px: float, width: int, bar: Bar) -> float:
    """Which side of the stripe's median column (``stripe_px``) the white bar goes in a frame ``width`` px wide: +1
    (right, ``bar.offset_px`` away) where the bar and three of its sigmas fit, else -1 (left)."""
    return 1.0 if stripe_px + bar.offset_px + 3 * bar.sigma_px <= width - 1 else -1.0


def with_white_bar(photo, truth_columns, *, fringe_channel: int | None = None, fringe_dn: float = 0.0,
                   bar: Bar = BAR):
    """``photo`` (H, W) or (H, W, 3), integer DN, with :data:`DISTRACTORS`' white bar added: a vertical Gaussian line
    of ``bar.peak_dn`` and ``bar.sigma_px``, ``bar.offset_px`` right of the median of ``truth_columns`` (px, NaN: no
    stripe), or left where the right has no room, in every channel and row, clipped at the top of the dtype's range.
    Unchanged where ``truth_columns`` has no column. With ``fringe_channel`` (a colour photograph's channel index, the
    laser's), that channel gains a line of ``fringe_dn`` (DN) ``bar.fringe_px`` beyond the bar: the ``rival-fringe``
    distractor's fringe.

    Examples
    --------
    >>> img = np.zeros((4, 60), np.uint8)
    >>> out = with_white_bar(img, np.full(4, 10.0))
    >>> int(np.argmax(out[0])), int(out[0, 30]), out.dtype.name
    (30, 200, 'uint8')
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
    col = c + _bar_side(c, W, bar) * bar.offset_px
    line = bar.peak_dn * np.exp(-0.5 * ((np.arange(W) - col) / bar.sigma_px) ** 2)
    line = line[None, :, None] if a.ndim == 3 else line[None, :]
    if fringe_channel is not None and a.ndim == 3:
        away = col + (bar.fringe_px if col > c else -bar.fringe_px)  # beyond the bar, further from the stripe
        line = np.repeat(line, a.shape[2], axis=2)
        line[..., fringe_channel] += float(fringe_dn) * np.exp(-0.5 * ((np.arange(W) - away) / bar.sigma_px) ** 2)[None, :]
    top = float(np.iinfo(a.dtype).max) if np.issubdtype(a.dtype, np.integer) else np.inf
    out = np.clip(a.astype(np.float64) + line, 0.0, top)
    return np.rint(out).astype(a.dtype) if np.issubdtype(a.dtype, np.integer) else out.astype(a.dtype)


def with_rival_fringe(rgb, truth_columns, laser: str, *, bar: Bar = BAR):
    """``rgb`` (H, W, 3), integer DN, with the ``rival-fringe`` distractor: :func:`with_white_bar` with a fringe in the
    laser's channel whose laser evidence (:func:`stripe_evidence` read along the fringe's column) is
    ``bar.fringe_share`` of the stripe's (:func:`stripe_evidence` along ``truth_columns``, px, NaN: no stripe). The
    fringe's peak (DN) is found by bisection: evidence is read over each row's median, so a fringe's evidence is less
    than its peak by what the row's noise and texture hold, and clipping bends it. Unchanged without a stripe row or a
    stripe with no evidence; the greatest fringe the range allows where the share is out of reach.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> rgb = rng.integers(40, 60, (8, 60, 3)).astype(np.uint8); rgb[:, 10, 0] = 110
    >>> t = np.full(8, 10.0)
    >>> half = Bar(fringe_share=0.5)
    >>> out = with_rival_fringe(rgb, t, "red", bar=half)
    >>> fringe = np.full(8, 10.0 + half.offset_px + half.fringe_px)
    >>> round(stripe_evidence(out, fringe, "red") / stripe_evidence(rgb, t, "red"), 1)
    0.5
    """
    from bench.evaluate.pixels import LASER_INDEX

    a = np.asarray(rgb)
    t = np.asarray(truth_columns, dtype=np.float64)
    target = float(bar.fringe_share) * stripe_evidence(a, t, laser)
    if target <= 0.0:
        return a.copy()
    c = float(np.nanmedian(t))
    along = np.where(np.isfinite(t), c + _bar_side(c, a.shape[1], bar) * (bar.offset_px + bar.fringe_px), np.nan)
    li = LASER_INDEX[laser]

    def made(dn):
        out = with_white_bar(a, t, fringe_channel=li, fringe_dn=dn, bar=bar)
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
    added to each frame's photograph (a grey case gets the white bar alone); ``jpeg_quality`` (1-95, or None)
    JPEG-compresses each frame's photograph after that, as a webcam or a phone does (:func:`scenes.jpeg_round_trip`;
    8-bit frames only)."""
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
    lo, hi = a[len(a) // 4], a[min(len(a) - 1, (3 * len(a)) // 4)]
    laser = laser_colour(scene.params["laser_wavelength_nm"])
    out = []
    for i, ang in enumerate(np.linspace(lo, hi, n_angles) if n_angles > 1 else [a[len(a) // 2]]):
        f = shrink_frame(scene.render(float(ang)), downscale)
        if distractor == "rival-fringe" and f.rgb is not None:
            f.rgb = with_rival_fringe(f.rgb, f.truth_columns, laser)
        elif distractor != "none":  # the white bar (a grey case's rival-fringe too)
            f.rgb = None if f.rgb is None else with_white_bar(f.rgb, f.truth_columns)
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


#: The keys of ``predict_check.json`` that name a check's configuration (:func:`check_identity`).
_IDENTITY = ("profile", "seed", "size", "n_angles", "downscale", "line_fwhm_mrad", "laser_power_mw", "channel",
             "distractor", "jpeg_quality", "truth", "rows", "states", "trackers", "settings")


def check_identity(doc: dict) -> dict:
    """What makes two checks the same configuration: the keys of a ``predict_check.json`` (or of :func:`study`'s
    options) that choose its cases, its scoring and its trackers.

    Examples
    --------
    >>> check_identity({"seed": 1, "profile": "field", "cases": {}})
    {'profile': 'field', 'seed': 1}
    """
    return {k: doc[k] for k in _IDENTITY if k in doc}


def study(*, out, profile: str = DEFAULTS["profile"], seed: int = DEFAULTS["seed"], size: int = DEFAULTS["size"],
          n_angles: int = DEFAULTS["n_angles"], downscale: int = DEFAULTS["downscale"],
          line_fwhm_mrad=DEFAULTS["line_fwhm_mrad"], laser_power_mw=DEFAULTS["laser_power_mw"],
          channel=DEFAULTS["channel"], distractor=DEFAULTS["distractor"], jpeg_quality=DEFAULTS["jpeg_quality"],
          truth=DEFAULTS["truth"], trackers=None, quiet: bool = False, family: str | None = DEFAULTS["family"],
          rows: str = DEFAULTS["rows"], states: str = DEFAULTS["states"], force: bool = False, settings=None) -> int:
    """Run the check and write ``predict_check.json``, ``predicted.csv`` and ``measured.csv`` into ``out``.

    Parameters
    ----------
    out : path
        Output folder (created). One holding another configuration's finished check is refused unless ``force``.
    profile : str
        The profile whose experiments are the cases (default ``field``).
    seed : int
        The cases' render seed (the procedure's rules were chosen at other seeds).
    size : int
        Render width of the cases (px; the height is 15/16 of it).
    n_angles : int
        Mirror angles per case.
    downscale : int
        Cases rendered this many times larger and shrunk back (:func:`case_frames`): stripes that stand as far above
        the noise as a phone's shrunk frames do.
    line_fwhm_mrad, laser_power_mw : float, optional
        Every case's laser line width (mrad) and laser power (mW) instead of its own.
    channel : str
        What the trackers see of a colour case (:data:`CASE_CHANNELS`).
    distractor : str
        What each case frame carries besides its render (:data:`DISTRACTORS`).
    jpeg_quality : int, optional
        JPEG-compress each case frame's photograph at this quality (1-95).
    truth : str
        What the measured side scores against (:data:`TRUTHS`). The prediction is the same either way.
    trackers : sequence of :class:`bench.config.TrackerSpec`, optional
        Default: the profile's trackers.
    quiet : bool
        No progress on stderr.
    family : str, optional
        A named render family (:data:`FAMILIES`): sets the options it names (:func:`family_options`).
    rows, states : str
        Which stripe rows the measured side scores (:data:`ROWS`) and how the others are read (:data:`STATE_READINGS`).
    force : bool
        Write over another configuration's finished check in ``out``.
    settings : bench.evaluate.predict_settings.PredictSettings, optional
        The tuned values the prediction and the measured side's row reading use (default: the product's), recorded in
        ``predict_check.json``: a candidate setting is checked on renders by passing it here.

    Returns
    -------
    int
        0.

    Raises
    ------
    bench.errors.ConfigError
        A bad option or family, or ``out`` holding another configuration's finished check (without ``force``).
    """
    import pandas as pd

    from bench.config import profile as load_profile
    from bench.errors import ConfigError
    from bench.evaluate import conditions as cond
    from bench.evaluate import rowstates as rs
    from bench.evaluate import stripe as sp
    from bench.evaluate.outcomes import STRIPE, UNKNOWN, UNSURE, distant_states, fallback_of, outcome_counts, \
        referenced_states
    from bench.evaluate.predict_settings import DEFAULT
    from bench.evaluate.prediction import compare_by_group, comparison_doc, per_group_error
    from bench.run import predict_frames as pf
    from bench.run.camera_view import colour_of, laser_colour
    from bench.run.track import build_trackers
    from bench.store.files import atomic_write_text

    for name, value, allowed in (("truth", truth, TRUTHS), ("rows", rows, ROWS), ("states", states, STATE_READINGS)):
        if value not in allowed:
            raise ConfigError(f"`{name}` must be one of {', '.join(allowed)}, got {value!r}")
    reading = states  # the option's value: the loop below names each case's row states ``states``
    s = DEFAULT if settings is None else settings
    if family is not None:
        opts = family_options(family, {"profile": profile, "downscale": downscale, "line_fwhm_mrad": line_fwhm_mrad,
                                       "laser_power_mw": laser_power_mw, "channel": channel, "distractor": distractor,
                                       "jpeg_quality": jpeg_quality})
        profile, downscale, line_fwhm_mrad = opts["profile"], opts["downscale"], opts["line_fwhm_mrad"]
        laser_power_mw, channel, distractor = opts["laser_power_mw"], opts["channel"], opts["distractor"]
        jpeg_quality = opts["jpeg_quality"]
    say = (lambda m: None) if quiet else (lambda m: print(m, file=sys.stderr, flush=True))
    config = load_profile(profile)
    width, height = int(size), int(size) * 15 // 16
    specs = trackers if trackers is not None else config.tracker_specs
    tr = build_trackers(specs)
    doc = {"kind": "predict_check", "profile": profile, "seed": int(seed), "size": int(size),
           "n_angles": int(n_angles), "downscale": int(downscale), "line_fwhm_mrad": line_fwhm_mrad,
           "laser_power_mw": laser_power_mw, "channel": channel, "distractor": distractor,
           "jpeg_quality": jpeg_quality, "truth": truth, "rows": rows, "states": reading, "trackers": list(tr),
           "settings": s.to_value()}
    outdir = Path(out)
    _refuse_other_check(outdir, doc, force)
    outdir.mkdir(parents=True, exist_ok=True)
    pred_rows, meas_rows, groups, frames_doc = [], [], {}, []
    for e_i, exp in enumerate(config.experiments):
        for name, case, params in case_frames(exp, config, seed=seed, width=width, height=height,
                                              n_angles=int(n_angles), downscale=downscale,
                                              line_fwhm_mrad=line_fwhm_mrad, laser_power_mw=laser_power_mw,
                                              channel=channel, distractor=distractor, jpeg_quality=jpeg_quality):
            img = case.image
            laser = laser_colour(params["laser_wavelength_nm"])
            states = referenced_states(img, case.truth_columns)
            plain = cond.measure(img, None, settings=s)
            if rows == "clear":  # a clipped core is seen; less the rows a photograph's reference leaves out as unclear
                along = sp.stripe_extents(img, None, measured=plain, guide=case.truth_columns, settings=s)
                states = rs.seen_states(img, case.truth_columns, rs.clipped_peaks(case.original, along, settings=s))
                unclear = rs.unclear_rows(along, case.original, guided=True, settings=s)
                states = np.where((states == STRIPE) & unclear, UNSURE, states).astype(np.int8)
            if reading == "fallback":  # as a reference without row states: far from the scored stripe rows, none
                states = fallback_of(states)
            near = distant_states(states, case.truth_columns) != states  # stripe-less rows near the stripe
            scored = scored_columns(img, case.truth_columns, states, truth)
            colour = colour_of(case.rgb, laser)  # as a scan passes a colour frame's evidence
            for lab, codes in pf.score_frame(tr, img, scored, states=states, colour=colour).items():
                far = outcome_counts(np.where(near, UNKNOWN, codes))
                meas_rows.append({"experiment": name, "tracker": lab, **outcome_counts(codes),
                                  "n_false_far": far["n_false"], "n_quiet_far": far["n_quiet"]})
            photo = pf.Photo(name, Path(name), img, None, case.original, laser, channel=case.channel,
                             fallback_rows=reading == "fallback")
            made, bad = pf.transplanted(photo, seed=seed, measured=plain, settings=s)
            bad = list(bad)
            frames_doc.append({"name": name, "case": exp.key, "status": "out of range" if bad else "matched",
                               "out_of_range": bad, "shift_px": made[0][4] if made else None,
                               "width_px": plain.width_px, "contrast": plain.contrast})
            if bad:
                say(f"stripebench predictcheck: {name}: out of range ({', '.join(bad)})")
                continue
            per = pf.transplant_outcomes(tr, made, laser=laser)
            for lab in tr:
                pred_rows.append({"name": name, "tracker": lab,
                                  **outcome_counts(np.concatenate(per[lab][:pf.N_FULL])), **pf.cut_counts(per[lab])})
            groups[name] = exp.key
            say(f"stripebench predictcheck: {name}: its stripe moved by {made[0][4]:+d} and {made[1][4]:+d} px "
                f"[case {e_i + 1}/{len(config.experiments)}]")
    predicted, measured = pd.DataFrame(pred_rows), pd.DataFrame(meas_rows)
    cases = compare_by_group(predicted, measured, groups) if pred_rows else {}
    pooled = compare_by_group(predicted, measured, {n: "all" for n in groups}) if pred_rows else {}
    # the false-report rate again on the stripe-less rows a photograph's reference scores
    distant = measured.assign(n_false=measured["n_false_far"], n_quiet=measured["n_quiet_far"])
    far = compare_by_group(predicted, distant, groups) if pred_rows else {}
    far_pooled = compare_by_group(predicted, distant, {n: "all" for n in groups}) if pred_rows else {}
    doc.update({"frames": frames_doc,
                "cases": {k: {**comparison_doc(v), FAR: comparison_doc(far[k])["false_report_rate"]}
                          for k, v in cases.items()},
                "pooled": {**comparison_doc(pooled["all"]), FAR: comparison_doc(far_pooled["all"])["false_report_rate"]}
                if pooled else None,
                "per_case": {**per_group_error(cases), FAR: per_group_error(far)["false_report_rate"]} if cases else None,
                "code": code_of_run()})
    atomic_write_text(outdir / "predict_check.json", json.dumps(doc, indent=1, default=float))
    atomic_write_text(outdir / "predicted.csv", predicted.to_csv(index=False))
    atomic_write_text(outdir / "measured.csv", measured.to_csv(index=False))
    _print_check(doc, cases, pooled, frames_doc, outdir)
    return 0


def _refuse_other_check(outdir: Path, doc: dict, force: bool) -> None:
    """Refuse (one :class:`bench.errors.ConfigError` line) to write into a folder holding a finished check of another
    configuration (:func:`check_identity`), unless ``force``."""
    from bench.errors import ConfigError, InputError
    from bench.store.textfiles import read_json

    path = outdir / "predict_check.json"
    if force or not path.exists():
        return
    try:
        old = read_json(path, "predictcheck result")
    except InputError:
        old = None
    if not isinstance(old, dict) or check_identity(old) != check_identity(doc):
        mine, theirs = check_identity(doc), check_identity(old) if isinstance(old, dict) else {}
        diff = next((k for k in _IDENTITY if mine.get(k) != theirs.get(k)), "the file")
        raise ConfigError(f"--out {str(outdir)!r} holds a finished check of another configuration ({diff}: "
                          f"{theirs.get(diff)!r} there, {mine.get(diff)!r} here); use --force to replace it")


def _print_check(doc, cases, pooled, frames_doc, outdir) -> None:
    """The check's table on stdout: per case and pooled, Spearman's rho and the mean |difference|."""
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


def code_of_run() -> dict:
    """What code a run was made by: ``revision`` (``git describe``, :func:`bench.store.provenance.git_revision`) and
    ``fingerprint``, a hash of the ``bench``, ``trackers`` and ``scenes`` source that ran
    (:func:`bench.store.provenance.source_fingerprint`): :func:`bench.studies.predict_score.paired` refuses two runs
    of the same code."""
    from bench.store.provenance import git_revision, source_fingerprint

    return {"revision": git_revision(), "fingerprint": source_fingerprint(("bench", "trackers", "scenes"))}


def scored_columns(image, truth_columns, states, truth: str = "render") -> np.ndarray:
    """The columns the measured side scores a case frame against (``truth``, :data:`TRUTHS`), shape (H,), px (NaN: no
    stripe): ``render``, ``truth_columns`` (the render's truth); ``reference``, the columns a photograph's reference
    would give (:func:`bench.evaluate.outcomes.referenced_columns` of ``image``), and in a row ``states`` calls a
    stripe row where the reference rule gives none (a clipped core in a glow, read as seen:
    :func:`bench.evaluate.rowstates.seen_states`, ``--rows clear``), the true column.

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
