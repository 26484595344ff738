"""Compile the trackers' and the renderer's kernels once, into their on-disk caches (``scripts/setup.sh`` runs it).

The trackers: every listed tracker tracks small synthetic frames through :func:`bench.run.track.track_frame`
(read-only views, as every run hands them) in each kind of frame a run gives it: an 8-bit mono render with and
without its laser-off frame, and a photograph's frame as ``auto`` makes it (float64) or as a plain channel makes it
(8-bit), with its colour evidence, with and without a laser-off frame; the compiled forms are cached beside their
source (numba's ``cache=True``). The renderer: the ``paper`` profile's experiments, two angles each at the profile's
size (Dr.Jit's kernels depend on it), into a temporary render cache and run folder, so that Dr.Jit's kernel cache
(``~/.drjit``) holds their kernels. Matplotlib's font cache is built too. A run's first frames then do not wait for
the compilers: an installation step, as building an extension is. Safe to run again (what is cached loads in
milliseconds); ``--trackers-only`` skips the renderer.
Prints one line.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def frames():
    """``(image, background, colour)`` triples of the kinds a run hands a tracker."""
    rng = np.random.default_rng(0)
    H, W = 48, 64
    x = np.arange(W)
    on = rng.normal(20.0, 2.0, (H, W))
    on[8:40] += 120.0 * np.exp(-0.5 * ((x - 30.0) / 1.2) ** 2)   # a stripe in rows 8-39, none above or below
    off = rng.normal(20.0, 2.0, (H, W))
    u8, u8_off = np.clip(on, 0, 255).astype(np.uint8), np.clip(off, 0, 255).astype(np.uint8)
    f64, f64_off = on.astype(np.float64), off.astype(np.float64)
    colour = np.zeros((H, W))
    colour[8:40, 28:33] = 0.9
    return [(u8, u8_off, None), (u8, None, None), (f64, f64_off, colour), (f64, None, colour), (f64, None, None),
            (u8, None, colour), (u8, u8_off, colour)]


def renderer_kernels() -> int:
    """Render the ``paper`` profile's experiments, two angles each, into a temporary render cache and run folder;
    returns the number of experiments."""
    import os
    import tempfile

    from bench.config import loading
    from bench.run import experiment
    from scenes.cache import ENV_CACHE_DIR

    config = loading.profile("paper")
    d = config.to_dict()
    # two trackers (one of them reads the laser-off frame, so that it is rendered as in a run) and few samples: the
    # harness's own work is not what is being compiled
    small = loading.with_overrides(config, real_set="", trackers=["threshold", "dp4"], baselines=["threshold"],
                                   dp=["dp4"], n_boot=10, n_samples=10,
                                   experiments=[{**e, "n_angles": 2} for e in d["experiments"]])
    old = os.environ.get(ENV_CACHE_DIR)
    with tempfile.TemporaryDirectory(prefix="stripebench-kernels-") as tmp:
        os.environ[ENV_CACHE_DIR] = os.path.join(tmp, "renders")
        try:
            experiment.run(small, os.path.join(tmp, "run"), progress=False, quiet=True)
        finally:
            if old is None:
                os.environ.pop(ENV_CACHE_DIR, None)
            else:
                os.environ[ENV_CACHE_DIR] = old
    return len(d["experiments"])


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--trackers-only", action="store_true", help="compile the trackers' kernels only")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    import trackers
    from bench.run.track import track_frame

    names = trackers.available()
    for name in names:
        t = trackers.make(name)
        for image, background, colour in frames():
            track_frame(t, image, background, colour)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot  # noqa: F401  (builds the font cache on a new machine)

    what = f"{len(names)} trackers"
    if not args.trackers_only:
        what += f" and the renderer on {renderer_kernels()} experiments"
    print(f"compile_kernels: {what} compiled and cached in {time.perf_counter() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
