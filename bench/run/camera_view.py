"""What a tracker sees of a rendered frame: the mono image, or one channel of a colour photograph.

A mono-camera frame (``scenes`` parameter ``camera = "mono"``) goes to the trackers as it is.
A colour-camera frame (``camera = "rgb"``) carries ``frame.rgb`` (and ``frame.rgb_background``);
the trackers get the 2-D image that ``stripebench track`` would make of the same photograph:
:func:`bench.evaluate.pixels.select_channel` with the same ``channel`` rule (default ``"auto"``) and the laser's
colour named from its wavelength (:func:`laser_colour`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["laser_colour", "tracker_images"]


def laser_colour(wavelength_nm: float) -> str:
    """``"blue"`` below 490 nm, ``"green"`` below 580 nm, else ``"red"`` (the name :func:`bench.evaluate.pixels.select_channel`
    takes).

    Examples
    --------
    >>> laser_colour(650.0), laser_colour(532.0), laser_colour(450.0)
    ('red', 'green', 'blue')
    """
    w = float(wavelength_nm)
    return "blue" if w < 490.0 else "green" if w < 580.0 else "red"


def tracker_images(frame, params=None, channel: str = "auto") -> tuple[np.ndarray, np.ndarray]:
    """The (image, background) pair a tracker gets from a :class:`scenes.Frame`.

    Parameters
    ----------
    frame : scenes.Frame
    params : mapping, optional
        The scene's parameters (``scene.params``); a colour frame needs its ``laser_wavelength_nm``
        (which names the laser's colour for ``channel``), a mono frame nothing.
    channel : str
        One of :data:`bench.store.realset.CHANNELS` (``"auto"``: the laser's channel minus the mean of the
        others on a colour photograph).

    Returns
    -------
    image, background : ndarray (H, W)
        ``frame.image`` and ``frame.background`` for a mono frame; for a colour frame
        :func:`bench.evaluate.pixels.select_channel` of ``frame.rgb`` and ``frame.rgb_background``
        (float64 for ``excess``/``gray``, uint8 for a plain channel).

    Raises
    ------
    ValueError
        A colour frame without ``params`` holding ``laser_wavelength_nm``; an unknown ``channel``.
    """
    from bench.evaluate.pixels import select_channel

    if getattr(frame, "rgb", None) is None:
        return frame.image, frame.background
    if params is None or "laser_wavelength_nm" not in params:
        raise ValueError("a colour frame needs the scene's `params` with `laser_wavelength_nm`, got "
                         f"{None if params is None else sorted(params)!r}")
    laser = laser_colour(params["laser_wavelength_nm"])
    return select_channel(frame.rgb, channel, laser), select_channel(frame.rgb_background, channel, laser)
