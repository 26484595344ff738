"""Distractors in rendered frames: what photographs of real rigs hold in the rows where there is no stripe.

The scene parameter ``distractor`` (:data:`DISTRACTORS`, default ``"none"``: the frame as rendered) adds
one to a frame after its unit renders come from the cache (like laser power and ambient light, it is not
in the render cache key: the renders stay cached and cheap), before the sensor or the colour camera
(:func:`apply`), and, for an overlay, after it (:func:`draw`). Every distractor goes with a stripe that
starts or ends mid-frame: the laser's light is cut from a band of rows at the top or the
bottom (:func:`cut_rows`, 30-55 % of the height: the object is short and nothing behind it in range takes
the sheet; inter-reflected laser light in those rows is cut too), and the distractor stands mostly in
those rows:

``short``
    the cut alone;
``door_edge``
    a lit door edge: a sharp vertical edge, the light falling off over 8-40 px on one side, over the cut
    rows, and in half the frames the door frame's lit edge (a line 1-2 px wide); white light;
``lamp``
    a lamp: a clipping Gaussian blob (6-16 px), warm light;
``leds``
    two to four clusters of LED dots (1-2 px), one in four of the laser's own hue, the others green,
    blue or white; three in four clusters in the cut rows;
``window``
    a window: bright panes (clipping) with one or two dark mullions, daylight;
``sphere``
    a lit sphere in front of the scene (diffuse shading and a specular highlight from a lamp): it hides
    what is behind it, the stripe included;
``overlay``
    a grey frame drawn round the image (1-4 px, inset 0-12 px) and, in half the frames, a drawn line
    (nearly vertical, 1-2 px, grey), drawn on both the laser-on and the laser-off frame after capture;
    the rows under the frame's bars have no stripe either.

Levels are given in DN of the camera (the light the camera records, in band for the mono camera:
:func:`dn_radiance`), placements drawn from ``numpy.random.default_rng([seed, index, 0xD15])`` of the
scene's ``seed``: fixed in the image for every mirror angle of a scan. The truth follows: a row whose
stripe is cut, hidden by the sphere or under a drawn pixel has none (NaN column, no point).
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["DISTRACTORS", "Distractor", "build", "apply", "draw", "cut_rows", "dn_radiance", "band_index",
           "for_scene", "truth_without"]

DISTRACTORS = ("none", "short", "door_edge", "lamp", "leds", "window", "sphere", "overlay")
_TAG = 0xD15  # the placements' stream, apart from every other use of a scene's seed

# the distractors' colours, as (R, G, B) shares of their level (the mono camera sees the laser's channel)
_WHITE = np.ones(3)
_WARM = np.array([1.0, 0.8, 0.55])
_DAYLIGHT = np.array([0.9, 0.95, 1.0])
_LED = {"laser": None, "green": np.array([0.1, 1.0, 0.3]), "blue": np.array([0.15, 0.3, 1.0]), "white": _WHITE}


@dataclasses.dataclass(frozen=True)
class Distractor:
    """One frame's distractor, in the image's pixels.

    Attributes
    ----------
    kind : str
        One of :data:`DISTRACTORS`.
    light_dn : ndarray, shape (H, W, 3)
        Light added to the scene (both frames), per colour channel, in DN of the camera.
    hide : ndarray, shape (H, W), bool
        Pixels where the distractor stands in front of the scene: the scene's light (laser included) is
        replaced by ``light_dn`` there.
    cut : ndarray, shape (H,), bool
        Rows whose laser light is cut.
    drawn : list of (ndarray (H, W) bool, float)
        Pixels drawn on both frames after capture, and their grey level (DN).
    """

    kind: str
    light_dn: np.ndarray
    hide: np.ndarray
    cut: np.ndarray
    drawn: list

    def stripe_less(self, columns) -> np.ndarray:
        """Rows whose stripe the distractor removes: cut, or at a column (``columns`` (H,), px, NaN where
        none) hidden or drawn over; (H,) bool."""
        col = np.asarray(columns, float)
        H, W = self.hide.shape
        rows = np.arange(H)
        ok = np.isfinite(col)
        c = np.clip(np.rint(np.where(ok, col, 0)).astype(int), 0, W - 1)
        covered = self.hide[rows, c].copy()
        for mask, _ in self.drawn:
            covered |= mask[rows, c]
        return ok & (self.cut | covered)


def dn_radiance(sensor) -> float:
    """The in-band radiance that gives 1 DN on ``sensor`` (a :class:`scenes.sensor.SensorModel`), W m⁻² sr⁻¹."""
    return float(sensor.gain_e_per_dn / sensor.electrons_per_radiance)


def band_index(wavelength_nm: float) -> int:
    """The colour channel (0 R, 1 G, 2 B) of a laser's wavelength: blue below 490 nm, green below 580 nm,
    else red (the names :func:`bench.run.camera_view.laser_colour` gives)."""
    w = float(wavelength_nm)
    return 2 if w < 490.0 else 1 if w < 580.0 else 0


def for_scene(params: dict) -> Distractor | None:
    """The distractor of a scene's validated ``params`` (:func:`build` with its ``distractor``, ``seed``,
    size and laser colour); None for ``"none"``."""
    if params.get("distractor", "none") == "none":
        return None
    k = band_index(params["laser_wavelength_nm"])
    laser = np.full(3, 0.08)
    laser[k] = 1.0
    return build(params["distractor"], params["seed"], (params["height"], params["width"]), laser)


def truth_without(truth, d: Distractor | None):
    """A frame's :class:`scenes.frame.Truth` with the rows whose stripe ``d`` removes made stripe-less
    (NaN column and point, not on the object, part -1); as given without a distractor."""
    if d is None:
        return truth
    gone = d.stripe_less(truth.columns)
    if not gone.any():
        return truth
    cols = np.where(gone, np.nan, truth.columns)
    points = np.where(gone[:, None], np.nan, truth.points_cm)
    part = np.where(gone, -1, truth.part).astype(np.int8)
    return dataclasses.replace(truth, columns=cols, points_cm=points, on_object=truth.on_object & ~gone, part=part)


def cut_rows(rng, H: int) -> np.ndarray:
    """The rows whose laser light a distractor cuts: the top or the bottom 30-55 % of the height, (H,) bool."""
    n = int(rng.uniform(0.3, 0.55) * H)
    cut = np.zeros(H, bool)
    if rng.uniform() < 0.5:
        cut[:n] = True
    else:
        cut[H - n:] = True
    return cut


def _band(cut) -> tuple[int, int]:
    rows = np.nonzero(cut)[0]
    return int(rows[0]), int(rows[-1]) + 1


def _blob(H, W, cy, cx, rad):
    yy, xx = np.mgrid[0:H, 0:W]
    return np.exp(-((yy - cy) ** 2 + (xx - cx) ** 2) / (2.0 * rad * rad))


def build(kind: str, seed: int, shape: tuple[int, int], laser_rgb=(1.0, 0.08, 0.08)) -> Distractor | None:
    """The distractor ``kind`` of a scene with ``seed``, for frames of ``shape`` (H, W); None for ``"none"``.

    Parameters
    ----------
    kind : str
        One of :data:`DISTRACTORS`.
    seed : int
        The scene's seed (placements: ``default_rng([seed, index, 0xD15])``).
    shape : (int, int)
    laser_rgb : sequence of 3 floats
        The laser's colour as the colour camera sees it (an LED of "the laser's own hue" takes it).

    Examples
    --------
    >>> d = build("short", 0, (60, 64))
    >>> bool(d.cut.sum() >= 18 and (d.cut[0] or d.cut[-1])), float(d.light_dn.max())
    (True, 0.0)
    """
    if kind not in DISTRACTORS:
        raise ValueError(f"`distractor` must be one of {', '.join(DISTRACTORS)}, got {kind!r}")
    if kind == "none":
        return None
    H, W = shape
    rng = np.random.default_rng([int(seed), DISTRACTORS.index(kind), _TAG])
    light = np.zeros((H, W, 3))
    hide = np.zeros((H, W), bool)
    cut = cut_rows(rng, H)
    drawn: list = []
    a, b = _band(cut)
    if kind == "door_edge":
        x0 = rng.uniform(0.15, 0.85) * W
        side = rng.choice([-1.0, 1.0])
        d = side * (np.arange(W) - x0)
        edge = np.where(d >= 0, np.exp(-np.clip(d, 0, None) / rng.uniform(8, 40) * W / 512), 0.0)
        level = rng.uniform(80, 200)
        light[a:b] += level * edge[None, :, None] * _WHITE
        if rng.uniform() < 0.5:  # the door frame's lit edge
            xf = int(np.clip(x0 - side * rng.uniform(0.04, 0.12) * W, 2, W - 4))
            light[a:b, xf:xf + int(rng.integers(1, 3))] += rng.uniform(40, 120) * _WHITE
    elif kind == "lamp":
        g = _blob(H, W, rng.uniform(a, b), rng.uniform(0.1, 0.9) * W, rng.uniform(6, 16) * W / 512)
        light += rng.uniform(300, 800) * g[..., None] * _WARM
    elif kind == "leds":
        laser = np.asarray(laser_rgb, float)
        for _ in range(int(rng.integers(2, 5))):
            y = rng.uniform(a, b) if rng.uniform() < 0.75 else rng.uniform(0, H)
            x = rng.uniform(0.05, 0.95) * W
            hue = ("laser", "green", "blue", "white")[int(rng.integers(0, 4))]
            colour = laser if hue == "laser" else _LED[hue]
            step = rng.uniform(4, 10) * W / 512
            for i in range(int(rng.integers(1, 4))):
                for j in range(int(rng.integers(2, 5))):
                    dot = _blob(H, W, y + i * step, x + j * step, rng.uniform(0.8, 1.5) * W / 512)
                    light += rng.uniform(150, 400) * dot[..., None] * colour
    elif kind == "window":
        w = int(max(rng.uniform(0.12, 0.25) * W, 4))
        x0 = int(np.clip(rng.uniform(0.02, 0.98) * W - w / 2, 0, W - w))
        y0, y1 = a + int(0.1 * (b - a)), b - int(0.1 * (b - a))
        pane = np.zeros((H, W))
        pane[y0:y1, x0:x0 + w] = rng.uniform(250, 600)
        for _ in range(int(rng.integers(1, 3))):
            m = int(rng.uniform(x0 + 0.2 * w, x0 + 0.8 * w))
            pane[y0:y1, m:m + max(1, int(rng.integers(3, 7) * W / 512))] = 0.0
        hide |= pane > 0
        light += pane[..., None] * _DAYLIGHT
    elif kind == "sphere":
        rad = rng.uniform(0.1, 0.2) * H
        cy = float(np.clip(rng.uniform(a, b), rad, H - rad))
        cx = rng.uniform(0.2, 0.8) * W
        yy, xx = np.mgrid[0:H, 0:W]
        nx, ny = (xx - cx) / rad, (yy - cy) / rad
        inside = nx * nx + ny * ny < 1.0
        nz = np.sqrt(np.clip(1.0 - nx * nx - ny * ny, 0.0, None))
        lamp = np.array([rng.uniform(-0.8, 0.8), rng.uniform(-0.8, 0.2), 1.0])
        lamp /= np.linalg.norm(lamp)
        diffuse = np.clip(nx * lamp[0] + ny * lamp[1] + nz * lamp[2], 0.0, None)
        half = lamp + np.array([0.0, 0.0, 1.0])
        half /= np.linalg.norm(half)
        spec = np.clip(nx * half[0] + ny * half[1] + nz * half[2], 0.0, None) ** rng.uniform(40, 120)
        shade = np.where(inside, rng.uniform(120, 250) * diffuse + 600.0 * spec, 0.0)
        hide |= inside
        light += shade[..., None] * _WARM
    elif kind == "overlay":
        inset, thick = int(rng.integers(0, 13)), int(rng.integers(1, 5))
        frame = np.zeros((H, W), bool)
        frame[inset:H - inset, inset:inset + thick] = True
        frame[inset:H - inset, W - inset - thick:W - inset] = True
        frame[inset:inset + thick, inset:W - inset] = True
        frame[H - inset - thick:H - inset, inset:W - inset] = True
        drawn.append((frame, float(rng.uniform(60, 160))))
        if rng.uniform() < 0.5:
            x0 = rng.uniform(0.1, 0.9) * W
            slope = rng.uniform(-0.15, 0.15)
            y0, y1 = int(rng.uniform(0.0, 0.3) * H), int(rng.uniform(0.7, 1.0) * H)
            line = np.zeros((H, W), bool)
            rows = np.arange(y0, y1)
            xs = np.clip(np.rint(x0 + slope * (rows - y0)).astype(int), 0, W - 2)
            for k in range(int(rng.integers(1, 3))):
                line[rows, xs + k] = True
            drawn.append((line, float(rng.uniform(60, 200))))
    return Distractor(kind, light, hide, cut, drawn)


def apply(d: Distractor | None, laser: np.ndarray, ambient: np.ndarray, per_dn: np.ndarray):
    """The radiances of a frame with the distractor: ``(laser, ambient)`` as given (a new copy otherwise).

    Parameters
    ----------
    d : Distractor or None
    laser, ambient : ndarray, shape (H, W) or (H, W, 3)
        The laser's and the ambient light's radiance (mono, or per colour channel).
    per_dn : ndarray, shape (C,)
        The radiance of 1 DN per channel (mono: one value, the laser's channel's share of the light taken).

    Returns
    -------
    laser, ambient : ndarray of float32, the shapes given
        The laser's light cut from the cut rows and the hidden pixels; the ambient light replaced by the
        distractor's where it hides the scene, and its light added elsewhere.
    """
    if d is None:
        return laser, ambient
    mono = laser.ndim == 2
    lz = np.array(laser, np.float64, copy=True)
    am = np.array(ambient, np.float64, copy=True)
    lz[d.cut] = 0.0
    lz[d.hide] = 0.0
    if mono:
        extra = d.light_dn[..., 0] * float(per_dn[0])  # the mono camera behind its filter: the laser's (red) band
    else:
        extra = d.light_dn * np.asarray(per_dn, float)[None, None, :]
    am[d.hide] = 0.0
    am += extra
    return lz.astype(np.float32), am.astype(np.float32)


def draw(d: Distractor | None, image: np.ndarray) -> np.ndarray:
    """``image`` (H, W) or (H, W, 3) uint8 with the distractor's drawn pixels (a copy; as given without any)."""
    if d is None or not d.drawn:
        return image
    out = np.array(image, copy=True)
    for mask, grey in d.drawn:
        out[mask] = np.uint8(np.clip(np.rint(grey), 0, 255))
    return out
