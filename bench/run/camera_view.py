"""What a tracker sees of a rendered frame or a photograph: the mono image, or one channel of a colour photograph,
and the laser colour's evidence of a colour one.

A mono-camera frame (``scenes`` parameter ``camera = "mono"``) goes to the trackers as it is.
A colour-camera frame (``camera = "rgb"``) carries ``frame.rgb`` (and ``frame.rgb_background``);
the trackers get the 2-D image that ``stripebench track`` would make of the same photograph:
:func:`bench.evaluate.pixels.select_channel` with the same ``channel`` rule (default ``"auto"``) and the laser's
colour named from its wavelength (:func:`laser_colour`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["laser_colour", "tracker_images", "colour_of", "frame_colour"]


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


def colour_of(rgb, laser: str, rotate_deg: int = 0) -> np.ndarray | None:
    """The colour evidence a tracker gets with a colour photograph (:func:`trackers.colour_evidence`), turned
    as the tracker's frame is; None for no photograph or a grey one (three equal channels): the one home of what
    every run (renders, photographs, tuning frames) passes as ``colour``.

    Parameters
    ----------
    rgb : array_like, shape (H0, W0, 3), or None
        The photograph in its own orientation (DN).
    laser : {'red', 'green', 'blue'}
    rotate_deg : int
        The turn (counter-clockwise, degrees) that gives the tracker's frame.

    Returns
    -------
    ndarray of float64, shape (H, W), in [0, 1], or None

    Examples
    --------
    >>> px = np.zeros((2, 3, 3)); px[:, 1] = [200.0, 20.0, 20.0]
    >>> colour_of(px, "red", 90).shape, colour_of(px[..., 0], "red")
    ((3, 2), None)
    """
    if rgb is None:
        return None
    a = np.asarray(rgb)
    if a.ndim != 3 or (np.array_equal(a[..., 0], a[..., 1]) and np.array_equal(a[..., 0], a[..., 2])):
        return None
    from bench.evaluate.pixels import rotate_image
    from trackers import colour_evidence

    return rotate_image(colour_evidence(a, laser), rotate_deg)


def frame_colour(frame, params=None) -> np.ndarray | None:
    """The colour evidence of a rendered :class:`scenes.Frame` (:func:`colour_of` of ``frame.rgb``); None for a
    mono-camera frame."""
    if getattr(frame, "rgb", None) is None or params is None or "laser_wavelength_nm" not in params:
        return None
    return colour_of(frame.rgb, laser_colour(params["laser_wavelength_nm"]))
