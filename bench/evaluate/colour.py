"""What a tracker sees of a colour photograph: the ``auto`` channel rule.

The colour excess (the laser's channel minus the mean of the other two)
removes white and grey light, but a stripe bright enough to clip the laser's
channel is white in its core ((255, 244, 230) for a red laser: the sensor's
other channels see the laser too) and coloured only on its flanks, so its
excess has a hole where the stripe is. The laser's channel alone keeps the
core but lets every bright white or warm surface compete.

:func:`saturation_blend` takes the excess where the laser's channel is well
below saturation and moves to the laser's channel as it approaches
saturation: with ``L`` the laser's channel, ``m`` the mean of the other two,
``S`` the saturation level and ``w = clip((L - knee S) / ((1 - knee) S), 0, 1)``,

    v = max(L - (1 - w) m, 0),

which is the excess ``L - m`` for ``L <= knee S`` and ``L`` at saturation,
continuous in between. The default :data:`AUTO_KNEE` was chosen by
``stripebench tune threshold`` (``bench/studies/tune_threshold.py``).
"""

from __future__ import annotations

import numpy as np

__all__ = ["AUTO_KNEE", "LASER_INDEX", "saturation_level", "saturation_blend"]

#: The knee of the ``auto`` rule, as a fraction of the saturation level
#: (chosen by ``stripebench tune threshold``).
AUTO_KNEE = 0.9
LASER_INDEX = {"red": 0, "green": 1, "blue": 2}


def saturation_level(image) -> float:
    """The value at which a pixel of ``image`` is clipped: the dtype's maximum
    for integer images (255 for 8 bit, 65535 for 16 bit), the largest value
    for float images (at least the smallest positive float).

    Examples
    --------
    >>> saturation_level(np.zeros((2, 2, 3), np.uint8)), saturation_level(np.array([[0.5, 2.0]]))
    (255.0, 2.0)
    """
    img = np.asarray(image)
    if img.dtype.kind in "ui":
        return float(np.iinfo(img.dtype).max)
    return max(float(np.max(img)) if img.size else 0.0, float(np.finfo(np.float64).tiny))


def saturation_blend(image, laser: str = "red", knee: float = AUTO_KNEE) -> np.ndarray:
    """The ``auto`` channel of a colour photograph (module docstring).

    Parameters
    ----------
    image : ndarray, shape (H, W, 3)
        RGB photograph in its own units (DN).
    laser : {'red', 'green', 'blue'}
    knee : float
        In [0, 1]: the fraction of the saturation level where the move from
        the excess to the laser's channel starts; 1: only clipped pixels take
        the laser's channel.

    Returns
    -------
    ndarray of float64, shape (H, W)

    Examples
    --------
    >>> px = np.array([[[255, 244, 230], [176, 7, 8], [120, 110, 100]]], np.uint8)  # core, flank, wall
    >>> saturation_blend(px, "red", 0.8).round(1).tolist()
    [[255.0, 168.5, 15.0]]
    """
    if laser not in LASER_INDEX:
        raise ValueError(f"`laser` must be one of {', '.join(LASER_INDEX)}, got {laser!r}")
    if isinstance(knee, bool) or not isinstance(knee, (int, float)) or not 0.0 <= knee <= 1.0:
        raise ValueError(f"`knee` must be a number in [0, 1], got {knee!r}")
    img = np.asarray(image)
    if img.ndim != 3 or img.shape[2] != 3:
        raise ValueError(f"`image` must have shape (H, W, 3), got {img.shape}")
    sat = saturation_level(img)
    f = img.astype(np.float64)
    k = LASER_INDEX[laser]
    others = [i for i in range(3) if i != k]
    L = f[..., k]
    m = 0.5 * (f[..., others[0]] + f[..., others[1]])
    if knee >= 1.0:
        w = (L >= sat).astype(np.float64)
    else:
        w = np.clip((L - knee * sat) / ((1.0 - knee) * sat), 0.0, 1.0)
    return np.maximum(L - (1.0 - w) * m, 0.0)

