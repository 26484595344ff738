"""Speed of every registered tracker on 512x480 frames (``stripebench perf``).

For each tracker: the median time of ``track()`` per frame over the same
frames, and the time of its first call in a fresh process (numba's JIT
compile, measured with an empty cache, and the load from the on-disk cache)
reported separately. On the same frames and in the same run, skimage's
``MCP_Geometric`` solves the same graph (node cost ``1/(I+1)``, edge cost the
mean of the two node costs times the step length, all top-row starts, all
bottom-row ends, then the traceback): ``dp4`` is compared with its
4-connected run and ``dp8`` with its 8-connected run.

The frames are synthetic (seeded): a Gaussian stripe wandering across the
frame with a dim stretch and a cut, 400-lux-like background and noise; or
your own frames with ``--frames`` (``.npy`` or 8-bit PNG files); or the
photographs of a real set with ``--real [DIR]`` (default: the shipped set,
frames as the trackers see them there, of mixed sizes).
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import time

import numpy as np

__all__ = ["synthetic_frames", "time_trackers", "time_mcp", "first_call_seconds", "main"]

TARGETS = {"ratio_dp": 100.0, "threshold_ms": 0.5, "centroid_ms": 0.5}
#: Upper bounds in ms per frame on 512x480 frames.
MS_TARGETS = {"threshold": 0.5, "centroid": 0.5, "gauss3": 1.0, "parabolic": 1.0, "blais_rioux": 1.0, "com_bg": 1.0,
              "steger": 20.0}
#: Upper bounds as multiples of another tracker's time in the same run.
RATIO_TARGETS = {"dp8_subpixel": ("dp8", 1.5)}


def synthetic_frames(n: int = 6, height: int = 480, width: int = 512, seed: int = 0) -> list[np.ndarray]:
    """``n`` seeded 8-bit frames with one stripe each, dimmed over a stretch
    and cut over a few rows (the paper's unclear traces)."""
    from trackers.testing import make_stripe_image

    frames = []
    rng = np.random.default_rng(seed)
    for k in range(n):
        img, _ = make_stripe_image(height, width, sigma_px=1.5, peak=150.0, background=6.0, noise=1.5, seed=seed + k)
        img = img.astype(np.float64)
        a = int(rng.integers(0, height - 80))
        img[a : a + 60] = 6.0 + 0.08 * (img[a : a + 60] - 6.0)
        b = int(rng.integers(0, height - 10))
        img[b : b + 6] = 6.0
        frames.append(np.clip(np.rint(img), 0, 255).astype(np.uint8))
    return frames


def _median_ms(fn, frames, repeats: int) -> float:
    for f in frames[:1]:
        fn(f)  # warm: JIT and caches
    times = []
    for _ in range(repeats):
        for f in frames:
            t0 = time.perf_counter()
            fn(f)
            times.append(time.perf_counter() - t0)
    return 1e3 * float(np.median(times))


def time_trackers(names, frames, repeats: int = 5) -> dict[str, float]:
    """Median milliseconds per frame of ``track()`` for each tracker name."""
    import trackers

    out = {}
    for name in names:
        tracker = trackers.make(name)
        out[name] = _median_ms(tracker.track, frames, repeats)
    return out


def time_mcp(frames, connectivity: int, repeats: int = 1) -> float:
    """Median milliseconds per frame of skimage MCP_Geometric on the DP graph."""
    from skimage.graph import MCP_Geometric

    def solve(img):
        cost = 1.0 / (img.astype(np.float64) + 1.0)
        H, W = cost.shape
        m = MCP_Geometric(cost, fully_connected=connectivity == 8)
        costs, _ = m.find_costs([(0, j) for j in range(W)], [(H - 1, j) for j in range(W)])
        return m.traceback((H - 1, int(np.argmin(costs[-1]))))

    return _median_ms(solve, frames, repeats)


def first_call_seconds(name: str, cache_dir: str | None) -> float:
    """Seconds of the first ``track()`` in a fresh process (JIT or cache load).

    ``cache_dir=None`` uses the normal numba cache; a path uses that
    directory as numba's cache (an empty one measures a cold compile).
    """
    code = (
        "import time, numpy as np, trackers\n"
        f"t = trackers.make({name!r}); img = np.zeros((48, 64), np.uint8); img[:, 30] = 200\n"
        "t0 = time.perf_counter(); t.track(img); print(time.perf_counter() - t0)\n"
    )
    env = dict(os.environ)
    if cache_dir is not None:
        env["NUMBA_CACHE_DIR"] = cache_dir
    root = pathlib.Path(__file__).resolve().parents[2]
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=root, check=True)
    return float(out.stdout.strip().splitlines()[-1])


def _load_frames(paths) -> list[np.ndarray]:
    frames = []
    for p in paths:
        p = pathlib.Path(p)
        if p.suffix == ".npy":
            frames.append(np.load(p))
        else:
            from skimage.io import imread

            img = imread(p)
            frames.append(img if img.ndim == 2 else img[..., 0])
    return frames


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="stripebench perf", description=__doc__.split("\n\n")[0])
    parser.add_argument("--trackers", help="comma-separated tracker names (default: all registered)")
    parser.add_argument("--frames", nargs="+", metavar="FILE", help="time on these frames (.npy or PNG)")
    parser.add_argument("--real", nargs="?", const="", metavar="DIR",
                        help="time on the frames of a real set (default: the shipped bench/data/real)")
    parser.add_argument("--n-frames", type=int, default=6, help="synthetic frames (default 6)")
    parser.add_argument("--repeats", type=int, default=5, help="passes over the frames (default 5)")
    parser.add_argument("--no-jit", action="store_true", help="skip the first-call (JIT) measurements")
    parser.add_argument("--json", metavar="FILE", help="also write the figures as JSON")
    args = parser.parse_args(argv)

    import trackers

    names = trackers.available() if not args.trackers else [n.strip() for n in args.trackers.split(",") if n.strip()]
    for n in names:
        if n not in trackers.available():
            parser.error(f"unknown tracker {n!r}; available: {', '.join(trackers.available())}")
    if args.n_frames < 1 or args.repeats < 1:
        parser.error("--n-frames and --repeats must be >= 1")
    if args.frames and args.real is not None:
        parser.error("give --frames or --real, not both")
    if args.real is not None:
        from .. import real

        try:
            frames = [im.load()[0] for im in real.load_dataset(args.real or real.SHIPPED)]
        except real.DatasetError as exc:
            parser.error(f"--real: {exc}")
    else:
        frames = _load_frames(args.frames) if args.frames else synthetic_frames(args.n_frames)
    shape = frames[0].shape
    sizes = "mixed sizes, first " if len({f.shape for f in frames}) > 1 else ""
    print(f"stripebench perf: {len(frames)} frame(s) of {sizes}{shape[1]}x{shape[0]}, {args.repeats} pass(es), "
          f"median ms per frame (numba threads: 1 process, {os.cpu_count()} cores)", flush=True)

    ms = time_trackers(names, frames, args.repeats)
    mcp = {4: time_mcp(frames, 4), 8: time_mcp(frames, 8)}
    jit = {}
    if not args.no_jit:
        with tempfile.TemporaryDirectory() as empty:
            for n in names:
                jit[n] = (first_call_seconds(n, os.path.join(empty, n)), first_call_seconds(n, None))

    rows = []
    for n in names:
        conn = 4 if n == "dp4" else 8 if n == "dp8" else None
        ratio = mcp[conn] / ms[n] if conn else None
        rows.append({"tracker": n, "ms_per_frame": ms[n], "mcp_ms": mcp[conn] if conn else None, "speedup_vs_mcp": ratio,
                     "first_call_cold_s": jit.get(n, (None, None))[0], "first_call_cached_s": jit.get(n, (None, None))[1]})
    print(f"{'tracker':<14}{'ms/frame':>10}{'MCP ms':>10}{'x MCP':>9}{'1st call cold s':>17}{'1st call cached s':>19}")
    for r in rows:
        f = lambda v, spec: format(v, spec) if v is not None else "-"  # noqa: E731
        print(f"{r['tracker']:<14}{r['ms_per_frame']:>10.3f}{f(r['mcp_ms'], '.1f'):>10}{f(r['speedup_vs_mcp'], '.0f'):>9}"
              f"{f(r['first_call_cold_s'], '.2f'):>17}{f(r['first_call_cached_s'], '.2f'):>19}")
    print(f"MCP_Geometric on the same frames: {mcp[4]:.1f} ms (4-connected), {mcp[8]:.1f} ms (8-connected)")
    verdicts = []
    for r in rows:
        if r["speedup_vs_mcp"] is not None:
            ok = r["speedup_vs_mcp"] >= TARGETS["ratio_dp"]
            verdicts.append(f"{r['tracker']} {r['speedup_vs_mcp']:.0f}x MCP (target >= 100x): {'met' if ok else 'MISSED'}")
        limit = MS_TARGETS.get(r["tracker"])
        if limit is not None:
            ok = r["ms_per_frame"] < limit
            verdicts.append(f"{r['tracker']} {r['ms_per_frame']:.3f} ms (target < {limit:g} ms): "
                            f"{'met' if ok else 'MISSED'}")
        ref, factor = RATIO_TARGETS.get(r["tracker"], (None, None))
        if ref in ms:
            ratio = r["ms_per_frame"] / ms[ref]
            verdicts.append(f"{r['tracker']} {ratio:.2f}x {ref} (target <= {factor:g}x): "
                            f"{'met' if ratio <= factor else 'MISSED'}")
    for v in verdicts:
        print("  " + v)
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps({"frames": len(frames), "shape": list(shape), "rows": rows,
                                                       "mcp_ms": {str(k): v for k, v in mcp.items()}}, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
