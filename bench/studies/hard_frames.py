"""Seeded synthetic photographs of the frames that defeat frame-wide thresholds.

Built in numpy (no rendering), for the tuning procedures of
:mod:`bench.studies.tune_threshold` and the tests of the threshold-type trackers. Each
frame is an 8-bit RGB photograph of a scene with albedo ``a`` (H, W, 3) in
ambient light ``L`` (H, W, 3) and a laser line of colour ``c`` and profile
``P`` (a pixel-integrated Gaussian of the stripe's width around its centre in
each row)::

    I = clip(round(a * (L + A(r) * c * P) + noise), 0, 255)

where ``A(r)`` is the stripe's brightness along the rows (in DN on a white
surface) and the noise is Gaussian with variance ``read^2 + gain * I`` (read
and shot noise). The laser's colour has *crosstalk*: a red laser is
``c = (1, x, x)`` with ``x`` of 0.04-0.15, so a stripe bright enough to clip
the red channel turns white in its core and stays red on its flanks, as in
photographs. The stripe's column jumps at a few rows (object edges), and it
leaves the surface in a few stretches of rows (no stripe there: the truth is
NaN), each of one of the kinds of stripe-less row that real frames have
(:data:`VOIDS`):

``edge``
    the first or last rows of the frame: the stripe ran past an object's edge
    and the scene goes on without it;
``shadow``
    rows in the middle: the laser is occluded, the scene is unchanged;
``mirror``
    the surface reflects the laser away, and a blurred reflection of the stripe
    shows beside its path (a false stripe: a report there is a false one);
``dark``
    nothing behind: the rows are black but for the sensor's noise (the renders'
    void past the table's edge);
``textured``
    the stripe is gone and the surface there is strongly textured (print,
    foliage): bright pixels everywhere, none of them the stripe.

Kinds (:data:`KINDS`), the failure classes of real photographs:

``printed``
    a white board with dark print blocks and lines in bright room light; the
    stripe is faint against the white and vanishes on the print.
``noisy_floor``
    a floor with pixel-scale texture (carpet, concrete) in room light and a
    thin stripe.
``polished``
    a dark polished stone with veins, specular glints and a blurred mirror
    reflection of the stripe beside it.
``daylight``
    strong, coloured daylight brightening towards one side, over
    foliage-coloured or white surfaces; in half the frames a window that
    clips in the upper rows.
``noisy_sensor``
    a dim scene taken with heavy sensor noise.
``saturated_wide``
    a wide stripe that clips, with a glow around it and glints beside it, on a
    white glossy object.
``thin_faint``
    a thin, faint stripe in a dark room with a bright lamp in the frame.
``plain``
    the renders' easy case: a dark scene and a clear stripe.
``dim``
    the renders' hard case: an almost black scene (a few DN of ambient light,
    little noise, so the 8-bit frame is mostly one or two levels) and a stripe
    of a few to a few tens of DN, as on absorbing or patchy surfaces.

The distractor kinds (:data:`DISTRACTORS`): what photographs of real rigs hold in the rows where
there is no stripe. In each the stripe also starts or ends mid-frame (the object covers part of
the height), so a stretch of stripe-less rows faces the distractor:

``dark_room``
    a dark room lit through a door ajar: a lit door edge (a sharp vertical edge, the light falling
    off on one side) over the upper rows and, in half the frames, the door frame's lit edge (a thin
    bright line); the stripe on a short object low in the frame.
``lamps_leds``
    a dim room with a lamp (a clipping blob) and clusters of LED dots (1-3 px, some of the laser's
    own colour), most of them in the rows the stripe does not reach.
``window``
    a room with a window (bright panes, dark mullions, sharp edges) in the rows the stripe does not
    reach.
``skin``
    a hand beside the stripe (a shaded, skin-coloured region: bright in a red laser's channel),
    reaching into the rows past the stripe's end.
``short``
    a plain room and a stripe on a short object (35-65 % of the rows without it, above or below),
    with a table edge at the object's foot and faint print on the wall.
``overlay``
    a grey frame drawn round the image (1-4 px, inset by 0-12 px; in the laser-off frame too, as
    drawn on the recording) and, in half the frames, a drawn line: ridges of a stripe's width, grey,
    often brighter than the stripe; the rows under the frame's bars have no stripe.
``lit_sphere``
    a sphere lit by a lamp (diffuse shading and a specular highlight) beside the stripe and in the
    rows past its end; where the sphere hides the stripe there is none.

Examples
--------
>>> f = hard_frame("printed", seed=3)
>>> f.rgb.shape, f.rgb.dtype, f.laser, f.truth.shape
((300, 400, 3), dtype('uint8'), 'red', (300,))
>>> bool(np.isnan(f.truth).any() and np.isfinite(f.truth).any())
True
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage as ndi

from bench.evaluate.colour import LASER_INDEX
from bench.evaluate.outcomes import HIT_PX, hits

__all__ = ["KINDS", "DISTRACTORS", "VOIDS", "HardFrame", "hard_frame", "hard_frames", "argmax_right", "plateau_middles"]

#: The kinds that hold a distractor in stripe-less rows (see the module docstring); the last of :data:`KINDS`.
DISTRACTORS = ("dark_room", "lamps_leds", "window", "skin", "short", "overlay", "lit_sphere")
KINDS = ("printed", "noisy_floor", "polished", "daylight", "noisy_sensor", "saturated_wide", "thin_faint", "plain",
         "dim") + DISTRACTORS
#: The kinds of stripe-less stretch (see the module docstring).
VOIDS = ("edge", "shadow", "mirror", "dark", "textured")
_SIZES = ((240, 320), (300, 400), (480, 512))


@dataclass(frozen=True)
class HardFrame:
    """One synthetic photograph.

    Attributes
    ----------
    kind : str
        One of :data:`KINDS`.
    seed : int
    rgb : ndarray of uint8, shape (H, W, 3)
        The photograph.
    laser : str
        ``'red'`` or ``'green'``.
    truth : ndarray of float64, shape (H,)
        The stripe's centre per row (px, pixel-centre convention); NaN where
        the stripe is not on the surface.
    colour_background : bool
        Whether the surfaces are coloured (True) or grey/white (False).
    saturated : bool
        Whether the stripe clips the laser's channel in some row.
    rgb_off : ndarray of uint8, shape (H, W, 3)
        The laser-off frame of the same view (same scene, its own noise).
    """

    kind: str
    seed: int
    rgb: np.ndarray
    laser: str
    truth: np.ndarray
    colour_background: bool
    saturated: bool
    rgb_off: np.ndarray

    @property
    def laser_channel(self) -> np.ndarray:
        """The laser's colour channel, (H, W) uint8: the frame a mono camera behind a filter sees."""
        return np.ascontiguousarray(self.rgb[..., LASER_INDEX[self.laser]])

    @property
    def laser_channel_off(self) -> np.ndarray:
        """The laser's colour channel of the laser-off frame, (H, W) uint8."""
        return np.ascontiguousarray(self.rgb_off[..., LASER_INDEX[self.laser]])


def _stripe_path(rng, H: int, W: int) -> tuple[np.ndarray, np.ndarray, list]:
    """Centre per row (smooth wander, 0-2 jumps), the rows where the stripe is absent and
    the absent stretches ``(start, stop, void)`` (2-4 of them, kinds of :data:`VOIDS`)."""
    rows = np.arange(H)
    centre = W * rng.uniform(0.3, 0.7) + W * rng.uniform(0.03, 0.12) * np.sin(
        2 * np.pi * rows / H * rng.uniform(0.5, 1.5) + rng.uniform(0, 2 * np.pi))
    centre += rng.uniform(-0.05, 0.05) * W * (rows / H - 0.5)
    for _ in range(int(rng.integers(0, 3))):
        at = int(rng.integers(H // 6, H - H // 6))
        centre[at:] += rng.choice([-1, 1]) * rng.uniform(0.04, 0.2) * W
    centre = np.clip(centre, 0.08 * W, 0.92 * W)
    absent = np.zeros(H, bool)
    stretches = []
    voids = list(rng.permutation(len(VOIDS))[: int(rng.integers(2, 5))])
    for v in voids:
        n = int(rng.uniform(0.05, 0.12) * H)
        if VOIDS[v] == "edge":
            a = 0 if rng.uniform() < 0.5 else H - n
        else:
            a = int(rng.integers(n, H - 2 * n))
        absent[a:a + n] = True
        stretches.append((a, a + n, VOIDS[v]))
    return centre, absent, stretches


def _profile(centre, W: int, sigma: float) -> np.ndarray:
    from scipy.special import erf

    edges = np.arange(W + 1) - 0.5
    z = (edges[None, :] - centre[:, None]) / (np.sqrt(2.0) * sigma)
    return np.sqrt(2.0 * np.pi) * sigma * 0.5 * np.diff(erf(z), axis=1)


def _blobs(rng, H, W, n, r_lo, r_hi):
    yy, xx = np.mgrid[0:H, 0:W]
    out = np.zeros((H, W))
    for _ in range(n):
        cy, cx, rad = rng.uniform(0, H), rng.uniform(0, W), rng.uniform(r_lo, r_hi)
        out += np.exp(-((yy - cy) ** 2 + (xx - cx) ** 2) / (2 * rad * rad))
    return out


def _smooth_field(rng, H, W, scale):
    f = ndi.gaussian_filter(rng.normal(0, 1, (H, W)), scale, mode="reflect")
    return f / (f.std() + 1e-12)


@dataclass
class _Look:
    """A frame's surfaces and light before noise: what each kind sets (:data:`_LOOKS`)."""

    albedo: np.ndarray  # (H, W)
    ambient: np.ndarray  # (H, W) DN on white
    sigma: float  # the stripe's Gaussian width, px
    amp: float  # the stripe's brightness on white, DN
    read: float  # read noise, DN
    gain: float  # shot noise: variance gain x signal
    extra: np.ndarray  # (H, W) white light added on top of everything (glints, lamps), DN
    laser_extra: np.ndarray  # (H, W) laser light besides the stripe (glow, reflections), DN on white
    extra_rgb: np.ndarray | None = None  # (H, W, 3) coloured light added on top (LEDs, skin, lamps), DN
    draw: list = field(default_factory=list)  # (mask (H, W), grey level or RGB) drawn over both frames after capture


def _printed(s, rng, H, W, centre, absent) -> None:
    """The ``printed`` kind's surfaces, light and stripe (see the module docstring)."""
    s.albedo = np.full((H, W), 0.85)
    for _ in range(int(rng.integers(8, 25))):  # print blocks and lines
        h, w = int(rng.integers(2, H // 6)), int(rng.integers(2, W // 5))
        y, x = int(rng.integers(0, H - h)), int(rng.integers(0, W - w))
        s.albedo[y:y + h, x:x + w] = rng.uniform(0.05, 0.3)
    s.albedo = ndi.gaussian_filter(s.albedo, 0.7)
    s.ambient = rng.uniform(120, 200) * (1 + 0.1 * _smooth_field(rng, H, W, 40))
    s.amp = rng.uniform(40, 90)
    s.sigma = rng.uniform(0.9, 2.0)


def _noisy_floor(s, rng, H, W, centre, absent) -> None:
    """The ``noisy_floor`` kind's surfaces, light and stripe (see the module docstring)."""
    s.albedo = np.clip(0.5 + 0.12 * ndi.gaussian_filter(rng.normal(0, 1, (H, W)), 0.6) / 0.35
                       + 0.1 * _smooth_field(rng, H, W, 25), 0.05, 1.0)
    s.ambient = rng.uniform(80, 150) * np.ones((H, W))
    s.amp = rng.uniform(160, 320)
    s.sigma = rng.uniform(0.6, 1.1)
    s.read = 3.0


def _polished(s, rng, H, W, centre, absent) -> None:
    """The ``polished`` kind's surfaces, light and stripe (see the module docstring)."""
    veins = np.abs(_smooth_field(rng, H, W, 6))
    s.albedo = np.clip(0.25 + 0.1 * _smooth_field(rng, H, W, 30) + 0.25 * np.exp(-4 * veins)
                       + 0.03 * rng.normal(0, 1, (H, W)), 0.05, 1.0)
    s.ambient = rng.uniform(60, 140) * np.ones((H, W))
    s.amp = rng.uniform(200, 450)
    s.sigma = rng.uniform(1.0, 2.5)
    s.extra = 300.0 * _blobs(rng, H, W, int(rng.integers(2, 7)), 1.0, 3)
    shift = rng.choice([-1, 1]) * rng.uniform(8, 30)
    refl = 0.25 * _profile(centre + shift, W, 3 * s.sigma)  # the mirrored stripe, blurred
    s.laser_extra = s.amp * refl * (~absent)[:, None]


def _daylight(s, rng, H, W, centre, absent) -> None:
    """The ``daylight`` kind's surfaces, light and stripe (see the module docstring)."""
    yy, xx = np.mgrid[0:H, 0:W]
    ang = rng.uniform(0, 2 * np.pi)
    ramp = np.cos(ang) * xx / W + np.sin(ang) * yy / H
    ramp = (ramp - ramp.min()) / (np.ptp(ramp) + 1e-12)
    s.ambient = rng.uniform(60, 110) + rng.uniform(80, 160) * ramp
    s.albedo = np.clip(0.6 + 0.15 * _smooth_field(rng, H, W, 15), 0.1, 1.0)
    wx = int(rng.choice([0, W - W // 6]))  # a window at one side, clipping, in the upper rows (half the frames)
    wy = int(rng.uniform(0.1, 0.3) * H) if rng.uniform() < 0.5 else 0
    s.albedo[:wy, wx:wx + W // 6] = 1.0
    s.ambient[:wy, wx:wx + W // 6] = 400.0
    s.amp = rng.uniform(100, 200)
    s.sigma = rng.uniform(1.0, 2.5)
    s.read = 2.5


def _noisy_sensor(s, rng, H, W, centre, absent) -> None:
    """The ``noisy_sensor`` kind's surfaces, light and stripe (see the module docstring)."""
    s.albedo = np.clip(0.6 + 0.15 * _smooth_field(rng, H, W, 30), 0.2, 1.0)
    s.ambient = rng.uniform(20, 60) * np.ones((H, W))
    s.amp = rng.uniform(110, 190)
    s.sigma = rng.uniform(1.2, 2.2)
    s.read, s.gain = rng.uniform(8, 14), 0.3


def _saturated_wide(s, rng, H, W, centre, absent) -> None:
    """The ``saturated_wide`` kind's surfaces, light and stripe (see the module docstring)."""
    s.albedo = np.clip(0.85 + 0.08 * _smooth_field(rng, H, W, 20), 0.3, 1.0)
    s.ambient = rng.uniform(25, 70) * np.ones((H, W))
    s.amp = rng.uniform(700, 2500)
    s.sigma = rng.uniform(2.5, 5.0)
    glow = _profile(centre, W, rng.uniform(10, 20))
    s.laser_extra = 0.06 * s.amp * glow / glow.max() * (~absent)[:, None]
    near = np.zeros((H, W))
    yy, xx = np.mgrid[0:H, 0:W]
    for _ in range(int(rng.integers(3, 8))):  # glints within 40 px of the stripe
        r0 = int(rng.integers(0, H))
        cx = centre[r0] + rng.choice([-1, 1]) * rng.uniform(12, 40)
        near += np.exp(-((yy - r0) ** 2 + (xx - cx) ** 2) / (2 * rng.uniform(1.5, 3) ** 2))
    s.extra += 200.0 * near


def _thin_faint(s, rng, H, W, centre, absent) -> None:
    """The ``thin_faint`` kind's surfaces, light and stripe (see the module docstring)."""
    s.albedo = np.clip(0.6 + 0.1 * _smooth_field(rng, H, W, 20), 0.2, 1.0)
    s.ambient = rng.uniform(15, 40) * np.ones((H, W))
    s.amp = rng.uniform(50, 100)
    s.sigma = rng.uniform(0.5, 0.8)
    s.extra = 600.0 * _blobs(rng, H, W, 1, 6, 14)  # a lamp


def _plain(s, rng, H, W, centre, absent) -> None:
    """The ``plain`` kind's surfaces, light and stripe (see the module docstring)."""
    s.albedo = np.full((H, W), 0.8)
    s.ambient = np.full((H, W), rng.uniform(5, 20))
    s.amp = rng.uniform(120, 220)


def _dim(s, rng, H, W, centre, absent) -> None:
    """The ``dim`` kind's surfaces, light and stripe (see the module docstring)."""
    s.albedo = np.clip(0.6 + 0.15 * _smooth_field(rng, H, W, 30), 0.2, 1.0)
    s.ambient = np.full((H, W), rng.uniform(1.0, 5.0))
    s.amp = rng.uniform(4.0, 40.0)
    s.sigma = rng.uniform(0.7, 1.6)
    s.read, s.gain = rng.uniform(0.2, 0.6), 0.05


def _cut(rng, H, absent, lo: float, hi: float, top=None) -> int:
    """The stripe starts or ends mid-frame: the first (``top``) or last rows, a fraction in
    ``[lo, hi]`` of the height, lose it (in place); returns the row where it starts (or ends)."""
    n = int(rng.uniform(lo, hi) * H)
    top = bool(rng.uniform() < 0.5) if top is None else top
    if top:
        absent[:n] = True
        return n
    absent[H - n:] = True
    return H - n


def _rows_of(cut: int, H: int, absent) -> tuple[int, int]:
    """The stripe-less end of the frame that :func:`_cut` made: ``(start, stop)`` rows."""
    return (0, cut) if absent[0] else (cut, H)


def _dark_room(s, rng, H, W, centre, absent) -> None:
    """The ``dark_room`` kind (see the module docstring)."""
    s.albedo = np.clip(0.5 + 0.1 * _smooth_field(rng, H, W, 25), 0.1, 1.0)
    s.ambient = np.full((H, W), rng.uniform(2.0, 8.0))
    s.amp = rng.uniform(60, 160)
    s.sigma = rng.uniform(0.8, 1.8)
    cut = _cut(rng, H, absent, 0.3, 0.6, top=True)
    x0 = int(rng.uniform(0.15, 0.85) * W)
    side = rng.choice([-1, 1])
    d = side * (np.arange(W) - x0)
    band = np.where(d >= 0, np.exp(-np.clip(d, 0, None) / rng.uniform(8, 40)), 0.0)
    y1 = int(rng.uniform(0.8 * cut, cut + 0.3 * (H - cut)))  # the door's lit edge over the upper rows
    s.extra[:y1] += rng.uniform(60, 200) * band[None, :]
    if rng.uniform() < 0.5:  # the door frame's edge catching the light: a thin bright line
        xf = int(np.clip(x0 - side * rng.uniform(20, 60), 2, W - 4))
        s.extra[:y1, xf:xf + int(rng.integers(1, 3))] += rng.uniform(40, 120)


def _lamps_leds(s, rng, H, W, centre, absent) -> None:
    """The ``lamps_leds`` kind (see the module docstring)."""
    s.albedo = np.clip(0.5 + 0.1 * _smooth_field(rng, H, W, 25), 0.1, 1.0)
    s.ambient = np.full((H, W), rng.uniform(5.0, 20.0))
    s.amp = rng.uniform(80, 180)
    cut = _cut(rng, H, absent, 0.3, 0.5)
    a, b = _rows_of(cut, H, absent)
    yy, xx = np.mgrid[0:H, 0:W]
    cy, cx, rad = rng.uniform(a, b), rng.uniform(0.1, 0.9) * W, rng.uniform(6, 16)  # the lamp
    s.extra += rng.uniform(300, 800) * np.exp(-((yy - cy) ** 2 + (xx - cx) ** 2) / (2 * rad * rad))
    s.extra_rgb = np.zeros((H, W, 3))
    for _ in range(int(rng.integers(2, 5))):  # LED clusters, three in four in the stripe-less rows
        y = rng.uniform(a, b) if rng.uniform() < 0.75 else rng.uniform(0, H)
        x = rng.uniform(0.05, 0.95) * W
        hue = int(rng.integers(0, 4))  # the laser's own hue (red), green, blue, white
        colour = (np.array([1.0, 0.1, 0.08]), np.array([0.1, 1.0, 0.3]), np.array([0.15, 0.3, 1.0]),
                  np.ones(3))[hue]
        step = rng.uniform(4, 10)
        n_row, n_col = int(rng.integers(1, 4)), int(rng.integers(2, 5))
        for i in range(n_row):
            for j in range(n_col):
                r0 = rng.uniform(0.8, 1.5)
                dot = np.exp(-((yy - (y + i * step)) ** 2 + (xx - (x + j * step)) ** 2) / (2 * r0 * r0))
                s.extra_rgb += rng.uniform(150, 400) * dot[..., None] * colour[None, None, :]


def _window(s, rng, H, W, centre, absent) -> None:
    """The ``window`` kind (see the module docstring)."""
    s.albedo = np.clip(0.6 + 0.1 * _smooth_field(rng, H, W, 25), 0.2, 1.0)
    s.ambient = np.full((H, W), rng.uniform(20.0, 60.0))
    s.amp = rng.uniform(100, 200)
    cut = _cut(rng, H, absent, 0.3, 0.55)
    a, b = _rows_of(cut, H, absent)
    w = int(rng.uniform(0.12, 0.25) * W)
    x0 = int(rng.uniform(0.02, 0.98) * W - w / 2)
    x0 = int(np.clip(x0, 0, W - w))
    y0, y1 = a + int(0.1 * (b - a)), b - int(0.1 * (b - a))
    pane = np.zeros((H, W))
    pane[y0:y1, x0:x0 + w] = rng.uniform(250, 600)
    for _ in range(int(rng.integers(1, 3))):  # mullions
        m = int(rng.uniform(x0 + 0.2 * w, x0 + 0.8 * w))
        pane[y0:y1, m:m + int(rng.integers(3, 7))] = 0.0
    s.extra += pane


def _skin(s, rng, H, W, centre, absent) -> None:
    """The ``skin`` kind (see the module docstring)."""
    s.albedo = np.clip(0.4 + 0.1 * _smooth_field(rng, H, W, 25), 0.1, 1.0)
    s.ambient = np.full((H, W), rng.uniform(60.0, 140.0))
    s.amp = rng.uniform(120, 240)
    cut = _cut(rng, H, absent, 0.2, 0.4)
    a, b = _rows_of(cut, H, absent)
    yy, xx = np.mgrid[0:H, 0:W]
    side = rng.choice([-1, 1])
    cx = float(np.median(centre)) + side * rng.uniform(0.1, 0.2) * W  # beside the stripe
    cy = 0.5 * (a + b) + rng.uniform(-0.3, 0.3) * H
    ax, ay = rng.uniform(0.06, 0.14) * W, rng.uniform(0.2, 0.4) * H
    inside = ((xx - cx) / ax) ** 2 + ((yy - cy) / ay) ** 2
    shade = np.clip(1.0 - inside, 0.0, None) ** 0.3 * (1 + 0.15 * _smooth_field(rng, H, W, 8))
    skin = np.array([0.95, 0.62, 0.5]) * rng.uniform(0.5, 1.2) * float(np.median(s.ambient))
    s.extra_rgb = np.clip(shade, 0, None)[..., None] * skin[None, None, :]


def _short(s, rng, H, W, centre, absent) -> None:
    """The ``short`` kind (see the module docstring)."""
    s.albedo = np.clip(0.6 + 0.08 * _smooth_field(rng, H, W, 20), 0.2, 1.0)
    for _ in range(int(rng.integers(3, 10))):  # faint print on the wall
        h, w = int(rng.integers(2, 8)), int(rng.integers(10, W // 4))
        y, x = int(rng.integers(0, H - h)), int(rng.integers(0, W - w))
        s.albedo[y:y + h, x:x + w] *= rng.uniform(0.6, 0.9)
    s.ambient = np.full((H, W), rng.uniform(10.0, 40.0))
    s.amp = rng.uniform(50, 160)
    cut = _cut(rng, H, absent, 0.35, 0.65)
    obj = slice(cut, H) if absent[0] else slice(0, cut)  # the object, brighter than the wall: an edge at the cut
    s.albedo[obj] = np.clip(s.albedo[obj] * rng.uniform(1.1, 1.4), 0.0, 1.0)


def _overlay(s, rng, H, W, centre, absent) -> None:
    """The ``overlay`` kind (see the module docstring)."""
    s.albedo = np.clip(0.6 + 0.1 * _smooth_field(rng, H, W, 25), 0.2, 1.0)
    s.ambient = np.full((H, W), rng.uniform(5.0, 30.0))
    s.amp = rng.uniform(150, 300)
    _cut(rng, H, absent, 0.2, 0.4)
    inset, thick = int(rng.integers(0, 13)), int(rng.integers(1, 5))
    grey = float(rng.uniform(60, 160))
    frame = np.zeros((H, W), bool)
    frame[inset:H - inset, inset:inset + thick] = True
    frame[inset:H - inset, W - inset - thick:W - inset] = True
    frame[inset:inset + thick, inset:W - inset] = True
    frame[H - inset - thick:H - inset, inset:W - inset] = True
    absent[inset:inset + thick] = True  # the frame's bars hide the stripe
    absent[H - inset - thick:H - inset] = True
    s.draw.append((frame, grey))
    if rng.uniform() < 0.5:  # a drawn line, nearly vertical, on the side away from the stripe
        mid = float(np.median(centre))
        x0 = rng.uniform(0.6, 0.9) * W if mid < W / 2 else rng.uniform(0.1, 0.4) * W
        slope = rng.uniform(-0.15, 0.15)
        y0, y1 = int(rng.uniform(0.0, 0.3) * H), int(rng.uniform(0.7, 1.0) * H)
        line = np.zeros((H, W), bool)
        rows = np.arange(y0, y1)
        xs = np.clip(np.rint(x0 + slope * (rows - y0)).astype(int), 0, W - 2)
        width = int(rng.integers(1, 3))
        for k in range(width):
            line[rows, xs + k] = True
        hidden = np.zeros(H, bool)
        hidden[rows] = np.abs(xs - centre[rows]) < 4  # where it crosses the stripe, it hides it
        absent |= hidden
        s.draw.append((line, float(rng.uniform(60, 200))))


def _lit_sphere(s, rng, H, W, centre, absent) -> None:
    """The ``lit_sphere`` kind (see the module docstring)."""
    s.albedo = np.clip(0.5 + 0.1 * _smooth_field(rng, H, W, 25), 0.1, 1.0)
    s.ambient = np.full((H, W), rng.uniform(20.0, 60.0))
    s.amp = rng.uniform(80, 180)
    cut = _cut(rng, H, absent, 0.25, 0.5)
    a, b = _rows_of(cut, H, absent)
    rad = rng.uniform(0.1, 0.2) * H
    cy = float(np.clip(rng.uniform(a, b), rad, H - rad))
    side = rng.choice([-1, 1])
    cx = float(np.clip(float(np.median(centre)) + side * rng.uniform(0.5, 1.5) * rad, rad, W - rad))
    yy, xx = np.mgrid[0:H, 0:W]
    nx, ny = (xx - cx) / rad, (yy - cy) / rad
    inside = nx * nx + ny * ny < 1.0
    nz = np.sqrt(np.clip(1.0 - nx * nx - ny * ny, 0.0, None))
    light = np.array([rng.uniform(-0.8, 0.8), rng.uniform(-0.8, 0.2), 1.0])
    light /= np.linalg.norm(light)
    diffuse = np.clip(nx * light[0] + ny * light[1] + nz * light[2], 0.0, None)
    half = light + np.array([0.0, 0.0, 1.0])
    half /= np.linalg.norm(half)
    spec = np.clip(nx * half[0] + ny * half[1] + nz * half[2], 0.0, None) ** rng.uniform(40, 120)
    sphere = np.where(inside, rng.uniform(120, 250) * diffuse + 600.0 * spec, 0.0)
    s.albedo = np.where(inside, 0.0, s.albedo)  # the sphere hides what is behind it
    s.extra += sphere
    rows = np.arange(H)
    c = np.clip(np.rint(centre).astype(int), 0, W - 1)
    absent |= inside[rows, c]  # the stripe behind the sphere is hidden


#: Each kind's look, applied to the defaults in :func:`hard_frame` (the draws in this order).
_LOOKS = {"printed": _printed, "noisy_floor": _noisy_floor, "polished": _polished, "daylight": _daylight,
          "noisy_sensor": _noisy_sensor, "saturated_wide": _saturated_wide, "thin_faint": _thin_faint,
          "plain": _plain, "dim": _dim, "dark_room": _dark_room, "lamps_leds": _lamps_leds, "window": _window,
          "skin": _skin, "short": _short, "overlay": _overlay, "lit_sphere": _lit_sphere}


def hard_frame(kind: str, seed: int, *, colour_background: bool | None = None) -> HardFrame:
    """One seeded synthetic photograph of ``kind`` (see the module docstring).

    Parameters
    ----------
    kind : str
        One of :data:`KINDS`.
    seed : int
        Seed (>= 0); every random choice (size, laser, surfaces, path, noise) follows from it.
    colour_background : bool, optional
        Force coloured (True) or grey/white (False) surfaces; by default the seed chooses.

    Returns
    -------
    HardFrame
    """
    if kind not in KINDS:
        raise ValueError(f"`kind` must be one of {', '.join(KINDS)}, got {kind!r}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"`seed` must be an integer >= 0, got {seed!r}")
    rng = np.random.default_rng([KINDS.index(kind), int(seed)])
    H, W = _SIZES[int(rng.integers(0, len(_SIZES)))]
    laser = "green" if rng.uniform() < 0.35 else "red"
    k = LASER_INDEX[laser]
    coloured = bool(rng.uniform() < 0.5) if colour_background is None else bool(colour_background)
    centre, absent, stretches = _stripe_path(rng, H, W)
    rows = np.arange(H)
    tint = np.ones(3)
    if coloured:  # a surface colour: the laser's own hue, or a warm or foliage-like one
        choice = int(rng.integers(0, 3))
        tint = (np.array([1.0, 0.35, 0.3]) if choice == 0 else np.array([1.0, 0.8, 0.55]) if choice == 1
                else np.array([0.35, 0.8, 0.35]))
    s = _Look(albedo=np.ones((H, W)), ambient=np.full((H, W), 20.0), sigma=rng.uniform(1.0, 2.0),
              amp=rng.uniform(80, 160), read=1.5, gain=0.05, extra=np.zeros((H, W)), laser_extra=np.zeros((H, W)))
    _LOOKS[kind](s, rng, H, W, centre, absent)
    albedo, ambient, sigma, amp, read, gain, extra, laser_extra = (s.albedo, s.ambient, s.sigma, s.amp, s.read,
                                                                    s.gain, s.extra, s.laser_extra)
    for a, b, void in stretches:  # what the stripe-less stretches show instead of the stripe
        if void == "mirror":
            shift = rng.choice([-1, 1]) * rng.uniform(10, 60)
            ghost = rng.uniform(0.2, 0.6) * amp * _profile(centre[a:b] + shift, W, rng.uniform(1.5, 4.0) * sigma)
            laser_extra[a:b] += ghost
        elif void == "dark":
            albedo[a:b] = 0.0
            extra[a:b] = 0.0
        elif void == "textured":
            level = float(np.median(ambient[a:b]))
            tex = np.clip(0.5 + 0.35 * ndi.gaussian_filter(rng.normal(0, 1, (b - a, W)), rng.uniform(0.6, 2.0))
                          / 0.3, 0.02, 1.0)
            albedo[a:b] = tex
            ambient[a:b] = max(level, 40.0) * rng.uniform(1.0, 2.5)
    along = amp * np.clip(1 + 0.35 * np.sin(2 * np.pi * rows / H * rng.uniform(0.3, 1.2) + rng.uniform(0, 6)),
                          0.3, None)
    if kind == "saturated_wide":
        along = np.maximum(along, 400.0)
    prof = along[:, None] * _profile(centre, W, sigma) * (~absent)[:, None] + laser_extra
    cross = rng.uniform(0.04, 0.15)
    colour = np.full(3, cross)
    colour[k] = 1.0
    a3 = albedo[..., None] * tint[None, None, :]
    def shoot(clean):
        noisy = clean + rng.normal(0, 1, clean.shape) * np.sqrt(read ** 2 + gain * np.clip(clean, 0, None))
        return np.clip(np.rint(noisy), 0, 255).astype(np.uint8)

    off = a3 * ambient[..., None] + extra[..., None]
    if s.extra_rgb is not None:
        off = off + s.extra_rgb
    rgb = shoot(off + a3 * prof[..., None] * colour[None, None, :])
    rgb_off = shoot(off)
    for mask, value in s.draw:  # drawn on the recording: the same pixels in both frames
        rgb[mask] = np.clip(np.rint(value), 0, 255)
        rgb_off[mask] = np.clip(np.rint(value), 0, 255)
    truth = np.where(absent, np.nan, centre)
    saturated = bool((rgb[..., k][~absent] == 255).any()) if (~absent).any() else False
    return HardFrame(kind, int(seed), rgb, laser, truth, coloured, saturated, rgb_off)


def hard_frames(kinds=KINDS, seeds=range(4)) -> list[HardFrame]:
    """:func:`hard_frame` for every kind and seed (kinds outer)."""
    return [hard_frame(kd, int(s)) for kd in kinds for s in seeds]


def argmax_right(frame: np.ndarray, truth, tol_px: float = HIT_PX) -> float:
    """Fraction of the stripe rows (finite ``truth``) whose brightest pixel lies within ``tol_px`` of it.

    The brightest pixel of a row whose maximum is a plateau (clipped) is the
    plateau's middle (:func:`plateau_middles`).

    Examples
    --------
    >>> argmax_right(np.array([[0, 9, 0, 0, 0, 0], [9, 0, 0, 0, 0, 0]]), [1.0, 5.0])
    0.5
    """
    f = np.asarray(frame)
    t = np.asarray(truth, float)
    ok = np.isfinite(t)
    if not ok.any():
        return float("nan")
    cols = plateau_middles(f)
    return float(np.mean(hits(cols[ok], t[ok], tol_px)))


def plateau_middles(frame) -> np.ndarray:
    """Per row, the middle ``(lo + hi) // 2`` of the run of equal maxima around the leftmost maximum, (H,) int.

    Examples
    --------
    >>> plateau_middles(np.array([[0, 9, 9, 9, 0, 9]])).tolist()
    [2]
    """
    f = np.asarray(frame)
    H, W = f.shape
    left = np.argmax(f, axis=1)
    top = f[np.arange(H), left]
    out = left.copy()
    for r in range(H):
        hi = left[r]
        while hi + 1 < W and f[r, hi + 1] == top[r]:
            hi += 1
        out[r] = (left[r] + hi) // 2
    return out
