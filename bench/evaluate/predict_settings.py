"""The tuned values of ``stripebench predict`` in one settings object, passed down to every rule that reads one.

:class:`PredictSettings` is a frozen dataclass: each field is one value with its unit and one line of why. The
prediction's functions take it as ``settings`` (default :data:`DEFAULT`); a prediction writes it into its
provenance (``predict.json``) and :meth:`PredictSettings.from_value` reads it back. docs/predict.md has the table.

Examples
--------
>>> s = PredictSettings(dim_share=0.25)
>>> PredictSettings.from_value(s.to_value()) == s, s.path_cap_k, DEFAULT.max_width_px
(True, 12.0, 13)
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields

from bench.evaluate.outcomes import REFERENCE_HALF_WIDTH

__all__ = ["PredictSettings", "DEFAULT"]


@dataclass(frozen=True)
class PredictSettings:
    """Every tuned value of the prediction (module docstring). Units in the names; the why beside each field."""

    # -- image conditions (bench.evaluate.conditions.measure) ------------------------------------------------------
    #: noise units: a row's stripe is visible when its peak stands this high over the row's median (as a reference)
    visible_k: float = 6.0
    #: px: adjacent visible rows whose peaks lie further apart make a jump (an object's edge, not a wobble)
    jump_px: float = 4.0
    #: px: pixels this near a row's argmax are the stripe's band, left out of the noise, texture and rivals
    band_px: int = 6
    #: px: the side of the square tiles the sensor noise is read in (flat patches of a frame)
    tile_px: int = 16
    #: percent: the tile whose noise is the sensor's (the flattest quarter of the frame)
    noise_percentile: float = 25.0
    #: DN: the least noise, an 8-bit frame's quantisation (1/sqrt(12))
    noise_floor_dn: float = 1.0 / math.sqrt(12.0)
    #: one unit of each measure in the conditions' distance (after its log10 or linear transform)
    condition_scales: tuple = (("contrast", 0.15), ("width_px", 0.12), ("saturated", 0.1), ("background", 0.05),
                               ("texture", 0.15), ("rival", 0.1), ("visible", 0.1), ("jumps", 0.05), ("gaps", 1.0),
                               ("laser_share", 0.1), ("noise_dn", 0.15))
    #: ratio: a stripe seems to run across the frame when, turned a quarter, its peaks jump this many times less often
    across_jumps: float = 2.0
    #: share: ... or when it is seen in under this share of the rows it is seen in turned (a note only)
    across_seen: float = 0.5
    #: ratio: another laser colour's excess shows the stripe at least this many times as clearly (a note only)
    other_laser_contrast: float = 2.0

    # -- the stripe estimate (bench.evaluate.stripe) ------------------------------------------------------------------
    #: noise units: the path's score is capped here, so a rival far brighter than the stripe counts no more than it
    path_cap_k: float = 12.0
    #: rows of a clear stripe: what the path pays to move more than 1 px between rows (an object's edge)
    path_jump: float = 2.0
    #: share of one clear row: all rows' tie-breaking brightness together, so only near-ties turn on it
    path_tie: float = 0.1
    #: px: the Gaussian the tie-break smooths each row with, so a clipped plateau's middle stands highest
    tie_sigma_px: float = 2.0
    #: rows: a path row guides only with ``support_min`` visible rows within this many either side (a stripe is a run)
    support_rows: int = 3
    #: rows: ... at least this many (itself included)
    support_min: int = 4
    #: rows: a row's guide is the median path column of the strong rows within this many either side
    guide_rows: int = 7
    #: px (FWHM): the argmax guide for stripes at most this wide (phone-like, thin), the path for wider ones
    auto_width_px: float = 3.0
    #: share of pixels: the argmax guide also where this many stand at the path's cap (a noiseless JPEG's walls)
    auto_capped: float = 0.12
    #: px: two guides of a row are weighed by the laser evidence within this distance (a guide is a median of peaks)
    arbiter_half_px: int = 2
    #: share of the typical evidence: a guide with less is no laser (a white lamp, a bar), where guides part or alone
    evidence_share: float = 0.2
    #: tracker frames of a colour photograph guided by the laser's colour: those that are its colour themselves
    colour_guided: tuple = ("auto", "excess")

    # -- the stripe's extent and centre (bench.evaluate.stripe.stripe_extents) -----------------------------------------
    #: noise units: the extent runs over the columns standing this high over the window's median
    edge_k: float = 2.0
    #: share of the peak's height: the extent reaches across a dip to a second hump this high (a split white core)
    dip_share: float = 0.5
    #: px: the extent is widened this much each side (the stripe's tails under ``edge_k``)
    pad_px: int = 2
    #: px: the most an extent reaches either side of its peak (a bloom or lit surface beyond stays in place)
    max_half_px: int = 30
    #: px: the centre is the centroid of the excess over half the peak within this distance of the peak
    centre_half_px: int = 3

    # -- the move (bench.evaluate.transplant) ------------------------------------------------------------------------
    #: px: the clean plate's line is anchored on the median of this many pixels either side of the extent
    side_px: int = 3
    #: px: the least shift, so a narrow stripe still moves clear of its old place
    min_shift_px: int = 12
    #: px: each direction's shift is sought this far beyond the least, to land on as few rivals as it can
    rival_search_px: int = 16
    #: share of the stripe's height: a pixel standing this high over its row is a rival (a tracker may take it)
    rival_share: float = 1.0
    #: noise units (at least 1 DN): a pixel this near the top counts as clipped and stays clipped when moved (JPEG)
    clip_noise_k: float = 2.0
    #: share of the visible span cut off each end in the false-report frames (stripe-less rows of the photograph)
    end_cut: float = 0.15
    #: rows: ... only where at least this many rows of the span stay moved
    end_cut_min_rows: int = 40
    #: rows: a photograph is predicted only where the moved stripe is seen in this many rows of its two moved frames
    min_rows: int = 10
    #: a photograph whose stripe is wider than the reference window is predicted shrunk by the least factor that
    #: brings it in range (a coarse answer, labelled so) rather than left out
    shrink_coarse: bool = True

    # -- reading the rows as a reference does (bench.evaluate.rowstates) --------------------------------------------------
    #: share of the typical height: a row standing lower is left out as unclear, as the shipped references leave it
    dim_share: float = 0.2
    #: share of the range's top: a clipped core in a glow this bright is a stripe row, as the references score it
    glow_share: float = 0.8
    #: px: the glow is read this far from the peak at least ...
    glow_near_px: int = 4
    #: px: ... and at most
    glow_far_px: int = 12

    # -- what predict states (bench.evaluate.predict_loro) -----------------------------------------------------------
    #: share: the intervals' nominal coverage (split conformal over the shipped rigs' errors): wide enough to hold most
    #: measured figures, narrow enough to tell a good tracker from a poor one (a tenth of F1)
    interval_level: float = 0.8
    #: share of draws: a tracker that is the best this often is tied with the pick (it may well be the best instead)
    tie_chance: float = 0.1
    #: draws of the photographs and a rig's errors behind the chance that the pick is best
    pick_draws: int = 1000

    @property
    def guide_half_px(self) -> int:
        """px: each row's stripe is sought this near its guide: the real set's reference window (one home,
        :data:`bench.evaluate.outcomes.REFERENCE_HALF_WIDTH`)."""
        return REFERENCE_HALF_WIDTH

    @property
    def max_width_px(self) -> float:
        """px (FWHM): a stripe wider than the reference window cannot be read by the reference rule: out of range."""
        return 2 * self.guide_half_px + 1

    @property
    def min_frame_px(self) -> tuple[int, int]:
        """(rows, columns): the least frame the estimate reads: its support window down the rows, 8 columns across."""
        return 2 * self.support_rows + 1, 8

    def scale(self, measure: str) -> float:
        """One unit of ``measure`` in the conditions' distance (:attr:`condition_scales`)."""
        return dict(self.condition_scales)[measure]

    def to_value(self) -> dict:
        """The settings as plain JSON data (tuples as lists), what a prediction's provenance holds."""
        out = asdict(self)
        return {k: [list(x) if isinstance(x, tuple) else x for x in v] if isinstance(v, tuple) else v
                for k, v in out.items()}

    @classmethod
    def from_value(cls, value) -> "PredictSettings":
        """The settings :meth:`to_value` wrote, checked: every field present, of its type; nothing else.

        Raises
        ------
        ValueError
            Not a mapping, a field missing or unknown, or a value of the wrong type.
        """
        if not isinstance(value, dict):
            raise ValueError(f"prediction settings must be a mapping, got {type(value).__name__}")
        names = [f.name for f in fields(cls)]
        extra, missing = sorted(set(value) - set(names)), [n for n in names if n not in value]
        if extra or missing:
            raise ValueError(f"prediction settings: unknown {extra}" if extra else
                             f"prediction settings: missing {missing}")
        out = {}
        for f in fields(cls):
            v, default = value[f.name], getattr(DEFAULT, f.name)
            if isinstance(default, tuple):
                if not isinstance(v, list):
                    raise ValueError(f"prediction settings: `{f.name}` must be a list, got {v!r}")
                v = tuple(tuple(x) if isinstance(x, list) else x for x in v)
            elif isinstance(default, bool):
                if not isinstance(v, bool):
                    raise ValueError(f"prediction settings: `{f.name}` must be true or false, got {v!r}")
            elif not isinstance(v, (int, float)) or isinstance(v, bool) or \
                    (isinstance(default, int) and not isinstance(v, int)) or not math.isfinite(v):
                raise ValueError(f"prediction settings: `{f.name}` must be a finite {type(default).__name__}, "
                                 f"got {v!r}")
            out[f.name] = v
        return cls(**out)


#: The settings ``stripebench predict`` runs with.
DEFAULT = PredictSettings()
