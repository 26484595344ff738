"""One colour per tracker label, for every figure, report and ``stripebench track`` overlay.

Fixed for the registered trackers, else a stable hash of the label (never its
position in a list, so a tracker keeps its colour whatever runs beside it). No
colour is black or white: overlays draw them on dimmed photographs.
"""

from __future__ import annotations

import hashlib

__all__ = ["TRACKER_COLOURS", "REFERENCE_COLOUR", "tracker_colour", "tracker_rgb"]

TRACKER_COLOURS = {
    "threshold": "#e000e0", "centroid": "#7f7f7f", "dp4": "#2ca02c", "dp8": "#17becf", "dp4_iso": "#98df8a",
    "dp8_iso": "#9edae5", "gauss3": "#ff7f0e", "parabolic": "#ffbb78", "blais_rioux": "#9467bd",
    "steger": "#8c564b", "com_bg": "#e377c2", "dp8_subpixel": "#1f77b4", "learned": "#5254a3",
    # the paper profile's other readings of the method without DP (bench/evaluate/readings.py)
    "threshold_gaps": "#595959", "argmax": "#d62728", "dp4_oneframe": "#006d2c", "dp_gap": "#bcbd22",
}
_PALETTE = ["#d62728", "#bcbd22", "#393b79", "#637939", "#8c6d31", "#843c39", "#7b4173", "#3182bd", "#e6550d",
            "#31a354", "#756bb1", "#636363"]
#: The colour of a photograph's reference columns in overlays.
REFERENCE_COLOUR = "#00c800"


def tracker_colour(label: str) -> str:
    """The colour of a tracker label as ``#rrggbb``.

    Examples
    --------
    >>> tracker_colour("dp4"), tracker_colour("my-tracker") == tracker_colour("my-tracker")
    ('#2ca02c', True)
    """
    if label in TRACKER_COLOURS:
        return TRACKER_COLOURS[label]
    return _PALETTE[int(hashlib.sha1(label.encode()).hexdigest(), 16) % len(_PALETTE)]


def tracker_rgb(label: str) -> tuple[int, int, int]:
    """:func:`tracker_colour` as an ``(r, g, b)`` tuple of 0..255 (for drawing on images).

    Examples
    --------
    >>> tracker_rgb("dp4")
    (44, 160, 44)
    """
    h = tracker_colour(label).lstrip("#")
    return int(h[0:2], 16), int(h[2:4], 16), int(h[4:6], 16)
