"""An example stripebench tracker plugin (see ``docs/plugins.md``).

>>> import numpy as np
>>> from trackers.testing import make_stripe_image
>>> image, true_cols = make_stripe_image(height=8, width=32, seed=0)
>>> track = ExamplePeakTracker().track(image)
>>> bool(np.nanmax(np.abs(track.columns - true_cols)) < 0.2)
True
"""

import numpy as np

from trackers import Real, Track, Tracker

__all__ = ["ExamplePeakTracker"]


class ExamplePeakTracker(Tracker):
    """Brightest pixel of each row, refined by a 3-point parabola.

    Parameters
    ----------
    min_contrast : float
        Rows whose peak rises less than this fraction of the frame's range
        (largest minus smallest value) above the row's median report no stripe:
        a rule in the frame's own units, so 8-bit, 16-bit and float frames alike.

    Score: the peak level (DN).
    """

    name = "example_peak"  # must equal the entry-point name
    subpixel = True

    def __init__(self, min_contrast=0.1):
        self.min_contrast = min_contrast  # stored unchanged: track() checks it against parameter_constraints

    parameter_constraints = {"min_contrast": Real(low=0, high=1)}  # a finite real in [0, 1]

    def find_stripe(self, image, background):
        img = image.astype(np.float64)
        H, W = img.shape
        rows = np.arange(H)
        peak = np.argmax(img, axis=1)
        level = img[rows, peak]
        left = img[rows, np.clip(peak - 1, 0, W - 1)]
        right = img[rows, np.clip(peak + 1, 0, W - 1)]
        denom = left - 2.0 * level + right
        with np.errstate(divide="ignore", invalid="ignore"):
            offset = np.where(denom < 0, 0.5 * (left - right) / denom, 0.0)
        inner = (peak > 0) & (peak < W - 1)
        cols = peak + np.where(inner, np.clip(offset, -0.5, 0.5), 0.0)
        found = (level - np.median(img, axis=1) >= self.min_contrast * np.ptp(img)) & (np.ptp(img) > 0)
        return Track(np.where(found, cols, np.nan), np.where(found, level, np.nan))
