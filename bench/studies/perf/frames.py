"""A varied, seeded set of synthetic frames for speed benchmarks.

Every kind the DP solver finds hard or easy: a clean stripe, heavy noise,
long dim gaps and cuts, bright blobs beside the stripe, bright ambient
gradients, saturated wide stripes, two stripes, large sideways jumps of the
stripe (depth discontinuities), saturated specular streaks beside the
stripe (glints of the laser); at 512x480, 960x600, 960x540 and 360x640
(width x height; the last two are the sizes of the widest and the tallest
real photographs the solver was measured on).
"""

from __future__ import annotations

import numpy as np

__all__ = ["KINDS", "SIZES", "varied_frames"]

#: Frame kinds, in the order :func:`varied_frames` builds them.
KINDS = ("clean", "noisy", "gaps", "blobs", "gradient", "saturated", "two_stripes", "jumps", "streaks")
#: Frame sizes (height, width) in pixels.
SIZES = ((480, 512), (600, 960), (540, 960), (640, 360))


def _frame(kind: str, height: int, width: int, seed: int) -> np.ndarray:
    from trackers.testing import make_stripe_image, stripe_profile

    rng = np.random.default_rng(seed)
    bg = 6.0
    if kind == "jumps":  # the stripe jumps sideways by 1/8 to 1/4 of the width at 3 rows
        _, centre = make_stripe_image(height, width, seed=seed)
        shift = np.zeros(height)
        for r in np.sort(rng.integers(height // 8, height - height // 8, 3)):
            step = rng.uniform(width / 8, width / 4) * rng.choice([-1.0, 1.0])
            shift[r:] += step
        centre = np.clip(centre + shift - np.median(shift), 4.0, width - 5.0)
        img = bg + stripe_profile(centre, width, 1.5, 150.0) + rng.normal(0.0, 1.5, (height, width))
    elif kind == "saturated":
        img, _ = make_stripe_image(height, width, sigma_px=3.0, peak=700.0, background=bg, noise=1.5, seed=seed)
    else:
        noise = 8.0 if kind == "noisy" else 1.5
        peak = 60.0 if kind == "noisy" else 150.0
        img, _ = make_stripe_image(height, width, sigma_px=1.5, peak=peak, background=bg, noise=noise, seed=seed)
    img = img.astype(np.float64)
    yy, xx = np.mgrid[0:height, 0:width]
    if kind == "gaps":
        for _ in range(3):  # long dim stretches and cuts
            n = max(1, height // 8)
            a = int(rng.integers(0, max(1, height - n)))
            img[a : a + n] = bg + 0.05 * (img[a : a + n] - bg)
        n = max(1, min(15, height // 8))
        b = int(rng.integers(0, max(1, height - n)))
        img[b : b + n] = bg
    elif kind == "blobs":
        for _ in range(12):  # bright blobs (glints) anywhere
            cy, cx = rng.uniform(0, height), rng.uniform(0, width)
            r = rng.uniform(3, 15)
            img += 250.0 * np.exp(-((yy - cy) ** 2 + (xx - cx) ** 2) / (2 * r * r))
    elif kind == "gradient":  # a bright ambient ramp, brightest at one side
        angle = rng.uniform(0, 2 * np.pi)
        ramp = (np.cos(angle) * xx / width + np.sin(angle) * yy / height)
        img += 120.0 * (ramp - ramp.min()) / (np.ptp(ramp) + 1e-12)
    elif kind == "streaks":  # saturated vertical glints of the laser 10-40 px beside the stripe
        _, centre = make_stripe_image(height, width, seed=seed)
        for _ in range(4):
            n = int(rng.integers(max(2, height // 16), max(3, height // 5)))
            a = int(rng.integers(0, max(1, height - n)))
            side = rng.choice([-1.0, 1.0]) * rng.uniform(10.0, 40.0)
            c = np.clip(centre[a : a + n] + side, 0.0, width - 1.0)
            img[a : a + n] += stripe_profile(c, width, rng.uniform(1.0, 3.0), 600.0)
    elif kind == "two_stripes":
        other, _ = make_stripe_image(height, width, sigma_px=1.5, peak=150.0, background=0.0, noise=0.0,
                                     seed=seed + 1000)
        shift = int(rng.integers(width // 8, width // 4))
        img += np.roll(other.astype(np.float64), shift, axis=1)
    # the paper's unclear traces in every kind: a dimmed stretch
    if kind not in ("clean", "saturated"):
        n = max(1, min(40, height // 8))
        a = int(rng.integers(0, max(1, height - n)))
        img[a : a + n] = bg + 0.1 * (img[a : a + n] - bg)
    return np.clip(np.rint(img), 0, 255).astype(np.uint8)


def varied_frames(per_kind: int = 2, seed: int = 0, sizes=SIZES) -> list[tuple[str, np.ndarray]]:
    """``per_kind`` seeded 8-bit frames of every kind at every size.

    Parameters
    ----------
    per_kind : int, default 2
        Frames of each kind and size.
    seed : int, default 0
        Base seed; frame k of a kind and size uses ``seed + k`` and the
        kind's index, so the same seed gives the same frames.
    sizes : sequence of (height, width), default :data:`SIZES`

    Returns
    -------
    list of (label, image)
        ``label`` reads ``"<kind> <width>x<height>"``; images are uint8.

    Examples
    --------
    >>> frames = varied_frames(1, sizes=((48, 64),))  # 9 kinds
    >>> [label for label, _ in frames][:2], frames[0][1].shape
    (['clean 64x48', 'noisy 64x48'], (48, 64))
    """
    if isinstance(per_kind, bool) or not isinstance(per_kind, int) or per_kind < 1:
        raise ValueError(f"`per_kind` must be an integer >= 1, got {per_kind!r}")
    out = []
    for height, width in sizes:
        for ki, kind in enumerate(KINDS):
            for k in range(per_kind):
                out.append((f"{kind} {width}x{height}", _frame(kind, height, width, seed + 7919 * ki + k)))
    return out
